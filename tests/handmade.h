/* handmade.h - a DEM and its pyramid built by hand for t_verify, without
 * the checker and without tilepack: the DEM written as a float32 TIFF
 * (with voids), levels sub-sampled from it (displaced levels get random
 * offsets, kept on the level's boundary), local errors bounded from above
 * by interval arithmetic over the bounding box of each diamond triangle
 * (the DEM range against the corners' range), saturated through
 * bintree.c's children, padded, written with pyramid.h. Such E are true,
 * loose upper bounds: every check passes. */
#ifndef T_HANDMADE_H
#define T_HANDMADE_H

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "dem/dem.h"
#include "qem/fqm.h"
#include "geo/georef.h"
#include "pyramid/bintree.h"
#include "pyramid/pyramid.h"
#include "tiff.h"

#define NODATA -9999.0f

typedef struct {
	const char *name;
	int W, H;
	int disp[8];       /* per level */
	float *z;          /* filled, as dem.c gives it */
	unsigned char *v;  /* valid */
	georef geo;
	geo_ground m;
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

/* The DEM file (voids: a blob and a few samples), then read back
 * through dem.c so that the pyramid holds what the checker will see. */
static int
make_world(world *w, const char *tmp, const char *name, int W, int H)
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
	while (geo_level_size(W, w->nlev) > BT_SIZE ||
	    geo_level_size(H, w->nlev) > BT_SIZE)
		w->nlev++;
	w->nlev++;
	return geo_ground_init(&w->m, &w->geo, &e);
}

static void
free_world(world *w)
{
	free(w->z), free(w->v);
	geo_ground_free(&w->m);
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
static int
on_level(const grid *g, const int v[2])
{
	return v[0] >= 0 && v[1] >= 0 && v[0] < g->gw && v[1] < g->gh;
}

/* A bound of vertex (i, j)'s local error: over its diamond's triangles. */
static double
local_bound(const world *w, const grid *g, int i, int j)
{
	int tri[2][3][2], n = bt_diamond(i, j, tri);
	double e = 0;

	for (int q = 0; q < n; q++) {
		int k[3], in = 1;
		for (int c = 0; c < 3; c++) {
			in &= on_level(g, tri[q][c]);
			k[c] = in ? gidx(g, tri[q][c][0], tri[q][c][1]) : 0;
		}
		if (in)
			e = fmax(e, bound(w, g, k, 3));
	}
	return e;
}

/* E(i, j) raised to its children's. */
static void
saturate(grid *g, int i, int j)
{
	int ch[4][2], nc = bt_children(i, j, ch), k = gidx(g, i, j);

	for (int q = 0; q < nc; q++)
		if (on_level(g, ch[q]))
			g->e[k] = fmaxf(g->e[k],
			    g->e[gidx(g, ch[q][0], ch[q][1])]);
}

static void
errors(const world *w, grid *g)
{
	for (int j = 0; j < g->gh; j++)
		for (int i = 0; i < g->gw; i++)
			g->e[gidx(g, i, j)] = (float)local_bound(w, g, i, j);
	for (int h = 1; h <= BT_MAXH; h *= 2)
		for (int pass = 0; pass < 2; pass++)
			for (int j = 0; j < g->gh; j++)
				for (int i = 0; i < g->gw; i++) {
					bt_class c = bt_classify(i, j);
					if (c.kind != BT_CORNER && c.h == h &&
					    (c.kind == BT_SQUARE) == pass)
						saturate(g, i, j);
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
	return rs_put_georef(&w->geo, h, &e) < 0 ||
	    rs_set_int(h, FQM_ATTR_VERSION, FQM_VERSION, &e) < 0 ||
	    rs_set_string(h, FQM_ATTR_KIND, "vertices", &e) < 0 ||
	    rs_set_int(h, FQM_ATTR_LEVEL, l, &e) < 0 ||
	    rs_set_v2i(h, FQM_ATTR_SIZE0, w->W, w->H, &e) < 0 ||
	    rs_set_string(h, FQM_ATTR_MODE, mode, &e) < 0 ||
	    rs_set_string(h, FQM_ATTR_KERNEL, l ? "binomial" : "none",
	    &e) < 0 ?
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
		g.w = geo_level_size(w->W, l), g.h = geo_level_size(w->H, l);
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

#endif
