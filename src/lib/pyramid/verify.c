/* verify.c - the brute-force pyramid checker (see verify.h). */
#include "pyramid/verify.h"

#include <dirent.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fqm.h"
#include "core/georef.h"
#include "pyramid/pyramid.h"
#include "core/raster.h"

#define NV PYRAMID_N                            /* vertices of a block */
#define LEAVES (2 * BT_CELLS * BT_CELLS)   /* triangles of a full block */
#define BARY_EPS 1e-9                      /* closed triangles */
#define ABS_EPS 1e-3                       /* metres, float32 heights */
#define REL_EPS 1e-6                       /* of |z| */

static const char *const kind_names[VF_NKIND] = {
	"index", "border", "padding", "saturation", "matching", "fold",
	"error", "base", "local", "coverage",
};

const char *
vf_kind_name(int kind)
{
	return kind >= 0 && kind < VF_NKIND ? kind_names[kind] : "?";
}

void
vf_opts_init(vf_opts *o)
{
	memset(o, 0, sizeof *o);
	o->nsweep = 10;
	o->max_issues = 20;
	o->local = 1;
}

/* --- the explicit bintree ------------------------------------------- */

static int
grow(vf_tree *t, int *n, const int a[2], const int b[2], const int p[2])
{
	int k = (*n)++, m[2], *slot;
	vf_node *d;

	if (k >= VF_NODES)
		return -1;
	d = &t->node[k];
	for (int q = 0; q < 2; q++) {
		d->a[q] = (unsigned char)a[q], d->b[q] = (unsigned char)b[q];
		d->p[q] = (unsigned char)p[q];
	}
	d->m = d->kid[0] = d->kid[1] = -1;
	/* legs of length 1: the hypotenuse midpoint is off the grid */
	if ((a[0] + b[0]) % 2 != 0 || (a[1] + b[1]) % 2 != 0)
		return k;
	m[0] = (a[0] + b[0]) / 2, m[1] = (a[1] + b[1]) / 2;
	d->m = m[1] * BT_SIZE + m[0];
	slot = t->dia[d->m];
	if (slot[1] >= 0)
		return -1; /* a third triangle for one midpoint */
	slot[slot[0] >= 0] = k;
	if ((d->kid[0] = grow(t, n, a, p, m)) < 0 ||
	    (d->kid[1] = grow(t, n, p, b, m)) < 0)
		return -1;
	return k;
}

static int
corner(int k)
{
	return k == 0 || k == BT_CELLS || k == BT_CELLS * BT_SIZE ||
	    k == NV - 1;
}

static int
on_border(int k)
{
	int c = k % BT_SIZE, r = k / BT_SIZE;

	return c == 0 || r == 0 || c == BT_CELLS || r == BT_CELLS;
}

int
vf_tree_init(vf_tree *t, tl_err *e)
{
	static const int o[2] = { 0, 0 }, f[2] = { BT_CELLS, BT_CELLS };
	static const int tr[2] = { BT_CELLS, 0 }, bl[2] = { 0, BT_CELLS };
	int n = 0;

	memset(t, 0, sizeof *t);
	t->node = tl_alloc(VF_NODES, sizeof *t->node, e);
	t->dia = tl_alloc(NV, sizeof *t->dia, e);
	if (t->node == NULL || t->dia == NULL) {
		vf_tree_free(t);
		return -1;
	}
	for (int k = 0; k < NV; k++)
		t->dia[k][0] = t->dia[k][1] = -1;
	/* the roots share the diagonal (0,0)-(128,128) */
	if ((t->root[0] = grow(t, &n, o, f, tr)) < 0 ||
	    (t->root[1] = grow(t, &n, f, o, bl)) < 0 || n != VF_NODES)
		goto bad;
	/* what the split rule implies; a failure is a bug here */
	for (int k = 0; k < NV; k++) {
		int have = (t->dia[k][0] >= 0) + (t->dia[k][1] >= 0);
		int want = corner(k) ? 0 : on_border(k) ? 1 : 2;
		if (have != want)
			goto bad;
	}
	return 0;
bad:
	vf_tree_free(t);
	return tl_fail(e, "bintree: the split rule did not give one node per "
	    "border midpoint and two per inner one");
}

void
vf_tree_free(vf_tree *t)
{
	free(t->node);
	free(t->dia);
	t->node = NULL;
	t->dia = NULL;
}

/* The (block, node) pairs whose node has (gi, gj) as its midpoint. */
static int
holders(const vf_tree *t, int bx, int by, int gi, int gj, int hb[2][2],
    int hn[2])
{
	int n = 0;

	if (gi < 0 || gj < 0 || gi > bx * BT_CELLS || gj > by * BT_CELLS)
		return 0;
	for (int bj = gj / BT_CELLS - 1; bj <= gj / BT_CELLS; bj++)
		for (int bi = gi / BT_CELLS - 1; bi <= gi / BT_CELLS; bi++) {
			int c = gi - bi * BT_CELLS, r = gj - bj * BT_CELLS;
			if (bi < 0 || bj < 0 || bi >= bx || bj >= by ||
			    c > BT_CELLS || r > BT_CELLS)
				continue;
			for (int q = 0; q < 2; q++) {
				int k = t->dia[r * BT_SIZE + c][q];
				if (k < 0 || n == 2)
					continue;
				hb[n][0] = bi, hb[n][1] = bj;
				hn[n++] = k;
			}
		}
	return n;
}

int
vf_diamond(const vf_tree *t, int bx, int by, int gi, int gj,
    int tri[2][3][2])
{
	int hb[2][2], hn[2], n = holders(t, bx, by, gi, gj, hb, hn);

	for (int q = 0; q < n; q++) {
		const vf_node *d = &t->node[hn[q]];
		int ox = hb[q][0] * BT_CELLS, oy = hb[q][1] * BT_CELLS;
		tri[q][0][0] = d->a[0] + ox, tri[q][0][1] = d->a[1] + oy;
		tri[q][1][0] = d->b[0] + ox, tri[q][1][1] = d->b[1] + oy;
		tri[q][2][0] = d->p[0] + ox, tri[q][2][1] = d->p[1] + oy;
	}
	return n;
}

int
vf_parents(const vf_tree *t, int bx, int by, int gi, int gj, int p[2][2])
{
	int tri[2][3][2], n = vf_diamond(t, bx, by, gi, gj, tri);

	for (int q = 0; q < n; q++)
		p[q][0] = tri[q][2][0], p[q][1] = tri[q][2][1];
	return n;
}

int
vf_children(const vf_tree *t, int bx, int by, int gi, int gj, int c[4][2])
{
	int hb[2][2], hn[2], n = holders(t, bx, by, gi, gj, hb, hn), nc = 0;

	for (int q = 0; q < n; q++)
		for (int s = 0; s < 2; s++) {
			int kid = t->node[hn[q]].kid[s], m;
			if (kid < 0 || (m = t->node[kid].m) < 0)
				continue;
			c[nc][0] = m % BT_SIZE + hb[q][0] * BT_CELLS;
			c[nc][1] = m / BT_SIZE + hb[q][1] * BT_CELLS;
			nc++;
		}
	return nc;
}

