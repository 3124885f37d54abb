/* view.c - the world in metres, the camera and the block level of detail
 * (see view.h). */
#include "play/view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fqm.h"

int
world_open(world *w, const char *dir, tl_err *e)
{
	memset(w, 0, sizeof *w);
	snprintf(w->dir, sizeof w->dir, "%s", dir);
	if (pyramid_index_read(dir, &w->ix, e) < 0)
		return -1;
	if (geo_metric_init(&w->m, &w->ix.geo, e) < 0) {
		pyramid_index_free(&w->ix);
		return -1;
	}
	w->ci = (w->ix.size0[0] - 1) / 2.0;
	w->cj = (w->ix.size0[1] - 1) / 2.0;
	w->zmin = INFINITY, w->zmax = -INFINITY;
	for (int l = 0; l < w->ix.nlevels; l++) {
		pyramid_level *L = &w->ix.lev[l];
		for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++) {
			w->zmin = fmin(w->zmin, L->zmin[k]);
			w->zmax = fmax(w->zmax, L->zmax[k]);
		}
	}
	if (!(w->zmin <= w->zmax))
		w->zmin = w->zmax = 0;
	/* skirts hang to a floor under everything */
	w->base = w->zmin - 0.02 * (w->zmax - w->zmin) - 1;
	return 0;
}

void
world_close(world *w)
{
	pyramid_index_free(&w->ix);
	geo_metric_free(&w->m);
}

/* World x: metres along row J from the centre column (for a per-row
 * metric (I - ci) * dx at the fractional row J); world y: metres along
 * column I from the centre row, northward (rows run south). */
void
world_pos(const world *w, double I, double J, double X, double Y, double z,
    double out[3])
{
	out[0] = geo_x(&w->m, w->ci, I, J) + X;
	out[1] = -(geo_y(&w->m, I, J) - geo_y(&w->m, I, w->cj)) - Y;
	out[2] = z;
}

void
world_block_box(const world *w, int level, int bi, int bj, double lo[3],
    double hi[3])
{
	const pyramid_level *L = &w->ix.lev[level];
	double s = (double)(1L << level), span = BT_CELLS * s;
	double pad = L->displaced ? 0.5 * s : 0;
	int k = bj * L->blocks[0] + bi;

	lo[0] = lo[1] = INFINITY, hi[0] = hi[1] = -INFINITY;
	for (int c = 0; c < 4; c++) {
		double p[3];
		double I = bi * span + (c & 1 ? span + pad : -pad);
		double J = bj * span + (c & 2 ? span + pad : -pad);
		world_pos(w, I, J, 0, 0, 0, p);
		for (int a = 0; a < 2; a++)
			lo[a] = fmin(lo[a], p[a]), hi[a] = fmax(hi[a], p[a]);
	}
	lo[2] = L->zmin[k], hi[2] = L->zmax[k];
}

/* --- camera ------------------------------------------------------------ */

static void
sub(const double a[3], const double b[3], double r[3])
{
	r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2];
}

static double
dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void
crs(const double a[3], const double b[3], double r[3])
{
	r[0] = a[1] * b[2] - a[2] * b[1];
	r[1] = a[2] * b[0] - a[0] * b[2];
	r[2] = a[0] * b[1] - a[1] * b[0];
}

static void
unit(double a[3])
{
	double n = sqrt(dot(a, a));

	if (n > 0)
		a[0] /= n, a[1] /= n, a[2] /= n;
}

/* Row-major 4x4 products, then stored column-major for GL. */
static void
view_matrix(const camera *c, double m[4][4])
{
	double f[3], s[3], u[3];

	sub(c->target, c->eye, f);
	unit(f);
	crs(f, c->up, s);
	unit(s);
	crs(s, f, u);
	memset(m, 0, 16 * sizeof(double));
	for (int k = 0; k < 3; k++)
		m[0][k] = s[k], m[1][k] = u[k], m[2][k] = -f[k];
	m[0][3] = -dot(s, c->eye);
	m[1][3] = -dot(u, c->eye);
	m[2][3] = dot(f, c->eye);
	m[3][3] = 1;
}

