/* undisplaced_scan.c - the kernel's integer scan: the local and base
 * errors of an undisplaced level, by whole DEM columns (see
 * exact_error.c for when it serves, level_impl.h).
 *
 * tri_row (exact_error.c) finds, for one DEM row and one triangle, the chord
 * through the triangle in double-precision geometry with tolerances EPS,
 * then the largest |plane - DEM| over the valid samples on it. On an
 * undisplaced level every triangle of the 4-8 hierarchy (and every leaf)
 * has integer vertices and edges that are level, upright or at 45
 * degrees, and a DEM row lies at y = J / step: the chord's ends are then
 * whole DEM columns, exactly those tri_row's ceil/floor produce (its
 * divisions are by powers of two, hence exact, and with step <=
 * SCAN_MAXSTEP no tolerance reaches the next row or column: 1/step and
 * f's resolution 1/(step x 128) stay far above EPS, EPS x step far below
 * one column). So the chords are found once per row, scale, kind and
 * centre row, relative to the centre, and each diamond only adds its
 * column. The value measured is tri_row's own: the same plane normal
 * from the same vertices in the same order, the same z0 and slope, the
 * same z0 + dz * x - DEM in doubles (x = i / step, a power of two, is
 * i times 1/step exactly), the same maximum (the order of a maximum
 * without NaN does not matter; an invalid sample is NaN here and never
 * wins).
 *
 * The rows come a batch at a time (BATCH, lv_error_rows): the plane's
 * normal depends on the triangle, not on the row, so each triangle's is
 * found once per centre for every row of the batch through it, and only
 * z0, which the row's y enters, per row (batch_body). */
#include "pack/level_impl.h"

#include <math.h>
#include <stdlib.h>

/* A triangle relative to its centre (cx, cy), whatever the DEM row: the
 * row-free part of tri_row's set-up. */
typedef struct {
	int ok;             /* its rows are on the grid */
	int ox[3], oy[3];   /* its vertices less the centre, in order */
	int wx[3];          /* ox less the window's c0: where, in the
	                     * window's rows, centre cx's vertices are */
	int xmin, xmax;     /* of ox */
	const float *zr[3]; /* the vertices' rows of heights */
	/* tri_row's p[k] - p[0] in x and y, its normal's z (n[2]): whole
	 * numbers and their differences, exact */
	double d1x, d1y, d2x, d2y, n2;
	double rn2;         /* 1 / n2 when n2 is a power of 2, else 0 */
	double inv;         /* 1 / step, exact: found once, not per centre */
} tmpl;

/* tri_row's chord, in whole DEM columns: the row r (DEM rows, less cy x
 * step) against each edge; level edges count when the row is on them.
 * Whether the row crosses t; its columns less cx x step in lo, hi. */
static int
chord(const tmpl *t, long S, long r, long *lo, long *hi)
{
	long X[3], Y[3], ymin, ymax, xl = 0, xr = 0;
	int any = 0;

	for (int k = 0; k < 3; k++)
		X[k] = t->ox[k] * S, Y[k] = t->oy[k] * S;
	ymin = ymax = Y[0];
	for (int k = 1; k < 3; k++)
		ymin = Y[k] < ymin ? Y[k] : ymin, ymax = Y[k] > ymax ? Y[k] : ymax;
	if (r < ymin || r > ymax)
		return 0;
	for (int k = 0; k < 3; k++) {
		long ax = X[k], ay = Y[k], bx = X[(k + 1) % 3], by = Y[(k + 1) % 3];
		long x0, x1;
		if (ay == by) {
			if (r != ay)
				continue;
			x0 = ax < bx ? ax : bx, x1 = ax < bx ? bx : ax;
		} else {
			if ((r - ay) * (by > ay ? 1 : -1) < 0 ||
			    (by - r) * (by > ay ? 1 : -1) < 0)
				continue;
			/* slopes 0 or +-1: (r - ay) (bx - ax) / (by - ay)
			 * exactly, without a division */
			assert(bx == ax || bx - ax == by - ay ||
			    bx - ax == ay - by);
			x0 = x1 = ax + (bx == ax ? 0 : bx - ax == by - ay ?
			    r - ay : ay - r);
		}
		if (!any || x0 < xl)
			xl = x0;
		if (!any || x1 > xr)
			xr = x1;
		any = 1;
	}
	*lo = xl, *hi = xr;
	return any;
}

