/* fqm0_kernel.c - the quadrics of level 0: for every DEM vertex, the sum
 * of the Garland-Heckbert face quadrics of the triangles around it (M.
 * Garland and P. S. Heckbert, "Surface Simplification Using Quadric Error
 * Metrics", SIGGRAPH 1997; quadric.h), which is the fundamental quadric
 * map of QEM-filtering (F. Löffler and H. Schumann, "QEM-Filtering: A
 * New Technique For Feature-Sensitive Terrain Mesh Simplification",
 * section 3.2; ../shared/papers/qem-filtering-loeffler-schumann.txt)
 * over the DEM's grid in ground metres (georef.h). Declared in fqm0.h.
 *
 * Two variants, one result bit for bit (tests/qem/t_fqm0.c):
 *   fqm_band0 + fqm_row0   the definition: a band of cells, each cell's
 *                          four triangles (both diagonals at half weight,
 *                          so the FQM does not depend on a choice of
 *                          diagonal), summed into each corner; clear, and
 *                          what the tests and the filter's checks use.
 *   fqm_step0(_encode)     the production kernel (dem2fqm, fqm0.c): the
 *                          same arithmetic, operation for operation, two
 *                          cells at a time in SIMD lanes and streamed
 *                          row by row without a band (a band of a wide
 *                          DEM outgrows the caches). */
#include "qem/fqm0.h"

#include <assert.h>
#include <math.h>
#include <string.h>

_Static_assert(FQM_BAND0_DOUBLES == 4 * 6, "4 corners x a[6]");

/* The four triangles of a cell, both diagonals; the corner each one
 * leaves out: a corner's sum is the cell's total minus that triangle. */
static const int celltri[4][3] = {
	{ 0, 1, 2 }, { 0, 2, 3 }, /* diagonal 0-2 */
	{ 0, 1, 3 }, { 1, 2, 3 }, /* diagonal 1-3 */
};
static const int without[4] = { 3, 1, 2, 0 }; /* corner k: all but this */

void
fqm_band0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_ground *m,
    double *band)
{
	/* the metric along rows J and J + 1, taken at each cell's middle
	 * column (one value per row for per-row metrics) */
	double sx0[GEO_MAX_NODES], sx1[GEO_MAX_NODES];
	double y0[GEO_MAX_NODES], y1[GEO_MAX_NODES];

	geo_row_sx(m, J, sx0), geo_row_sx(m, J + 1, sx1);
	geo_row_y(m, J, y0), geo_row_y(m, J + 1, y1);
	for (int i = 0; i + 1 < w; i++) {
		double *out = band + (size_t)i * FQM_BAND0_DOUBLES, I = i + 0.5;
		double a = geo_on_row(m, sx0, I), b = geo_on_row(m, sx1, I);
		double dy = geo_on_row(m, y1, I) - geo_on_row(m, y0, I);
		double p[4][3] = {
			{ -0.5 * a, 0, z0[i] },
			{ 0.5 * a, 0, z0[i + 1] },
			{ 0.5 * b, dy, z1[i + 1] },
			{ -0.5 * b, dy, z1[i] },
		};
		int ok[4] = { v0[i], v0[i + 1], v1[i + 1], v1[i] };
		quadric t[4], total;

		quadric_zero(&total);
		for (int k = 0; k < 4; k++) {
			const int *c = celltri[k];
			quadric_zero(&t[k]);
			if (ok[c[0]] && ok[c[1]] && ok[c[2]])
				quadric_add_triangle(&t[k], p[c[0]], p[c[1]],
				    p[c[2]], 0.5);
			quadric_add(&total, &t[k], 1);
		}
		for (int k = 0; k < 4; k++)
			for (int c = 0; c < 6; c++)
				out[k * 6 + c] = total.a[c] - t[without[k]].a[c];
	}
}

#define BAND FQM_BAND0_DOUBLES

