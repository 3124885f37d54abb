/* solve.c - per-level vertex placement (the streaming fold fix of the
 * 3D mode is solve_fold.c; see solve.h).
 *
 * A vertex goes where its filtered quadric is least: the optimal
 * placement of M. Garland and P. S. Heckbert ("Surface Simplification
 * Using Quadric Error Metrics", SIGGRAPH 1997; quadric.h), applied, as
 * QEM-filtering does, to each vertex of a sub-sampled regular level
 * instead of to an edge collapse (F. Löffler and H. Schumann,
 * "QEM-Filtering: A New Technique For Feature-Sensitive Terrain Mesh
 * Simplification", section 3.4, "computation of the vertex position";
 * ../shared/papers/qem-filtering-loeffler-schumann.txt): along z only
 * (1D displacement, the grid kept) or in x, y, z (3D). The comparison
 * modes are the paper's baseline: heights filtered, or sub-sampled. */
#include "qem/solve.h"
#include "qem/solve_fold.h"
#include "base/pool.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/simd.h"

static const char *const mode_names[] = {
	[SOLVE_QEM1D] = "qem1d", [SOLVE_QEM3D] = "qem3d",
	[SOLVE_FILTERED] = "filtered", [SOLVE_SUBSAMPLE] = "subsample",
};

int
solve_mode_parse(const char *s, enum solve_mode *m)
{
	for (int k = 0; k < 4; k++)
		if (strcmp(s, mode_names[k]) == 0) {
			*m = (enum solve_mode)k;
			return 0;
		}
	return -1;
}

const char *
solve_mode_name(enum solve_mode m)
{
	assert((unsigned)m <= SOLVE_SUBSAMPLE);
	return mode_names[m];
}

int
solve_init(solve_state *s, enum solve_mode mode, int level, int w, int h,
    const geo_ground *m, tl_err *e)
{
	memset(s, 0, sizeof *s);
	s->mode = mode;
	s->rel = 1e-3;
	s->shrink = 0.05;
	s->level = level;
	s->w = w, s->h = h;
	s->m = m;
	s->known = getenv("TL_SOLVE_FULL") == NULL;
	if (mode != SOLVE_QEM3D)
		return 0;
	s->hist[0] = tl_alloc(w, sizeof *s->hist[0], e);
	s->hist[1] = tl_alloc(w, sizeof *s->hist[1], e);
	s->mark = tl_alloc(2 * (size_t)w, 1, e); /* and the last round's */
	s->mbuf = tl_alloc((size_t)10 * w, sizeof *s->mbuf, e);
	s->grid = tl_alloc(w, sizeof *s->grid, e); /* zeroed: +0 */
	for (int r = 0; s->mbuf != NULL && r < 5; r++) {
		s->msx[r] = s->mbuf + (size_t)r * w;
		s->my[r] = s->mbuf + (size_t)(5 + r) * w;
	}
	if (s->hist[0] == NULL || s->hist[1] == NULL || s->mark == NULL ||
	    s->mbuf == NULL || s->grid == NULL) {
		solve_free(s);
		return -1;
	}
	return 0;
}

int
solve_pool(solve_state *s, struct tl_pool *p, tl_err *e)
{
	free(s->markt);
	s->markt = NULL, s->pool = p;
	if (p == NULL || s->mode != SOLVE_QEM3D)
		return 0;
	s->markt = tl_alloc((size_t)tl_pool_threads(p), (size_t)s->w, e);
	return s->markt != NULL ? 0 : -1;
}

void
solve_free(solve_state *s)
{
	free(s->hist[0]), free(s->hist[1]), free(s->mark), free(s->mbuf);
	free(s->markt), free(s->grid);
	s->grid = NULL;
	s->hist[0] = s->hist[1] = NULL, s->mark = NULL, s->mbuf = NULL;
	s->markt = NULL;
}

int
solve_cell_ok(const double p[4][2], const double g[4][2], double min)
{
	static const int tri[4][3] = {
		{ 0, 1, 2 }, { 0, 2, 3 }, { 0, 1, 3 }, { 1, 2, 3 },
	};

	for (int t = 0; t < 4; t++) {
		const int *c = tri[t];
		double want = min * cross(g[c[0]], g[c[1]], g[c[2]]);
		if (!(cross(p[c[0]], p[c[1]], p[c[2]]) >= want))
			return 0;
	}
	return 1;
}

