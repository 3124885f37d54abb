/* t_verify - the pyramid checker (verify.h): its bintree derivation
 * against bintree.c, then hand-built pyramids that must pass and one
 * corruption at a time that must be caught.
 *
 * The pyramids are built here without verify.c: a DEM written as a
 * float32 TIFF (with voids), levels sub-sampled from it (displaced
 * levels get random offsets, kept on the level's boundary), local errors
 * bounded from above by interval arithmetic over the bounding box of
 * each diamond triangle (the DEM range against the corners' range),
 * saturated through bintree.c's children, padded, written with
 * pyramid.h. Such E are true, loose upper bounds: every check passes. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <tiffio.h>
#include <unistd.h>

#include "pyramid/bintree.h"
#include "core/dem.h"
#include "core/fqm.h"
#include "core/georef.h"
#include "pyramid/pyramid.h"
#include "tap.h"
#include "pyramid/verify.h"

#define NODATA -9999.0f

static char tmp[PATH_MAX - 64];

/* --- the derivation against bintree.c ------------------------------- */

static int
same_tri(const int a[3][2], const int b[3][2])
{
	int ends = (a[0][0] == b[0][0] && a[0][1] == b[0][1] &&
	    a[1][0] == b[1][0] && a[1][1] == b[1][1]) ||
	    (a[0][0] == b[1][0] && a[0][1] == b[1][1] &&
	    a[1][0] == b[0][0] && a[1][1] == b[0][1]);

	return ends && a[2][0] == b[2][0] && a[2][1] == b[2][1];
}

static int
inside(int n, const int p[2])
{
	return p[0] >= 0 && p[1] >= 0 && p[0] <= n && p[1] <= n;
}

/* Sets of points: equal when each of a is in b and the sizes match. */
static int
same_points(int na, int a[][2], int nb, int b[][2])
{
	if (na != nb)
		return 0;
	for (int i = 0; i < na; i++) {
		int found = 0;
		for (int j = 0; j < nb; j++)
			found |= a[i][0] == b[j][0] && a[i][1] == b[j][1];
		if (!found)
			return 0;
	}
	return 1;
}

static void
test_relations(const vf_tree *t)
{
	int nb = 3, n = nb * BT_CELLS;
	long bad_d = 0, bad_p = 0, bad_c = 0, checked = 0;

	for (int j = 0; j <= n; j++)
		for (int i = 0; i <= n; i++) {
			int td[2][3][2], vd[2][3][2], tp[2][2], vp[2][2];
			int tc[4][2], vc[4][2], keep[4][2], ntd, nvd, k = 0;
			int ntp, ntc;
			/* bintree.c's triangles, parents, children within
			 * the level's blocks */
			ntd = bt_diamond(i, j, td);
			nvd = vf_diamond(t, nb, nb, i, j, vd);
			for (int q = 0; q < ntd; q++)
				if (inside(n, td[q][2])) {
					int hit = 0;
					for (int r = 0; r < nvd; r++)
						hit |= same_tri(td[q], vd[r]);
					k++;
					if (!hit && bad_d++ < 8)
						printf("# (%d,%d): bt_diamond has "
						    "(%d,%d)-(%d,%d) apex (%d,%d), "
						    "the block's tree not\n", i, j,
						    td[q][0][0], td[q][0][1],
						    td[q][1][0], td[q][1][1],
						    td[q][2][0], td[q][2][1]);
				}
			bad_d += k != nvd;
			ntp = bt_parents(i, j, tp);
			for (int q = k = 0; q < ntp; q++)
				if (inside(n, tp[q]))
					memcpy(keep[k++], tp[q], sizeof keep[0]);
			bad_p += !same_points(k, keep, vf_parents(t, nb, nb, i,
			    j, vp), vp);
			ntc = bt_children(i, j, tc);
			for (int q = k = 0; q < ntc; q++)
				if (inside(n, tc[q]))
					memcpy(keep[k++], tc[q], sizeof keep[0]);
			bad_c += !same_points(k, keep, vf_children(t, nb, nb, i,
			    j, vc), vc);
			checked++;
		}
	ok(bad_d == 0, "diamonds from the explicit trees = bt_diamond over a "
	    "3x3-block level (%ld vertices, %ld differ)", checked, bad_d);
	ok(bad_p == 0, "parents = bt_parents (%ld differ)", bad_p);
	ok(bad_c == 0, "children = bt_children (%ld differ)", bad_c);
}

/* bt_select's and vf_select's triangles, sorted, for one block. */
typedef struct {
	int n;
	int (*tri)[6];
} tris;

