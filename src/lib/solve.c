/* solve.c - per-level vertex placement, and the streaming fold fix of the
 * 3D mode (see solve.h). */
#include "solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const mode_names[] = {
	[SV_QEM1D] = "qem1d", [SV_QEM3D] = "qem3d",
	[SV_FILTERED] = "filtered", [SV_SUBSAMPLE] = "subsample",
};

int
sv_mode_parse(const char *s, enum sv_mode *m)
{
	for (int k = 0; k < 4; k++)
		if (strcmp(s, mode_names[k]) == 0) {
			*m = (enum sv_mode)k;
			return 0;
		}
	return -1;
}

const char *
sv_mode_name(enum sv_mode m)
{
	return mode_names[m];
}

int
sv_init(sv_solver *s, enum sv_mode mode, int level, int w, int h,
    const geo_metric *m, tl_err *e)
{
	memset(s, 0, sizeof *s);
	s->mode = mode;
	s->rel = 1e-3;
	s->shrink = 0.05;
	s->level = level;
	s->w = w, s->h = h;
	s->m = m;
	if (mode != SV_QEM3D)
		return 0;
	s->prev = tl_alloc(w, sizeof *s->prev, e);
	s->mark = tl_alloc(w, 1, e);
	if (s->prev == NULL || s->mark == NULL) {
		sv_free(s);
		return -1;
	}
	return 0;
}

void
sv_free(sv_solver *s)
{
	free(s->prev), free(s->mark);
	s->prev = NULL, s->mark = NULL;
}

static double
cross(const double o[2], const double a[2], const double b[2])
{
	return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

int
sv_cell_ok(const double p[4][2], const double g[4][2], double min)
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

/* Level-0 row of level row j (rows past the DEM continue its spacing). */
static long
row0(const sv_solver *s, int j)
{
	return (long)j << s->level;
}

/* Corners of cell (i, top .. top+1) on the grid and displaced. Rows hold
 * the offsets of the top and bottom rows (NULL: on the grid). */
static int
cell_ok(const sv_solver *s, int i, int top, const sv_vertex *a,
    const sv_vertex *b)
{
	const sv_vertex *row[2] = { a, b };
	double g[4][2], p[4][2];
	static const int di[4] = { 0, 1, 1, 0 }, dj[4] = { 0, 0, 1, 1 };
	double y0 = fqm_y(s->m, row0(s, top));

	for (int k = 0; k < 4; k++) {
		long J = row0(s, top + dj[k]);
		const sv_vertex *v = row[dj[k]] ? &row[dj[k]][i + di[k]] : NULL;
		g[k][0] = di[k] * (double)(1L << s->level) * fqm_dx(s->m, J);
		g[k][1] = fqm_y(s->m, J) - y0;
		p[k][0] = g[k][0] + (v ? v->x : 0);
		p[k][1] = g[k][1] + (v ? v->y : 0);
	}
	return sv_cell_ok(p, g, s->shrink);
}

/* Marks the vertices of row j whose cells break the invariant; returns
 * how many cells did. */
static int
mark_bad(sv_solver *s, int j, const sv_vertex *cur)
{
	int bad = 0;

	memset(s->mark, 0, s->w);
	for (int i = 0; i + 1 < s->w; i++) {
		int ok = 1;
		if (j > 0 && !cell_ok(s, i, j - 1, s->prev, cur))
			ok = 0;
		if (j + 1 < s->h && !cell_ok(s, i, j, cur, NULL))
			ok = 0;
		if (!ok) {
			s->mark[i] = s->mark[i + 1] = 1;
			bad++;
		}
	}
	return bad;
}

/* The free 3D minimiser, clamped to half a cell, boundary vertices kept
 * on their boundary. */
static void
place3d(const sv_solver *s, int i, int j, const fqm_vertex *in,
    sv_vertex *o)
{
	double v[3], hx, hy, up, down;
	long J = row0(s, j), step = 1L << s->level;

	q_min_3d(&in->q, s->rel, v);
	hx = 0.5 * (double)step * fqm_dx(s->m, J);
	up = j > 0 ? fqm_y(s->m, J) - fqm_y(s->m, J - step) : INFINITY;
	down = fqm_y(s->m, J + step) - fqm_y(s->m, J);
	hy = 0.5 * (up < down ? up : down);
	o->x = i == 0 || i == s->w - 1 ? 0 : fmax(-hx, fmin(hx, v[0]));
	o->y = j == 0 || j == s->h - 1 ? 0 : fmax(-hy, fmin(hy, v[1]));
}

static void
fix_folds(sv_solver *s, int j, sv_vertex *cur)
{
	/* Halving converges on the grid, where every invariant holds; after
	 * a few halvings, put the stubborn vertices on the grid. Each round
	 * puts at least one more vertex there, so this ends. */
	for (int round = 0; round <= 6 + s->w; round++) {
		if (mark_bad(s, j, cur) == 0)
			return;
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

void
sv_row(sv_solver *s, const fqm_vertex *in, sv_vertex *out)
{
	int j = s->row++;

	for (int i = 0; i < s->w; i++) {
		out[i].v = in[i].v;
		out[i].x = out[i].y = 0;
		switch (s->mode) {
		case SV_FILTERED:
			out[i].z = in[i].z;
			continue;
		case SV_SUBSAMPLE:
			out[i].z = in[i].s;
			continue;
		case SV_QEM3D:
			place3d(s, i, j, &in[i], &out[i]);
			break;
		case SV_QEM1D:
			break;
		}
	}
	if (s->mode == SV_QEM3D)
		fix_folds(s, j, out);
	if (s->mode == SV_QEM1D || s->mode == SV_QEM3D)
		for (int i = 0; i < s->w; i++) {
			double z = 0;
			/* no plane at all (a void region): the reference height */
			if (q_min_z(&in[i].q, out[i].x, out[i].y, &z) < 0)
				z = 0;
			out[i].z = in[i].z + z;
		}
	if (s->mode == SV_QEM3D)
		memcpy(s->prev, out, (size_t)s->w * sizeof *out);
}