void
fqm_row0(const double *above, const double *below, const float *z,
    const unsigned char *valid, int w, fqm_vertex *out)
{
	for (int i = 0; i < w; i++) {
		fqm_vertex *o = &out[i];
		/* (band, cell, corner) touching vertex i */
		const double *c[4] = {
			above && i > 0 ? above + (size_t)(i - 1) * BAND + 2 * 6 :
			    NULL,
			above && i + 1 < w ? above + (size_t)i * BAND + 3 * 6 :
			    NULL,
			below && i > 0 ? below + (size_t)(i - 1) * BAND + 1 * 6 :
			    NULL,
			below && i + 1 < w ? below + (size_t)i * BAND + 0 * 6 :
			    NULL,
		};
		quadric_zero(&o->q);
		for (int k = 0; k < 4; k++)
			if (c[k] != NULL)
				for (int a = 0; a < 6; a++)
					o->q.a[a] += c[k][a];
		o->z = o->s = z[i];
		o->v = valid[i] ? 1 : 0;
	}
}

/* --- level 0, streamed (fqm_step0) ------------------------------------
 * fqm_band0's and fqm_row0's arithmetic, operation for operation, with
 * two neighbouring cells at once, a cell a lane of a quadric_v2, so that
 * the divisions and square roots are done in pairs, and what depends on
 * the metric only once per band (per-row metrics) or pair of cells. The
 * bits are fqm_band0's: quadric_triangle_a2 is quadric_add_triangle's
 * but for zeros' signs, which the corner sums cannot tell (see there),
 * and a triangle that fqm_band0 skips (a void corner, or degenerate) is
 * computed and masked to its +0. */

/* The metric along rows J and J + 1 (see fqm_band0). */
typedef struct {
	const geo_ground *m;
	double sx0[GEO_MAX_NODES], sx1[GEO_MAX_NODES];
	double y0[GEO_MAX_NODES], y1[GEO_MAX_NODES];
} band_ground;

static void
band_ground_of(const geo_ground *m, int J, band_ground *b)
{
	b->m = m;
	geo_row_sx(m, J, b->sx0), geo_row_sx(m, J + 1, b->sx1);
	geo_row_y(m, J, b->y0), geo_row_y(m, J + 1, b->y1);
}

/* The x, y parts of the 4 triangles (celltri) of two cells, a cell a
 * lane. They depend on the metric only: one for a whole band of a
 * per-row metric, whose cells are alike. */
typedef struct {
	quadric_xy2 t[4];
} pair_shape;

/* Cell i's trapezoid, as fqm_band0 makes it: x, y of the edges
 * e1 = p1 - p0, e2 = p2 - p0 of each triangle k, xy[k] = x1 y1 x2 y2. */
static void
cell_xy(const band_ground *b, size_t i, double xy[4][4])
{
	const geo_ground *m = b->m;
	double I = i + 0.5;
	double a = geo_on_row(m, b->sx0, I), c = geo_on_row(m, b->sx1, I);
	double dy = geo_on_row(m, b->y1, I) - geo_on_row(m, b->y0, I);
	const double p[4][2] = {
		{ -0.5 * a, 0 }, { 0.5 * a, 0 }, { 0.5 * c, dy }, { -0.5 * c, dy },
	};

	for (int k = 0; k < 4; k++) {
		const int *t = celltri[k];
		for (int d = 0; d < 2; d++) {
			xy[k][d] = p[t[1]][d] - p[t[0]][d];
			xy[k][2 + d] = p[t[2]][d] - p[t[0]][d];
		}
	}
}

/* The shape of cells i and j (lanes 0 and 1). */
static void
pair_shape_of(const band_ground *b, size_t i, size_t j, pair_shape *s)
{
	double u[4][4], v[4][4];

	cell_xy(b, i, u), cell_xy(b, j, v);
	for (int k = 0; k < 4; k++)
		quadric_xy2_init(&s->t[k], (quadric_v2){ u[k][0], v[k][0] },
		    (quadric_v2){ u[k][1], v[k][1] },
		    (quadric_v2){ u[k][2], v[k][2] },
		    (quadric_v2){ u[k][3], v[k][3] });
}

