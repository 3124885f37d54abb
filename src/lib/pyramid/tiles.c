/* tiles.c - exact local errors, saturation and blocks of a level (see
 * tiles.h). */
#include "pyramid/tiles.h"
#include "pyramid/tiles_impl.h"
#include "core/progress.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* fmin/fmax are library calls here; these inline. */
static inline double
dmin(double a, double b)
{
	return a < b ? a : b;
}

static inline double
dmax(double a, double b)
{
	return a > b ? a : b;
}

/* Loads level row r (the next one): a real row, or past the last one a
 * copy of it; columns past the last real one copy its height (padding). */
static int
load_row(state *s, int r, tl_err *e)
{
	const tiles_level *L = s->L;
	int n = L->size[0], m = L->size[1];
	size_t o;
	long J = (long)r << L->level;

	/* the rows it overwrites are behind every block row still to go */
	assert(r == s->loaded);
	assert(r < RINGV || r - RINGV < s->next_bj * BT_CELLS);
	assert(r < RINGE || r - RINGE < s->next_bj * BT_CELLS - REACH);
	s->loaded++;
	o = slot(s, r);
	if (r < m) {
		if (L->row(L->row_ctx, r, s->rz, L->displaced ? s->rx : NULL,
		    L->displaced ? s->ry : NULL, e) < 0)
			return -1;
		memcpy(s->z + o, s->rz, (size_t)n * sizeof *s->z);
		if (L->displaced) {
			memcpy(s->ox + o, s->rx, (size_t)n * sizeof *s->ox);
			memcpy(s->oy + o, s->ry, (size_t)n * sizeof *s->oy);
		}
	} else {
		memcpy(s->z + o, s->z + slot(s, m - 1),
		    (size_t)n * sizeof *s->z);
		if (L->displaced) {
			memset(s->ox + o, 0, (size_t)n * sizeof *s->ox);
			memset(s->oy + o, 0, (size_t)n * sizeof *s->oy);
		}
	}
	for (int i = n; i < s->P; i++) {
		s->z[o + i] = s->z[o + n - 1];
		if (L->displaced)
			s->ox[o + i] = s->oy[o + i] = 0;
	}
	memset(s->acc + eslot(s, r), 0, (size_t)s->P * sizeof *s->acc);
	o = (size_t)(r & (RINGV - 1)) * s->nn; /* this row's scales */
	geo_row_sx(L->m, (double)J, s->sx + o);
	geo_row_sy(L->m, (double)J, s->sy + o);
	return 0;
}

static int
ensure(state *s, int r, tl_err *e)
{
	if (r > s->Q - 1)
		r = s->Q - 1;
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
	k = s->nk[gi], u = s->nu[gi];
	*sx = x[k] + u * (x[k + 1] - x[k]);
	*sy = y[k] + u * (y[k + 1] - y[k]);
}

/* Where each column falls among the lattice's node columns, as
 * geo_on_row finds it. */
static void
node_columns(state *s)
{
	const geo_metric *m = s->L->m;

	for (int gi = 0; gi < s->P; gi++) {
		double t = gi * s->step * m->inv;
		if (!(t > 0))
			s->nk[gi] = 0, s->nu[gi] = 0;
		else if (t >= m->nx - 1)
			s->nk[gi] = m->nx - 2, s->nu[gi] = 1;
		else
			s->nk[gi] = (int)t, s->nu[gi] = t - s->nk[gi];
	}
}

/* Position (level units) and height of grid vertex (gi, gj). */
static inline void
vertex(const state *s, int gi, int gj, double p[3])
{
	size_t o = slot(s, gj) + gi;

	p[0] = gi, p[1] = gj, p[2] = s->z[o];
	if (s->L->displaced) {
		double sx, sy;
		scales(s, gi, gj, &sx, &sy);
		p[0] += s->ox[o] / sx / s->step;
		p[1] += s->oy[o] / sy / s->step;
	}
}

