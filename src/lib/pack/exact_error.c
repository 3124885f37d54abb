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
 * Which variant serves which case (lv_error_rows picks, a batch of DEM
 * rows at a time; each is exact and they agree bit for bit where more
 * than one applies):
 *
 *   undisplaced levels (QEM-1D), step <= SCAN_MAXSTEP
 *       undisplaced_scan.c: every triangle has integer vertices and
 *       level, upright or 45-degree edges, so its chord along a DEM row is
 *       whole DEM columns, found once per row, scale, kind and centre row
 *       and shifted along it: no per-triangle geometry; each triangle's
 *       plane set up once for the batch's rows. The common case.
 *   displaced levels (QEM-3D), a batch whose rows of positions all
 *   have offsets 0 (level 0; step <= SCAN_MAXSTEP)
 *       undisplaced_scan.c too: the positions are the grid's exactly
 *       (batch_flat; t_displaced_scan).
 *   displaced levels (QEM-3D), other batches
 *       the batched path here: tri_row's general chord of a triangle
 *       with displaced (float32 offset) corners, closed with tolerances
 *       EPS, for four (triangle, DEM row) pairs at once (batch_flush:
 *       the same operations lane by lane), each triangle gathered once
 *       for the batch's rows (batch_tri), its vertices read by rows of
 *       each scale's positions (vrows), each position found once per
 *       scale (vc_fill); the loops visit every diamond a row can reach
 *       (h + margin). tri_row a triangle at a time is the reference
 *       (TL_EXACT_REF, for the tests: t_displaced_scan).
 *   undisplaced levels coarser than SCAN_MAXSTEP
 *       tri_row: there the integer scan's argument that EPS changes
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

/* The batched path, a batch of DEM rows at once (level_crew.c's
 * BATCH): each triangle a row body would visit is found, rejected or
 * gathered once for all the batch's rows, as tri_row gathers one (its
 * rejections, its vertices), and each (triangle, row) pair it measures
 * goes to a lane; four lanes are set up together, tri_row's chord and
 * plane lane by lane in v4d (the same operations in the same order, each
 * with its row's y: the same bits), then swept one by one by sweep. Its
 * divisions are four lanes' at once, and the set-up has no branch to
 * mispredict. A pair is measured when tri_row, called by the row body of
 * its row, would measure it: the rows' loops and rejections are kept as
 * tests per row (rowset). Errors raise a diamond's local error or a
 * block's base error by max, whose order does not matter (a float's
 * rounding keeps order); -1 (nothing measured) raises nothing, as local
 * and base errors start at 0. */
typedef struct {
	double x[3][4], y[3][4], z[3][4]; /* the lanes' vertices */
	double yr[4];       /* the lanes' rows (level units) */
	double inv;         /* 1 / step */
	const double *dd[4]; /* and their samples */
	float *acc[4];      /* a diamond's local error to raise, or NULL */
	double *base[4];    /* else a block's base error */
	int n;
} batch;

/* The batch's DEM rows J0 .. J0 + n - 1 as the row bodies see each: its
 * level row y, its samples, the centre rows of each scale (c0 .. c1) and
 * the leaf rows (r0 .. r1) its loops visit, unclamped. */
typedef struct {
	int J0, n;
	double y[BATCH];
	const double *dd[BATCH];
	long c0[8][BATCH], c1[8][BATCH];
	long r0[BATCH], r1[BATCH];
} rowset;

static inline __attribute__((always_inline)) v4d
v4min(v4d a, v4d b)
{
	v4d r;

	for (int k = 0; k < 4; k++)
		r[k] = a[k] < b[k] ? a[k] : b[k];
	return r;
}

/* m ? a : b, lane by lane, for masks of all ones or zeros */
static inline __attribute__((always_inline)) v4d
v4sel(v4l m, v4d a, v4d b)
{
	return (v4d)((m & (v4l)a) | (~m & (v4l)b));
}

static inline __attribute__((always_inline)) v4d
v4set(double a)
{
	return (v4d){ a, a, a, a };
}

/* tri_row's chord (xl, xr) of the lanes' triangles at rows yv: edge a-b
 * crossed, a level edge on the row whole. */