/* 1 when the metric of a row is bounded (on_grid's condition). */
static int
bounded(const double *sx, const double *y, int w)
{
	for (int i = 0; i < w; i++)
		if (!(fabs(sx[i]) <= 1e100 && fabs(y[i]) <= 1e100))
			return 0;
	return 1;
}

/* The metric at the vertices of rows j-2 .. j+2, once per row: the fold
 * fix asks for it a hundred times per vertex. Rows come in order, so
 * four of the five are the previous row's, moved up. */
static void
cache_ground(solve_state *s, int j)
{
	int r0 = 0;

	if (j > 0) {
		double *x = s->msx[0], *y = s->my[0];
		for (int r = 0; r < 4; r++) {
			s->msx[r] = s->msx[r + 1], s->my[r] = s->my[r + 1];
			s->mfin[r] = s->mfin[r + 1];
		}
		s->msx[4] = x, s->my[4] = y;
		r0 = 4;
	}
	for (int r = r0; r < 5; r++) {
		double J = row0(s, j - 2 + r), sx[GEO_MAX_NODES];
		/* geo_sx bit for bit, the row's interpolation once */
		geo_row_sx(s->m, J, sx);
		for (int i = 0; i < s->w; i++) {
			s->msx[r][i] = geo_on_row(s->m, sx, row0(s, i));
			s->my[r][i] = geo_y(s->m, row0(s, i), J);
		}
		s->mfin[r] = bounded(s->msx[r], s->my[r], s->w);
	}
}

/* 1 when vertex in's minimiser is known: b = 0 (every vertex of level
 * 0: its planes pass through it), +0 in each coordinate, which is what
 * quadric_min_3d gives bit for bit (+0 - (u.b / w) u with u.b = ±0, A's
 * eigenvectors finite), without its eigen-decomposition. */
static int
known_min(const solve_state *s, const fqm_vertex *in)
{
	return s->known && in->q.b[0] == 0 && in->q.b[1] == 0 &&
	    in->q.b[2] == 0;
}

/* fmax(-h, fmin(h, v)), inline where no zero can tie (h > 0, and so -h
 * < 0 < h) and no NaN enters: then fmin and fmax pick the smaller and
 * larger of two numbers, and equal ones are the same number. */
static inline double
clamp(double v, double h)
{
	if (h > 0 && v == v)
		return v < -h ? -h : v > h ? h : v;
	return fmax(-h, fmin(h, v));
}

/* The free 3D minimiser v, clamped to half a cell, boundary vertices kept
 * on their boundary. */
static void
clamp3d(const solve_state *s, int i, int j, const double v[3],
    solve_vertex *o)
{
	double hx, hy, up, down;
	long step = 1L << s->level;

	hx = 0.5 * (double)step * s->msx[2][i];
	up = j > 0 ? s->my[2][i] - s->my[1][i] : INFINITY;
	down = s->my[3][i] - s->my[2][i];
	hy = 0.5 * (up < down ? up : down);
	o->x = i == 0 || i == s->w - 1 ? 0 : clamp(v[0], hx);
	o->y = j == 0 || j == s->h - 1 ? 0 : clamp(v[1], hy);
}

/* The free placements of vertices i0 .. i1-1 of the row (a pool's
 * range: each vertex on its own, so any cut gives the same bits). */
typedef struct {
	const solve_state *s;
	int j;
	const fqm_vertex *in;
	solve_vertex *out;
} placing;

static void
place_range(void *arg, int k, int i0, int i1)
{
	const placing *p = arg;

	const solve_state *s = p->s;
	double v[2][3];

	for (int i = i0; i < i1; i++) {
		if (known_min(s, &p->in[i])) {
			v[0][0] = v[0][1] = v[0][2] = 0;
		} else if (i + 1 < i1 && !known_min(s, &p->in[i + 1])) {
			/* two unknowns: one eigen-decomposition on both */
			quadric_min_3d2(&p->in[i].q, &p->in[i + 1].q, s->rel,
			    v[0], v[1]);
			clamp3d(s, i, p->j, v[0], &p->out[i]);
			i++;
			clamp3d(s, i, p->j, v[1], &p->out[i]);
			continue;
		} else
			quadric_min_3d(&p->in[i].q, s->rel, v[0]);
		clamp3d(s, i, p->j, v[0], &p->out[i]);
	}
}