/* Row k (vertices k x 2^hk) of scale 2^hk's positions: vertex()'s. */
static void
vc_fill(state *s, int hk, int k)
{
	int h = 1 << hk, r = k & (VC_ROWS - 1), n = s->vc[hk].n;
	double *x = s->vc[hk].x + (size_t)r * n, *y = s->vc[hk].y +
	    (size_t)r * n;

	for (int m = 0; m < n; m++) {
		double p[3];
		vertex(s, m * h, k * h, p);
		x[m] = p[0], y[m] = p[1];
	}
	s->vc[hk].tag[r] = k;
}

/* vertex() of (gi, gj), both multiples of 2^hk: on displaced levels
 * from the scale's rows of positions, each found once while in use (a
 * DEM row reaches at most 6 consecutive rows of a scale's vertices and
 * rows come in order). */
static inline void
vertex_at(state *s, int hk, int gi, int gj, double p[3])
{
	int k, r;
	size_t o;

	if (!s->L->displaced) {
		p[0] = gi, p[1] = gj, p[2] = s->z[slot(s, gj) + gi];
		return;
	}
	assert(gi % (1 << hk) == 0 && gj % (1 << hk) == 0);
	k = gj >> hk, r = k & (VC_ROWS - 1);
	if (s->vc[hk].tag[r] != k)
		vc_fill(s, hk, k);
	o = (size_t)r * s->vc[hk].n + (gi >> hk);
	p[0] = s->vc[hk].x[o], p[1] = s->vc[hk].y[o];
	p[2] = s->z[slot(s, gj) + gi];
}

/* (long)ceil(x) and (long)floor(x), inline, for |x| < 2^62. */
static inline long
iceil(double x)
{
	long t = (long)x;
	return (double)t < x ? t + 1 : t;
}

static inline long
ifloor(double x)
{
	long t = (long)x;
	return (double)t > x ? t - 1 : t;
}

static int
on_grid(const state *s, const int v[2])
{
	return v[0] >= 0 && v[1] >= 0 && v[0] < s->P && v[1] < s->Q;
}

/* The largest |plane - DEM| over the valid samples of the current DEM row
 * (level row y) inside triangle t, closed; -1 when none is. */
static double
tri_row(state *s, const int t[3][2], double y, int hk)
{
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
		vertex_at(s, hk, t[k][0], t[k][1], p[k]);
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
	if (i0 < 0)
		i0 = 0;
	if (i1 > s->W0 - 1)
		i1 = s->W0 - 1;
	/* i / step is i x (1 / step) exactly: step is a power of 2 */
	return sweep(s->dd, i0, i1, z0, dz, 1 / s->step);
}

/* Raises the local errors of every diamond of scale h and one kind that
 * the DEM row (level row y) crosses. Square diamonds are centred on odd
 * multiples of h in both axes; edge diamonds on points with exactly one
 * odd multiple: |x - cx| + |y - cy| <= h. */
static void
row_diamonds(state *s, double y, int h, int hk, int edge)
{
	double reach = h + s->margin;
	long c0 = (long)ceil((y - reach) / h);
	long c1 = (long)floor((y + reach) / h);

	for (long c = c0 > 0 ? c0 : 0; c <= c1 && c * h < s->Q; c++) {
		long cy = c * h, x0;
		if (!edge && (c & 1) == 0)
			continue; /* square centres: odd multiples */
		x0 = edge && (c & 1) ? 0 : h;
		for (long cx = x0; cx < s->P; cx += 2 * h) {
			int tri[2][3][2];
			int nt = bt_diamond((int)cx, (int)cy, tri);
			float *acc = &s->acc[eslot(s, (int)cy) + cx];
			for (int k = 0; k < nt; k++) {
				double err = tri_row(s, tri[k], y, hk);
				if (err > *acc)
					*acc = (float)err;
			}
		}
	}
}