static inline __attribute__((always_inline)) void
chord_edge(v4d ax, v4d ay, v4d bx, v4d by, const v4d *yp, v4d *xl,
    v4d *xr)
{
	const v4d eps = v4set(EPS), yv = *yp;
	v4d f, x;
	v4l lev = v4abs(by - ay) <= eps, on = v4abs(yv - ay) <= eps;
	v4l in, ml, ms;

	f = (yv - ay) / (by - ay); /* level lanes: not used */
	in = ~((f < v4set(-EPS)) | (f > v4set(1 + EPS)));
	f = v4min(v4set(1), v4max(v4set(0), f));
	x = ax + f * (bx - ax);
	ml = lev & on, ms = ~lev & in;
	*xl = v4sel(ml, v4min(*xl, v4min(ax, bx)),
	    v4sel(ms, v4min(*xl, x), *xl));
	*xr = v4sel(ml, v4max(*xr, v4max(ax, bx)),
	    v4sel(ms, v4max(*xr, x), *xr));
}

/* The chord of all three edges, in tri_row's order. */
static inline __attribute__((always_inline)) void
batch_chord(const v4d X[3], const v4d Y[3], const v4d *yp, v4d *xl,
    v4d *xr)
{
	*xl = v4set(INFINITY), *xr = v4set(-INFINITY);
	for (int k = 0; k < 3; k++)
		chord_edge(X[k], Y[k], X[(k + 1) % 3], Y[(k + 1) % 3], yp, xl,
		    xr);
}

static inline __attribute__((always_inline)) void
batch_flush(share *sh, batch *b)
{
	const state *s = sh->s;
	v4d X[3], Y[3], Z[3], xl, xr, n0, n1, n2, v, yv;
	double XL[4], XR[4], N2[4], DZ[4], Z0[4], lo[4], hi[4];

	for (int k = 0; k < 3; k++) {
		memcpy(&X[k], b->x[k], sizeof X[k]);
		memcpy(&Y[k], b->y[k], sizeof Y[k]);
		memcpy(&Z[k], b->z[k], sizeof Z[k]);
	}
	memcpy(&yv, b->yr, sizeof yv);
	batch_chord(X, Y, &yv, &xl, &xr);
	n0 = (Y[1] - Y[0]) * (Z[2] - Z[0]) - (Z[1] - Z[0]) * (Y[2] - Y[0]);
	n1 = (Z[1] - Z[0]) * (X[2] - X[0]) - (X[1] - X[0]) * (Z[2] - Z[0]);
	n2 = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
	memcpy(XL, &xl, sizeof XL), memcpy(XR, &xr, sizeof XR);
	memcpy(N2, &n2, sizeof N2);
	v = -n0 / n2, memcpy(DZ, &v, sizeof DZ);
	v = Z[0] - (n1 * (yv - Y[0]) - n0 * X[0]) / n2;
	memcpy(Z0, &v, sizeof Z0);
	v = (xl - v4set(EPS)) * s->step, memcpy(lo, &v, sizeof lo);
	v = (xr + v4set(EPS)) * s->step, memcpy(hi, &v, sizeof hi);
	for (int k = 0; k < b->n; k++) {
		long i0, i1;
		double err;
		if (XL[k] > XR[k] || N2[k] == 0)
			continue;
		i0 = iceil(lo[k]), i1 = ifloor(hi[k]);
		if (i0 < s->d0)
			i0 = s->d0;
		if (i1 > s->dend - 1)
			i1 = s->dend - 1;
		err = sweep(b->dd[k], s->d0, i0, i1, Z0[k], DZ[k], b->inv);
		if (b->acc[k] != NULL) {
			if (err > *b->acc[k])
				*b->acc[k] = (float)err;
		} else if (err > *b->base[k])
			*b->base[k] = err;
	}
	b->n = 0;
}

/* The three rows of vertices a centre row's triangles use, cy - h, cy
 * and cy + h (a leaf row's: cj, cj + 1), each found when first asked
 * for: vertex_at's positions and heights, by row. */
typedef struct {
	int cy, h, hk, got[3];
	const double *x[3], *y[3];
	const float *z[3];
} vrows;

static inline __attribute__((always_inline)) void
vrows_init(vrows *R, int cy, int h, int hk)
{
	R->cy = cy, R->h = h, R->hk = hk;
	R->got[0] = R->got[1] = R->got[2] = 0;
}