long
vf_select(const vf_tree *t, const unsigned char *sel, int *out)
{
	int stack[64], top = 0;
	long n = 0;

	stack[top++] = t->root[1];
	stack[top++] = t->root[0];
	while (top > 0) {
		const vf_node *d = &t->node[stack[--top]];
		if (d->m >= 0 && sel[d->m]) {
			stack[top++] = d->kid[1];
			stack[top++] = d->kid[0];
		} else
			out[n++] = (int)(d - t->node);
	}
	return n;
}

/* --- the checker's state -------------------------------------------- */

typedef struct {
	const char *dir;
	vf_opts o;
	vf_report *r;
	vf_index ix;
	vf_tree tree;
	dem *dem;
	int W, H;          /* level-0 size */
	geo_metric metric; /* for QEM-3D offsets */
	tl_err *e;
} checker;

typedef struct {
	int ok;                /* read and usable */
	float *z, *e, *x, *y;  /* NV each; x, y NULL unless displaced */
	double *px, *py;       /* level-0 grid position of each vertex */
} blk;

/* DEM rows j0 .. j0+n-1, full width; f: bit 0 valid, bit 1 covered */
typedef struct {
	int j0, n, cap;
	float *z;
	unsigned char *f;
} dwin;

typedef struct {
	checker *c;
	const vf_ilevel *L;
	vf_level *R;
	int l, s, bx, by, disp;
	double *tau;
	int ntau;
	blk *row[2];             /* the block row above, this one */
	unsigned char *inside;   /* bx x NV: strictly inside an emitted edge */
	unsigned char *bot[2];   /* ntau x bx x 129: bottom rows of inside */
	unsigned char *sel, *used;
	int *emit;
	int *w0, *w1;            /* DEM rows of each block row */
	dwin w;
} lv;

typedef struct {
	double dev, adj; /* largest |surface - DEM|, and less REL_EPS |z| */
	int I, J, n;     /* worst sample; samples inside */
} devmax;

static void
note(checker *c, int kind, int level, int bi, int bj, int gi, int gj,
    double tau, const char *fmt, ...) __attribute__((format(printf, 9, 10)));

static void
note(checker *c, int kind, int level, int bi, int bj, int gi, int gj,
    double tau, const char *fmt, ...)
{
	vf_report *r = c->r;
	int *kept = level >= 0 ? r->lev[level].kept : r->kept;
	vf_issue *s;
	va_list ap;

	r->count[kind]++;
	r->total++;
	if (level >= 0)
		r->lev[level].count[kind]++;
	if (kept[kind] >= c->o.max_issues)
		return;
	if (r->nissue == r->capissue) {
		int cap = r->capissue ? 2 * r->capissue : 64;
		vf_issue *p = realloc(r->issue, (size_t)cap * sizeof *p);
		if (p == NULL)
			return; /* counted, not kept */
		r->issue = p, r->capissue = cap;
	}
	kept[kind]++;
	s = &r->issue[r->nissue++];
	s->kind = kind, s->level = level;
	s->block[0] = bi, s->block[1] = bj;
	s->vertex[0] = gi, s->vertex[1] = gj;
	s->tau = tau;
	va_start(ap, fmt);
	vsnprintf(s->text, sizeof s->text, fmt, ap);
	va_end(ap);
}

/* A note about vertex k of block (bi, bj) of the level. */
#define VNOTE(v, kind, bi, bj, k, tau, ...)                                  \
	note((v)->c, kind, (v)->l, bi, bj, (bi) * BT_CELLS + (k) % BT_SIZE,  \
	    (bj) * BT_CELLS + (k) / BT_SIZE, tau, __VA_ARGS__)
#define BNOTE(v, kind, bi, bj, ...)                                          \
	note((v)->c, kind, (v)->l, bi, bj, -1, -1, NAN, __VA_ARGS__)

static int
selected(const blk *b, int k, double tau)
{
	return corner(k) || b->e[k] > tau;
}

/* --- reading blocks ------------------------------------------------- */