/* The pair code is inlined where it is called with constant triangle k,
 * lane count d and flags, so that the corners it reads and its branches
 * are settled when compiling. */
#define PAIR_INLINE static inline __attribute__((always_inline))

/* Triangle k's A (t[6]) of two cells, corner heights z[] a cell a lane;
 * returns its len (see quadric_triangle_a2). */
PAIR_INLINE quadric_v2
pair_triangle(const pair_shape *s, const quadric_v2 z[4], int k,
    quadric_v2 t[6])
{
	const int *c = celltri[k];

	return quadric_triangle_a2(&s->t[k], z[c[1]] - z[c[0]],
	    z[c[2]] - z[c[0]], 0.5, t);
}

/* What the corners of a pair of cells are: all real samples; in each
 * cell two voids or more, so that every triangle has one and the pair
 * adds nothing (fqm_band0's zero quadrics); anything else. */
enum { PAIR_FULL, PAIR_EMPTY, PAIR_SOME };

static inline int
pair_kind(const unsigned char *v0, const unsigned char *v1, size_t i)
{
	int a = v0[i] != 0, b = v0[i + 1] != 0, c = v0[i + 2] != 0;
	int d = v1[i] != 0, e = v1[i + 1] != 0, f = v1[i + 2] != 0;

	if (a && b && c && d && e && f)
		return PAIR_FULL;
	if (a + b + e + d <= 2 && b + c + f + e <= 2)
		return PAIR_EMPTY;
	return PAIR_SOME;
}

/* The 4 triangles' A (t[k]) of two cells: +0 for one with a corner whose
 * validity mask ok[] is 0 and for a degenerate one (fqm_band0 adds
 * nothing to their zero quadrics). */
PAIR_INLINE void
pair_triangles(const pair_shape *s, const quadric_v2 z[4],
    const quadric_m2 ok[4], quadric_v2 t[4][6])
{
	quadric_m2 keep[4], all;

#pragma GCC unroll 4
	for (int k = 0; k < 4; k++) {
		const int *c = celltri[k];
		quadric_v2 len = pair_triangle(s, z, k, t[k]);
		keep[k] = ok[c[0]] & ok[c[1]] & ok[c[2]] &
		    (quadric_m2)(len > 0);
	}
	/* all kept, as nearly always: nothing to mask */
	all = keep[0] & keep[1] & keep[2] & keep[3];
	if (all[0] != -1 || all[1] != -1)
		for (int k = 0; k < 4; k++)
			for (int a = 0; a < 6; a++)
				t[k][a] = (quadric_v2)((quadric_m2)t[k][a] &
				    keep[k]);
}

/* fqm_band0's corner sums C[k] of two cells of the given kind: the
 * triangles' total in their order from 0 (fqm_band0's quadric_add of
 * each to a zero total), less the triangle that leaves corner k out. */
PAIR_INLINE void
pair_corners(const pair_shape *s, const quadric_v2 z[4],
    const quadric_m2 ok[4], int kind, quadric_v2 C[4][6])
{
	quadric_v2 t[4][6];

	if (kind == PAIR_EMPTY) /* then the sums are of constant +0s */
		for (int k = 0; k < 4; k++)
			for (int a = 0; a < 6; a++)
				t[k][a] = (quadric_v2){ 0, 0 };
	else
		pair_triangles(s, z, ok, t);
#pragma GCC unroll 6
	for (int a = 0; a < 6; a++) {
		quadric_v2 total = 0 + t[0][a] + t[1][a] + t[2][a] + t[3][a];
		for (int k = 0; k < 4; k++)
			C[k][a] = total - t[without[k]][a];
	}
}

/* A validity byte as a lane mask. */
static inline long long
mask_of(unsigned char v)
{
	return -(long long)(v != 0);
}