static void
proj_matrix(const camera *c, double m[4][4])
{
	double t = 1 / tan(c->fovy / 2), a = (double)c->width / c->height;
	double n = c->znear, f = c->zfar;

	memset(m, 0, 16 * sizeof(double));
	m[0][0] = t / a;
	m[1][1] = t;
	m[2][2] = -(f + n) / (f - n);
	m[2][3] = -2 * f * n / (f - n);
	m[3][2] = -1;
}

void
cam_matrices(const camera *c, float view[16], float proj[16])
{
	double v[4][4], p[4][4];

	view_matrix(c, v);
	proj_matrix(c, p);
	for (int r = 0; r < 4; r++)
		for (int k = 0; k < 4; k++) {
			view[k * 4 + r] = (float)v[r][k];
			proj[k * 4 + r] = (float)p[r][k];
		}
}

void
cam_frustum(const camera *c, double planes[6][4])
{
	double v[4][4], p[4][4], m[4][4];

	view_matrix(c, v);
	proj_matrix(c, p);
	for (int r = 0; r < 4; r++)
		for (int k = 0; k < 4; k++) {
			m[r][k] = 0;
			for (int q = 0; q < 4; q++)
				m[r][k] += p[r][q] * v[q][k];
		}
	/* Gribb-Hartmann: row 3 +- rows 0, 1, 2 */
	for (int i = 0; i < 3; i++)
		for (int k = 0; k < 4; k++) {
			planes[2 * i][k] = m[3][k] + m[i][k];
			planes[2 * i + 1][k] = m[3][k] - m[i][k];
		}
}

int
box_outside(const double planes[6][4], const double lo[3], const double hi[3])
{
	for (int i = 0; i < 6; i++) {
		/* the box corner farthest along the plane's normal */
		double p[3];
		for (int k = 0; k < 3; k++)
			p[k] = planes[i][k] >= 0 ? hi[k] : lo[k];
		if (dot(planes[i], p) + planes[i][3] < 0)
			return 1;
	}
	return 0;
}

double
cam_pixels_per_metre(const camera *c, double d)
{
	double k = c->height / 2.0 / tan(c->fovy / 2);

	return k / (d > 1e-6 ? d : 1e-6);
}

double
cam_box_distance(const camera *c, const double lo[3], const double hi[3])
{
	double s = 0;

	for (int k = 0; k < 3; k++) {
		double d = c->eye[k] < lo[k] ? lo[k] - c->eye[k] :
		    c->eye[k] > hi[k] ? c->eye[k] - hi[k] : 0;
		s += d * d;
	}
	return sqrt(s);
}

/* The world's box: all of level 0. */
static void
world_box(const world *w, double lo[3], double hi[3])
{
	const pyramid_level *L = &w->ix.lev[0];
	double a[3], b[3];

	world_block_box(w, 0, 0, 0, lo, hi);
	world_block_box(w, 0, L->blocks[0] - 1, L->blocks[1] - 1, a, b);
	for (int k = 0; k < 2; k++)
		lo[k] = fmin(lo[k], a[k]), hi[k] = fmax(hi[k], b[k]);
	/* the footprint of the real DEM, not the padding */
	{
		double p[3], q[3];
		world_pos(w, 0, 0, 0, 0, 0, p);
		world_pos(w, w->ix.size0[0] - 1, w->ix.size0[1] - 1, 0, 0, 0, q);
		lo[0] = fmin(p[0], q[0]), hi[0] = fmax(p[0], q[0]);
		lo[1] = fmin(p[1], q[1]), hi[1] = fmax(p[1], q[1]);
	}
	lo[2] = w->zmin, hi[2] = w->zmax;
}

void
cam_fit_depth(camera *c, const world *w)
{
	double lo[3], hi[3], far = 0;

	world_box(w, lo, hi);
	lo[2] = w->base;
	for (int k = 0; k < 8; k++) {
		double p[3] = { k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1],
			k & 4 ? hi[2] : lo[2] }, d[3];
		sub(p, c->eye, d);
		far = fmax(far, sqrt(dot(d, d)));
	}
	c->zfar = far * 1.05 + 1;
	c->znear = fmax(c->zfar / 1e5, fmax(0.05,
	    0.5 * cam_box_distance(c, lo, hi)));
}

