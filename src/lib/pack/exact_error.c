/* exact_error.c - the hot kernel: the local and base errors one DEM row
 * raises in a share's columns (see level.h). Most of tilepack's cycles
 * are spent here and in undisplaced_scan.c.
 *
 * What it computes: for every valid DEM sample and every diamond of the
 * 4-8 bintree whose (closed) area holds it, the vertical distance between
 * the sample and the diamond's two triangles without its centre vertex;
 * a vertex's local error is the largest such distance over all samples,
 * a block's base error the largest from its finest triangles. This is
 * the object-space vertex error of the VGIS terrain engine (Lindstrom,
 * Koller, Ribarsky, Hodges, Faust and Turner, "Real-time, continuous
 * level of detail rendering of height fields", SIGGRAPH 96) and of
 * Lindstrom and Pascucci ("Terrain simplification simplified", IEEE TVCG
 * 2002: the diamonds and nested errors of a 4-8 hierarchy), measured
 * exactly against every sample rather than bounded; level_saturate.c
 * then nests it (Pajarola, "Large scale terrain visualization using the
 * restricted quadtree triangulation", IEEE Visualization 98; the survey
 * in ../shared/papers, section 3.6).
 *
 * Which variant serves which case (lv_error_row picks; each is exact and
 * they agree bit for bit where more than one applies):
 *
 *   undisplaced levels (QEM-1D), step <= SCAN_MAXSTEP
 *       undisplaced_scan.c: every triangle has integer vertices and
 *       level, upright or 45-degree edges, so its chord along a DEM row is
 *       whole DEM columns, found once per row, scale, kind and centre row
 *       and shifted along it: no per-triangle geometry. The common case.
 *   displaced levels (QEM-3D)
 *       tri_row here: the general chord of a triangle with displaced
 *       (float32 offset) corners, closed with tolerances EPS, each
 *       vertex's position found once per scale (vertex_at); the row
 *       bodies visit every diamond a row can reach (h + margin).
 *   undisplaced levels coarser than SCAN_MAXSTEP
 *       tri_row too: there the integer scan's argument that EPS changes
 *       nothing no longer holds.
 *
 * Both variants have an AVX2 copy and a plain one of their hot loops
 * (the same operations lane by lane, no FMA: level_impl.h), chosen at
 * run time by state.avx2; sweep (level_impl.h) is the innermost loop of
 * both. Like meshoptimizer's and netpbm's kernels, the choice is made
 * once, here, and the callers do not know which ran. */
#include "pack/level_impl.h"

#include <assert.h>
#include <math.h>
#include <string.h>

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
void
lv_node_columns(state *s)
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
vc_fill(share *t, int hk, int k)
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
vertex_at(share *t, int hk, int gi, int gj, double p[3])
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
tri_row(share *sh, const int t[3][2], double y, int hk)
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
row_diamonds_body(share *t, double y, int h, int hk, int edge)
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
row_leaves_body(share *sh, double y)
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
row_displaced_body(share *t, double y)
{
	for (int h = 1, hk = 0; h <= BT_MAXH; h *= 2, hk++) {
		row_diamonds_body(t, y, h, hk, 0);
		row_diamonds_body(t, y, h, hk, 1);
	}
	row_leaves_body(t, y);
}

TL_AVX2 static void
row_displaced_avx2(share *t, double y)
{
	row_displaced_body(t, y);
}

static void
row_displaced(share *t, double y)
{
	row_displaced_body(t, y);
}

void
lv_error_row(share *t, int J)
{
	double y = J / t->s->step;

	if (t->s->scan)
		lv_scan_undisplaced(t, J);
	else if (t->s->avx2)
		row_displaced_avx2(t, y);
	else
		row_displaced(t, y);
}