/* What step0 carries along a row. */
typedef struct {
	size_t w;
	const float *z0, *z1;
	const unsigned char *v0, *v1;
	double *part;          /* 6 planes of w */
	quadric_v2 c1[6], c2[6]; /* corners 1 and 2 of the last pair, lane 1
	                        * the cell left of the next pair's */
	fqm_vertex *out;       /* or */
	float *const *qa;
} row_pass;

/* Two floats, to store two lanes converted at once. */
typedef float pair_f2 __attribute__((vector_size(2 * sizeof(float))));

/* Cells i and i + d (d 1, or 0 for a lone last cell), a lane each, and
 * vertices i and i + d of the row. Vertex i's sum is fqm_row0's, in its
 * order: part[] holds the band above's two terms, cells i - 1 and i of
 * this band add the last two, and their corners 2 and 3 start the next
 * row's part[]. first: i is 0, the vertex without a cell on its left;
 * kind: pair_kind's, or PAIR_SOME when not known. */
PAIR_INLINE void
pair_step(row_pass *r, const pair_shape *s, size_t i, size_t d, int first,
    int kind)
{
	const float *z0 = r->z0, *z1 = r->z1;
	const unsigned char *v0 = r->v0, *v1 = r->v1;
	const quadric_v2 z[4] = {
		{ z0[i], z0[i + d] }, { z0[i + 1], z0[i + 1 + d] },
		{ z1[i + 1], z1[i + 1 + d] }, { z1[i], z1[i + d] },
	};
	quadric_m2 ok[4] = { { -1, -1 }, { -1, -1 }, { -1, -1 }, { -1, -1 } };
	quadric_v2 C[4][6], q[6], nxt[6];
	double *p = r->part + i;
	size_t w = r->w;

	if (kind == PAIR_SOME) {
		const quadric_m2 m[4] = {
			{ mask_of(v0[i]), mask_of(v0[i + d]) },
			{ mask_of(v0[i + 1]), mask_of(v0[i + 1 + d]) },
			{ mask_of(v1[i + 1]), mask_of(v1[i + 1 + d]) },
			{ mask_of(v1[i]), mask_of(v1[i + d]) },
		};
		for (int k = 0; k < 4; k++)
			ok[k] = m[k];
	}
	pair_corners(s, z, ok, kind, C);
	/* vertices i and i + 1, a lane each (lane 1 unused when d is 0) */
#pragma GCC unroll 6
	for (int a = 0; a < 6; a++) {
		quadric_v2 pa;
		memcpy(&pa, p + a * w, sizeof pa); /* p[w - 1] is vertex n */
		q[a] = pa + (quadric_v2){ r->c1[a][1], C[1][a][0] } + C[0][a];
		nxt[a] = 0 + (quadric_v2){ r->c2[a][1], C[2][a][0] } +
		    C[3][a];
		if (first) /* vertex 0: no cell on its left */
			q[a][0] = pa[0] + C[0][a][0], nxt[a][0] = 0 +
			    C[3][a][0];
		/* lane 1 is the cell left of the next pair */
		r->c1[a] = d ? C[1][a] : (quadric_v2){ 0, C[1][a][0] };
		r->c2[a] = d ? C[2][a] : (quadric_v2){ 0, C[2][a][0] };
	}
	if (r->out != NULL) {
		for (int a = 0; a < 6; a++) {
			r->out[i].q.a[a] = q[a][0];
			if (d)
				r->out[i + 1].q.a[a] = q[a][1];
		}
	} else {
#pragma GCC unroll 6
		for (int a = 0; a < 6; a++) {
			pair_f2 f = __builtin_convertvector(q[a], pair_f2);
			if (d)
				memcpy(r->qa[a] + i, &f, sizeof f);
			else
				r->qa[a][i] = f[0];
		}
	}
#pragma GCC unroll 6
	for (int a = 0; a < 6; a++) {
		if (d)
			memcpy(p + a * w, &nxt[a], sizeof nxt[a]);
		else
			p[a * w] = nxt[a][0];
	}
}