/* The template of triangle tri about (cx, cy); its rows of heights are
 * set once a DEM row crosses it (the_rows). */
static void
make_tmpl(const state *s, tmpl *t, const int tri[3][2], int cx, int cy)
{
	t->ok = 1;
	for (int k = 0; k < 3; k++) {
		t->ox[k] = tri[k][0] - cx, t->oy[k] = tri[k][1] - cy;
		t->wx[k] = t->ox[k] - s->c0;
		if (tri[k][1] < 0 || tri[k][1] >= s->Q)
			t->ok = 0;
	}
	if (!t->ok)
		return;
	t->xmin = t->xmax = t->ox[0];
	for (int k = 1; k < 3; k++) {
		t->xmin = t->ox[k] < t->xmin ? t->ox[k] : t->xmin;
		t->xmax = t->ox[k] > t->xmax ? t->ox[k] : t->xmax;
	}
	t->d1x = (double)tri[1][0] - tri[0][0];
	t->d1y = (double)tri[1][1] - tri[0][1];
	t->d2x = (double)tri[2][0] - tri[0][0];
	t->d2y = (double)tri[2][1] - tri[0][1];
	t->n2 = t->d1x * t->d2y - t->d1y * t->d2x;
	t->inv = 1 / s->step;
	/* x / n2 is x x (1 / n2), rounded once, when n2 is a power of 2
	 * (every triangle here: legs h or 2h, or 1 for leaves) */
	{
		int ex;
		t->rn2 = t->n2 != 0 && fabs(frexp(t->n2, &ex)) == 0.5 ?
		    1 / t->n2 : 0;
	}
}

/* A DEM row's chord through a triangle (chord), and what tri_row takes
 * from the row: its y less p[0][1] (whole numbers over a power of 2,
 * exact) */
typedef struct {
	const double *dd;   /* the row's samples: DEM column i at i - d0 */
	long lo, hi;        /* its columns less cx x step */
	long wlo;           /* lo less the window's d0 */
	double ym;
	double xlo;         /* lo x inv */
} brow;

/* A triangle and the batch's rows through it: ns short chords (at most
 * SHORT samples, n2 a power of 2), measured LANES centres at a time; nl
 * others, a centre at a time. */
typedef struct {
	tmpl t;
	int ns, nl;
	brow s[BATCH], l[BATCH];
} btri;

/* Four centres at once: short chords (every one of level 0's, most of
 * level 1's) make the set-up the cost, and its arithmetic is the same
 * for every centre of a template: each lane does tri_row's and sweep's
 * operations in their order (v4d, level_impl.h). */
#define LANES 4
typedef int v4i __attribute__((vector_size(16)));
typedef float v4f __attribute__((vector_size(16)));
/* chords of fewer samples than this go LANES centres at a time; longer
 * ones are swept along the row (sweep_into), which loads contiguously
 * but sets up a centre at a time: up to here (levels 1 to 3's mid
 * scales) the lanes' set-up shared by four outweighs their loads a
 * sample at a time (perf stat, N48W125; with the set-up once per batch,
 * 16 to 64 measured the same, scripts/bench-kernel) */
#define SHORT 28

/* The heights of vertex r of template t at centres cx, cx + stride, ...
 * (LANES of them): vectors built from scalars, not through memory (store
 * forwarding). */