/* Raises the base errors of the blocks whose finest triangles (a cell's
 * two, diagonal by the parity of ci + cj as in the bintree) the DEM row
 * crosses. */
static void
row_leaves(state *s, double y)
{
	double mg = s->L->displaced ? 1 : EPS;
	long r0 = (long)floor(y - mg), r1 = (long)floor(y + mg);

	for (long cj = r0 > 0 ? r0 : 0; cj <= r1 && cj < s->Q - 1; cj++)
		for (int ci = 0; ci < s->P - 1; ci++) {
			int a[2] = { ci, (int)cj }, b[2] = { ci + 1, (int)cj };
			int c[2] = { ci + 1, (int)cj + 1 };
			int d[2] = { ci, (int)cj + 1 };
			int t[2][3][2];
			double *base = &s->base[(size_t)(cj / BT_CELLS) *
			    s->bx + ci / BT_CELLS];
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
				double err = tri_row(s, t[k], y, 0);
				if (err > *base)
					*base = err;
			}
		}
}

static void
dem_row(state *s, int J)
{
	double y = J / s->step;

	for (int i = 0; i < s->W0; i++)
		s->dd[i] = s->dv[i] ? (double)s->dz[i] : NAN;
	if (s->scan)
		tiles_scan_row(s, J);
	else {
		for (int h = 1, hk = 0; h <= BT_MAXH; h *= 2, hk++) {
			row_diamonds(s, y, h, hk, 0);
			row_diamonds(s, y, h, hk, 1);
		}
		row_leaves(s, y);
	}
	for (int I = 0; I < s->W0; I++)
		s->st->samples += s->dv[I];
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

static int
emit_row(state *s, int bj, tl_err *e)
{
	pyramid_block *b = &s->blk;
	int g0 = bj * BT_CELLS - REACH;

	saturate(s, bj);
	for (int bi = 0; bi < s->bx; bi++) {
		b->level = s->L->level, b->bi = bi, b->bj = bj;
		b->base = s->base[(size_t)bj * s->bx + bi];
		b->zmin = INFINITY, b->zmax = -INFINITY;
		double emax = 0;
		for (int r = 0; r < BT_SIZE; r++) {
			int gj = bj * BT_CELLS + r;
			size_t o = slot(s, gj) + (size_t)bi * BT_CELLS;
			/* the block's rows lie in the band's middle */
			assert(gj - g0 >= REACH && gj - g0 < BAND - REACH);
			const float *band = s->band + (size_t)(gj - g0) * s->P +
			    (size_t)bi * BT_CELLS;
			for (int c = 0; c < BT_SIZE; c++) {
				int k = r * BT_SIZE + c;
				int corner = r % BT_CELLS == 0 &&
				    c % BT_CELLS == 0;
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
		if (emax > s->st->max_e)
			s->st->max_e = emax;
		if (b->base > s->st->max_base)
			s->st->max_base = b->base;
		if (s->L->block(s->L->block_ctx, b, e) < 0)
			return -1;
	}
	return 0;
}

static void
state_free(state *s)
{
	free(s->z), free(s->ox), free(s->oy), free(s->sx), free(s->sy);
	free(s->nk), free(s->nu);
	free(s->acc), free(s->base), free(s->band);
	free(s->rz), free(s->rx), free(s->ry), free(s->dz), free(s->dv);
	pyramid_block_free(&s->blk);
	free(s->dd);
	for (int k = 0; k < 8; k++)
		free(s->vc[k].x), free(s->vc[k].y);
}

/* The displaced levels' rows of positions (vertex_at). */
static int
vc_init(state *s, tl_err *e)
{
	for (int hk = 0; (1 << hk) <= BT_MAXH; hk++) {
		s->vc[hk].n = (s->P - 1) / (1 << hk) + 1;
		for (int r = 0; r < VC_ROWS; r++)
			s->vc[hk].tag[r] = -1;
		if (!s->L->displaced)
			continue;
		s->vc[hk].x = tl_alloc((size_t)VC_ROWS * s->vc[hk].n,
		    sizeof *s->vc[hk].x, e);
		s->vc[hk].y = tl_alloc((size_t)VC_ROWS * s->vc[hk].n,
		    sizeof *s->vc[hk].y, e);
		if (s->vc[hk].x == NULL || s->vc[hk].y == NULL)
			return -1;
	}
	return 0;
}

static int
state_init(state *s, const tiles_level *L, dem *d, tl_err *e)
{
	const georef *g = dem_georef(d);
	size_t ring;

	memset(s, 0, sizeof *s);
	s->L = L, s->d = d;
	s->W0 = g->width;
	s->bx = pyramid_nblocks(L->size[0]);
	s->by = pyramid_nblocks(L->size[1]);
	s->P = s->bx * BT_CELLS + 1, s->Q = s->by * BT_CELLS + 1;
	s->step = (double)(1L << L->level);
	/* QEM-3D offsets stay within half a cell (fqmsolve(1)) */
	s->margin = L->displaced ? 0.5 + 1e-6 : EPS;
	s->scan = !L->displaced && s->step <= SCAN_MAXSTEP;
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
	s->base = tl_alloc((size_t)s->bx * s->by, sizeof *s->base, e);
	s->band = tl_alloc((size_t)BAND * s->P, sizeof *s->band, e);
	s->rz = tl_alloc(L->size[0], sizeof *s->rz, e);
	s->dz = tl_alloc(g->width, sizeof *s->dz, e);
	s->dv = tl_alloc(g->width, 1, e);
	if (L->displaced) {
		s->ox = tl_alloc(ring, sizeof *s->ox, e);
		s->oy = tl_alloc(ring, sizeof *s->oy, e);
		s->rx = tl_alloc(L->size[0], sizeof *s->rx, e);
		s->ry = tl_alloc(L->size[0], sizeof *s->ry, e);
	}
	if (!s->z || !s->acc || !s->sx || !s->sy || !s->base || !s->band ||
	    (L->displaced && s->nn > 1 && (!s->nk || !s->nu)) ||
	    !s->rz || !s->dz || !s->dv || (L->displaced && (!s->ox ||
	    !s->oy || !s->rx || !s->ry)) ||
	    pyramid_block_alloc(&s->blk, L->displaced, e) < 0 ||
	    (s->dd = tl_alloc((size_t)s->W0 + 1, sizeof *s->dd, e)) == NULL ||
	    vc_init(s, e) < 0) {
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

int
tiles_run(const tiles_level *L, dem *d, tiles_stats *st, tl_err *e)
{
	const georef *g = dem_georef(d);
	tl_progress pr;
	state s;
	int r = -1;

	memset(st, 0, sizeof *st);
	if (state_init(&s, L, d, e) < 0)
		return -1;
	s.st = st;
	tl_progress_start(&pr, L->label ? L->label : "", g->height);
	if (L->label == NULL)
		pr.on = 0;
	for (int J = 0; J < g->height; J++) {
		double y = J / s.step;
		/* diamond vertices reach 2 x 64 rows (+ margin) below */
		if (ensure(&s, (int)y + 2 * BT_MAXH + 2, e) < 0 ||
		    dem_read_row(d, J, s.dz, s.dv, e) < 0)
			goto done;
		dem_row(&s, J);
		while (s.next_bj < s.by && ready(&s, s.next_bj, y))
			if (emit_row(&s, s.next_bj++, e) < 0)
				goto done;
		tl_progress_step(&pr, J + 1);
	}
	if (ensure(&s, s.Q - 1, e) < 0)
		goto done;
	while (s.next_bj < s.by)
		if (emit_row(&s, s.next_bj++, e) < 0)
			goto done;
	tl_progress_end(&pr);
	r = 0;
done:
	state_free(&s);
	return r;
}