static void
bt_emit(void *ctx, const int t[3][2])
{
	tris *s = ctx;
	int *o = s->tri[s->n++];

	for (int k = 0; k < 3; k++)
		o[2 * k] = t[k][0], o[2 * k + 1] = t[k][1];
}

static int
cmp6(const void *a, const void *b)
{
	return memcmp(a, b, 6 * sizeof(int));
}

static const float *sel_e;
static double sel_tau;

static int
bt_split(void *ctx, int gi, int gj)
{
	(void)ctx;
	return sel_e[gj * BT_SIZE + gi] > sel_tau;
}

static void
test_select(const vf_tree *t)
{
	static float e[PYRAMID_N];
	static unsigned char sel[PYRAMID_N];
	static int out[2 * BT_CELLS * BT_CELLS];
	tris a, b;
	unsigned s = 7;
	long bad = 0, n = 0, full;

	a.tri = calloc(2 * BT_CELLS * BT_CELLS, sizeof *a.tri);
	b.tri = calloc(2 * BT_CELLS * BT_CELLS, sizeof *b.tri);
	memset(sel, 1, sizeof sel);
	full = vf_select(t, sel, out);
	ok(full == 2L * BT_CELLS * BT_CELLS, "full selection: %ld leaves",
	    full);
	/* random errors scaled by the vertex's scale, saturated by bintree.c */
	for (int k = 0; k < PYRAMID_N; k++) {
		s = s * 1103515245u + 12345u;
		e[k] = (float)((s >> 16) % 1000) *
		    (float)bt_classify(k % BT_SIZE, k / BT_SIZE).h;
	}
	for (int h = 1; h <= BT_MAXH; h *= 2)
		for (int pass = 0; pass < 2; pass++)
			for (int k = 0; k < PYRAMID_N; k++) {
				bt_class c = bt_classify(k % BT_SIZE, k / BT_SIZE);
				int ch[4][2], nc;
				if (c.h != h || (c.kind == BT_SQUARE) != pass)
					continue;
				nc = bt_children(k % BT_SIZE, k / BT_SIZE, ch);
				for (int q = 0; q < nc; q++)
					if (inside(BT_CELLS, ch[q]))
						e[k] = fmaxf(e[k], e[ch[q][1] *
						    BT_SIZE + ch[q][0]]);
			}
	sel_e = e;
	for (sel_tau = 0; sel_tau < 64000; sel_tau = sel_tau * 3 + 100) {
		for (int k = 0; k < PYRAMID_N; k++)
			sel[k] = e[k] > sel_tau;
		a.n = b.n = 0;
		bt_select(0, 0, bt_split, NULL, bt_emit, &a);
		b.n = (int)vf_select(t, sel, out);
		for (int q = 0; q < b.n; q++) {
			const vf_node *d = &t->node[out[q]];
			int *o = b.tri[q];
			o[0] = d->a[0], o[1] = d->a[1], o[2] = d->b[0];
			o[3] = d->b[1], o[4] = d->p[0], o[5] = d->p[1];
		}
		qsort(a.tri, a.n, sizeof *a.tri, cmp6);
		qsort(b.tri, b.n, sizeof *b.tri, cmp6);
		bad += a.n != b.n || memcmp(a.tri, b.tri, a.n * sizeof *a.tri);
		n++;
	}
	ok(bad == 0, "vf_select = bt_select on saturated random errors "
	    "(%ld taus, %ld differ)", n, bad);
	free(a.tri), free(b.tri);
}

/* --- a DEM and a pyramid built by hand ------------------------------ */

typedef struct {
	const char *name;
	int W, H;
	int disp[8];       /* per level */
	float *z;          /* filled, as dem.c gives it */
	unsigned char *v;  /* valid */
	georef geo;
	geo_metric m;
	char dem[PATH_MAX];
	dem_opts dopt;
	int nlev;
} world;

static float
terrain(int i, int j, unsigned *s)
{
	*s = *s * 1103515245u + 12345u;
	return (float)(300 + 40 * sin(i * 0.031) * cos(j * 0.043) +
	    0.15 * i - 0.1 * j + 8 * sin(i * 0.21 + j * 0.17) +
	    ((*s >> 16) % 1000) / 1000.0 - 0.5);
}

static int
write_tiff(const char *path, int w, int h, const float *z)
{
	TIFF *t = TIFFOpen(path, "w");
	int r = 0;

	if (t == NULL)
		return -1;
	TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
	TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
	TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 32);
	TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
	TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
	TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
	TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
	TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, 16);
	for (int j = 0; j < h && r == 0; j++)
		if (TIFFWriteScanline(t, (void *)(z + (size_t)j * w), j, 0) < 0)
			r = -1;
	TIFFClose(t);
	return r;
}