static inline __attribute__((always_inline)) v4d
heights4(const tmpl *t, int r, int cx, int stride)
{
	const float *z = t->zr[r] + t->wx[r] + cx;

	return (v4d){ z[0], z[stride], z[2 * stride], z[3 * stride] };
}

/* The lanes' sample o of their chords (q0 .. q3: the chords' first
 * samples) against their planes z + dz x, raising w. */
static inline __attribute__((always_inline)) v4d
sample4(const double *q0, const double *q1, const double *q2,
    const double *q3, long o, v4d x, v4d z, v4d dz, v4d w)
{
	v4d v = { q0[o], q1[o], q2[o], q3[o] };

	return v4max(v4abs(z + dz * x - v), w);
}

/* b's triangle at centres cx, cx + stride, ... (LANES of them, cd as
 * doubles) along each of its short rows, every chord inside the DEM
 * row, raising w: tri_row's plane lane by lane, set up once for all the
 * rows (heights, e1, e2, n0, n1, dz and n0 x p00), its z0 per row (the
 * multiplying branch: n2 a power of 2), then sweep's samples. The
 * maximum keeps w where d is NaN (an invalid sample), as sweep does. */
static inline __attribute__((always_inline)) v4d
btri_at4(const state *s, const btri *b, int cx, int stride, v4d cd, v4d w)
{
	const tmpl *t = &b->t;
	v4d z0, z1, z2, e1, e2, n0, n1, n0p, dz;
	long S = (long)s->step, c0 = (long)cx * S, d = (long)stride * S;
	double inv = t->inv, rn2 = t->rn2;

	z0 = heights4(t, 0, cx, stride);
	z1 = heights4(t, 1, cx, stride);
	z2 = heights4(t, 2, cx, stride);
	e1 = z1 - z0, e2 = z2 - z0;
	n0 = t->d1y * e2 - e1 * t->d2y;
	n1 = e1 * t->d2x - t->d1x * e2;
	assert(rn2 != 0);
	dz = -n0 * rn2;
	n0p = n0 * (cd + (double)t->ox[0]);
	for (int j = 0; j < b->ns; j++) {
		const brow *r = &b->s[j];
		const double *q0, *q1, *q2, *q3;
		/* x: the columns times inv, (c S + lo) / S, stepped by inv:
		 * every term a whole number over a power of 2, so c + lo / S
		 * is that exactly, and so is each step (see sweep) */
		v4d z = z0 - (n1 * r->ym - n0p) * rn2, x = cd + r->xlo;
		long n = r->hi - r->lo;
		/* the lanes' chords stride x S apart in the row */
		q0 = r->dd + (c0 + r->wlo), q1 = q0 + d;
		q2 = q1 + d, q3 = q2 + d;
		/* the first three samples unrolled (most chords here are 1
		 * to 3 samples: no loop to set up), then the rest */
		w = sample4(q0, q1, q2, q3, 0, x, z, dz, w);
		if (n >= 1)
			x += inv, w = sample4(q0, q1, q2, q3, 1, x, z, dz, w);
		if (n >= 2)
			x += inv, w = sample4(q0, q1, q2, q3, 2, x, z, dz, w);
		for (long o = 3; o <= n; o++)
			x += inv, w = sample4(q0, q1, q2, q3, o, x, z, dz, w);
	}
	return w;
}

/* b's triangle at centre cx along its rows a (na of them) and l (nl),
 * each chord clipped to the window's DEM columns: tri_row's plane set up
 * once (divisions by n2 multiplications by 1 / n2 where that is exact),
 * its z0 per row, sweep's samples into one maximum; -1 when none. */