/* Row ri of R (grid row cy + (ri - 1) h, on the grid): vertex_at's. */
static void
vrows_fill(share *sh, vrows *R, int ri)
{
	const state *s = sh->s;
	int hk = R->hk, gj = R->cy + (ri - 1) * R->h, k = gj >> hk;
	int r = k & (VC_ROWS - 1);

	if (sh->vc[hk].tag[r] != k)
		vc_fill(sh, hk, k);
	R->x[ri] = sh->vc[hk].x + (size_t)r * sh->vc[hk].n;
	R->y[ri] = sh->vc[hk].y + (size_t)r * sh->vc[hk].n;
	R->z[ri] = s->z + slot(s, gj);
	R->got[ri] = 1;
}

/* The batch's rows j0 .. j1 (clamped) whose y lies in [a, b]: y = J /
 * step and a x step are exact (step is a power of 2), so y >= a is
 * J >= a x step. The callers test each row again as tri_row does. */
static inline __attribute__((always_inline)) void
rows_within(const state *s, const rowset *rs, double a, double b, int *j0,
    int *j1)
{
	long lo = iceil(a * s->step) - rs->J0, hi = ifloor(b * s->step) -
	    rs->J0;

	if (lo > *j0)
		*j0 = lo > rs->n ? rs->n : (int)lo;
	if (hi < *j1)
		*j1 = hi < -1 ? -1 : (int)hi;
}

/* Triangle t (its vertices on R's rows, from the centre or leaf row c,
 * visited by row j when cv0[j] <= c <= cv1[j]) into the batch for every
 * row whose body would visit it and whose tri_row would not reject it
 * before its chord (then it measures nothing): gathered once. */
static inline __attribute__((always_inline)) void
batch_tri(share *sh, batch *b, const rowset *rs, const int t[3][2],
    vrows *R, long c, const long *cv0, const long *cv1, float *acc,
    double *base)
{
	const state *s = sh->s;
	double p[3][3], ymin = INFINITY, ymax = -INFINITY, ya, yb;
	int lo = t[0][1], hi = t[0][1], j0 = 0, j1 = rs->n - 1;

	for (int k = 1; k < 3; k++)
		lo = t[k][1] < lo ? t[k][1] : lo, hi = t[k][1] > hi ? t[k][1] : hi;
	ya = lo - s->margin - EPS, yb = hi + s->margin + EPS;
	rows_within(s, rs, ya, yb, &j0, &j1);
	if (j0 > j1)
		return;
	for (int k = 0; k < 3; k++) {
		int gi = t[k][0], ri;
		if (!on_grid(s, t[k]))
			return;
		/* its row, cy + (ri - 1) h */
		ri = (t[k][1] - R->cy + R->h) >> R->hk;
		if (!R->got[ri])
			vrows_fill(sh, R, ri);
		p[k][0] = R->x[ri][(gi - s->c0) >> R->hk];
		p[k][1] = R->y[ri][(gi - s->c0) >> R->hk];
		p[k][2] = R->z[ri][gi - s->c0];
		ymin = dmin(ymin, p[k][1]), ymax = dmax(ymax, p[k][1]);
	}
	rows_within(s, rs, ymin - EPS, ymax + EPS, &j0, &j1);
	for (int j = j0; j <= j1; j++) {
		double y = rs->y[j];
		int n = b->n;
		if (c < cv0[j] || c > cv1[j] || y < ya || y > yb ||
		    y < ymin - EPS || y > ymax + EPS)
			continue;
		for (int k = 0; k < 3; k++)
			b->x[k][n] = p[k][0], b->y[k][n] = p[k][1],
			    b->z[k][n] = p[k][2];
		b->yr[n] = y, b->dd[n] = rs->dd[j];
		b->acc[n] = acc, b->base[n] = base;
		if (++b->n == 4)
			batch_flush(sh, b);
	}
}

/* The batch's diamonds of scale h, as row_diamonds_body visits them for
 * each row: a centre row's square (odd rows) and edge diamonds together,
 * so that its rows of vertices are found once. */
static inline __attribute__((always_inline)) void
batch_diamonds(share *t, const rowset *rs, int h, int hk, batch *b)
{
	state *s = t->s;
	const long *cv0 = rs->c0[hk], *cv1 = rs->c1[hk];

	for (long c = cv0[0] > 0 ? cv0[0] : 0; c <= cv1[rs->n - 1] &&
	    c * h < s->Q; c++) {
		long cy = c * h;
		vrows R;
		vrows_init(&R, (int)cy, h, hk);
		for (int edge = (c & 1) == 0; edge < 2; edge++) {
			long x0 = edge && (c & 1) ? 0 : h;
			if (t->lo > x0) /* the first centre in the share */
				x0 += (t->lo - x0 + 2 * h - 1) / (2 * h) *
				    (2 * h);
			for (long cx = x0; cx < s->cend && cx < t->hi;
			    cx += 2 * h) {
				int tri[2][3][2];
				int nt = bt_diamond((int)cx, (int)cy, tri);
				float *acc = &s->acc[eslot(s, (int)cy) +
				    (cx - s->c0)];
				for (int k = 0; k < nt; k++)
					batch_tri(t, b, rs, tri[k], &R, c, cv0,
					    cv1, acc, NULL);
			}
		}
	}
}