/* The DEM file (voids: a blob and a few samples), then read back
 * through dem.c so that the pyramid holds what the checker will see. */
static int
make_world(world *w, const char *name, int W, int H)
{
	float *raw = calloc((size_t)W * H, sizeof *raw);
	unsigned s = 11;
	tl_err e;
	dem *d;

	memset(w->disp, 0, sizeof w->disp);
	w->name = name, w->W = W, w->H = H;
	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++) {
			int blob = (i - W / 3) * (i - W / 3) +
			    (j - H / 2) * (j - H / 2) < 36;
			raw[(size_t)j * W + i] = blob || (i * 7 + j * 13) % 997
			    == 0 ? NODATA : terrain(i, j, &s);
		}
	snprintf(w->dem, sizeof w->dem, "%s/%s.tif", tmp, name);
	if (write_tiff(w->dem, W, H, raw) < 0)
		return -1;
	free(raw);
	memset(&w->dopt, 0, sizeof w->dopt);
	w->dopt.cell[0] = 2, w->dopt.cell[1] = 3;
	w->dopt.has_nodata = 1, w->dopt.nodata = NODATA;
	if ((d = dem_open(w->dem, &w->dopt, &e)) == NULL) {
		printf("# %s\n", e.msg);
		return -1;
	}
	w->geo = *dem_georef(d);
	w->z = calloc((size_t)W * H, sizeof *w->z);
	w->v = calloc((size_t)W * H, 1);
	for (int j = 0; j < H; j++)
		dem_read_row(d, j, w->z + (size_t)j * W, w->v + (size_t)j * W,
		    &e);
	dem_close(d);
	w->nlev = 0;
	while (fqm_level_size(W, w->nlev) > BT_SIZE ||
	    fqm_level_size(H, w->nlev) > BT_SIZE)
		w->nlev++;
	w->nlev++;
	return geo_metric_init(&w->m, &w->geo, &e);
}

static void
free_world(world *w)
{
	free(w->z), free(w->v);
	geo_metric_free(&w->m);
}

/* One level on the whole grid of its blocks (gw x gh vertices). */
typedef struct {
	int l, s, w, h, bx, by, gw, gh, disp;
	float *z, *e, *x, *y;
	double *px, *py;
} grid;

static int
gidx(const grid *g, int i, int j)
{
	return j * g->gw + i;
}

/* Valid DEM range over a box of level-0 positions, widened by a sample. */
static int
dem_range(const world *w, double x0, double x1, double y0, double y1,
    double *lo, double *hi)
{
	int i0 = (int)fmax(0, floor(x0) - 1), i1 = (int)fmin(w->W - 1, ceil(x1) + 1);
	int j0 = (int)fmax(0, floor(y0) - 1), j1 = (int)fmin(w->H - 1, ceil(y1) + 1);
	int n = 0;

	*lo = INFINITY, *hi = -INFINITY;
	for (int j = j0; j <= j1; j++)
		for (int i = i0; i <= i1; i++)
			if (w->v[(size_t)j * w->W + i]) {
				double z = w->z[(size_t)j * w->W + i];
				*lo = fmin(*lo, z), *hi = fmax(*hi, z);
				n++;
			}
	return n;
}

/* An upper bound of |surface - DEM| over the samples of the polygon of
 * grid vertices k[0..n-1]. */
static double
bound(const world *w, const grid *g, const int *k, int n)
{
	double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
	double zl = INFINITY, zh = -INFINITY, dl, dh;

	for (int q = 0; q < n; q++) {
		x0 = fmin(x0, g->px[k[q]]), x1 = fmax(x1, g->px[k[q]]);
		y0 = fmin(y0, g->py[k[q]]), y1 = fmax(y1, g->py[k[q]]);
		zl = fmin(zl, g->z[k[q]]), zh = fmax(zh, g->z[k[q]]);
	}
	if (dem_range(w, x0, x1, y0, y1, &dl, &dh) == 0)
		return 0;
	return fmax(0, fmax(dh - zl, zh - dl));
}

static double
unit_rand(unsigned *s)
{
	*s = *s * 1103515245u + 12345u;
	return ((*s >> 8) & 0xffff) / 65535.0;
}

