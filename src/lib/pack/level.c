/* level.c - exact local errors, saturation and blocks of a level (see
 * level.h). */
#include "pack/level.h"
#include "pack/level_impl.h"
#include "base/pool.h"
#include "base/progress.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* fmin/fmax are library calls here; these inline. */
static inline __attribute__((always_inline)) double
dmin(double a, double b)
{
	return a < b ? a : b;
}

static inline __attribute__((always_inline)) double
dmax(double a, double b)
{
	return a > b ? a : b;
}

/* The first level rows of heights and of local errors still to be read:
 * the rings' rows below them may be overwritten. A part reads heights
 * 2 x 64 (+ margin) rows above its batch's first DEM row and gives out
 * local errors from next_out; blocks read their saturation bands. */
static int
keep_v(const state *s)
{
	return s->part != NULL ? s->yfirst - 2 * BT_MAXH - 2 :
	    s->next_bj * BT_CELLS;
}

static int
keep_e(const state *s)
{
	return s->part != NULL ? s->next_out : s->next_bj * BT_CELLS - REACH;
}

/* Loads level row r (the next one): a real row, or past the last one a
 * copy of it; columns past the last real one copy its height (padding).
 * Its local errors start at 0, or are read (tiles_run_merged). */
static int
load_row(state *s, int r, tl_err *e)
{
	const tiles_level *L = s->L;
	int n = L->size[0], m = L->size[1];
	size_t o;
	long J = (long)r << L->level;

	/* the rows it overwrites are behind every row still to be read */
	assert(r == s->loaded && r < s->r1);
	assert(r - RINGV < keep_v(s) || r - RINGV < s->r0);
	assert(r - RINGE < keep_e(s) || r - RINGE < s->r0);
	s->loaded++;
	/* the window's real columns: c0 .. nr-1 (the piece's first block
	 * column is a real one, so n - 1 >= c0) */
	int nr = s->cend < n ? s->cend : n, c = s->c0;
	o = slot(s, r);
	assert(n - 1 >= c);
	if (r < m) {
		if (L->row(L->row_ctx, r, c, nr - c, s->z + o,
		    L->displaced ? s->ox + o : NULL,
		    L->displaced ? s->oy + o : NULL, e) < 0)
			return -1;
	} else {
		memcpy(s->z + o, s->z + slot(s, m - 1),
		    (size_t)(nr - c) * sizeof *s->z);
		if (L->displaced) {
			memset(s->ox + o, 0, (size_t)(nr - c) * sizeof *s->ox);
			memset(s->oy + o, 0, (size_t)(nr - c) * sizeof *s->oy);
		}
	}
	for (int i = nr - c; i < s->P; i++) { /* padding: level columns n.. */
		s->z[o + i] = s->z[o + n - 1 - c];
		if (L->displaced)
			s->ox[o + i] = s->oy[o + i] = 0;
	}
	memset(s->acc + eslot(s, r), 0, (size_t)s->P * sizeof *s->acc);
	if (s->in != NULL && s->in(s->in_ctx, r, s->acc + eslot(s, r) +
	    (s->lo - s->c0), e) < 0)
		return -1;
	o = (size_t)(r & (RINGV - 1)) * s->nn; /* this row's scales */
	geo_row_sx(L->m, (double)J, s->sx + o);
	geo_row_sy(L->m, (double)J, s->sy + o);
	return 0;
}

static int
ensure(state *s, int r, tl_err *e)
{
	if (r > s->r1 - 1)
		r = s->r1 - 1;
	while (s->loaded <= r)
		if (load_row(s, s->loaded, e) < 0)
			return -1;
	return 0;
}

/* Metres per level-0 column and row step at grid vertex (gi, gj):
 * geo_on_row of the row's scales, bit for bit, with the column's place
 * among the nodes computed once per level (this is the innermost loop). */
static inline void
scales(const state *s, int gi, int gj, double *sx, double *sy)
{
	size_t o = (size_t)(gj & (RINGV - 1)) * s->nn;
	const double *x = s->sx + o, *y = s->sy + o;
	double u;
	int k;

	if (s->nn == 1) {
		*sx = x[0], *sy = y[0];
		return;
	}
	k = s->nk[gi - s->c0], u = s->nu[gi - s->c0];
	*sx = x[k] + u * (x[k + 1] - x[k]);
	*sy = y[k] + u * (y[k + 1] - y[k]);
}

/* Where each column falls among the lattice's node columns, as
 * geo_on_row finds it. */
static void
node_columns(state *s)
{
	const geo_ground *m = s->L->m;

	for (int gi = s->c0; gi < s->cend; gi++) {
		double t = gi * s->step * m->inv;
		int k = gi - s->c0;
		if (!(t > 0))
			s->nk[k] = 0, s->nu[k] = 0;
		else if (t >= m->nx - 1)
			s->nk[k] = m->nx - 2, s->nu[k] = 1;
		else
			s->nk[k] = (int)t, s->nu[k] = t - s->nk[k];
	}
}