/* The last row's A: what the band above gave (fqm_row0 without a band
 * below). */
static void
last0(const double *part, size_t w, fqm_vertex *out, float *const qa[6])
{
	for (int a = 0; a < 6; a++)
		for (size_t i = 0; i < w; i++) {
			if (out != NULL)
				out[i].q.a[a] = part[a * w + i];
			else
				qa[a][i] = (float)part[a * w + i];
		}
}

/* fqm_step0's work: A of row J's vertices into out[].q.a or, encoded,
 * into the channel planes qa[] (the other of the two NULL), from the
 * cells of band J in pairs (pair_step). */
static void
step0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, size_t w, int J, const geo_ground *m,
    double *part, fqm_vertex *out, float *const qa[6])
{
	size_t n = w - 1, i; /* cells */
	int full;
	row_pass r = { w, z0, z1, v0, v1, part, { { 0 } }, { { 0 } }, out,
	    qa };
	band_ground b;
	pair_shape s;

	if (z1 == NULL) {
		last0(part, w, out, qa);
		return;
	}
	full = memchr(v0, 0, w) == NULL && memchr(v1, 0, w) == NULL;
	band_ground_of(m, J, &b);
	/* a per-row metric's cells are alike: one shape for the band */
	pair_shape_of(&b, 0, 1, &s);
	pair_step(&r, &s, 0, 1, 1, PAIR_SOME); /* w >= 3: two cells at least */
	for (i = 2; i + 1 < n; i += 2) {
		if (!m->per_row)
			pair_shape_of(&b, i, i + 1, &s);
		switch (full ? PAIR_FULL : pair_kind(v0, v1, i)) {
		case PAIR_FULL:
			pair_step(&r, &s, i, 1, 0, PAIR_FULL);
			break;
		case PAIR_EMPTY:
			pair_step(&r, &s, i, 1, 0, PAIR_EMPTY);
			break;
		default:
			pair_step(&r, &s, i, 1, 0, PAIR_SOME);
		}
	}
	if (i < n) {
		if (!m->per_row)
			pair_shape_of(&b, i, i, &s);
		pair_step(&r, &s, i, 0, 0, PAIR_SOME);
	}
	for (int a = 0; a < 6; a++) { /* vertex n: no cell on its right */
		double *p = part + a * w + n, q = p[0] + r.c1[a][1];
		if (out != NULL)
			out[n].q.a[a] = q;
		else
			qa[a][n] = (float)q;
		p[0] = 0 + r.c2[a][1];
	}
}

void
fqm_step0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_ground *m,
    double *part, fqm_vertex *out)
{
	for (int i = 0; i < w; i++) {
		fqm_vertex *o = &out[i];
		quadric_zero(&o->q);
		o->z = o->s = z0[i];
		o->v = v0[i] ? 1 : 0;
	}
	step0(z0, v0, z1, v1, (size_t)w, J, m, part, out, NULL);
}

void
fqm_step0_encode(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_ground *m,
    double *part, const fqm_layout *L, float *row)
{
	size_t W = (size_t)w;
	float *qa[6];

	assert(fqm_layout_ok(L));
	for (int a = 0; a < 6; a++)
		qa[a] = row + (size_t)L->q[a] * W;
	step0(z0, v0, z1, v1, W, J, m, part, NULL, qa);
	/* b = 0 and c = 0: +0.0f is all zero bytes */
	for (int c = 6; c < 10; c++)
		memset(row + (size_t)L->q[c] * W, 0, W * sizeof *row);
	/* Z and S, as fqm_row0 and fqm_encode make them: a float height
	 * (finite) is its own double and back */
	memcpy(row + (size_t)L->z * W, z0, W * sizeof *row);
	memcpy(row + (size_t)L->s * W, z0, W * sizeof *row);
	for (size_t i = 0; i < W; i++)
		row[(size_t)L->v * W + i] = v0[i] ? 1 : 0;
}
