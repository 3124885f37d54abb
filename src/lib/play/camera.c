/* camera.c - matrices, frustum, projection and named views (see
 * camera.h). */
#include "play/camera.h"

#include <assert.h>
#include <string.h>

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
cross(const double a[3], const double b[3], double r[3])
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
	cross(f, c->up, s);
	unit(s);
	cross(s, f, u);
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

	assert(c->width > 0 && c->height > 0);
	memset(m, 0, 16 * sizeof(double));
	m[0][0] = t / a;
	m[1][1] = t;
	m[2][2] = -(f + n) / (f - n);
	m[2][3] = -2 * f * n / (f - n);
	m[3][2] = -1;
}

void
camera_matrices(const camera *c, float view[16], float proj[16])
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
camera_frustum(const camera *c, double planes[6][4])
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

double
camera_pixels_per_metre(const camera *c, double d)
{
	double k = c->height / 2.0 / tan(c->fovy / 2);

	return k / (d > 1e-6 ? d : 1e-6);
}

double
camera_box_distance(const camera *c, const double lo[3], const double hi[3])
{
	double s = 0;

	for (int k = 0; k < 3; k++) {
		double d = c->eye[k] < lo[k] ? lo[k] - c->eye[k] :
		    c->eye[k] > hi[k] ? c->eye[k] - hi[k] : 0;
		s += d * d;
	}
	return sqrt(s);
}

void
camera_project(const camera *c, const double p[3], int px[2])
{
	float view[16], proj[16];
	double eye[4], clip[4];

	camera_matrices(c, view, proj);
	/* column-major: clip = proj (view (p, 1)) */
	for (int r = 0; r < 4; r++) {
		eye[r] = view[12 + r];
		for (int a = 0; a < 3; a++)
			eye[r] += view[4 * a + r] * p[a];
	}
	for (int r = 0; r < 4; r++) {
		clip[r] = 0;
		for (int a = 0; a < 4; a++)
			clip[r] += proj[4 * a + r] * eye[a];
	}
	px[0] = (int)floor((clip[0] / clip[3] + 1) / 2 * c->width);
	px[1] = (int)floor((1 - clip[1] / clip[3]) / 2 * c->height);
}

void
camera_fit_depth(camera *c, const world *w)
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
	    0.5 * camera_box_distance(c, lo, hi)));
}

void
camera_look(camera *c, const world *w, const double eye[3],
    const double target[3])
{
	double d[3], n;

	for (int a = 0; a < 3; a++)
		c->eye[a] = eye[a], c->target[a] = target[a];
	sub(target, eye, d);
	n = sqrt(dot(d, d));
	c->up[0] = 0, c->up[1] = 0, c->up[2] = 1;
	if (n > 0 && fabs(d[2]) > 0.999 * n)
		c->up[1] = 1, c->up[2] = 0;
	camera_fit_depth(c, w);
}

int
camera_view_known(const char *name)
{
	return strcmp(name, "overview") == 0 || strcmp(name, "oblique") == 0;
}

int
camera_named(camera *c, const world *w, const char *name)
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
	camera_fit_depth(c, w);
	return 0;
}