static void
fill_grid(const world *w, grid *g)
{
	unsigned s = 99 + g->l;

	for (int j = 0; j < g->gh; j++)
		for (int i = 0; i < g->gw; i++) {
			int k = gidx(g, i, j), ri = i < g->w ? i : g->w - 1;
			int rj = j < g->h ? j : g->h - 1;
			long I = (long)ri * g->s, J = (long)rj * g->s;
			double di = 0, dj = 0, sx, sy;
			I = I < w->W ? I : w->W - 1, J = J < w->H ? J : w->H - 1;
			g->z[k] = w->z[J * w->W + I];
			g->px[k] = (double)i * g->s, g->py[k] = (double)j * g->s;
			if (!g->disp)
				continue;
			g->x[k] = g->y[k] = 0;
			if (i != ri || j != rj)
				continue; /* padding */
			/* offsets in metres, kept on the boundary, under
			 * 0.15 cells: no triangle folds */
			if (i > 0 && i < g->w - 1)
				di = (unit_rand(&s) - 0.5) * 0.3 * g->s;
			if (j > 0 && j < g->h - 1)
				dj = (unit_rand(&s) - 0.5) * 0.3 * g->s;
			geo_scale(&w->m, g->px[k], g->py[k], &sx, &sy);
			g->x[k] = (float)(di * sx), g->y[k] = (float)(dj * sy);
			geo_offset_to_grid(&w->m, g->px[k], g->py[k], g->x[k],
			    g->y[k], &di, &dj);
			g->px[k] += di, g->py[k] += dj;
		}
}

/* Local error bounds, saturated children first (t_bintree's order). */
static void
errors(const world *w, grid *g)
{
	for (int j = 0; j < g->gh; j++)
		for (int i = 0; i < g->gw; i++) {
			int tri[2][3][2], n = bt_diamond(i, j, tri);
			double e = 0;
			for (int q = 0; q < n; q++) {
				int k[3], in = 1;
				for (int c = 0; c < 3; c++) {
					in &= tri[q][c][0] >= 0 && tri[q][c][1] >= 0 &&
					    tri[q][c][0] < g->gw && tri[q][c][1] < g->gh;
					k[c] = in ? gidx(g, tri[q][c][0],
					    tri[q][c][1]) : 0;
				}
				if (in)
					e = fmax(e, bound(w, g, k, 3));
			}
			g->e[gidx(g, i, j)] = (float)e;
		}
	for (int h = 1; h <= BT_MAXH; h *= 2)
		for (int pass = 0; pass < 2; pass++)
			for (int j = 0; j < g->gh; j++)
				for (int i = 0; i < g->gw; i++) {
					bt_class c = bt_classify(i, j);
					int ch[4][2], nc, k = gidx(g, i, j);
					if (c.kind == BT_CORNER || c.h != h ||
					    (c.kind == BT_SQUARE) != pass)
						continue;
					nc = bt_children(i, j, ch);
					for (int q = 0; q < nc; q++)
						if (ch[q][0] >= 0 && ch[q][1] >= 0 &&
						    ch[q][0] < g->gw && ch[q][1] < g->gh)
							g->e[k] = fmaxf(g->e[k],
							    g->e[gidx(g, ch[q][0], ch[q][1])]);
				}
	for (int j = 0; j < g->gh; j += BT_CELLS)
		for (int i = 0; i < g->gw; i += BT_CELLS)
			g->e[gidx(g, i, j)] = FLT_MAX;
}

static int
attrs(const world *w, int l, const char *mode, rs_header *h)
{
	tl_err e;

	rs_header_init(h, 0, 0);
	return geo_to_header(&w->geo, h, &e) < 0 ||
	    rs_set_int(h, "fqm:version", FQM_VERSION, &e) < 0 ||
	    rs_set_string(h, "fqm:kind", "vertices", &e) < 0 ||
	    rs_set_int(h, "fqm:level", l, &e) < 0 ||
	    rs_set_v2i(h, "fqm:size0", w->W, w->H, &e) < 0 ||
	    rs_set_string(h, "fqm:mode", mode, &e) < 0 ||
	    rs_set_string(h, "fqm:kernel", l ? "binomial" : "none", &e) < 0 ?
	    -1 : 0;
}

static const char *
mode_of(const world *w, int l)
{
	return w->disp[l] ? "qem3d" : "qem1d";
}