static void
check_vgis(lv *v, const rs_header *h, int bi, int bj)
{
	size_t k = (size_t)bj * v->bx + bi;
	int iv, p[2];
	double d, zr[2];

	if (rs_get_int(h, "vgis:version", &iv) < 0 || iv != PYRAMID_VERSION)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:version missing or not %d",
		    PYRAMID_VERSION);
	if (rs_get_int(h, "vgis:level", &iv) < 0 || iv != v->l)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:level missing or not %d",
		    v->l);
	if (rs_get_v2i(h, "vgis:block", p) < 0 || p[0] != bi || p[1] != bj)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:block missing or not "
		    "(%d,%d)", bi, bj);
	if (rs_get_v2i(h, "vgis:origin", p) < 0 || p[0] != bi * BT_CELLS ||
	    p[1] != bj * BT_CELLS)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:origin missing or not "
		    "(%d,%d)", bi * BT_CELLS, bj * BT_CELLS);
	if (rs_get_double(h, "vgis:base_error", &d) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:base_error missing");
	else if (d != v->L->base[k])
		BNOTE(v, VF_INDEX, bi, bj, "vgis:base_error %.9g, the index "
		    "says %.9g", d, v->L->base[k]);
	if (rs_get_v2d(h, "vgis:zrange", zr) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:zrange missing");
	else if (zr[0] != v->L->zmin[k] || zr[1] != v->L->zmax[k])
		BNOTE(v, VF_INDEX, bi, bj, "vgis:zrange %.9g..%.9g, the index "
		    "says %.9g..%.9g", zr[0], zr[1], v->L->zmin[k],
		    v->L->zmax[k]);
}

static void
check_fqm(lv *v, const rs_header *h, int bi, int bj)
{
	const checker *c = v->c;
	georef g;
	tl_err e;
	const char *s, *what;
	int iv, p[2];

	if (rs_get_string(h, "geo:model") == NULL ||
	    rs_get_v2d(h, "geo:origin", (double[2]){ 0 }) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "geo:model or geo:origin missing");
	else if (geo_from_header(&g, h, &e) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "%s", e.msg);
	else if ((what = geo_differs(&g, &c->ix.geo)) != NULL)
		BNOTE(v, VF_INDEX, bi, bj, "geo:%s differs from the index's "
		    "georef", what);
	if (rs_get_int(h, "fqm:level", &iv) < 0 || iv != v->l)
		BNOTE(v, VF_INDEX, bi, bj, "fqm:level missing or not %d", v->l);
	if (rs_get_v2i(h, "fqm:size0", p) < 0 || p[0] != c->ix.size0[0] ||
	    p[1] != c->ix.size0[1])
		BNOTE(v, VF_INDEX, bi, bj, "fqm:size0 missing or not %dx%d",
		    c->ix.size0[0], c->ix.size0[1]);
	if ((s = rs_get_string(h, "fqm:mode")) == NULL ||
	    strcmp(s, v->L->mode) != 0)
		BNOTE(v, VF_INDEX, bi, bj, "fqm:mode %s, the index says %s",
		    s ? s : "missing", v->L->mode);
	if ((s = rs_get_string(h, "fqm:kernel")) == NULL ||
	    strcmp(s, v->L->kernel) != 0)
		BNOTE(v, VF_INDEX, bi, bj, "fqm:kernel %s, the index says %s",
		    s ? s : "missing", v->L->kernel);
}

static void
positions(lv *v, blk *b, int bi, int bj)
{
	for (int k = 0; k < NV; k++) {
		long gi = (long)bi * BT_CELLS + k % BT_SIZE;
		long gj = (long)bj * BT_CELLS + k / BT_SIZE;
		double di = 0, dj = 0;
		if (v->disp && isfinite(b->x[k]) && isfinite(b->y[k]))
			geo_offset_to_grid(&v->c->metric, (double)(gi * v->s),
			    (double)(gj * v->s), b->x[k], b->y[k], &di, &dj);
		b->px[k] = (double)(gi * v->s) + di;
		b->py[k] = (double)(gj * v->s) + dj;
	}
}

static int
channels_ok(const lv *v, const rs_header *h)
{
	if (h->nch != (v->disp ? 4 : 2) || rs_channel(h, "E") < 0 ||
	    rs_channel(h, "Z") < 0)
		return 0;
	return !v->disp || (rs_channel(h, "X") >= 0 && rs_channel(h, "Y") >= 0);
}

static void
channel_list(const rs_header *h, char *buf, size_t n)
{
	size_t len = 0;

	buf[0] = '\0';
	for (int c = 0; c < h->nch && len < n; c++)
		len += snprintf(buf + len, n - len, "%s%s", c ? " " : "",
		    h->ch[c]);
}

/* Reads block (bi, bj) into b; quiet: no notes (the pre-pass). */
static void
load_block(lv *v, blk *b, int bi, int bj, int quiet)
{
	char path[4096], chs[256];
	float row[4 * BT_SIZE];
	const rs_header *h;
	rs_reader *rd;
	tl_err e;
	int ch[4], n;

	b->ok = 0;
	pyramid_block_path(path, sizeof path, v->c->dir, v->l, bi, bj);
	if ((rd = rs_open(path, &e)) == NULL) {
		if (!quiet)
			BNOTE(v, VF_INDEX, bi, bj, "%s", e.msg);
		return;
	}
	h = rs_header_of(rd);
	if (h->width != BT_SIZE || h->height != BT_SIZE) {
		if (!quiet)
			BNOTE(v, VF_INDEX, bi, bj, "%s: %dx%d, a block is "
			    "129x129", path, h->width, h->height);
		goto done;
	}
	if (!channels_ok(v, h)) {
		channel_list(h, chs, sizeof chs);
		if (!quiet)
			BNOTE(v, VF_INDEX, bi, bj, "%s: channels %s, expected "
			    "%s", path, chs, v->disp ? "E X Y Z" : "E Z");
		goto done;
	}
	if (!quiet) {
		check_vgis(v, h, bi, bj);
		check_fqm(v, h, bi, bj);
	}
	n = h->nch;
	ch[0] = rs_channel(h, "Z"), ch[1] = rs_channel(h, "E");
	ch[2] = rs_channel(h, "X"), ch[3] = rs_channel(h, "Y");
	for (int j = 0; j < BT_SIZE; j++) {
		float *dst[4] = { b->z, b->e, b->x, b->y };
		if (rs_read_row(rd, row, &e) < 0) {
			if (!quiet)
				BNOTE(v, VF_INDEX, bi, bj, "%s", e.msg);
			goto done;
		}
		for (int q = 0; q < n; q++)
			memcpy(dst[q] + j * BT_SIZE, row + ch[q] * BT_SIZE,
			    BT_SIZE * sizeof *row);
	}
	positions(v, b, bi, bj);
	b->ok = 1;
done:
	rs_close(rd);
}

/* --- per-block checks ----------------------------------------------- */

static void
check_content(lv *v, const blk *b, int bi, int bj)
{
	size_t k = (size_t)bj * v->bx + bi;
	double zmin = INFINITY, zmax = -INFINITY, emax = 0;
	int bad = 0;

	for (int q = 0; q < NV; q++) {
		if (!isfinite(b->z[q]) || (v->disp &&
		    (!isfinite(b->x[q]) || !isfinite(b->y[q])))) {
			if (bad++ == 0)
				VNOTE(v, VF_INDEX, bi, bj, q, NAN, "Z %g X %g "
				    "Y %g: not finite", b->z[q],
				    v->disp ? b->x[q] : 0.0,
				    v->disp ? b->y[q] : 0.0);
			continue;
		}
		zmin = fmin(zmin, b->z[q]), zmax = fmax(zmax, b->z[q]);
		if (isfinite(b->e[q]) && b->e[q] < FLT_MAX)
			emax = fmax(emax, b->e[q]);
	}
	if (zmin != v->L->zmin[k] || zmax != v->L->zmax[k])
		BNOTE(v, VF_INDEX, bi, bj, "Z ranges %.9g..%.9g, the index "
		    "says %.9g..%.9g", zmin, zmax, v->L->zmin[k],
		    v->L->zmax[k]);
	if (emax != v->L->emax[k])
		BNOTE(v, VF_INDEX, bi, bj, "largest finite E %.9g, the index "
		    "says %.9g", emax, v->L->emax[k]);
	v->R->emax = fmax(v->R->emax, emax);
}

/* Vertices past the level's size copy the nearest real one, which is in
 * the same block (only the last block column and row hold padding). */
static void
check_padding(lv *v, const blk *b, int bi, int bj)
{
	for (int k = 0; k < NV; k++) {
		int gi = bi * BT_CELLS + k % BT_SIZE;
		int gj = bj * BT_CELLS + k / BT_SIZE, ri, rj, q;
		if (gi < v->L->size[0] && gj < v->L->size[1])
			continue;
		ri = gi < v->L->size[0] ? gi : v->L->size[0] - 1;
		rj = gj < v->L->size[1] ? gj : v->L->size[1] - 1;
		q = (rj - bj * BT_CELLS) * BT_SIZE + ri - bi * BT_CELLS;
		if (q < 0 || q >= NV)
			continue; /* a level larger than its blocks: index */
		if (b->z[k] != b->z[q] || (v->disp &&
		    (b->x[k] != 0 || b->y[k] != 0)))
			VNOTE(v, VF_PADDING, bi, bj, k, NAN, "Z %.9g X %g Y %g, "
			    "the edge vertex (%d,%d) has Z %.9g", b->z[k],
			    v->disp ? b->x[k] : 0.0, v->disp ? b->y[k] : 0.0,
			    ri, rj, b->z[q]);
	}
}

static void
check_saturation(lv *v, const blk *b, int bi, int bj)
{
	const vf_tree *t = &v->c->tree;

	for (int k = 0; k < NV; k++) {
		float e = b->e[k];
		if (corner(k) ? e != FLT_MAX : !(e >= 0 && e < FLT_MAX))
			VNOTE(v, VF_SATURATION, bi, bj, k, NAN, "E %g: %s", e,
			    corner(k) ? "a corner's E must be FLT_MAX" :
			    "must be finite and >= 0");
	}
	/* apex p is a parent of midpoint m: E(p) >= E(m), NaN failing */
	for (int n = 0; n < VF_NODES; n++) {
		const vf_node *d = &t->node[n];
		int p = d->p[1] * BT_SIZE + d->p[0];
		if (d->m >= 0 && !(b->e[p] >= b->e[d->m]))
			VNOTE(v, VF_SATURATION, bi, bj, d->m, NAN, "E %.9g "
			    "above its parent (%d,%d)'s %.9g", b->e[d->m],
			    bi * BT_CELLS + d->p[0], bj * BT_CELLS + d->p[1],
			    b->e[p]);
	}
}

static int
differ(float a, float b)
{
	return memcmp(&a, &b, sizeof a) != 0;
}

/* Vertex ka of block a and kb of block b are one level vertex. */
static void
border_pair(lv *v, const blk *a, int ai, int aj, int ka, const blk *b,
    int bi, int bj, int kb)
{
	char buf[160];
	size_t n = 0;
	const char *name[4] = { "Z", "E", "X", "Y" };
	const float *pa[4] = { a->z, a->e, a->x, a->y };
	const float *pb[4] = { b->z, b->e, b->x, b->y };

	buf[0] = '\0';
	for (int q = 0; q < (v->disp ? 4 : 2); q++)
		if (differ(pa[q][ka], pb[q][kb]) && n < sizeof buf)
			n += snprintf(buf + n, sizeof buf - n, "%s%s %.9g vs %.9g",
			    n ? ", " : "", name[q], pa[q][ka], pb[q][kb]);
	if (n > 0)
		VNOTE(v, VF_BORDER, ai, aj, ka, NAN, "%s in block (%d,%d)",
		    buf, bi, bj);
}

static void
check_borders(lv *v, int bi, int bj)
{
	const blk *b = &v->row[1][bi], *left, *up;

	if (bi > 0 && (left = &v->row[1][bi - 1])->ok)
		for (int r = 0; r < BT_SIZE; r++)
			border_pair(v, b, bi, bj, r * BT_SIZE, left, bi - 1, bj,
			    r * BT_SIZE + BT_CELLS);
	if (bj > 0 && (up = &v->row[0][bi])->ok)
		for (int c = 0; c < BT_SIZE; c++)
			border_pair(v, b, bi, bj, c, up, bi, bj - 1,
			    BT_CELLS * BT_SIZE + c);
}

/* --- the DEM -------------------------------------------------------- */

/* Largest deviation of triangle (x, y, z)[3] from the valid DEM samples
 * it holds (closed); marks them covered when cover is set. */
static void
tri_dev(const checker *c, dwin *w, const double x[3], const double y[3],
    const double z[3], int cover, devmax *d)
{
	double det = (x[1] - x[0]) * (y[2] - y[0]) -
	    (y[1] - y[0]) * (x[2] - x[0]);
	double lo = fmin(y[0], fmin(y[1], y[2]));
	double hi = fmax(y[0], fmax(y[1], y[2]));
	double xl = fmin(x[0], fmin(x[1], x[2]));
	double xh = fmax(x[0], fmax(x[1], x[2]));
	long j0 = (long)ceil(lo - 1e-6), j1 = (long)floor(hi + 1e-6);
	long i0 = (long)ceil(xl - 1e-6), i1 = (long)floor(xh + 1e-6);

	if (det == 0 || !isfinite(det))
		return;
	j0 = j0 < w->j0 ? w->j0 : j0;
	j1 = j1 > w->j0 + w->n - 1 ? w->j0 + w->n - 1 : j1;
	i0 = i0 < 0 ? 0 : i0;
	i1 = i1 > c->W - 1 ? c->W - 1 : i1;
	for (long J = j0; J <= j1; J++) {
		size_t off = (size_t)(J - w->j0) * c->W;
		double ey = J - y[0];
		for (long I = i0; I <= i1; I++) {
			double ex = I - x[0];
			double u = (ex * (y[2] - y[0]) - ey * (x[2] - x[0])) / det;
			double t = ((x[1] - x[0]) * ey - (y[1] - y[0]) * ex) / det;
			double zs, zd, dev, adj;
			if (u < -BARY_EPS || t < -BARY_EPS || u + t > 1 + BARY_EPS)
				continue;
			if (cover)
				w->f[off + I] |= 2;
			if (!(w->f[off + I] & 1))
				continue;
			zs = z[0] + u * (z[1] - z[0]) + t * (z[2] - z[0]);
			zd = w->z[off + I];
			dev = fabs(zs - zd);
			adj = dev - REL_EPS * fmax(fabs(zs), fabs(zd));
			d->n++;
			if (dev > d->dev)
				d->dev = dev;
			if (adj > d->adj || d->n == 1) {
				d->adj = adj;
				d->I = (int)I, d->J = (int)J;
			}
		}
	}
}

static void
node_tri(const blk *b, const vf_node *d, double x[3], double y[3],
    double z[3])
{
	int k[3] = { d->a[1] * BT_SIZE + d->a[0], d->b[1] * BT_SIZE + d->b[0],
		d->p[1] * BT_SIZE + d->p[0] };

	for (int q = 0; q < 3; q++)
		x[q] = b->px[k[q]], y[q] = b->py[k[q]], z[q] = b->z[k[q]];
}

static int
node_dev(lv *v, const blk *b, const vf_node *d, int cover, devmax *m)
{
	double x[3], y[3], z[3];

	memset(m, 0, sizeof *m);
	node_tri(b, d, x, y, z);
	tri_dev(v->c, &v->w, x, y, z, cover, m);
	return m->n;
}

/* Base error (the leaves) and local errors (split triangles). */
static void
check_base_local(lv *v, int bi, int bj)
{
	const blk *b = &v->row[1][bi];
	const vf_tree *t = &v->c->tree;
	double base = v->L->base[(size_t)bj * v->bx + bi];
	devmax m, worst = { 0 };

	for (int n = 0; n < VF_NODES; n++) {
		const vf_node *d = &t->node[n];
		if (d->m >= 0 && !v->c->o.local)
			continue;
		if (node_dev(v, b, d, 0, &m) == 0)
			continue;
		if (d->m < 0) {
			v->R->base_real = fmax(v->R->base_real, m.dev);
			if (worst.n == 0 || m.adj > worst.adj)
				worst = m;
			continue;
		}
		v->R->local_max = fmax(v->R->local_max, m.dev);
		if (m.adj > b->e[d->m] + ABS_EPS)
			VNOTE(v, VF_LOCAL, bi, bj, d->m, NAN, "E %.9g, its "
			    "triangle with apex (%d,%d) is %.6g m off DEM "
			    "sample (%d,%d)", b->e[d->m],
			    bi * BT_CELLS + d->p[0], bj * BT_CELLS + d->p[1],
			    m.dev, m.I, m.J);
	}
	if (worst.n > 0 && worst.adj > base + ABS_EPS)
		BNOTE(v, VF_BASE, bi, bj, "base error %.9g, the finest "
		    "triangles are %.6g m off DEM sample (%d,%d)", base,
		    worst.dev, worst.I, worst.J);
}

/* Rows [w->j0, upto) are final: their valid samples must be covered. */
static void
finalize_rows(lv *v, int upto)
{
	const checker *c = v->c;
	dwin *w = &v->w;
	int last = w->j0 + w->n;

	for (int J = w->j0; J < upto && J < last; J++) {
		const unsigned char *f = w->f + (size_t)(J - w->j0) * c->W;
		for (int I = 0; I < c->W; I++) {
			int bi, bj;
			if (!(f[I] & 1))
				continue;
			v->R->samples++;
			if (f[I] & 2)
				continue;
			bi = I / (BT_CELLS * v->s), bj = J / (BT_CELLS * v->s);
			bi = bi < v->bx ? bi : v->bx - 1;
			bj = bj < v->by ? bj : v->by - 1;
			note(v->c, VF_COVERAGE, v->l, bi, bj, -1, -1, 0, "DEM "
			    "sample (%d,%d) lies in no triangle at tau 0", I, J);
		}
	}
}

/* Moves the window to rows a..b (a never decreases). */
static int
slide(lv *v, int a, int b)
{
	checker *c = v->c;
	dwin *w = &v->w;
	int drop = a - w->j0;

	finalize_rows(v, a);
	if (drop >= w->n)
		w->n = 0;
	else if (drop > 0) {
		w->n -= drop;
		memmove(w->z, w->z + (size_t)drop * c->W,
		    (size_t)w->n * c->W * sizeof *w->z);
		memmove(w->f, w->f + (size_t)drop * c->W, (size_t)w->n * c->W);
	}
	w->j0 = a;
	for (int J = a + w->n; J <= b; J++) {
		size_t off = (size_t)(J - a) * c->W;
		if (J - a >= w->cap)
			return tl_fail(c->e, "verify: DEM window overflow");
		if (dem_read_row(c->dem, J, w->z + off, w->f + off, c->e) < 0)
			return -1;
		w->n++;
	}
	return 0;
}

/* DEM rows each block row's triangles reach (a pre-pass reads the
 * blocks of displaced levels), made monotone and contiguous so that a
 * sliding window meets every row once and rows it leaves are final. */
static int
plan_rows(lv *v)
{
	const checker *c = v->c;
	int by = v->by, *lo, *hi, cap = 1;
	blk *b = &v->row[0][0];

	lo = tl_alloc(by, sizeof *lo, c->e);
	hi = tl_alloc(by, sizeof *hi, c->e);
	if (lo == NULL || hi == NULL) {
		free(lo), free(hi);
		return -1;
	}
	for (int bj = 0; bj < by; bj++) {
		double ymin = (double)bj * BT_CELLS * v->s;
		double ymax = (double)(bj + 1) * BT_CELLS * v->s;
		for (int bi = 0; v->disp && bi < v->bx; bi++) {
			load_block(v, b, bi, bj, 1);
			for (int k = 0; b->ok && k < NV; k++)
				ymin = fmin(ymin, b->py[k]),
				ymax = fmax(ymax, b->py[k]);
		}
		lo[bj] = (int)fmax(0, fmin(c->H - 1, floor(ymin)));
		hi[bj] = (int)fmax(0, fmin(c->H - 1, ceil(ymax)));
	}
	b->ok = 0;
	for (int bj = by - 2; bj >= 0; bj--)
		lo[bj] = lo[bj] < lo[bj + 1] ? lo[bj] : lo[bj + 1];
	for (int bj = 1; bj < by; bj++)
		hi[bj] = hi[bj] > hi[bj - 1] ? hi[bj] : hi[bj - 1];
	for (int bj = 0; bj < by; bj++) {
		v->w0[bj] = bj == 0 ? 0 : lo[bj] < hi[bj - 1] + 1 ? lo[bj] :
		    hi[bj - 1] + 1;
		v->w1[bj] = bj == by - 1 ? c->H - 1 : hi[bj];
		if (v->w1[bj] - v->w0[bj] + 1 > cap)
			cap = v->w1[bj] - v->w0[bj] + 1;
	}
	free(lo), free(hi);
	v->w.cap = cap;
	v->w.z = tl_alloc((size_t)cap * c->W, sizeof *v->w.z, c->e);
	v->w.f = tl_alloc((size_t)cap * c->W, 1, c->e);
	return v->w.z && v->w.f ? 0 : -1;
}

/* --- selections ----------------------------------------------------- */

static long long
cross2(const vf_node *d)
{
	long long ux = d->b[0] - d->a[0], uy = d->b[1] - d->a[1];
	long long wx = d->p[0] - d->a[0], wy = d->p[1] - d->a[1];

	return ux * wy - uy * wx;
}

/* Marks the grid points strictly inside edge p-q (axis or diagonal). */
static void
mark_edge(unsigned char *in, const unsigned char p[2],
    const unsigned char q[2])
{
	int di = (q[0] > p[0]) - (q[0] < p[0]);
	int dj = (q[1] > p[1]) - (q[1] < p[1]);

	for (int i = p[0] + di, j = p[1] + dj; i != q[0] || j != q[1];
	    i += di, j += dj)
		in[j * BT_SIZE + i] = 1;
}

static void
check_fold(lv *v, const blk *b, const vf_node *d, int bi, int bj, double tau)
{
	double x[3], y[3], z[3], s;

	node_tri(b, d, x, y, z);
	s = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
	if (!(s * (double)cross2(d) > 0))
		VNOTE(v, VF_FOLD, bi, bj, d->p[1] * BT_SIZE + d->p[0], tau,
		    "triangle (%d,%d)-(%d,%d) apex here: displaced area %.3g, "
		    "grid area %.3g", bi * BT_CELLS + d->a[0],
		    bj * BT_CELLS + d->a[1], bi * BT_CELLS + d->b[0],
		    bj * BT_CELLS + d->b[1], s / 2, cross2(d) / 2.0);
}

static void
check_error(lv *v, const blk *b, const vf_node *d, int bi, int bj, int t,
    double *worst)
{
	double tau = v->tau[t];
	double base = v->L->base[(size_t)bj * v->bx + bi];
	double bound = fmax(tau, base);
	devmax m;

	if (node_dev(v, b, d, t == 0, &m) == 0)
		return;
	*worst = fmax(*worst, m.dev);
	if (m.adj > bound + ABS_EPS)
		VNOTE(v, VF_ERROR, bi, bj, d->p[1] * BT_SIZE + d->p[0], tau,
		    "triangle (%d,%d)-(%d,%d) apex here is %.6g m off DEM "
		    "sample (%d,%d), bound %.6g", bi * BT_CELLS + d->a[0],
		    bj * BT_CELLS + d->a[1], bi * BT_CELLS + d->b[0],
		    bj * BT_CELLS + d->b[1], m.dev, m.I, m.J, bound);
}

static void
emitted(lv *v, const blk *b, int bi, int bj, int t, long n)
{
	const vf_tree *tr = &v->c->tree;
	unsigned char *in = v->inside + (size_t)bi * NV;
	double tau = v->tau[t], worst = 0;
	double base = v->L->base[(size_t)bj * v->bx + bi];
	long long area2 = 0;

	memset(v->used, 0, NV);
	memset(in, 0, NV);
	for (long q = 0; q < n; q++) {
		const vf_node *d = &tr->node[v->emit[q]];
		long long a = cross2(d);
		v->used[d->a[1] * BT_SIZE + d->a[0]] = 1;
		v->used[d->b[1] * BT_SIZE + d->b[0]] = 1;
		v->used[d->p[1] * BT_SIZE + d->p[0]] = 1;
		mark_edge(in, d->a, d->b);
		mark_edge(in, d->b, d->p);
		mark_edge(in, d->p, d->a);
		area2 += a < 0 ? -a : a;
		if (v->disp)
			check_fold(v, b, d, bi, bj, tau);
		if (v->c->dem != NULL)
			check_error(v, b, d, bi, bj, t, &worst);
	}
	if (area2 != 2L * BT_CELLS * BT_CELLS)
		note(v->c, VF_MATCHING, v->l, bi, bj, -1, -1, tau, "triangle "
		    "areas sum to %g cells, the block has %d", area2 / 2.0,
		    BT_CELLS * BT_CELLS);
	if (v->c->dem == NULL)
		return;
	v->R->tau[t].maxerr = fmax(v->R->tau[t].maxerr, worst);
	if (tau > base && (isnan(v->R->tight) || worst / tau > v->R->tight)) {
		v->R->tight = worst / tau;
		v->R->tight_tau = tau;
		v->R->tight_block[0] = bi, v->R->tight_block[1] = bj;
	}
}

static void
select_block(lv *v, int bi, int bj, int t)
{
	const blk *b = &v->row[1][bi];
	const vf_tree *tr = &v->c->tree;
	const unsigned char *in = v->inside + (size_t)bi * NV;
	double tau = v->tau[t];
	long n;

	for (int k = 0; k < NV; k++)
		v->sel[k] = (unsigned char)selected(b, k, tau);
	for (int q = 0; q < VF_NODES; q++) {
		const vf_node *d = &tr->node[q];
		if (d->m >= 0 && v->sel[d->m] &&
		    !v->sel[d->p[1] * BT_SIZE + d->p[0]])
			VNOTE(v, VF_MATCHING, bi, bj, d->m, tau, "selected (E "
			    "%.9g), its parent (%d,%d) is not (E %.9g)",
			    b->e[d->m], bi * BT_CELLS + d->p[0],
			    bj * BT_CELLS + d->p[1],
			    b->e[d->p[1] * BT_SIZE + d->p[0]]);
	}
	n = vf_select(tr, v->sel, v->emit);
	v->R->tau[t].triangles += n;
	emitted(v, b, bi, bj, t, n);
	for (int k = 0; k < NV; k++) {
		if (v->sel[k] && !v->used[k])
			VNOTE(v, VF_MATCHING, bi, bj, k, tau, "selected (E "
			    "%.9g) but a corner of no triangle", b->e[k]);
		if (v->sel[k] && in[k])
			VNOTE(v, VF_MATCHING, bi, bj, k, tau, "selected (E "
			    "%.9g) but strictly inside a triangle's edge "
			    "(T-vertex)", b->e[k]);
	}
}

/* A vertex strictly inside an edge of block a, selected in block b. */
static void
cross_pair(lv *v, const unsigned char *ina, int ai, int aj, int ka,
    const blk *b, int bi, int bj, int kb, double tau)
{
	if (ina[ka] && selected(b, kb, tau))
		VNOTE(v, VF_MATCHING, ai, aj, ka, tau, "strictly inside a "
		    "triangle's edge here, selected in block (%d,%d) (E %.9g): "
		    "T-vertex across the border", bi, bj, b->e[kb]);
}

static void
cross_borders(lv *v, int bj, int t)
{
	double tau = v->tau[t];
	size_t stride = (size_t)v->bx * BT_SIZE;

	for (int bi = 0; bi < v->bx; bi++) {
		const blk *b = &v->row[1][bi], *l = &v->row[1][bi - (bi > 0)];
		const blk *u = &v->row[0][bi];
		const unsigned char *in = v->inside + (size_t)bi * NV;
		const unsigned char *inl = in - (bi > 0 ? NV : 0);
		const unsigned char *up = v->bot[0] + t * stride + bi * BT_SIZE;
		if (!b->ok)
			continue;
		memcpy(v->bot[1] + t * stride + bi * BT_SIZE,
		    in + BT_CELLS * BT_SIZE, BT_SIZE);
		for (int r = 0; bi > 0 && l->ok && r < BT_SIZE; r++) {
			int kb = r * BT_SIZE, kl = kb + BT_CELLS;
			cross_pair(v, in, bi, bj, kb, l, bi - 1, bj, kl, tau);
			cross_pair(v, inl, bi - 1, bj, kl, b, bi, bj, kb, tau);
		}
		for (int c = 0; bj > 0 && u->ok && c < BT_SIZE; c++) {
			int ku = BT_CELLS * BT_SIZE + c;
			cross_pair(v, in, bi, bj, c, u, bi, bj - 1, ku, tau);
			if (up[c] && selected(b, c, tau))
				VNOTE(v, VF_MATCHING, bi, bj - 1, ku, tau,
				    "strictly inside a triangle's edge here, "
				    "selected in block (%d,%d) (E %.9g): "
				    "T-vertex across the border", bi, bj,
				    b->e[c]);
		}
	}
}

/* --- a level -------------------------------------------------------- */

static int
make_taus(lv *v)
{
	const vf_opts *o = &v->c->o;
	double emax = 0;
	size_t nb = (size_t)v->bx * v->by;
	int n, zero = 0;

	for (size_t k = 0; k < nb; k++)
		if (v->L->emax[k] >= 0 && v->L->emax[k] < FLT_MAX)
			emax = fmax(emax, v->L->emax[k]);
	if (o->tau != NULL) {
		for (int k = 0; k < o->ntau; k++)
			zero |= o->tau[k] == 0;
		n = o->ntau + !zero;
	} else
		n = emax > 0 && o->nsweep > 1 ? o->nsweep : 1;
	v->tau = tl_alloc(n, sizeof *v->tau, v->c->e);
	v->R->tau = tl_alloc(n, sizeof *v->R->tau, v->c->e);
	if (v->tau == NULL || v->R->tau == NULL)
		return -1;
	v->ntau = v->R->ntau = n;
	if (o->tau != NULL) {
		/* tau 0 first: the coverage check runs on it */
		v->tau[0] = 0;
		for (int k = 0, q = 1; k < o->ntau; k++) {
			if (o->tau[k] == 0 && zero) {
				zero = 0;
				continue;
			}
			v->tau[q++] = o->tau[k];
		}
	} else
		for (int k = 1; k < n; k++)
			v->tau[k] = n == 2 ? emax :
			    emax * pow(1000, -(double)(n - 1 - k) / (n - 2));
	for (int k = 0; k < n; k++) {
		v->R->tau[k].tau = v->tau[k];
		v->R->tau[k].maxerr = v->c->dem ? 0 : NAN;
	}
	return 0;
}

static int
blk_alloc(blk *b, int disp, tl_err *e)
{
	memset(b, 0, sizeof *b);
	b->z = tl_alloc(NV, sizeof *b->z, e);
	b->e = tl_alloc(NV, sizeof *b->e, e);
	b->px = tl_alloc(NV, sizeof *b->px, e);
	b->py = tl_alloc(NV, sizeof *b->py, e);
	if (disp) {
		b->x = tl_alloc(NV, sizeof *b->x, e);
		b->y = tl_alloc(NV, sizeof *b->y, e);
	}
	return b->z && b->e && b->px && b->py && (!disp || (b->x && b->y)) ?
	    0 : -1;
}

static void
blk_free(blk *b)
{
	free(b->z), free(b->e), free(b->x), free(b->y);
	free(b->px), free(b->py);
}

static void
lv_free(lv *v)
{
	for (int q = 0; q < 2; q++) {
		for (int bi = 0; v->row[q] && bi < v->bx; bi++)
			blk_free(&v->row[q][bi]);
		free(v->row[q]);
		free(v->bot[q]);
	}
	free(v->inside), free(v->sel), free(v->used), free(v->emit);
	free(v->w0), free(v->w1), free(v->w.z), free(v->w.f);
	free(v->tau);
}

static int
lv_init(lv *v, checker *c, int l)
{
	tl_err *e = c->e;

	memset(v, 0, sizeof *v);
	v->c = c;
	v->L = &c->ix.lev[l];
	v->R = &c->r->lev[l];
	v->l = l;
	v->s = 1 << l;
	v->bx = v->L->blocks[0], v->by = v->L->blocks[1];
	v->disp = v->L->displaced;
	if (make_taus(v) < 0)
		return -1;
	for (int q = 0; q < 2; q++) {
		v->row[q] = tl_alloc(v->bx, sizeof *v->row[q], e);
		v->bot[q] = tl_alloc((size_t)v->ntau * v->bx, BT_SIZE, e);
		if (v->row[q] == NULL || v->bot[q] == NULL)
			return -1;
		for (int bi = 0; bi < v->bx; bi++)
			if (blk_alloc(&v->row[q][bi], v->disp, e) < 0)
				return -1;
	}
	v->inside = tl_alloc((size_t)v->bx, NV, e);
	v->sel = tl_alloc(NV, 1, e);
	v->used = tl_alloc(NV, 1, e);
	v->emit = tl_alloc(LEAVES, sizeof *v->emit, e);
	v->w0 = tl_alloc(v->by, sizeof *v->w0, e);
	v->w1 = tl_alloc(v->by, sizeof *v->w1, e);
	if (!v->inside || !v->sel || !v->used || !v->emit || !v->w0 || !v->w1)
		return -1;
	return c->dem != NULL ? plan_rows(v) : 0;
}

/* Nothing in DIR/<level> but the blocks the index lists. */
static void
check_strays(lv *v)
{
	char path[4096], want[64];
	struct dirent *de;
	DIR *d;

	snprintf(path, sizeof path, "%s/%d", v->c->dir, v->l);
	if ((d = opendir(path)) == NULL) {
		note(v->c, VF_INDEX, v->l, -1, -1, -1, -1, NAN, "%s: no level "
		    "directory", path);
		return;
	}
	while ((de = readdir(d)) != NULL) {
		int r, c;
		if (strcmp(de->d_name, ".") == 0 || strcmp(de->d_name, "..") == 0)
			continue;
		if (sscanf(de->d_name, "%d_%d.exr", &r, &c) == 2) {
			snprintf(want, sizeof want, "%d_%d.exr", r, c);
			if (strcmp(want, de->d_name) == 0 && r >= 0 && c >= 0 &&
			    r < v->by && c < v->bx)
				continue;
		}
		note(v->c, VF_INDEX, v->l, -1, -1, -1, -1, NAN, "%s/%s: not a "
		    "block of the index", path, de->d_name);
	}
	closedir(d);
}

static int
check_row(lv *v, int bj)
{
	blk *tmp = v->row[0];
	unsigned char *bot;

	v->row[0] = v->row[1], v->row[1] = tmp;
	for (int bi = 0; bi < v->bx; bi++) {
		blk *b = &v->row[1][bi];
		load_block(v, b, bi, bj, 0);
		if (!b->ok)
			continue;
		v->R->blocks_read++;
		check_content(v, b, bi, bj);
		check_padding(v, b, bi, bj);
		check_saturation(v, b, bi, bj);
		check_borders(v, bi, bj);
	}
	if (v->c->dem != NULL) {
		if (slide(v, v->w0[bj], v->w1[bj]) < 0)
			return -1;
		for (int bi = 0; bi < v->bx; bi++)
			if (v->row[1][bi].ok)
				check_base_local(v, bi, bj);
	}
	for (int t = 0; t < v->ntau; t++) {
		for (int bi = 0; bi < v->bx; bi++)
			if (v->row[1][bi].ok)
				select_block(v, bi, bj, t);
		cross_borders(v, bj, t);
	}
	bot = v->bot[0];
	v->bot[0] = v->bot[1], v->bot[1] = bot;
	return 0;
}

static int
check_level(checker *c, int l)
{
	lv v;
	int r = -1;

	if (lv_init(&v, c, l) < 0)
		goto done;
	v.R->tight = NAN;
	v.R->base_real = v.R->local_max = c->dem ? 0 : NAN;
	for (int bj = 0; bj < v.by; bj++)
		if (check_row(&v, bj) < 0)
			goto done;
	if (c->dem != NULL)
		finalize_rows(&v, v.w.j0 + v.w.n);
	check_strays(&v);
	r = 0;
done:
	lv_free(&v);
	return r;
}

/* --- the pyramid ---------------------------------------------------- */

/* Levels as vgis(5) says: sizes halving, the top the first of one block. */
static void
check_levels(checker *c)
{
	const vf_index *ix = &c->ix;
	int top = 0;

	while (fqm_level_size(ix->size0[0], top) > BT_SIZE ||
	    fqm_level_size(ix->size0[1], top) > BT_SIZE)
		top++;
	if (ix->nlevels != top + 1)
		note(c, VF_INDEX, -1, -1, -1, -1, -1, NAN, "%d levels, a %dx%d "
		    "DEM has %d (the top is the first of one block)",
		    ix->nlevels, ix->size0[0], ix->size0[1], top + 1);
	for (int l = 0; l < ix->nlevels; l++) {
		const vf_ilevel *L = &ix->lev[l];
		size_t nb = (size_t)L->blocks[0] * L->blocks[1];
		int w = fqm_level_size(ix->size0[0], l);
		int h = fqm_level_size(ix->size0[1], l);
		if (L->level != l || L->size[0] != w || L->size[1] != h)
			note(c, VF_INDEX, l, -1, -1, -1, -1, NAN, "index entry "
			    "%d says level %d of %dx%d, level %d is %dx%d", l,
			    L->level, L->size[0], L->size[1], l, w, h);
		for (size_t k = 0; k < nb; k++) {
			int bi = (int)(k % L->blocks[0]);
			int bj = (int)(k / L->blocks[0]);
			if (!(L->zmin[k] <= L->zmax[k]) || !isfinite(L->zmin[k]) ||
			    !isfinite(L->zmax[k]) || !(L->base[k] >= 0) ||
			    !isfinite(L->base[k]) || !(L->emax[k] >= 0) ||
			    !(L->emax[k] < FLT_MAX) ||
			    (l == 0 && L->base[k] != 0))
				note(c, VF_INDEX, l, bi, bj, -1, -1, NAN, "index "
				    "lists zmin %g zmax %g base %g max %g",
				    L->zmin[k], L->zmax[k], L->base[k],
				    L->emax[k]);
		}
	}
}

static void
check_top_strays(checker *c)
{
	struct dirent *de;
	DIR *d;

	if ((d = opendir(c->dir)) == NULL)
		return;
	while ((de = readdir(d)) != NULL) {
		const char *s = de->d_name;
		int l;
		if (strcmp(s, ".") == 0 || strcmp(s, "..") == 0 ||
		    strcmp(s, "index.json") == 0)
			continue;
		if (tl_parse_int(s, &l) == 0 && l >= 0 && l < c->ix.nlevels &&
		    s[0] != '+' && (s[0] != '0' || s[1] == '\0'))
			continue;
		note(c, VF_INDEX, -1, -1, -1, -1, -1, NAN, "%s/%s: neither "
		    "index.json nor a level directory", c->dir, s);
	}
	closedir(d);
}

static int
open_dem(checker *c, const char *path, const dem_opts *dopt)
{
	static const dem_opts none;
	const georef *g;
	const char *what;

	if ((c->dem = dem_open(path, dopt ? dopt : &none, c->e)) == NULL)
		return -1;
	g = dem_georef(c->dem);
	c->W = g->width, c->H = g->height;
	if (c->W != c->ix.size0[0] || c->H != c->ix.size0[1])
		return tl_fail(c->e, "%s: %dx%d samples, the pyramid was made "
		    "from %dx%d", path, c->W, c->H, c->ix.size0[0],
		    c->ix.size0[1]);
	if ((what = geo_differs(g, &c->ix.geo)) != NULL)
		note(c, VF_INDEX, -1, -1, -1, -1, -1, NAN, "%s: georef %s "
		    "differs from the index's", path, what);
	c->r->dem = 1;
	return 0;
}

static int
report_init(checker *c)
{
	vf_report *r = c->r;

	r->size0[0] = c->ix.size0[0], r->size0[1] = c->ix.size0[1];
	r->lev = tl_alloc(c->ix.nlevels, sizeof *r->lev, c->e);
	if (r->lev == NULL)
		return -1;
	r->nlevels = c->ix.nlevels;
	for (int l = 0; l < r->nlevels; l++) {
		const vf_ilevel *L = &c->ix.lev[l];
		vf_level *R = &r->lev[l];
		size_t nb = (size_t)L->blocks[0] * L->blocks[1];
		R->level = l;
		R->size[0] = L->size[0], R->size[1] = L->size[1];
		R->blocks[0] = L->blocks[0], R->blocks[1] = L->blocks[1];
		R->displaced = L->displaced;
		for (size_t k = 0; k < nb; k++)
			R->base = fmax(R->base, L->base[k]);
		R->tight = NAN;
	}
	return 0;
}

int
vf_check(const char *dir, const char *dem_path, const dem_opts *dopt,
    const vf_opts *o, vf_report *r, tl_err *e)
{
	checker c;
	int ret = -1, disp = 0;

	memset(&c, 0, sizeof c);
	memset(r, 0, sizeof *r);
	c.dir = dir, c.r = r, c.e = e;
	if (o != NULL)
		c.o = *o;
	else
		vf_opts_init(&c.o);
	if (c.o.max_issues < 0)
		c.o.max_issues = 0;
	if (vf_tree_init(&c.tree, e) < 0)
		return -1;
	if (vf_index_read(dir, &c.ix, e) < 0)
		goto done;
	if (report_init(&c) < 0)
		goto done;
	c.W = c.ix.size0[0], c.H = c.ix.size0[1];
	if (dem_path != NULL && open_dem(&c, dem_path, dopt) < 0)
		goto done;
	for (int l = 0; l < c.ix.nlevels; l++)
		disp |= c.ix.lev[l].displaced;
	if (disp && geo_metric_init(&c.metric, &c.ix.geo, e) < 0)
		goto done;
	check_levels(&c);
	check_top_strays(&c);
	for (int l = 0; l < c.ix.nlevels; l++)
		if (check_level(&c, l) < 0)
			goto done;
	ret = 0;
done:
	if (c.dem != NULL)
		dem_close(c.dem);
	geo_metric_free(&c.metric);
	vf_index_free(&c.ix);
	vf_tree_free(&c.tree);
	return ret;
}

void
vf_report_free(vf_report *r)
{
	for (int l = 0; l < r->nlevels && r->lev; l++)
		free(r->lev[l].tau);
	free(r->lev);
	free(r->issue);
	memset(r, 0, sizeof *r);
}
