/* solve_fold.c - the streaming fold fix of QEM-3D (solve_fold.h): the
 * triangles that half-cell moves can fold, checked row by row (on
 * vectors of cells and diamonds), and the marked vertices pulled back
 * toward the grid until none folds. */
#include "qem/solve_fold.h"
#include "base/pool.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "base/simd.h"

/* 1 when every offset of a row is zero. */
int
solve_zero_row(const solve_vertex *o, int w)
{
	for (int i = 0; i < w; i++)
		if (o[i].x != 0 || o[i].y != 0)
			return 0;
	return 1;
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
	return solve_zero_row(cur, s->w);
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

void
solve_fix_folds(solve_state *s, int j, solve_vertex *cur)
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