static inline __attribute__((always_inline)) double
btri_at1(const state *s, const tmpl *t, const brow *a, int na,
    const brow *l, int nl, int cx)
{
	double z0, z1, z2, e1, e2, n0, n1, n0p, p00, dz, w;
	long S = (long)s->step, last = s->dend - 1;
	v4d m = { -1, -1, -1, -1 };

	z0 = t->zr[0][cx + t->wx[0]];
	z1 = t->zr[1][cx + t->wx[1]];
	z2 = t->zr[2][cx + t->wx[2]];
	e1 = z1 - z0, e2 = z2 - z0;
	n0 = t->d1y * e2 - e1 * t->d2y;
	n1 = e1 * t->d2x - t->d1x * e2;
	p00 = cx + t->ox[0];
	n0p = n0 * p00;
	dz = t->rn2 != 0 ? -n0 * t->rn2 : -n0 / t->n2;
	for (int j = 0; j < na + nl; j++) {
		const brow *r = j < na ? &a[j] : &l[j - na];
		long i0 = (long)cx * S + r->lo, i1 = (long)cx * S + r->hi;
		double z;
		i0 = i0 > s->d0 ? i0 : s->d0;
		i1 = i1 < last ? i1 : last;
		if (i0 > i1)
			continue;
		if (t->rn2 != 0)
			z = z0 - (n1 * r->ym - n0p) * t->rn2;
		else
			z = z0 - (n1 * r->ym - n0p) / t->n2;
		sweep_into(r->dd, s->d0, i0, i1, z, dz, t->inv, &m);
	}
	w = m[0];
	for (int k = 1; k < LANES; k++)
		w = m[k] > w ? m[k] : w;
	return w;
}

/* Where an error goes: a diamond's local error (a float per centre
 * column) or, for leaves, its block's base error (a double per block
 * column). The order of a maximum does not matter. */
typedef struct {
	float *acc;   /* a window row: level column cx at cx - c0 */
	int c0;
	double *base; /* a block row's: block column b at b - b0 */
	int b0;
} sink;

static inline __attribute__((always_inline)) void
raise_at(const sink *o, int cx, double err)
{
	/* a maximum, not a branch (which the data decide, and often
	 * mispredict): err > was exactly when (float)err > was or both are
	 * the same float (rounding to a float keeps the order), and a NaN
	 * is never chosen either way */
	if (o->acc != NULL) {
		float *a = &o->acc[cx - o->c0], was = *a, f = (float)err;
		*a = f > was ? f : was;
	} else {
		double *b = &o->base[cx / BT_CELLS - o->b0], was = *b;
		*b = err > was ? err : was;
	}
}

/* A block's base error gathered in a register while a template of
 * leaves scans: its cells raise one double per 128 of them, which
 * through memory is a chain of dependent loads and stores. Stored when
 * the block changes and when the scan ends; a maximum's order does not
 * matter and no error is NaN, so the base ends as the errors raising it
 * one by one would leave it. */
typedef struct {
	const sink *o;
	int blk;      /* the block column gathered in m; -1: none yet */
	v4d m;
} gather;

static inline __attribute__((always_inline)) void
gather_flush(gather *g)
{
	double w = g->m[0], *b;

	if (g->blk < 0)
		return;
	for (int k = 1; k < LANES; k++)
		w = g->m[k] > w ? g->m[k] : w;
	b = &g->o->base[g->blk - g->o->b0];
	*b = w > *b ? w : *b;
}

/* err's lanes: errors of cells in cx's block */
static inline __attribute__((always_inline)) void
gather_raise(gather *g, int cx, v4d err)
{
	int blk = cx / BT_CELLS;

	if (blk != g->blk) {
		gather_flush(g);
		g->blk = blk, g->m = err;
	} else
		g->m = v4max(err, g->m);
}

/* One centre's error, or LANES of them (stride apart) from a vector;
 * leaves: o is a block row's base errors (a constant: each kind has its
 * own copy of the loops, with no test per centre). */
static inline __attribute__((always_inline)) void
raise1(const sink *o, gather *g, int leaves, int cx, double err)
{
	if (!leaves)
		raise_at(o, cx, err);
	else
		gather_raise(g, cx, (v4d){ err, err, err, err });
}