/* A cell's two finest triangles, diagonal by the parity of ci + cj as
 * in the bintree. */
static inline __attribute__((always_inline)) void
leaf_tris(int ci, int cj, int t[2][3][2])
{
	int a[2] = { ci, cj }, b[2] = { ci + 1, cj };
	int c[2] = { ci + 1, cj + 1 }, d[2] = { ci, cj + 1 };

	if ((ci + cj) % 2 == 0) {
		memcpy(t[0][0], a, 8), memcpy(t[0][1], b, 8);
		memcpy(t[0][2], c, 8), memcpy(t[1][0], a, 8);
		memcpy(t[1][1], c, 8), memcpy(t[1][2], d, 8);
	} else {
		memcpy(t[0][0], a, 8), memcpy(t[0][1], b, 8);
		memcpy(t[0][2], d, 8), memcpy(t[1][0], b, 8);
		memcpy(t[1][1], c, 8), memcpy(t[1][2], d, 8);
	}
}

/* The batch's leaves, as row_leaves_body visits them for each row. */
static inline __attribute__((always_inline)) void
batch_leaves(share *sh, const rowset *rs, batch *bt)
{
	const state *s = sh->s;
	int lo = leaf_lo(sh), hi = leaf_hi(sh);

	for (long cj = rs->r0[0] > 0 ? rs->r0[0] : 0; cj <= rs->r1[rs->n - 1]
	    && cj < s->Q - 1; cj++) {
		vrows R;
		vrows_init(&R, (int)cj, 1, 0);
		for (int ci = lo; ci < hi; ci++) {
			int t[2][3][2];
			double *base = base_at(sh, (int)cj, ci);
			leaf_tris(ci, (int)cj, t);
			for (int k = 0; k < 2; k++)
				batch_tri(sh, bt, rs, t[k], &R, cj, rs->r0,
				    rs->r1, NULL, base);
		}
	}
}

/* The batch's rows: its set-up and every scale, inlined into both copies
 * below (the AVX2 one and the plain one differ only in their target). */
static inline __attribute__((always_inline)) void
batch_body(share *t, const rowset *rs)
{
	batch b;

	memset(&b, 0, sizeof b);
	b.inv = 1 / t->s->step;
	for (int h = 1, hk = 0; h <= BT_MAXH; h *= 2, hk++)
		batch_diamonds(t, rs, h, hk, &b);
	batch_leaves(t, rs, &b);
	if (b.n > 0)
		batch_flush(t, &b);
}

TL_AVX2 static void
rows_displaced_avx2(share *t, const rowset *rs)
{
	batch_body(t, rs);
}

static void
rows_displaced(share *t, const rowset *rs)
{
	batch_body(t, rs);
}

/* Raises the local errors of every diamond of scale h and one kind that
 * the DEM row (level row y) crosses, by tri_row. Square diamonds are
 * centred on odd multiples of h in both axes; edge diamonds on points
 * with exactly one odd multiple: |x - cx| + |y - cy| <= h. */
static void
row_diamonds(share *t, double y, int h, int hk, int edge)
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

/* Raises the base errors of the blocks whose finest triangles the DEM
 * row crosses, by tri_row. */
static void
row_leaves(share *sh, double y)
{
	const state *s = sh->s;
	double mg = s->L->displaced ? 1 : EPS;
	long r0 = (long)floor(y - mg), r1 = (long)floor(y + mg);
	int lo = leaf_lo(sh), hi = leaf_hi(sh);

	for (long cj = r0 > 0 ? r0 : 0; cj <= r1 && cj < s->Q - 1; cj++) {
		for (int ci = lo; ci < hi; ci++) {
			int t[2][3][2];
			double *base = base_at(sh, (int)cj, ci);
			leaf_tris(ci, (int)cj, t);
			for (int k = 0; k < 2; k++) {
				double err = tri_row(sh, t[k], y, 0);
				if (err > *base)
					*base = err;
			}
		}
	}
}