static int
write_level(const world *w, const char *dir, grid *g, pyramid_level *L)
{
	pyramid_block b;
	rs_header h;
	char path[PATH_MAX];
	tl_err e;
	int r = 0;

	if (pyramid_block_alloc(&b, g->disp, &e) < 0 ||
	    attrs(w, g->l, mode_of(w, g->l), &h) < 0)
		return -1;
	snprintf(path, sizeof path, "%s/%d", dir, g->l);
	mkdir(path, 0777);
	for (int bj = 0; bj < g->by && r == 0; bj++)
		for (int bi = 0; bi < g->bx && r == 0; bi++) {
			size_t kb = (size_t)bj * g->bx + bi;
			double zl = INFINITY, zh = -INFINITY, em = 0, base = 0;
			for (int k = 0; k < PYRAMID_N; k++) {
				int c = k % BT_SIZE, q = k / BT_SIZE;
				int gk = gidx(g, bi * BT_CELLS + c, bj * BT_CELLS + q);
				b.z[k] = g->z[gk], b.e[k] = g->e[gk];
				if (g->disp)
					b.x[k] = g->x[gk], b.y[k] = g->y[gk];
				zl = fmin(zl, b.z[k]), zh = fmax(zh, b.z[k]);
				if (b.e[k] < FLT_MAX)
					em = fmax(em, b.e[k]);
				if (g->l > 0 && c < BT_CELLS && q < BT_CELLS) {
					int cell[4] = { gk, gk + 1, gk + g->gw + 1,
						gk + g->gw };
					base = fmax(base, bound(w, g, cell, 4));
				}
			}
			b.level = g->l, b.bi = bi, b.bj = bj;
			b.zmin = L->zmin[kb] = zl, b.zmax = L->zmax[kb] = zh;
			b.base = L->base[kb] = base;
			L->emax[kb] = em;
			pyramid_block_path(path, sizeof path, dir, g->l, bi, bj);
			r = pyramid_block_write(path, &b, &h, &e);
		}
	if (r < 0)
		printf("# %s\n", e.msg);
	rs_header_free(&h);
	pyramid_block_free(&b);
	return r;
}

static int
build(const world *w, const char *dir)
{
	pyramid_index ix;
	tl_err e;
	int r = 0;

	mkdir(dir, 0777);
	memset(&ix, 0, sizeof ix);
	ix.version = VGIS_VERSION;
	ix.size0[0] = w->W, ix.size0[1] = w->H;
	ix.geo = w->geo;
	ix.lev = calloc(w->nlev, sizeof *ix.lev);
	ix.nlevels = w->nlev;
	for (int l = 0; l < w->nlev && r == 0; l++) {
		pyramid_level *L = &ix.lev[l];
		grid g = { .l = l, .s = 1 << l, .disp = w->disp[l] };
		g.w = fqm_level_size(w->W, l), g.h = fqm_level_size(w->H, l);
		if (pyramid_level_init(L, l, g.w, g.h, &e) < 0)
			return -1;
		L->displaced = g.disp;
		snprintf(L->mode, sizeof L->mode, "%s", mode_of(w, l));
		snprintf(L->kernel, sizeof L->kernel, "%s",
		    l ? "binomial" : "none");
		g.bx = L->blocks[0], g.by = L->blocks[1];
		g.gw = g.bx * BT_CELLS + 1, g.gh = g.by * BT_CELLS + 1;
		size_t n = (size_t)g.gw * g.gh;
		g.z = calloc(n, sizeof *g.z), g.e = calloc(n, sizeof *g.e);
		g.x = calloc(n, sizeof *g.x), g.y = calloc(n, sizeof *g.y);
		g.px = calloc(n, sizeof *g.px), g.py = calloc(n, sizeof *g.py);
		fill_grid(w, &g);
		errors(w, &g);
		r = write_level(w, dir, &g, L);
		free(g.z), free(g.e), free(g.x), free(g.y), free(g.px);
		free(g.py);
	}
	if (r == 0 && pyramid_index_write(dir, &ix, &e) < 0) {
		printf("# %s\n", e.msg);
		r = -1;
	}
	pyramid_index_free(&ix);
	return r;
}

/* --- running the checker -------------------------------------------- */

static vf_report rep;

static int
check(const world *w, const char *dir, int with_dem)
{
	vf_opts o;
	tl_err e;

	vf_report_free(&rep);
	vf_opts_init(&o);
	if (vf_check(dir, with_dem ? w->dem : NULL, &w->dopt, &o, &rep,
	    &e) < 0) {
		printf("# vf_check: %s\n", e.msg);
		return -1;
	}
	return 0;
}

static void
show(int kind)
{
	for (int k = 0; k < rep.nissue; k++)
		if (kind < 0 || rep.issue[k].kind == kind) {
			printf("#   level %d block (%d,%d) vertex (%d,%d): %s: %s\n",
			    rep.issue[k].level, rep.issue[k].block[0],
			    rep.issue[k].block[1], rep.issue[k].vertex[0],
			    rep.issue[k].vertex[1],
			    vf_kind_name(rep.issue[k].kind), rep.issue[k].text);
			if (kind < 0 && k > 10)
				break;
		}
}