static inline __attribute__((always_inline)) void
raise4(const sink *o, gather *g, int leaves, int cx, int stride, v4d err)
{
	if (!leaves) {
		/* raise_at's maximum, the lanes rounded to floats at once
		 * (as each (float) cast rounds); the centres are apart */
		v4f f = __builtin_convertvector(err, v4f);
		float *a = &o->acc[cx - o->c0];
#pragma GCC unroll 4
		for (int k = 0; k < LANES; k++) {
			float was = a[k * stride];
			a[k * stride] = f[k] > was ? f[k] : was;
		}
	} else if (cx / BT_CELLS == (cx + (LANES - 1) * stride) / BT_CELLS)
		gather_raise(g, cx, err);
	else
		for (int k = 0; k < LANES; k++)
			raise1(o, g, leaves, cx + k * stride, err[k]);
}

/* The centres first, first + stride, ... below end whose template t's
 * vertices are in the window: end lowered, first raised by whole strides. */
static inline void
window(const state *s, const tmpl *t, int *first, int *end, int stride)
{
	if (*end > s->cend - t->xmax)
		*end = s->cend - t->xmax;
	if (*first < s->c0 - t->xmin)
		*first += (s->c0 - t->xmin - *first + stride - 1) / stride *
		    stride;
}

/* A DEM row's triangles a batch of rows at once (lv_error_rows' BATCH):
 * a triangle's plane depends on its centre, not on the row, so it is
 * set up once per centre (or LANES of them) for every row of the batch
 * through it, and only z0, which the row's y enters, is found per row,
 * by tri_row's expression. Errors raise their sinks by max, whose order
 * does not matter (a float's rounding keeps the order), so a centre's
 * rows go together.
 *
 * The nb triangles b (a diamond's or a cell's, of the same centres) at
 * centres first, first + stride, ... below end: LANES at a time where
 * every short chord is inside the DEM row and every vertex of those
 * triangles in the window, their short rows; a centre at a time the
 * long rows, and every row at the centres left. */
static inline __attribute__((always_inline)) void
batch_body(const state *s, const btri *b, int nb, const sink *o, int leaves,
    int first, int end, int stride)
{
	long S = (long)s->step, last = s->dend - 1, lo = 0, hi = 0;
	gather g = { o, -1, { 0, 0, 0, 0 } };
	int va = first, vb = end, cx, any = 0;

	for (int k = 0; k < nb; k++) {
		if (b[k].ns == 0)
			continue;
		window(s, &b[k].t, &va, &vb, stride);
		for (int j = 0; j < b[k].ns; j++) {
			const brow *r = &b[k].s[j];
			lo = !any || r->lo < lo ? r->lo : lo;
			hi = !any || r->hi > hi ? r->hi : hi;
			any = 1;
		}
	}
	while (any && va < vb && (long)va * S + lo < s->d0)
		va += stride;
	for (cx = va; any && cx + (LANES - 1) * stride < vb &&
	    (long)(cx + (LANES - 1) * stride) * S + hi <= last;
	    cx += LANES * stride) {
		v4d cd = __builtin_convertvector((v4i){ 0, 1, 2, 3 } * stride +
		    cx, v4d), w = { -1, -1, -1, -1 };
		for (int k = 0; k < nb; k++)
			if (b[k].ns > 0)
				w = btri_at4(s, &b[k], cx, stride, cd, w);
		raise4(o, &g, leaves, cx, stride, w);
	}
	vb = any ? cx : va;
	/* [va, vb): the short rows done; each triangle's rows at its
	 * centres (window) one by one */
	for (int k = 0; k < nb; k++) {
		const btri *t = &b[k];
		int f = first, e = end;
		if (t->ns + t->nl == 0)
			continue;
		window(s, &t->t, &f, &e, stride);
		for (cx = f; cx < e && cx < va; cx += stride)
			raise1(o, &g, leaves, cx, btri_at1(s, &t->t, t->s,
			    t->ns, t->l, t->nl, cx));
		for (; t->nl > 0 && cx < e && cx < vb; cx += stride)
			raise1(o, &g, leaves, cx, btri_at1(s, &t->t, NULL, 0,
			    t->l, t->nl, cx));
		cx = cx > vb ? cx : vb; /* both first + a multiple of stride */
		for (; cx < e; cx += stride)
			raise1(o, &g, leaves, cx, btri_at1(s, &t->t, t->s,
			    t->ns, t->l, t->nl, cx));
	}
	gather_flush(&g);
}

