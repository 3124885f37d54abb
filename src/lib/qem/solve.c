/* solve.c - per-level vertex placement, and the streaming fold fix of the
 * 3D mode (see solve.h).
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

static double
cross(const double o[2], const double a[2], const double b[2])
{
	return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
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

/* Level-0 row (or column) of level row (column) j. */
static double
row0(const solve_state *s, int j)
{
	return (double)j * (double)(1L << s->level);
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

/* 1 when every offset of a row is zero. */
static int
zero_row(const solve_vertex *o, int w)
{
	for (int i = 0; i < w; i++)
		if (o[i].x != 0 || o[i].y != 0)
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

/* The triangles the fold fix keeps positive: those of the bintree that
 * vertices moving up to half a cell can fold, i.e. the four of each cell
 * (both diagonals) and the two-cell triangles of scale-1 edge diamonds
 * (height one cell); larger ones need moves of over half a cell. As
 * (di, dj) offsets from an anchor vertex. */
static const int celltri[4][3][2] = {
	{ { 0, 0 }, { 1, 0 }, { 1, 1 } }, { { 0, 0 }, { 1, 1 }, { 0, 1 } },
	{ { 0, 0 }, { 1, 0 }, { 0, 1 } }, { { 1, 0 }, { 1, 1 }, { 0, 1 } },
};
/* around an edge vertex (c, r) of scale 1: hypotenuse horizontal (c odd,
 * r even) or vertical (c even, r odd) */
static const int edgetri[2][2][3][2] = {
	{ { { -1, 0 }, { 1, 0 }, { 0, -1 } }, { { -1, 0 }, { 1, 0 }, { 0, 1 } } },
	{ { { 0, -1 }, { 0, 1 }, { -1, 0 } }, { { 0, -1 }, { 0, 1 }, { 1, 0 } } },
};

/* The offsets of rows j-2 .. j+2 while row j is being fixed: earlier
 * rows as final, row j as now, later rows on the grid (s->grid, all +0,
 * as the literal 0 it stands for). */
static void
offset_rows(const solve_state *s, int j, const solve_vertex *cur,
    const solve_vertex *rows[5])
{
	rows[0] = s->hist[1], rows[1] = s->hist[0], rows[2] = cur;
	rows[3] = rows[4] = s->grid;
	(void)j;
}

/* 1 when triangle v[] (level vertices) keeps at least `shrink` of its
 * grid area with the same orientation. */
static inline __attribute__((always_inline)) int
tri_ok(const solve_state *s, int j, const solve_vertex *const rows[5],
    const int v[3][2])
{
	double g[3][2], p[3][2], ga, pa;
	int i0 = v[0][0], r0 = v[0][1] - j + 2;

	assert(r0 >= 0 && r0 < 5);
	for (int k = 0; k < 3; k++) {
		int r = v[k][1] - j + 2;
		const solve_vertex *o = &rows[r][v[k][0]];
		/* the metric cache holds rows j-2 .. j+2 */
		assert(r >= 0 && r < 5);
		/* in the frame of v[0], as geo_local puts it (georef.h) */
		g[k][0] = (row0(s, v[k][0]) - row0(s, i0)) * s->msx[r][i0];
		g[k][1] = s->my[r][i0] - s->my[r0][i0];
		p[k][0] = g[k][0] + o->x;
		p[k][1] = g[k][1] + o->y;
	}
	ga = cross(g[0], g[1], g[2]);
	pa = cross(p[0], p[1], p[2]);
	return ga > 0 ? pa >= s->shrink * ga : pa <= s->shrink * ga;
}

/* Checks one triangle (anchor + offsets) touching row j; marks its row-j
 * vertices when it breaks the invariant. */
static inline __attribute__((always_inline)) int
check(const solve_state *s, int j, const solve_vertex *const rows[5],
    int ci, int cj, const int (*t)[2], unsigned char *mark)
{
	int v[3][2], touches = 0;

	for (int k = 0; k < 3; k++) {
		v[k][0] = ci + t[k][0], v[k][1] = cj + t[k][1];
		if (v[k][0] < 0 || v[k][0] >= s->w || v[k][1] < 0 ||
		    v[k][1] >= s->h)
			return 0;
		touches |= v[k][1] == j;
	}
	if (!touches || tri_ok(s, j, rows, v))
		return 0;
	for (int k = 0; k < 3; k++)
		if (v[k][1] == j)
			mark[v[k][0]] = 1;
	return 1;
}

static inline vd
vcross(const vd o[2], const vd a[2], const vd b[2])
{
	return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* The x and y offsets of vertices i, i+1 of a row, a lane each. */
static inline void
offsets2(const solve_vertex *o, int i, vd *x, vd *y)
{
	vd a = vd_load(&o[i].x), b = vd_load(&o[i + 1].x);

	*x = __builtin_shufflevector(a, b, 0, 2);
	*y = __builtin_shufflevector(a, b, 1, 3);
}

/* 1 in the lanes where triangle (g, p) keeps its area (tri_ok's test);
 * the failures' row-j vertices marked (vertex k at column at[k] + lane
 * when in row j: row[k]). */
static inline int
tri_vec(const vd g[3][2], const vd p[3][2], vd sh, const int at[3],
    const int row[3], unsigned char *mark)
{
	vd ga = vcross(g[0], g[1], g[2]), pa = vcross(p[0], p[1], p[2]);
	vl ok = ((ga > 0) & (pa >= sh * ga)) | (~(ga > 0) & (pa <= sh * ga));
	int bad = 0;

	for (int l = 0; l < VEC_N; l++) {
		if (ok[l])
			continue;
		bad++;
		for (int k = 0; k < 3; k++)
			if (row[k])
				mark[at[k] + l] = 1;
	}
	return bad;
}

/* check() of the four triangles of the cells anchored at columns ci,
 * ci+1 of row cj (celltri's order), every vertex inside the level: each
 * triangle's g and p as tri_ok computes them, each computed once for the
 * triangles that share it (in frame ci: vertices 00, 10, 11, 01; in
 * frame ci+1, celltri[3]'s: 10, 11, 01). Returns the failures. */
static int
cells_vec(const solve_state *s, int j, const solve_vertex *const rows[5],
    int ci, int cj, unsigned char *mark)
{
	_Static_assert(VEC_N == 2, "cells_vec works on pairs");
	int ra = cj - j + 2, rb = ra + 1, bad = 0;
	int ina = cj == j, inb = cj + 1 == j;
	vd sh = vd_splat(s->shrink), X0, X1, oxa0, oya0, oxa1, oya1;
	vd oxb0, oyb0, oxb1, oyb1, g[7][2], p[7][2];
	vd sa0, sb0, sa1, sb1, ya0, yb0, ya1, yb1;

	assert(ra >= 0 && rb < 5);
	X0 = (vd){ row0(s, ci), row0(s, ci + 1) };
	X1 = (vd){ row0(s, ci + 1), row0(s, ci + 2) };
	sa0 = vd_load(s->msx[ra] + ci), sb0 = vd_load(s->msx[rb] + ci);
	sa1 = vd_load(s->msx[ra] + ci + 1), sb1 = vd_load(s->msx[rb] + ci + 1);
	ya0 = vd_load(s->my[ra] + ci), yb0 = vd_load(s->my[rb] + ci);
	ya1 = vd_load(s->my[ra] + ci + 1), yb1 = vd_load(s->my[rb] + ci + 1);
	offsets2(rows[ra], ci, &oxa0, &oya0);
	offsets2(rows[ra], ci + 1, &oxa1, &oya1);
	offsets2(rows[rb], ci, &oxb0, &oyb0);
	offsets2(rows[rb], ci + 1, &oxb1, &oyb1);
	/* frame ci: 00 10 11 01 */
	g[0][0] = (X0 - X0) * sa0, g[0][1] = ya0 - ya0;
	g[1][0] = (X1 - X0) * sa0, g[1][1] = ya0 - ya0;
	g[2][0] = (X1 - X0) * sb0, g[2][1] = yb0 - ya0;
	g[3][0] = (X0 - X0) * sb0, g[3][1] = yb0 - ya0;
	/* frame ci+1: 10 11 01 */
	g[4][0] = (X1 - X1) * sa1, g[4][1] = ya1 - ya1;
	g[5][0] = (X1 - X1) * sb1, g[5][1] = yb1 - ya1;
	g[6][0] = (X0 - X1) * sb1, g[6][1] = yb1 - ya1;
	p[0][0] = g[0][0] + oxa0, p[0][1] = g[0][1] + oya0;
	p[1][0] = g[1][0] + oxa1, p[1][1] = g[1][1] + oya1;
	p[2][0] = g[2][0] + oxb1, p[2][1] = g[2][1] + oyb1;
	p[3][0] = g[3][0] + oxb0, p[3][1] = g[3][1] + oyb0;
	p[4][0] = g[4][0] + oxa1, p[4][1] = g[4][1] + oya1;
	p[5][0] = g[5][0] + oxb1, p[5][1] = g[5][1] + oyb1;
	p[6][0] = g[6][0] + oxb0, p[6][1] = g[6][1] + oyb0;
	{
		static const int tv[4][3] = {
			{ 0, 1, 2 }, { 0, 2, 3 }, { 0, 1, 3 }, { 4, 5, 6 },
		};
		/* each vertex's column offset and whether it is in row A */
		static const int col[7] = { 0, 1, 1, 0, 1, 1, 0 };
		static const int rowa[7] = { 1, 1, 0, 0, 1, 0, 0 };
		for (int t = 0; t < 4; t++) {
			vd gg[3][2], pp[3][2];
			int at[3], row[3];
			for (int k = 0; k < 3; k++) {
				int v = tv[t][k];
				gg[k][0] = g[v][0], gg[k][1] = g[v][1];
				pp[k][0] = p[v][0], pp[k][1] = p[v][1];
				at[k] = ci + col[v];
				row[k] = rowa[v] ? ina : inb;
			}
			bad += tri_vec(gg, pp, sh, at, row, mark);
		}
	}
	return bad;
}

/* check() of triangles tri[0 .. nt-1] anchored at columns c, c + cs, ..
 * (VEC_N of them) of row cj, every vertex inside the level: tri_ok's
 * operations per triangle, on vectors of VEC_N anchors. Returns the
 * failures. */
static inline __attribute__((always_inline)) int
tris_vec(const solve_state *s, int j, const solve_vertex *const rows[5],
    int c, const int cs, int cj, const int (*tri)[3][2], const int nt,
    unsigned char *mark)
{
	vd sh = vd_splat(s->shrink);
	int bad = 0;

	for (int t = 0; t < nt; t++) {
		const int (*tt)[2] = tri[t];
		int r0 = cj + tt[0][1] - j + 2, touches = 0;
		vd g[3][2], p[3][2], ga, pa, c0;
		vl ok;
		for (int k = 0; k < 3; k++)
			touches |= cj + tt[k][1] == j;
		if (!touches)
			continue;
		assert(r0 >= 0 && r0 < 5);
		for (int l = 0; l < VEC_N; l++)
			c0[l] = row0(s, c + l * cs + tt[0][0]);
		for (int k = 0; k < 3; k++) {
			int r = cj + tt[k][1] - j + 2;
			vd ck, sx, y, y0, ox, oy;
			assert(r >= 0 && r < 5);
			for (int l = 0; l < VEC_N; l++) {
				int i = c + l * cs + tt[k][0];
				int i0 = c + l * cs + tt[0][0];
				ck[l] = row0(s, i);
				sx[l] = s->msx[r][i0], y[l] = s->my[r][i0];
				y0[l] = s->my[r0][i0];
				ox[l] = rows[r][i].x, oy[l] = rows[r][i].y;
			}
			g[k][0] = (ck - c0) * sx;
			g[k][1] = y - y0;
			p[k][0] = g[k][0] + ox;
			p[k][1] = g[k][1] + oy;
		}
		ga = vcross(g[0], g[1], g[2]);
		pa = vcross(p[0], p[1], p[2]);
		ok = ((ga > 0) & (pa >= sh * ga)) |
		    (~(ga > 0) & (pa <= sh * ga));
		for (int l = 0; l < VEC_N; l++) {
			if (ok[l])
				continue;
			bad++;
			for (int k = 0; k < 3; k++)
				if (cj + tt[k][1] == j)
					mark[c + l * cs + tt[k][0]] = 1;
		}
	}
	return bad;
}

/* The triangles anchored in columns i0 .. i1-1 (a pool's range k),
 * their row-j vertices that break the invariant marked in `mark`. */
typedef struct {
	const solve_state *s;
	int j;
	const solve_vertex *rows[5]; /* offset_rows */
	unsigned char *mark[TL_POOL_MAXTHREADS];
	int bad[TL_POOL_MAXTHREADS];
} marking;

static void
mark_range(void *arg, int k, int i0, int i1)
{
	marking *m = arg;
	const solve_state *s = m->s;
	int j = m->j, bad = 0;

	for (int cj = j - 1; cj <= j; cj++) {
		int ci = i0;
		/* whole vectors of cells inside the level */
		if (cj >= 0 && cj + 1 < s->h)
			for (; ci + VEC_N <= i1 && ci + VEC_N < s->w;
			    ci += VEC_N)
				bad += cells_vec(s, j, m->rows, ci, cj,
				    m->mark[k]);
		for (; ci < i1 && ci + 1 < s->w; ci++)
			for (int t = 0; t < 4; t++)
				bad += check(s, j, m->rows, ci, cj, celltri[t],
				    m->mark[k]);
	}
	for (int r = j - 1; r <= j + 1; r++) {
		/* the edge vertices of row r: every other column; whole
		 * vectors of their diamonds inside the level (anchors vs ..
		 * ve-1), then the others one by one */
		int kind = r & 1, vs = i0, ve = i0, last = 2 * (VEC_N - 1);
		if (r >= 1 && r + 1 < s->h) {
			vs = i0 + ((i0 & 1) == kind);
			if (vs < 1)
				vs += 2;
			for (ve = vs; ve + last < i1 && ve + last + 1 < s->w;
			    ve += 2 * VEC_N)
				bad += tris_vec(s, j, m->rows, ve, 2, r,
				    edgetri[kind], 2, m->mark[k]);
		}
		for (int c = i0; c < i1; c++) {
			int kd = (c & 1) && !(r & 1) ? 0 :
			    !(c & 1) && (r & 1) ? 1 : -1;
			if (kd < 0 || (c >= vs && c < ve))
				continue;
			for (int t = 0; t < 2; t++)
				bad += check(s, j, m->rows, c, r,
				    edgetri[kd][t], m->mark[k]);
		}
	}
	m->bad[k] = bad;
}

/* Marks the vertices of row j in triangles that break the invariant:
 * every checked triangle with a vertex in row j is positive with earlier
 * rows final and later rows on the grid. Then the next row can always be
 * fixed by moving only itself (on the grid, it meets this very test), so
 * rows are final as soon as they are fixed. Returns the failures. On a
 * pool each range marks its own copy, then the copies are merged: a
 * mark is a set, so the result is the same. */
static int
mark_bad(solve_state *s, int j, const solve_vertex *cur)
{
	marking m = { s, j, { 0 }, { 0 }, { 0 } };
	int n = s->pool != NULL ? tl_pool_threads(s->pool) : 1, bad = 0;

	offset_rows(s, j, cur, m.rows);
	memset(s->mark, 0, s->w);
	if (n == 1) {
		m.mark[0] = s->mark;
		mark_range(&m, 0, 0, s->w);
		return m.bad[0];
	}
	memset(s->markt, 0, (size_t)n * s->w);
	for (int k = 0; k < n; k++)
		m.mark[k] = s->markt + (size_t)k * s->w;
	tl_pool_for(s->pool, s->w, mark_range, &m);
	for (int k = 0; k < n; k++) {
		bad += m.bad[k];
		for (int i = 0; i < s->w; i++)
			s->mark[i] |= m.mark[k][i];
	}
	return bad;
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

/* 1 when the fold fix is known to change nothing on row j: the offsets
 * of rows j-2 .. j all zero, so every checked triangle is its grid
 * triangle (p = g + 0 has g's values, and so pa = ga), which keeps
 * `shrink` (0 .. 1) of its area whenever ga is a number; the metric's
 * cached rows bounded make it one. Level 0's rows are of this kind. */
static int
on_grid(const solve_state *s, int j, const solve_vertex *cur)
{
	if (!s->known || !(s->shrink >= 0 && s->shrink <= 1))
		return 0;
	/* the earlier rows' and the metric's, as they were stored */
	for (int r = 1; r <= 2 && r <= j; r++)
		if (!s->hzero[r - 1])
			return 0;
	for (int r = 0; r < 5; r++)
		if (!s->mfin[r])
			return 0;
	return zero_row(cur, s->w);
}

/* mark_bad after a round that changed only the vertices marked in
 * `prev`: a triangle with none of them is as it was, and it was good (a
 * bad one had all its row-j vertices marked), so only the triangles
 * anchored within a column of a marked vertex (a cell's at i-1 and i, an
 * edge diamond's at i-1 .. i+1) are checked again. The marks are the
 * same set; the count is 0 exactly when mark_bad's is. */
static int
mark_near(solve_state *s, int j, const solve_vertex *cur,
    const unsigned char *prev)
{
	marking m = { s, j, { 0 }, { s->mark }, { 0 } };
	int bad = 0, i = 0, a;

	offset_rows(s, j, cur, m.rows);
	memset(s->mark, 0, s->w);
	while (i < s->w) {
		if (!prev[i]) {
			i++;
			continue;
		}
		/* a run of marks, and the gaps of up to 2 columns after it,
		 * whose windows overlap */
		a = i;
		while (i < s->w && (prev[i] || (i + 1 < s->w && prev[i + 1]) ||
		    (i + 2 < s->w && prev[i + 2])))
			i++;
		mark_range(&m, 0, a > 0 ? a - 1 : 0, i + 1 < s->w ? i + 1 :
		    s->w);
		bad += m.bad[0];
	}
	return bad;
}

static void
fix_folds(solve_state *s, int j, solve_vertex *cur)
{
	unsigned char *prev = s->mark + s->w;

	if (on_grid(s, j, cur))
		return;
	/* Halving converges on the grid, where every invariant holds; after
	 * a few halvings, put the stubborn vertices on the grid. Each round
	 * puts at least one more vertex there, so this ends. */
	for (int round = 0; round <= 6 + s->w; round++) {
		if ((round == 0 ? mark_bad(s, j, cur) :
		    mark_near(s, j, cur, prev)) == 0)
			return;
		memcpy(prev, s->mark, s->w);
		for (int i = 0; i < s->w; i++) {
			if (!s->mark[i])
				continue;
			if (round < 6) {
				cur[i].x *= 0.5, cur[i].y *= 0.5;
				s->reduced += round == 0;
			} else {
				s->zeroed += cur[i].x != 0 || cur[i].y != 0;
				cur[i].x = cur[i].y = 0;
			}
		}
	}
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
		fix_folds(s, j, out);
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
		s->hzero[0] = zero_row(out, s->w);
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