int
cam_named(camera *c, const world *w, const char *name)
{
	double lo[3], hi[3], r, t = tan(c->fovy / 2);
	double aspect = (double)c->width / c->height;

	world_box(w, lo, hi);
	for (int k = 0; k < 3; k++)
		c->target[k] = (lo[k] + hi[k]) / 2;
	if (strcmp(name, "overview") == 0) {
		/* straight down, north up, the footprint just in frame */
		double half = fmax((hi[0] - lo[0]) / 2 / aspect,
		    (hi[1] - lo[1]) / 2);
		c->target[2] = w->zmin;
		c->eye[0] = c->target[0], c->eye[1] = c->target[1];
		c->eye[2] = w->zmax + half * 1.02 / t;
		c->up[0] = 0, c->up[1] = 1, c->up[2] = 0;
	} else if (strcmp(name, "oblique") == 0) {
		/* from the south-west, 30 degrees down */
		double d[3] = { -cos(M_PI / 4) * cos(M_PI / 6),
			-sin(M_PI / 4) * cos(M_PI / 6), sin(M_PI / 6) };
		r = 0.5 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
		    (hi[1] - lo[1]) * (hi[1] - lo[1]));
		for (int k = 0; k < 3; k++)
			c->eye[k] = c->target[k] + d[k] * r * 1.15 / t;
		c->up[0] = 0, c->up[1] = 0, c->up[2] = 1;
	} else
		return -1;
	cam_fit_depth(c, w);
	return 0;
}

/* --- level of detail --------------------------------------------------- */

typedef struct {
	const world *w;
	const camera *c;
	double planes[6][4];
	double pixels;
	lod_ready_fn ready;
	void *ctx;
	lod_block *out;
	int n, max;
} lod;

static int
exists(const world *w, int l, int bi, int bj)
{
	const pyramid_level *L = &w->ix.lev[l];

	return bi >= 0 && bj >= 0 && bi < L->blocks[0] && bj < L->blocks[1];
}

static void
emit(lod *s, int l, int bi, int bj, double dist)
{
	lod_block *b;

	if (s->n >= s->max)
		return;
	b = &s->out[s->n++];
	b->level = l, b->bi = bi, b->bj = bj;
	b->tau = s->pixels > 0 ? s->pixels /
	    cam_pixels_per_metre(s->c, dist) : -1;
}

static void
visit(lod *s, int l, int bi, int bj)
{
	double lo[3], hi[3], cull_lo[3], dist, base;
	const pyramid_level *L = &s->w->ix.lev[l];
	int ok = 1;

	world_block_box(s->w, l, bi, bj, lo, hi);
	memcpy(cull_lo, lo, sizeof lo);
	cull_lo[2] = s->w->base; /* skirts */
	if (box_outside(s->planes, cull_lo, hi))
		return;
	dist = cam_box_distance(s->c, lo, hi);
	base = L->base[bj * L->blocks[0] + bi];
	if (l == 0 || (s->pixels > 0 &&
	    base * cam_pixels_per_metre(s->c, dist) <= s->pixels)) {
		emit(s, l, bi, bj, dist);
		return;
	}
	/* refine only when every child can be drawn (asking loads them) */
	for (int k = 0; k < 4; k++) {
		int ci = 2 * bi + (k & 1), cj = 2 * bj + (k >> 1);
		if (exists(s->w, l - 1, ci, cj) && s->ready != NULL &&
		    !s->ready(s->ctx, l - 1, ci, cj))
			ok = 0;
	}
	if (!ok) {
		emit(s, l, bi, bj, dist);
		return;
	}
	for (int k = 0; k < 4; k++) {
		int ci = 2 * bi + (k & 1), cj = 2 * bj + (k >> 1);
		if (exists(s->w, l - 1, ci, cj))
			visit(s, l - 1, ci, cj);
	}
}

int
lod_select(const world *w, const camera *c, double pixels,
    lod_ready_fn ready, void *ctx, lod_block *out, int max)
{
	lod s = { w, c, { { 0 } }, pixels, ready, ctx, out, 0, max };
	int top = w->ix.nlevels - 1;
	const pyramid_level *L = &w->ix.lev[top];

	cam_frustum(c, s.planes);
	for (int bj = 0; bj < L->blocks[1]; bj++)
		for (int bi = 0; bi < L->blocks[0]; bi++)
			if (ready == NULL || ready(ctx, top, bi, bj))
				visit(&s, top, bi, bj);
	return s.n;
}