TL_AVX2 static void
batch_avx2(const state *s, const btri *b, int nb, const sink *o, int first,
    int end, int stride)
{
	if (o->acc != NULL)
		batch_body(s, b, nb, o, 0, first, end, stride);
	else
		batch_body(s, b, nb, o, 1, first, end, stride);
}

static void
batch_plain(const state *s, const btri *b, int nb, const sink *o, int first,
    int end, int stride)
{
	if (o->acc != NULL)
		batch_body(s, b, nb, o, 0, first, end, stride);
	else
		batch_body(s, b, nb, o, 1, first, end, stride);
}

/* The rows of a batch: J0 .. J0 + n - 1, row J's samples at dd[J - J0] */
typedef struct {
	int J0, n;
	double y[BATCH];
	const double *dd[BATCH];
} rows;

/* The nt triangles tri about (cx, cy) at centres first, first + stride,
 * ... below end, along the batch's rows that cross them (the rows
 * between a triangle's lowest and highest vertex, then chord), into the
 * sink mk() makes once a row does. */
typedef void (*sink_fn)(share *sh, int cy, sink *o);

static void
scan_rows(share *sh, const rows *R, const int tri[][3][2], int nt, int cx,
    int cy, sink_fn mk, int first, int end, int stride)
{
	const state *s = sh->s;
	long S = (long)s->step;
	btri b[2];
	int any = 0;
	sink o;

	for (int k = 0; k < nt; k++) {
		btri *t = &b[k];
		long ylo = tri[k][0][1], yhi = ylo;
		t->ns = t->nl = 0;
		make_tmpl(s, &t->t, tri[k], cx, cy);
		if (!t->t.ok || t->t.n2 == 0)
			continue;
		for (int v = 1; v < 3; v++) {
			ylo = tri[k][v][1] < ylo ? tri[k][v][1] : ylo;
			yhi = tri[k][v][1] > yhi ? tri[k][v][1] : yhi;
		}
		for (int j = 0; j < R->n; j++) {
			long J = R->J0 + j, lo, hi;
			brow *r;
			if (J < ylo * S || J > yhi * S ||
			    !chord(&t->t, S, J - (long)cy * S, &lo, &hi))
				continue;
			r = t->t.rn2 != 0 && hi - lo < SHORT ? &t->s[t->ns++] :
			    &t->l[t->nl++];
			r->dd = R->dd[j], r->lo = lo, r->hi = hi;
			r->wlo = lo - s->d0;
			r->ym = R->y[j] - (double)tri[k][0][1];
			r->xlo = lo * t->t.inv;
		}
		if (t->ns + t->nl == 0)
			continue;
		for (int v = 0; v < 3; v++)
			t->t.zr[v] = s->z + slot(s, tri[k][v][1]);
		any = 1;
	}
	if (!any)
		return;
	mk(sh, cy, &o);
	if (s->avx2)
		batch_avx2(s, b, nt, &o, first, end, stride);
	else
		batch_plain(s, b, nt, &o, first, end, stride);
}
static void
diamond_sink(share *sh, int cy, sink *o)
{
	const state *s = sh->s;

	o->acc = &s->acc[eslot(s, cy)], o->c0 = s->c0;
	o->base = NULL, o->b0 = 0;
}

/* row_diamonds (exact_error.c) for the batch's rows: the diamonds along a
 * centre row alternate between two shapes (square diamonds' diagonals
 * alternate; edge diamonds are all alike). Those centred in the share's
 * columns; the centre rows any of the rows reaches (a row that misses a
 * triangle has no chord through it). */