/* Every diamond and leaf the DEM row (level row y) crosses, by tri_row
 * one at a time: the reference (state.ref), and undisplaced levels
 * coarser than SCAN_MAXSTEP. The batched path's rowset keeps these
 * loops' bounds. */
static void
row_reference(share *t, double y)
{
	for (int h = 1, hk = 0; h <= BT_MAXH; h *= 2, hk++) {
		row_diamonds(t, y, h, hk, 0);
		row_diamonds(t, y, h, hk, 1);
	}
	row_leaves(t, y);
}

/* The rowset of DEM rows J0 .. J1-1, their samples dd apart from dd0:
 * row_diamonds' and row_leaves' bounds, by the same operations. */
static void
rowset_init(const state *s, rowset *rs, int J0, int J1, const double *dd0,
    size_t stride)
{
	rs->J0 = J0, rs->n = J1 - J0;
	for (int j = 0; j < rs->n; j++) {
		double y = (J0 + j) / s->step;
		rs->y[j] = y, rs->dd[j] = dd0 + (size_t)j * stride;
		for (int h = 1, hk = 0; h <= BT_MAXH; h *= 2, hk++) {
			double reach = h + s->margin;
			rs->c0[hk][j] = (long)ceil((y - reach) / h);
			rs->c1[hk][j] = (long)floor((y + reach) / h);
		}
		rs->r0[j] = (long)floor(y - 1), rs->r1[j] = (long)floor(y + 1);
	}
}

/* Level row gj's offsets all 0 (both signs of 0) in the columns t's
 * triangles reach (centres in [lo, hi), vertices h <= 64 away; leaves
 * 1), found once per row and share. */
static int
flat_row(share *t, int gj)
{
	const state *s = t->s;
	int *f = &t->flat[gj & (RINGV - 1)];
	int a = t->lo - BT_CELLS - s->c0, b = t->hi + BT_CELLS - s->c0;

	if (*f == gj + 1 || *f == -(gj + 1))
		return *f > 0;
	a = a > 0 ? a : 0, b = b < s->P ? b : s->P;
	{
		const float *x = s->ox + slot(s, gj), *y = s->oy + slot(s, gj);
		int k = a;
		while (k < b && x[k] == 0 && y[k] == 0)
			k++;
		*f = k == b ? gj + 1 : -(gj + 1);
	}
	return *f > 0;
}

/* Every row of positions the batch's rows J0 .. J1-1 may reach (centres
 * h + margin away, their vertices h further: 130 rows) has offsets all 0:
 * then every position is its grid point exactly (vertex: gi + 0 / sx /
 * step is gi), the level's geometry an undisplaced one, and the integer
 * scan raises tri_row's errors bit for bit (undisplaced_scan.c), its
 * wider reach only visiting triangles the row misses. Level 0 of QEM-3D
 * is so. */
static int
batch_flat(share *t, int J0, int J1)
{
	const state *s = t->s;
	int g0 = (int)floor(J0 / s->step) - 2 * BT_MAXH - 2;
	int g1 = (int)ceil((J1 - 1) / s->step) + 2 * BT_MAXH + 2;

	if (s->step > SCAN_MAXSTEP)
		return 0;
	g0 = g0 > s->r0 ? g0 : s->r0;
	g1 = g1 < s->loaded - 1 ? g1 : s->loaded - 1;
	g1 = g1 < s->Q - 1 ? g1 : s->Q - 1;
	for (int gj = g0; gj <= g1; gj++)
		if (!flat_row(t, gj))
			return 0;
	return 1;
}

void
lv_error_rows(share *t, int J0, int J1)
{
	const state *s = t->s;
	size_t stride = (size_t)(s->dend - s->d0 + 1);
	rowset rs;

	assert(J1 - J0 <= BATCH);
	if (J1 <= J0)
		return;
	if (s->scan || s->ref || !s->L->displaced || batch_flat(t, J0, J1)) {
		if (s->scan || (s->L->displaced && !s->ref)) {
			lv_scan_undisplaced(t, J0, J1);
			return;
		}
		for (int J = J0; J < J1; J++) {
			t->dd = s->dd + (size_t)(J - J0) * stride;
			row_reference(t, J / s->step);
		}
		return;
	}
	rowset_init(s, &rs, J0, J1, s->dd, stride);
	if (s->avx2)
		rows_displaced_avx2(t, &rs);
	else
		rows_displaced(t, &rs);
}