static void
counts(char *buf, size_t n)
{
	size_t len = 0;

	buf[0] = '\0';
	for (int k = 0; k < VF_NKIND && len < n; k++)
		if (rep.count[k])
			len += snprintf(buf + len, n - len, " %s %lld",
			    vf_kind_name(k), rep.count[k]);
}

static void
passes(const world *w, const char *dir)
{
	long long ntri = 0;
	double tight = 0;
	char c[256];

	if (check(w, dir, 1) < 0) {
		ok(0, "%s: the checker ran", w->name);
		return;
	}
	counts(c, sizeof c);
	ok(rep.total == 0, "%s: %d levels pass every check with the DEM "
	    "(%lld violations:%s)", w->name, rep.nlevels, rep.total, c);
	if (rep.total)
		show(-1);
	for (int l = 0; l < rep.nlevels; l++) {
		const vf_level *L = &rep.lev[l];
		ntri += L->tau[0].triangles;
		if (!isnan(L->tight))
			tight = fmax(tight, L->tight);
		printf("# level %d: %d taus, %lld triangles at tau 0, max "
		    "error %.4g at tau %g, tightness %.3f, base %.4g "
		    "(real %.4g), %lld samples\n", l, L->ntau,
		    L->tau[0].triangles, L->tau[L->ntau - 1].maxerr,
		    L->tau[L->ntau - 1].tau, L->tight, L->base, L->base_real,
		    L->samples);
	}
	ok(rep.dem && ntri > 0 && tight <= 1 && rep.lev[0].base_real == 0,
	    "%s: triangles counted, tightness %.3f <= 1, level 0 "
	    "reproduces every sample", w->name, tight);
	ok(check(w, dir, 0) == 0 && rep.total == 0 && !rep.dem &&
	    isnan(rep.lev[0].tau[0].maxerr), "%s: passes without the DEM",
	    w->name);
}

/* --- corruptions ---------------------------------------------------- */

static int
edit_block(const world *w, const char *dir, int l, int bi, int bj,
    void (*fn)(pyramid_block *, void *), void *arg)
{
	char path[PATH_MAX];
	pyramid_block b;
	rs_header h;
	tl_err e;
	int r;

	if (pyramid_block_alloc(&b, w->disp[l], &e) < 0)
		return -1;
	b.level = l, b.bi = bi, b.bj = bj;
	pyramid_block_path(path, sizeof path, dir, l, bi, bj);
	if (pyramid_block_read(path, &b, &e) < 0 ||
	    attrs(w, l, mode_of(w, l), &h) < 0) {
		printf("# %s\n", e.msg);
		pyramid_block_free(&b);
		return -1;
	}
	fn(&b, arg);
	r = pyramid_block_write(path, &b, &h, &e);
	rs_header_free(&h);
	pyramid_block_free(&b);
	return r;
}

static void
bump_z(pyramid_block *b, void *arg)
{
	int k = *(int *)arg;

	b->z[k] += 0.25f;
}

static void
lower_parent(pyramid_block *b, void *arg)
{
	/* the block's centre (scale 64), below its children on the axes */
	int m = 64 * BT_SIZE + 64;
	float c = fmaxf(fmaxf(b->e[64], b->e[128 * BT_SIZE + 64]),
	    fmaxf(b->e[64 * BT_SIZE], b->e[64 * BT_SIZE + 128]));

	(void)arg;
	b->e[m] = c / 2;
}

static void
corner_e(pyramid_block *b, void *arg)
{
	(void)arg;
	b->e[0] = 1000;
}

static void
scale_e(pyramid_block *b, void *arg)
{
	for (int k = 0; k < PYRAMID_N; k++)
		if (b->e[k] < FLT_MAX)
			b->e[k] *= *(float *)arg;
}

static void
move_x(pyramid_block *b, void *arg)
{
	int *a = arg; /* vertex, level cells, metres per cell */

	b->x[a[0]] += (float)a[1] * (float)a[2];
}

typedef int (*corrupt_fn)(const world *, const char *);

static int
c_border(const world *w, const char *d)
{
	int k = 40 * BT_SIZE + BT_CELLS; /* right edge of block (0,0) */

	return edit_block(w, d, 0, 0, 0, bump_z, &k);
}

static int
c_saturation(const world *w, const char *d)
{
	return edit_block(w, d, 0, 0, 0, lower_parent, NULL);
}