static void
scan_diamonds(share *sh, const rows *R, int h, int edge)
{
	state *s = sh->s;
	double reach = h + s->margin;
	long c0 = (long)ceil((R->y[0] - reach) / h);
	long c1 = (long)floor((R->y[R->n - 1] + reach) / h);
	int end = sh->hi < s->cend ? sh->hi : s->cend;

	for (long c = c0 > 0 ? c0 : 0; c <= c1 && c * h < s->Q; c++) {
		int cy = (int)(c * h), x0;
		if (!edge && (c & 1) == 0)
			continue; /* square centres: odd multiples */
		x0 = edge && (c & 1) ? 0 : h;
		if (x0 >= s->cend)
			continue;
		/* each shape's centres in the share: every other one */
		for (int ph = 0; ph < 2; ph++) {
			int tri[2][3][2], cx = x0 + 2 * h * ph, first = cx;
			int nt = bt_diamond(cx, cy, tri);
			if (first < sh->lo)
				first += (sh->lo - first + 4 * h - 1) /
				    (4 * h) * (4 * h);
			scan_rows(sh, R, tri, nt, cx, cy, diamond_sink, first,
			    end, 4 * h);
		}
	}
}

static void
leaf_sink(share *sh, int cj, sink *o)
{
	int lo = leaf_lo(sh);

	o->acc = NULL, o->c0 = 0;
	o->base = base_at(sh, cj, lo), o->b0 = lo / BT_CELLS;
}

/* row_leaves (exact_error.c) by templates, for the batch's rows: a cell's
 * diagonal alternates with ci + cj. */
static void
scan_leaves(share *sh, const rows *R)
{
	state *s = sh->s;
	int lo = leaf_lo(sh), end = leaf_hi(sh);

	if (lo >= end) /* a share of the halo only */
		return;

	long r0 = (long)floor(R->y[0] - EPS);
	long r1 = (long)floor(R->y[R->n - 1] + EPS);

	for (long cj = r0 > 0 ? r0 : 0; cj <= r1 && cj < s->Q - 1; cj++) {
		for (int ph = 0; ph < 2; ph++) {
			int ci = ph, j = (int)cj;
			int a[2] = { ci, j }, b[2] = { ci + 1, j };
			int c[2] = { ci + 1, j + 1 }, d[2] = { ci, j + 1 };
			int t[2][3][2];
#define SET(v, w) (v)[0] = (w)[0], (v)[1] = (w)[1]
			if ((ci + cj) % 2 == 0) {
				SET(t[0][0], a), SET(t[0][1], b), SET(t[0][2], c);
				SET(t[1][0], a), SET(t[1][1], c), SET(t[1][2], d);
			} else {
				SET(t[0][0], a), SET(t[0][1], b), SET(t[0][2], d);
				SET(t[1][0], b), SET(t[1][1], c), SET(t[1][2], d);
			}
#undef SET
			/* the cells of this parity, every other one */
			scan_rows(sh, R, t, 2, ci, j, leaf_sink,
			    lo + ((lo & 1) != ph), end, 2);
		}
	}
}

void
lv_scan_undisplaced(share *t, int J0, int J1)
{
	const state *s = t->s;
	size_t stride = (size_t)(s->dend - s->d0 + 1);
	rows R;

	assert(J1 > J0 && J1 - J0 <= BATCH);
	R.J0 = J0, R.n = J1 - J0;
	for (int j = 0; j < R.n; j++) {
		R.y[j] = (J0 + j) / s->step;
		R.dd[j] = s->dd + (size_t)j * stride;
	}
	for (int h = 1; h <= BT_MAXH; h *= 2) {
		scan_diamonds(t, &R, h, 0);
		scan_diamonds(t, &R, h, 1);
	}
	scan_leaves(t, &R);
}