/* Position (level units) and height of grid vertex (gi, gj). */
static inline void
vertex(const state *s, int gi, int gj, double p[3])
{
	size_t o = slot(s, gj) + (size_t)(gi - s->c0);

	assert(gi >= s->c0 && gi < s->cend);
	p[0] = gi, p[1] = gj, p[2] = s->z[o];
	if (s->L->displaced) {
		double sx, sy;
		scales(s, gi, gj, &sx, &sy);
		/* a row on a pole is one point (geo_offset_to_grid) */
		p[0] += sx > 0 ? s->ox[o] / sx / s->step : 0;
		p[1] += sy > 0 ? s->oy[o] / sy / s->step : 0;
	}
}

/* Row k (vertices k x 2^hk) of scale 2^hk's positions: vertex()'s, in
 * the columns the share's diamonds reach (h either side). */
static void
vc_fill(strip *t, int hk, int k)
{
	const state *s = t->s;
	int h = 1 << hk, r = k & (VC_ROWS - 1), n = t->vc[hk].n;
	double *x = t->vc[hk].x + (size_t)r * n, *y = t->vc[hk].y +
	    (size_t)r * n;
	/* window columns: the scale's column m at m - c0 / h */
	int m0 = (t->lo - s->c0) / h - 1, m1 = (t->hi - 1 - s->c0) / h + 2;

	for (int m = m0 > 0 ? m0 : 0; m < n && m < m1; m++) {
		double p[3];
		vertex(s, s->c0 + m * h, k * h, p);
		x[m] = p[0], y[m] = p[1];
	}
	t->vc[hk].tag[r] = k;
}

/* vertex() of (gi, gj), both multiples of 2^hk: on displaced levels
 * from the scale's rows of positions, each found once while in use (a
 * DEM row reaches at most 6 consecutive rows of a scale's vertices and
 * rows come in order). */
static inline __attribute__((always_inline)) void
vertex_at(strip *t, int hk, int gi, int gj, double p[3])
{
	const state *s = t->s;
	int k, r;
	size_t o;

	assert(gi >= s->c0 && gi < s->cend);
	if (!s->L->displaced) {
		p[0] = gi, p[1] = gj, p[2] = s->z[slot(s, gj) + (gi - s->c0)];
		return;
	}
	assert(((gi | gj) & ((1 << hk) - 1)) == 0); /* (both >= 0) */
	k = gj >> hk, r = k & (VC_ROWS - 1);
	if (t->vc[hk].tag[r] != k)
		vc_fill(t, hk, k);
	o = (size_t)r * t->vc[hk].n + ((gi - s->c0) >> hk);
	p[0] = t->vc[hk].x[o], p[1] = t->vc[hk].y[o];
	p[2] = s->z[slot(s, gj) + (gi - s->c0)];
}

/* (long)ceil(x) and (long)floor(x), inline, for |x| < 2^62. */
static inline __attribute__((always_inline)) long
iceil(double x)
{
	long t = (long)x;
	return (double)t < x ? t + 1 : t;
}

static inline __attribute__((always_inline)) long
ifloor(double x)
{
	long t = (long)x;
	return (double)t > x ? t - 1 : t;
}

static inline __attribute__((always_inline)) int
on_grid(const state *s, const int v[2])
{
	return v[0] >= s->c0 && v[1] >= 0 && v[0] < s->cend && v[1] < s->Q;
}

/* The largest |plane - DEM| over the valid samples of the current DEM row
 * (level row y) inside triangle t, closed; -1 when none is. */