/* 1 when every vertex of the row has b = 0 (place3d's known minimiser). */
static int
known_row(const solve_state *s, const fqm_vertex *in)
{
	if (!s->known)
		return 0;
	for (int i = 0; i < s->w; i++)
		if (!known_min(s, &in[i]))
			return 0;
	return 1;
}

void
solve_row(solve_state *s, const fqm_vertex *in, solve_vertex *out)
{
	int j = s->row++;

	assert(j < s->h); /* rows 0 .. h-1, in order */
	if (s->mode == SOLVE_QEM3D)
		cache_ground(s, j);
	for (int i = 0; i < s->w; i++) {
		out[i].v = in[i].v;
		out[i].x = out[i].y = 0;
		switch (s->mode) {
		case SOLVE_FILTERED:
			out[i].z = in[i].z;
			continue;
		case SOLVE_SUBSAMPLE:
			out[i].z = in[i].s;
			continue;
		case SOLVE_QEM3D:
		case SOLVE_QEM1D:
			break;
		}
	}
	if (s->mode == SOLVE_QEM3D) {
		placing p = { s, j, in, out };
		/* a row of known minimisers (level 0's) is cheaper here
		 * than the hand-overs to the pool */
		if (s->pool != NULL && !known_row(s, in))
			tl_pool_for(s->pool, s->w, place_range, &p);
		else
			place_range(&p, 0, 0, s->w);
		solve_fix_folds(s, j, out);
	}
	if (s->mode == SOLVE_QEM1D || s->mode == SOLVE_QEM3D)
		for (int i = 0; i < s->w; i++) {
			double z = 0;
			/* no plane at all (a void region): the reference height */
			if (quadric_min_z(&in[i].q, out[i].x, out[i].y, &z) < 0)
				z = 0;
			out[i].z = in[i].z + z;
		}
	if (s->mode == SOLVE_QEM3D) {
		solve_vertex *t = s->hist[1]; /* j-2 goes, j becomes j-1 */
		s->hist[1] = s->hist[0];
		s->hist[0] = t;
		memcpy(s->hist[0], out, (size_t)s->w * sizeof *out);
		s->hzero[1] = s->hzero[0];
		s->hzero[0] = solve_zero_row(out, s->w);
	}
}

int
solve_header(rs_header *oh, const rs_header *fqm, enum solve_mode mode,
    tl_err *e)
{
	if (rs_header_copy(oh, fqm, e) < 0)
		return -1;
	rs_clear_channels(oh);
	if (rs_add_channel(oh, "Z", e) < 0 || rs_add_channel(oh, "V", e) < 0)
		return -1;
	if (mode == SOLVE_QEM3D && (rs_add_channel(oh, "X", e) < 0 ||
	    rs_add_channel(oh, "Y", e) < 0))
		return -1;
	if (rs_set_string(oh, FQM_ATTR_KIND, "vertices", e) < 0)
		return -1;
	return rs_set_string(oh, FQM_ATTR_MODE, solve_mode_name(mode), e);
}

void
solve_encode(const rs_header *oh, const solve_vertex *v, float *row)
{
	int w = oh->width, cz = rs_channel(oh, "Z"), cv = rs_channel(oh, "V");
	int cx = rs_channel(oh, "X"), cy = rs_channel(oh, "Y");

	assert(cz >= 0 && cv >= 0);
	for (int i = 0; i < w; i++) {
		row[(size_t)cz * w + i] = (float)v[i].z;
		row[(size_t)cv * w + i] = (float)v[i].v;
		if (cx >= 0) {
			row[(size_t)cx * w + i] = (float)v[i].x;
			row[(size_t)cy * w + i] = (float)v[i].y;
		}
	}
}