static int
c_missing(const world *w, const char *d)
{
	char p[PATH_MAX];

	(void)w;
	pyramid_block_path(p, sizeof p, d, 0, 1, 0);
	return unlink(p);
}

static int
c_truncated(const world *w, const char *d)
{
	char p[PATH_MAX];
	struct stat st;

	(void)w;
	pyramid_block_path(p, sizeof p, d, 0, 0, 1);
	if (stat(p, &st) < 0)
		return -1;
	return truncate(p, st.st_size / 2);
}

static int
c_corner(const world *w, const char *d)
{
	return edit_block(w, d, 0, 1, 1, corner_e, NULL);
}

static int
c_zrange(const world *w, const char *d)
{
	pyramid_index ix;
	tl_err e;
	int r;

	(void)w;
	if (pyramid_index_read(d, &ix, &e) < 0)
		return -1;
	ix.lev[0].zmin[1] -= 1;
	ix.lev[0].zmax[1] += 1;
	r = pyramid_index_write(d, &ix, &e);
	pyramid_index_free(&ix);
	return r;
}

/* Every E of level 1 (a displaced one) scaled down: saturation, index
 * and matching still hold, the errors do not. */
static int
c_small_e(const world *w, const char *d)
{
	pyramid_index ix;
	tl_err e;
	float f = 0.02f;
	int r = 0;

	if (pyramid_index_read(d, &ix, &e) < 0)
		return -1;
	for (int bj = 0; bj < ix.lev[1].blocks[1] && r == 0; bj++)
		for (int bi = 0; bi < ix.lev[1].blocks[0] && r == 0; bi++) {
			r = edit_block(w, d, 1, bi, bj, scale_e, &f);
			ix.lev[1].emax[bj * ix.lev[1].blocks[0] + bi] =
			    (float)ix.lev[1].emax[bj * ix.lev[1].blocks[0] + bi] *
			    f;
		}
	if (r == 0)
		r = pyramid_index_write(d, &ix, &e);
	pyramid_index_free(&ix);
	return r;
}

static int
c_stray(const world *w, const char *d)
{
	char p[PATH_MAX];
	FILE *f;

	(void)w;
	snprintf(p, sizeof p, "%s/0/.0_0.exr.tmp", d);
	if ((f = fopen(p, "w")) == NULL)
		return -1;
	return fclose(f);
}

static int
c_padding(const world *w, const char *d)
{
	/* level 0 is 300 wide: block column 2 holds 256..384 */
	int k = 10 * BT_SIZE + 100;

	return edit_block(w, d, 0, 2, 0, bump_z, &k);
}

static int
c_fold(const world *w, const char *d)
{
	/* level 1 (s = 2, 2 m cells): 3 cells right */
	int a[3] = { 30 * BT_SIZE + 30, 3, 4 };

	return edit_block(w, d, 1, 0, 0, move_x, a);
}

static int
c_hole(const world *w, const char *d)
{
	/* a left-edge vertex of level 1 moved half a cell (2 m) inwards */
	int a[3] = { 50 * BT_SIZE, 1, 2 };

	return edit_block(w, d, 1, 0, 0, move_x, a);
}

static void
corruptions(const world *w)
{
	static const struct {
		const char *what;
		corrupt_fn fn;
		int kind, kind2;
	} t[] = {
		{ "Z changed on one side of a border", c_border, VF_BORDER, -1 },
		{ "E lowered below its child's", c_saturation, VF_SATURATION,
		    -1 },
		{ "a missing block", c_missing, VF_INDEX, VF_COVERAGE },
		{ "a truncated block file", c_truncated, VF_INDEX, -1 },
		{ "a corner's E not FLT_MAX", c_corner, VF_SATURATION, -1 },
		{ "index zmin/zmax that lie", c_zrange, VF_INDEX, -1 },
		{ "E too small for the DEM", c_small_e, VF_ERROR, VF_LOCAL },
		{ "a stray file in a level directory", c_stray, VF_INDEX, -1 },
		{ "a padding vertex that is no copy", c_padding, VF_PADDING,
		    -1 },
		{ "a displaced vertex moved 3 cells", c_fold, VF_FOLD, -1 },
		{ "an edge vertex moved inwards", c_hole, VF_COVERAGE, -1 },
	};
	char dir[PATH_MAX], c[256];
	size_t q;
	int st;

	for (q = 0; q < sizeof t / sizeof t[0]; q++) {
		snprintf(dir, sizeof dir, "%s/bad%zu", tmp, q);
		if (build(w, dir) < 0 || t[q].fn(w, dir) < 0 ||
		    check(w, dir, 1) < 0) {
			ok(0, "corruption: %s: set up", t[q].what);
			continue;
		}
		counts(c, sizeof c);
		ok(rep.count[t[q].kind] > 0 && (t[q].kind2 < 0 ||
		    rep.count[t[q].kind2] > 0), "caught: %s (%s%s%s:%s)",
		    t[q].what, vf_kind_name(t[q].kind),
		    t[q].kind2 >= 0 ? ", " : "",
		    t[q].kind2 >= 0 ? vf_kind_name(t[q].kind2) : "", c);
		show(t[q].kind);
	}
	/* the small E pass the structural checks: only the DEM sees them */
	snprintf(dir, sizeof dir, "%s/bad6", tmp);
	st = check(w, dir, 0);
	ok(st == 0 && rep.total == 0, "E too small: invisible without the "
	    "DEM (%lld violations)", rep.total);
}