static inline __attribute__((always_inline)) double
tri_row(strip *sh, const int t[3][2], double y, int hk)
{
	const state *s = sh->s;
	double p[3][3], xl = INFINITY, xr = -INFINITY, n[3], z0, dz;
	double ymin = INFINITY, ymax = -INFINITY;
	long i0, i1;

	/* cheap rejection on grid rows first (offsets are < 1 row) */
	{
		int lo = t[0][1], hi = t[0][1];
		for (int k = 1; k < 3; k++)
			lo = t[k][1] < lo ? t[k][1] : lo, hi = t[k][1] > hi ?
			    t[k][1] : hi;
		if (y < lo - s->margin - EPS || y > hi + s->margin + EPS)
			return -1;
	}
	for (int k = 0; k < 3; k++) {
		if (!on_grid(s, t[k]))
			return -1;
		vertex_at(sh, hk, t[k][0], t[k][1], p[k]);
		ymin = dmin(ymin, p[k][1]), ymax = dmax(ymax, p[k][1]);
	}
	if (y < ymin - EPS || y > ymax + EPS)
		return -1;
	for (int k = 0; k < 3; k++) { /* the row's chord through t */
		const double *a = p[k], *b = p[(k + 1) % 3];
		double x, f;
		if (fabs(b[1] - a[1]) <= EPS) {
			if (fabs(y - a[1]) <= EPS) {
				xl = dmin(xl, dmin(a[0], b[0]));
				xr = dmax(xr, dmax(a[0], b[0]));
			}
			continue;
		}
		f = (y - a[1]) / (b[1] - a[1]);
		if (f < -EPS || f > 1 + EPS)
			continue;
		f = dmin(1, dmax(0, f));
		x = a[0] + f * (b[0] - a[0]);
		xl = dmin(xl, x), xr = dmax(xr, x);
	}
	n[0] = (p[1][1] - p[0][1]) * (p[2][2] - p[0][2]) -
	    (p[1][2] - p[0][2]) * (p[2][1] - p[0][1]);
	n[1] = (p[1][2] - p[0][2]) * (p[2][0] - p[0][0]) -
	    (p[1][0] - p[0][0]) * (p[2][2] - p[0][2]);
	n[2] = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
	    (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
	if (xl > xr || n[2] == 0)
		return -1;
	/* along the row the plane is z0 + dz * x (level units) */
	dz = -n[0] / n[2];
	z0 = p[0][2] - (n[1] * (y - p[0][1]) - n[0] * p[0][0]) / n[2];
	i0 = iceil((xl - EPS) * s->step);
	i1 = ifloor((xr + EPS) * s->step);
	if (i0 < s->d0) /* the DEM's first column, or the window's */
		i0 = s->d0;
	if (i1 > s->dend - 1)
		i1 = s->dend - 1;
	/* i / step is i x (1 / step) exactly: step is a power of 2 */
	return sweep(sh->dd, s->d0, i0, i1, z0, dz, 1 / s->step);
}

/* Raises the local errors of every diamond of scale h and one kind that
 * the DEM row (level row y) crosses. Square diamonds are centred on odd
 * multiples of h in both axes; edge diamonds on points with exactly one
 * odd multiple: |x - cx| + |y - cy| <= h. */
static inline __attribute__((always_inline)) void
row_diamonds_body(strip *t, double y, int h, int hk, int edge)
{
	state *s = t->s;
	double reach = h + s->margin;
	long c0 = (long)ceil((y - reach) / h);
	long c1 = (long)floor((y + reach) / h);

	for (long c = c0 > 0 ? c0 : 0; c <= c1 && c * h < s->Q; c++) {
		long cy = c * h, x0;
		if (!edge && (c & 1) == 0)
			continue; /* square centres: odd multiples */
		x0 = edge && (c & 1) ? 0 : h;
		if (t->lo > x0) /* the first centre in the share */
			x0 += (t->lo - x0 + 2 * h - 1) / (2 * h) * (2 * h);
		for (long cx = x0; cx < s->cend && cx < t->hi; cx += 2 * h) {
			int tri[2][3][2];
			int nt = bt_diamond((int)cx, (int)cy, tri);
			float *acc = &s->acc[eslot(s, (int)cy) + (cx - s->c0)];
			for (int k = 0; k < nt; k++) {
				double err = tri_row(t, tri[k], y, hk);
				if (err > *acc)
					*acc = (float)err;
			}
		}
	}
}

/* Raises the base errors of the blocks whose finest triangles (a cell's
 * two, diagonal by the parity of ci + cj as in the bintree) the DEM row
 * crosses. */
static inline __attribute__((always_inline)) void
row_leaves_body(strip *sh, double y)
{
	const state *s = sh->s;
	double mg = s->L->displaced ? 1 : EPS;
	long r0 = (long)floor(y - mg), r1 = (long)floor(y + mg);

	int lo = leaf_lo(sh), hi = leaf_hi(sh);

	for (long cj = r0 > 0 ? r0 : 0; cj <= r1 && cj < s->Q - 1; cj++)
		for (int ci = lo; ci < hi; ci++) {
			int a[2] = { ci, (int)cj }, b[2] = { ci + 1, (int)cj };
			int c[2] = { ci + 1, (int)cj + 1 };
			int d[2] = { ci, (int)cj + 1 };
			int t[2][3][2];
			double *base = base_at(sh, (int)cj, ci);
			if ((ci + cj) % 2 == 0) {
				memcpy(t[0][0], a, 8), memcpy(t[0][1], b, 8);
				memcpy(t[0][2], c, 8), memcpy(t[1][0], a, 8);
				memcpy(t[1][1], c, 8), memcpy(t[1][2], d, 8);
			} else {
				memcpy(t[0][0], a, 8), memcpy(t[0][1], b, 8);
				memcpy(t[0][2], d, 8), memcpy(t[1][0], b, 8);
				memcpy(t[1][1], c, 8), memcpy(t[1][2], d, 8);
			}
			for (int k = 0; k < 2; k++) {
				double err = tri_row(sh, t[k], y, 0);
				if (err > *base)
					*base = err;
			}
		}
}

/* Both, inlined into the AVX2 copy or the plain one (level_impl.h,
 * TL_AVX2). */
static inline __attribute__((always_inline)) void
row_displaced_body(strip *t, double y)
{
	for (int h = 1, hk = 0; h <= BT_MAXH; h *= 2, hk++) {
		row_diamonds_body(t, y, h, hk, 0);
		row_diamonds_body(t, y, h, hk, 1);
	}
	row_leaves_body(t, y);
}

TL_AVX2 static void
row_displaced_avx2(strip *t, double y)
{
	row_displaced_body(t, y);
}

static void
row_displaced(strip *t, double y)
{
	row_displaced_body(t, y);
}

/* The errors DEM row J (t->dd) raises in t's columns. */
static void
scan_row(strip *t, int J)
{
	double y = J / t->s->step;

	if (t->s->scan)
		tiles_scan_row(t, J);
	else if (t->s->avx2)
		row_displaced_avx2(t, y);
	else
		row_displaced(t, y);
}

/* --- saturation ------------------------------------------------------- */

static void
raise(state *s, int g0, int lo, int hi, float *e, int ci, int cj)
{
	if (ci >= 0 && ci < s->P && cj >= lo && cj < hi) {
		float c = s->band[(size_t)(cj - g0) * s->P + ci];
		if (c > *e)
			*e = c;
	}
}

/* E = max(local, E of children), children first: edge(1), square(1),
 * edge(2), ..., square(64), over the band of rows g0 .. g0+BAND-1. */
static void
saturate(state *s, int bj)
{
	int g0 = bj * BT_CELLS - REACH, P = s->P;
	int lo = g0 > 0 ? g0 : 0, hi = g0 + BAND < s->Q ? g0 + BAND : s->Q;

	assert(lo >= g0 && hi <= g0 + BAND && lo < hi);
	for (int gj = lo; gj < hi; gj++)
		memcpy(s->band + (size_t)(gj - g0) * P, s->acc + eslot(s, gj),
		    (size_t)P * sizeof *s->band);
	for (int h = 1; h <= BT_MAXH; h *= 2) {
		int g = h / 2;
		/* edge(h), h > 1: children (gi +- h/2, gj +- h/2) */
		for (int gj = lo; h > 1 && gj < hi; gj++) {
			int gi0 = gj % (2 * h) == 0 ? h : gj % h == 0 &&
			    (gj / h) % 2 ? 0 : -1;
			if (gi0 < 0)
				continue;
			for (int gi = gi0; gi < P; gi += 2 * h) {
				float *e = &s->band[(size_t)(gj - g0) * P + gi];
				raise(s, g0, lo, hi, e, gi - g, gj - g);
				raise(s, g0, lo, hi, e, gi + g, gj - g);
				raise(s, g0, lo, hi, e, gi - g, gj + g);
				raise(s, g0, lo, hi, e, gi + g, gj + g);
			}
		}
		/* square(h): children (gi +- h, gj), (gi, gj +- h) */
		for (int gj = lo; gj < hi; gj++) {
			if (gj % h != 0 || (gj / h) % 2 == 0)
				continue;
			for (int gi = h; gi < P; gi += 2 * h) {
				float *e = &s->band[(size_t)(gj - g0) * P + gi];
				raise(s, g0, lo, hi, e, gi - h, gj);
				raise(s, g0, lo, hi, e, gi + h, gj);
				raise(s, g0, lo, hi, e, gi, gj - h);
				raise(s, g0, lo, hi, e, gi, gj + h);
			}
		}
	}
}

/* --- blocks ----------------------------------------------------------- */

/* Block bj, bi of the saturated band into b. */
static void
fill_block(const state *s, pyramid_block *b, int bi, int bj)
{
	int g0 = bj * BT_CELLS - REACH;
	double emax = 0;

	b->level = s->L->level, b->bi = bi, b->bj = bj;
	b->base = 0; /* the shares' base errors, merged */
	for (int k = 0; k < s->nstrip; k++)
		b->base = dmax(b->base, *base_at(&s->strips[k],
		    bj * BT_CELLS, bi * BT_CELLS));
	b->zmin = INFINITY, b->zmax = -INFINITY;
	for (int r = 0; r < BT_SIZE; r++) {
		int gj = bj * BT_CELLS + r;
		size_t o = slot(s, gj) + (size_t)(bi * BT_CELLS - s->c0);
		/* the block's rows lie in the band's middle */
		assert(gj - g0 >= REACH && gj - g0 < BAND - REACH);
		const float *band = s->band + (size_t)(gj - g0) * s->P +
		    (size_t)(bi * BT_CELLS - s->c0);
		for (int c = 0; c < BT_SIZE; c++) {
			int k = r * BT_SIZE + c;
			int corner = r % BT_CELLS == 0 && c % BT_CELLS == 0;
			b->z[k] = s->z[o + c];
			b->e[k] = corner ? FLT_MAX : band[c];
			if (!corner && b->e[k] > emax)
				emax = b->e[k];
			if (b->displaced) {
				b->x[k] = s->ox[o + c];
				b->y[k] = s->oy[o + c];
			}
			b->zmin = fmin(b->zmin, b->z[k]);
			b->zmax = fmax(b->zmax, b->z[k]);
		}
	}
	b->emax = emax;
}

/* The share's blocks of block row bj, handed to the caller (in parallel
 * with the other shares': writing a block is mostly compressing it). */
static void
emit_share(strip *t, int bj)
{
	const state *s = t->s;

	for (int bi = t->blo; bi < t->bhi && !t->failed; bi++) {
		pyramid_block *b = &t->blk;
		fill_block(s, b, bi, bj);
		t->max_e = dmax(t->max_e, b->emax);
		t->max_base = dmax(t->max_base, b->base);
		if (s->L->block(s->L->block_ctx, b, &t->err) < 0)
			t->failed = 1;
	}
}

static void
strips_free(state *s)
{
	for (int i = 0; s->strips != NULL && i < s->nstrip; i++) {
		strip *t = &s->strips[i];
		free(t->base);
		pyramid_block_free(&t->blk);
		for (int k = 0; k < 8; k++)
			free(t->vc[k].x), free(t->vc[k].y);
	}
	free(s->strips);
}

static void
state_free(state *s)
{
	free(s->z), free(s->ox), free(s->oy), free(s->sx), free(s->sy);
	free(s->nk), free(s->nu);
	free(s->acc), free(s->band);
	free(s->dz), free(s->dv);
	free(s->dd);
	strips_free(s);
}

/* A share's base errors and, displaced, its rows of positions
 * (vertex_at). */
static int
strip_init(state *s, strip *t, int lo, int hi, tl_err *e)
{
	t->s = s, t->lo = lo, t->hi = hi;
	if ((t->base = tl_alloc((size_t)(s->b1 - s->b0) * s->by,
	    sizeof *t->base, e)) == NULL ||
	    pyramid_block_alloc(&t->blk, s->L->displaced,
	    e) < 0)
		return -1;
	for (int hk = 0; (1 << hk) <= BT_MAXH; hk++) {
		t->vc[hk].n = (s->P - 1) / (1 << hk) + 1;
		for (int r = 0; r < VC_ROWS; r++)
			t->vc[hk].tag[r] = -1;
		if (!s->L->displaced)
			continue;
		t->vc[hk].x = tl_alloc((size_t)VC_ROWS * t->vc[hk].n,
		    sizeof *t->vc[hk].x, e);
		t->vc[hk].y = tl_alloc((size_t)VC_ROWS * t->vc[hk].n,
		    sizeof *t->vc[hk].y, e);
		if (t->vc[hk].x == NULL || t->vc[hk].y == NULL)
			return -1;
	}
	return 0;
}

/* The centres whose local errors the piece's saturation reads (its
 * block columns and REACH either side), in n shares of nearly equal
 * width (fewer when they are fewer than n columns); its blocks likewise. */
static int
strips_init(state *s, int n, tl_err *e)
{
	int lo = s->lo, hi = s->hi, nb = s->b1 - s->b0;

	if (n > hi - lo - 1)
		n = hi - lo - 1;
	if (n < 1)
		n = 1;
	if ((s->strips = tl_alloc(n, sizeof *s->strips, e)) == NULL)
		return -1;
	s->nstrip = n;
	for (int k = 0; k < n; k++) {
		strip *t = &s->strips[k];
		if (strip_init(s, t, lo + (int)((long)(hi - lo) * k / n),
		    lo + (int)((long)(hi - lo) * (k + 1) / n), e) < 0)
			return -1;
		t->blo = s->b0 + nb * k / n, t->bhi = s->b0 + nb * (k + 1) / n;
	}
	return 0;
}

/* The centres whose local errors saturating piece p reads: its block
 * columns and REACH either side. */
static void
centres(const tiles_level *L, const tiles_piece *p, int *lo, int *hi)
{
	int Pl = pyramid_nblocks(L->size[0]) * BT_CELLS + 1;

	*lo = p->b0 * BT_CELLS - REACH, *hi = p->b1 * BT_CELLS + REACH + 1;
	*lo = *lo > 0 ? *lo : 0, *hi = *hi < Pl ? *hi : Pl;
}

/* The rows a run reads: a part's, or every one. */
static void
state_rows(state *s, const tiles_part *q)
{
	if (q != NULL) {
		s->lo = q->lo, s->hi = q->hi;
		s->y0 = q->y0, s->y1 = q->y1;
		s->r0 = q->r0, s->r1 = q->r1;
		s->next_out = q->g0;
	} else {
		centres(s->L, &(tiles_piece){ s->b0, s->b1 }, &s->lo, &s->hi);
		s->y0 = 0, s->y1 = s->d != NULL ? dem_georef(s->d)->height : 0;
		s->r0 = 0, s->r1 = s->Q;
	}
	s->loaded = s->r0;
}

/* A run of piece pc: scanning d (all its rows, or part q's), or with d
 * NULL reading its local errors; w0 is the DEM's width. */
static int
state_init(state *s, const tiles_level *L, const tiles_piece *pc, int w0,
    dem *d, const tiles_part *q, tl_err *e)
{
	tiles_window win;
	size_t ring;

	memset(s, 0, sizeof *s);
	s->L = L, s->d = d;
	s->W0 = w0;
	s->bx = pyramid_nblocks(L->size[0]);
	s->by = pyramid_nblocks(L->size[1]);
	s->Pl = s->bx * BT_CELLS + 1, s->Q = s->by * BT_CELLS + 1;
	s->step = (double)(1L << L->level);
	tiles_piece_window(L, s->W0, pc, &win);
	s->b0 = pc->b0, s->b1 = pc->b1;
	s->c0 = win.c0, s->cend = win.c1, s->P = win.c1 - win.c0;
	s->d0 = win.d0, s->dend = win.d1;
	state_rows(s, q);
	/* QEM-3D offsets stay within half a cell (fqmsolve(1)) */
	s->margin = L->displaced ? 0.5 + 1e-6 : EPS;
	s->scan = !L->displaced && s->step <= SCAN_MAXSTEP;
#if defined(__x86_64__) || defined(__i386__)
	/* TL_NO_AVX2 set: the plain copies (t_level compares the two) */
	s->avx2 = __builtin_cpu_supports("avx2") && getenv("TL_NO_AVX2") == NULL;
#endif
	ring = (size_t)RINGV * s->P;
	s->z = tl_alloc(ring, sizeof *s->z, e);
	s->acc = tl_alloc((size_t)RINGE * s->P, sizeof *s->acc, e);
	s->nn = geo_row_nodes(L->m);
	if (L->displaced && s->nn > 1) {
		s->nk = tl_alloc(s->P, sizeof *s->nk, e);
		s->nu = tl_alloc(s->P, sizeof *s->nu, e);
	}
	s->sx = tl_alloc((size_t)RINGV * s->nn, sizeof *s->sx, e);
	s->sy = tl_alloc((size_t)RINGV * s->nn, sizeof *s->sy, e);
	if (q == NULL) /* a part saturates nothing */
		s->band = tl_alloc((size_t)BAND * s->P, sizeof *s->band, e);
	if (d != NULL) {
		s->dz = tl_alloc(s->dend - s->d0, sizeof *s->dz, e);
		s->dv = tl_alloc(s->dend - s->d0, 1, e);
		s->dd = tl_alloc((size_t)BATCH * (s->dend - s->d0 + 1),
		    sizeof *s->dd, e);
	}
	if (L->displaced) {
		s->ox = tl_alloc(ring, sizeof *s->ox, e);
		s->oy = tl_alloc(ring, sizeof *s->oy, e);
	}
	if (!s->z || !s->acc || !s->sx || !s->sy || (q == NULL && !s->band) ||
	    (L->displaced && s->nn > 1 && (!s->nk || !s->nu)) ||
	    (d != NULL && (!s->dz || !s->dv || !s->dd)) ||
	    (L->displaced && (!s->ox || !s->oy)) ||
	    strips_init(s, L->threads, e) < 0) {
		state_free(s);
		return -1;
	}
	if (s->nk != NULL)
		node_columns(s);
	return 0;
}

/* A block row is final once no DEM row left can reach the local errors
 * its saturation band reads: 64 rows past the band, plus the margin. */
static int
ready(const state *s, int bj, double y)
{
	return y >= bj * BT_CELLS + BT_CELLS + REACH + BT_MAXH + 2;
}

/* --- the shares on threads --------------------------------------------- */

/* A task for every share, on the pool's threads (base/pool.h): the
 * pool has a thread per share, so each range is one share (or, with
 * fewer threads, a few in a row). */
enum task { SCAN, EMIT };
_Static_assert(TILES_MAXTHREADS <= TL_POOL_MAXTHREADS, "a pool per piece");

typedef struct {
	tl_pool *pool;
	state *s;
	enum task task;
	int J0, J1, bj;    /* SCAN: DEM rows J0 .. J1-1; EMIT: block row bj */
} crew;

static void
scan_batch(strip *t, int J0, int J1)
{
	const state *s = t->s;

	for (int J = J0; J < J1; J++) {
		t->dd = s->dd + (size_t)(J - J0) * (s->dend - s->d0 + 1);
		scan_row(t, J);
	}
}

static void
do_shares(void *arg, int k, int i0, int i1)
{
	const crew *c = arg;

	(void)k;
	for (int i = i0; i < i1; i++)
		if (c->task == SCAN)
			scan_batch(&c->s->strips[i], c->J0, c->J1);
		else
			emit_share(&c->s->strips[i], c->bj);
}

/* The crew's task (set by the caller) on every share. */
static void
run_shares(state *s, crew *c)
{
	tl_pool_for(c->pool, s->nstrip, do_shares, c);
}

/* Block row bj: saturated, then its blocks handed out by the shares;
 * the failure told is the leftmost share's. */
static int
emit_row(state *s, crew *c, int bj, tl_err *e)
{
	saturate(s, bj);
	c->task = EMIT, c->bj = bj;
	run_shares(s, c);
	for (int k = 0; k < s->nstrip; k++) {
		const strip *t = &s->strips[k];
		if (t->failed) {
			*e = t->err;
			return -1;
		}
		s->st->max_e = dmax(s->st->max_e, t->max_e);
		s->st->max_base = dmax(s->st->max_base, t->max_base);
	}
	return 0;
}

/* The window's columns of DEM rows J0 .. J1-1 as doubles, NaN where not
 * valid; the valid samples of the piece's own columns counted (the
 * pieces' own columns partition the DEM's). */
static int
read_batch(state *s, int J0, int J1, tl_err *e)
{
	long n = s->dend - s->d0, S = (long)s->step;
	long own0 = s->b0 * BT_CELLS * S - s->d0;
	long own1 = s->b1 == s->bx ? n : s->b1 * BT_CELLS * S - s->d0;

	for (int J = J0; J < J1; J++) {
		double *dd = s->dd + (size_t)(J - J0) * (n + 1);
		long long k = 0;
		if (dem_read_span(s->d, J, (int)s->d0, (int)n, s->dz, s->dv,
		    e) < 0)
			return -1;
		for (long i = 0; i < n; i++)
			dd[i] = s->dv[i] ? (double)s->dz[i] : NAN;
		for (long i = own0; i < own1; i++)
			k += s->dv[i];
		s->st->samples += k;
	}
	return 0;
}

/* The block rows not yet handed out: every level row loaded (a merged
 * piece's local errors read as they are), each block row once its
 * saturation band is. */
static int
run_blocks(state *s, crew *c, tl_err *e)
{
	while (s->next_bj < s->by) {
		if (ensure(s, s->next_bj * BT_CELLS + BT_CELLS + REACH, e) < 0 ||
		    emit_row(s, c, s->next_bj++, e) < 0)
			return -1;
	}
	return 0;
}

/* A part's local errors of the rows no later DEM row can reach (below
 * level row `below`), given out. A DEM row at level row y reaches the
 * centres from y - 64 - margin (less than 65) on. */
static int
give_out(state *s, int below, tl_err *e)
{
	const tiles_part *q = s->part;

	for (; s->next_out < q->g1 && s->next_out < below; s->next_out++)
		if (s->out(s->out_ctx, s->next_out, s->acc + eslot(s,
		    s->next_out) + (q->lo - s->c0), e) < 0)
			return -1;
	return 0;
}

/* Every DEM row scanned (a part's), in batches, each block row handed
 * out once no later row can change it (a part's local errors likewise). */
static int
run_rows(state *s, crew *c, tl_progress *pr, tl_err *e)
{
	for (int J0 = s->y0; J0 < s->y1; J0 += BATCH) {
		int J1 = J0 + BATCH < s->y1 ? J0 + BATCH : s->y1;
		double y = (J1 - 1) / s->step;
		s->yfirst = (int)(J0 / s->step);
		/* diamond vertices reach 2 x 64 rows (+ margin) below */
		if (ensure(s, (int)y + 2 * BT_MAXH + 2, e) < 0 ||
		    read_batch(s, J0, J1, e) < 0)
			return -1;
		c->task = SCAN, c->J0 = J0, c->J1 = J1;
		run_shares(s, c);
		if (s->part != NULL &&
		    give_out(s, (int)floor(J1 / s->step) - BT_MAXH - 1, e) < 0)
			return -1;
		while (s->part == NULL && s->next_bj < s->by &&
		    ready(s, s->next_bj, y))
			if (emit_row(s, c, s->next_bj++, e) < 0)
				return -1;
		tl_progress_step(pr, J1 - s->y0);
		if (s->L->progress != NULL)
			s->L->progress(s->L->progress_ctx, J1 - J0);
	}
	if (s->part != NULL)
		return ensure(s, s->part->g1 - 1, e) < 0 ? -1 :
		    give_out(s, s->part->g1, e);
	return run_blocks(s, c, e);
}

/* How far past its blocks a piece's window reaches. Saturating a block
 * reads the local errors of its vertices' descendants: the farthest, 126
 * columns past the block's edge, is an edge(1) diamond down the chain
 * square(64) at the block's centre, edge(64) on its edge, square(32),
 * edge(32), ..., edge(1), and the vertices of that chain's diamonds
 * reach 127 columns past the edge (their triangles too; displaced, half
 * a column more). So 128 columns of heights and 128 x step of DEM
 * samples suffice, and 128 keeps the window's first column a multiple
 * of 128, so that saturation's parities are the level's. t_level checks
 * pieces against the whole level. */
#define HALO REACH

void
tiles_piece_window(const tiles_level *L, int w0, const tiles_piece *p,
    tiles_window *w)
{
	int Pl = pyramid_nblocks(L->size[0]) * BT_CELLS + 1;
	long S = 1L << L->level, c1;

	assert(p->b0 >= 0 && p->b0 < p->b1 &&
	    p->b1 <= pyramid_nblocks(L->size[0]));
	w->b0 = p->b0, w->b1 = p->b1;
	w->c0 = p->b0 * BT_CELLS - HALO;
	w->c0 = w->c0 > 0 ? w->c0 : 0;
	assert(w->c0 % (2 * BT_MAXH) == 0);
	c1 = (long)p->b1 * BT_CELLS + HALO + 1;
	w->c1 = c1 < Pl ? (int)c1 : Pl;
	w->d0 = (long)w->c0 * S;
	w->d1 = ((long)w->c1 - 1) * S + 1;
	w->d1 = w->d1 < w0 ? w->d1 : w0;
}

int
tiles_pieces(const tiles_level *L, int cols, tiles_piece *p, int max)
{
	int bx = pyramid_nblocks(L->size[0]), n = (bx + cols - 1) / cols;

	assert(cols >= 1);
	for (int k = 0; k < n && k < max; k++) {
		p[k].b0 = (int)((long)bx * k / n);
		p[k].b1 = (int)((long)bx * (k + 1) / n);
	}
	return n;
}

int
tiles_run(const tiles_level *L, dem *d, tiles_stats *st, tl_err *e)
{
	tiles_piece all = { 0, pyramid_nblocks(L->size[0]) };

	return tiles_run_piece(L, &all, d, st, e);
}

void
tiles_part_window(const tiles_level *L, const tiles_piece *p, int y0,
    int y1, tiles_part *q)
{
	int Q = pyramid_nblocks(L->size[1]) * BT_CELLS + 1;
	long S = 1L << L->level;

	assert(y0 >= 0 && y0 < y1);
	q->y0 = y0, q->y1 = y1;
	centres(L, p, &q->lo, &q->hi);
	/* a DEM row at level row y reaches centres y - 64 - margin ..
	 * y + 64 + margin (margin < 1), their vertices 64 rows further */
	q->g0 = (int)(y0 / S) - BT_MAXH - 1;
	q->g1 = (int)((y1 - 1) / S) + BT_MAXH + 2;
	q->g0 = q->g0 > 0 ? q->g0 : 0, q->g1 = q->g1 < Q ? q->g1 : Q;
	q->r0 = q->g0 - BT_MAXH, q->r1 = q->g1 + BT_MAXH;
	q->r0 = q->r0 > 0 ? q->r0 : 0, q->r1 = q->r1 < Q ? q->r1 : Q;
}

/* A run set up by state_init, on a pool of its shares' threads. */
static int
run(state *s, tiles_stats *st, tl_err *e)
{
	const tiles_level *L = s->L;
	tl_progress pr;
	crew c = { 0 };
	int r;

	s->st = st;
	c.s = s;
	if ((c.pool = tl_pool_new(s->nstrip, e)) == NULL)
		return -1;
	tl_progress_start(&pr, L->label ? L->label : "", s->y1 - s->y0);
	if (L->label == NULL)
		pr.on = 0;
	r = s->d != NULL ? run_rows(s, &c, &pr, e) : run_blocks(s, &c, e);
	if (r == 0)
		tl_progress_end(&pr);
	tl_pool_free(c.pool);
	return r;
}

int
tiles_run_piece(const tiles_level *L, const tiles_piece *pc, dem *d,
    tiles_stats *st, tl_err *e)
{
	state s;
	int r;

	assert(L->threads <= TILES_MAXTHREADS);
	memset(st, 0, sizeof *st);
	if (state_init(&s, L, pc, dem_georef(d)->width, d, NULL, e) < 0)
		return -1;
	r = run(&s, st, e);
	state_free(&s);
	return r;
}

int
tiles_run_part(const tiles_level *L, const tiles_piece *pc,
    const tiles_part *q, dem *d, tiles_err_fn out, void *ctx, double *base,
    tiles_stats *st, tl_err *e)
{
	size_t nb;
	state s;
	int r;

	assert(L->threads <= TILES_MAXTHREADS);
	assert(q->y1 <= dem_georef(d)->height);
	memset(st, 0, sizeof *st);
	if (state_init(&s, L, pc, dem_georef(d)->width, d, q, e) < 0)
		return -1;
	s.part = q, s.out = out, s.out_ctx = ctx;
	r = run(&s, st, e);
	/* the shares' base errors, merged (a maximum: any order) */
	nb = (size_t)(s.b1 - s.b0) * s.by;
	for (size_t i = 0; r == 0 && i < nb; i++) {
		base[i] = 0;
		for (int k = 0; k < s.nstrip; k++)
			base[i] = dmax(base[i], s.strips[k].base[i]);
	}
	state_free(&s);
	return r;
}

int
tiles_run_merged(const tiles_level *L, const tiles_piece *pc, int w0,
    tiles_err_fn in, void *ctx, const double *base, tiles_stats *st,
    tl_err *e)
{
	state s;
	int r;

	assert(L->threads <= TILES_MAXTHREADS);
	memset(st, 0, sizeof *st);
	if (state_init(&s, L, pc, w0, NULL, NULL, e) < 0)
		return -1;
	s.in = in, s.in_ctx = ctx;
	/* the parts' base errors, as the first share's */
	memcpy(s.strips[0].base, base, (size_t)(s.b1 - s.b0) * s.by *
	    sizeof *base);
	r = run(&s, st, e);
	state_free(&s);
	return r;
}