/* quadric_min_z's z, or 0 where it fails, on two vertices, with the
 * products by x = y = 0 (they decide the sign of a zero quotient, and so
 * that of Z + the quotient when Z is a zero). Lanes where it fails get
 * +0 bit for bit. */
static inline vd
min_z2(vd a13, vd a23, vd a33, vd b3)
{
	const double zero = 0; /* out.x, out.y */
	vd t = -(b3 + a13 * zero + a23 * zero) / a33;
	/* a33 > 0 and finite, and so the quotient */
	vl ok = (a33 > 0) & (a33 <= DBL_MAX) & (t >= -DBL_MAX) &
	    (t <= DBL_MAX);

	if (ok[0] && ok[1])
		return t;
	if (!ok[0] && !ok[1])
		return vd_splat(0);
	return (vd){ ok[0] ? t[0] : 0, ok[1] ? t[1] : 0 };
}

/* QEM-1D of n vertices on their grid positions: z = Z + quadric_min_z(q,
 * 0, 0) where a33 > 0 and the quotient is finite, else Z + 0: every
 * operation of solve_row's, in its order, on vectors. */
static void
qem1d_direct(const float *fa13, const float *fa23, const float *fa33,
    const float *fb3, const float *fz, float *out, size_t n)
{
	size_t i = 0;

	for (; i + 4 <= n; i += 4) {
		vd4 a13 = __builtin_convertvector(vf4_load(fa13 + i), vd4);
		vd4 a23 = __builtin_convertvector(vf4_load(fa23 + i), vd4);
		vd4 a33 = __builtin_convertvector(vf4_load(fa33 + i), vd4);
		vd4 b3 = __builtin_convertvector(vf4_load(fb3 + i), vd4);
		vd4 z = __builtin_convertvector(vf4_load(fz + i), vd4);
		vd lo = min_z2(__builtin_shufflevector(a13, a13, 0, 1),
		    __builtin_shufflevector(a23, a23, 0, 1),
		    __builtin_shufflevector(a33, a33, 0, 1),
		    __builtin_shufflevector(b3, b3, 0, 1));
		vd hi = min_z2(__builtin_shufflevector(a13, a13, 2, 3),
		    __builtin_shufflevector(a23, a23, 2, 3),
		    __builtin_shufflevector(a33, a33, 2, 3),
		    __builtin_shufflevector(b3, b3, 2, 3));
		z = z + __builtin_shufflevector(lo, hi, 0, 1, 2, 3);
		vf4_store(out + i, __builtin_convertvector(z, vf4));
	}
	for (; i < n; i++) {
		quadric q;
		double z = 0;
		q.a[QUADRIC_A13] = fa13[i], q.a[QUADRIC_A23] = fa23[i];
		q.a[QUADRIC_A33] = fa33[i], q.b[2] = fb3[i];
		if (quadric_min_z(&q, 0, 0, &z) < 0)
			z = 0;
		out[i] = (float)((double)fz[i] + z);
	}
}

void
solve_row_direct(solve_state *s, const fqm_layout *L, const float *in,
    const rs_header *oh, float *row)
{
	size_t w = (size_t)s->w;
	int cz = rs_channel(oh, "Z"), cv = rs_channel(oh, "V");

	assert(s->mode != SOLVE_QEM3D && s->row < s->h);
	assert(cz >= 0 && cv >= 0 && oh->width == s->w);
	s->row++;
	/* a float widened to double and back is itself: V, and Z or S,
	 * are copies */
	memcpy(row + (size_t)cv * w, in + (size_t)L->v * w, w * sizeof *row);
	if (s->mode == SOLVE_FILTERED || s->mode == SOLVE_SUBSAMPLE) {
		int c = s->mode == SOLVE_FILTERED ? L->z : L->s;
		memcpy(row + (size_t)cz * w, in + (size_t)c * w,
		    w * sizeof *row);
		return;
	}
	qem1d_direct(in + (size_t)L->q[QUADRIC_A13] * w,
	    in + (size_t)L->q[QUADRIC_A23] * w,
	    in + (size_t)L->q[QUADRIC_A33] * w, in + (size_t)L->q[8] * w,
	    in + (size_t)L->z * w, row + (size_t)cz * w, w);
}