/* --- the program ---------------------------------------------------- */

static int
run(const char *cmd)
{
	int s = system(cmd);

	return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
}

static void
program(const world *w, const char *good)
{
	char cmd[8 * PATH_MAX];

	if (access("build/tileplay", X_OK) != 0) {
		printf("ok %d - # SKIP build/tileplay not built\n", ++tap_n);
		return;
	}
	snprintf(cmd, sizeof cmd, "build/tileplay --verify %s --dem %s -s 2,3 "
	    "-N %g --tau 0.5,2,8 >%s/out 2>&1 && grep -q '^result: pass' "
	    "%s/out && grep -Eq '^ +8 +[0-9]+ +[0-9.e+-]+$' %s/out", good,
	    w->dem, NODATA, tmp, tmp, tmp);
	ok(run(cmd) == 0, "tileplay --verify --dem --tau: exit 0, "
	    "\"result: pass\", a row per tau");
	snprintf(cmd, sizeof cmd, "build/tileplay --verify %s/bad0 >%s/out "
	    "2>&1", tmp, tmp);
	ok(run(cmd) == 1, "tileplay --verify on a broken pyramid: exit 1");
	snprintf(cmd, sizeof cmd, "grep -q '^result: FAIL, [0-9]* violations:"
	    " border' %s/out && grep -q 'border: Z' %s/out", tmp, tmp);
	ok(run(cmd) == 0, "... the summary and the border violation printed");
	snprintf(cmd, sizeof cmd, "build/tileplay --verify %s/nosuch "
	    ">/dev/null 2>%s/err; s=$?; grep -q '^tileplay: .*nosuch/"
	    "index.json: ' %s/err && exit $s", tmp, tmp, tmp);
	ok(run(cmd) == 1, "tileplay --verify on no pyramid: exit 1, message");
}

int
main(void)
{
	vf_tree t;
	world w;
	tl_err e;
	char dir[PATH_MAX];

	snprintf(tmp, sizeof tmp, "%s/tlverify.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(tmp) == NULL || vf_tree_init(&t, &e) < 0) {
		ok(0, "set up");
		return tap_done();
	}
	test_relations(&t);
	test_select(&t);
	vf_tree_free(&t);

	/* one block, one level, 1D */
	if (make_world(&w, "small", 100, 90) == 0) {
		snprintf(dir, sizeof dir, "%s/small", tmp);
		ok(build(&w, dir) == 0 && w.nlev == 1, "small: built");
		passes(&w, dir);
		free_world(&w);
	}
	/* 2x2 blocks without padding, then a displaced 1x1 */
	if (make_world(&w, "exact", 257, 257) == 0) {
		w.disp[1] = 1;
		snprintf(dir, sizeof dir, "%s/exact", tmp);
		ok(build(&w, dir) == 0 && w.nlev == 2, "exact: built");
		passes(&w, dir);
		free_world(&w);
	}
	/* 3x2 blocks with padding, displaced levels 1 and 2 */
	if (make_world(&w, "padded", 300, 200) == 0) {
		w.disp[1] = w.disp[2] = 1;
		snprintf(dir, sizeof dir, "%s/padded", tmp);
		ok(build(&w, dir) == 0 && w.nlev == 3, "padded: built");
		passes(&w, dir);
		corruptions(&w);
		program(&w, dir);
		free_world(&w);
	}
	vf_report_free(&rep);
	if (tap_failed == 0) {
		char cmd[PATH_MAX + 16];
		snprintf(cmd, sizeof cmd, "rm -rf %s", tmp);
		run(cmd);
	} else
		printf("# kept %s\n", tmp);
	return tap_done();
}
