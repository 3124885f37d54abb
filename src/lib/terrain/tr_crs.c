/* tr_crs.c - the CRS term of a projected DEM's tile bound (tr_bound.c):
 * how far the drawn piece of a selected triangle, straight in
 * longitude and latitude, is from the selection, straight in the grid.
 *
 * S is a selected triangle (a piece of one, cut to the grid: tr_cut.c)
 * with level-0 places G_i and heights h_i, P its plane over the grid;
 * T' the straight triangle of the vertices' images l_i = phi(G_i) in
 * degrees, F_S the heights linear over T' (the tile's pieces of S carry
 * it: tr_clip.c). A_S, the affine map with A_S(l_i) = G_i, makes F_S =
 * P o A_S. A sample at place g, drawn at l = phi(g) under a piece of S,
 * is measured against Z(g), the selection's height there (the plane of
 * the selected triangle holding g, tr_gsel.c). With psi = phi^-1,
 *
 *   |F_S(l) - Z(g)| <= |P(a) - P(g)| + |P(g) - Z(g)|,  a = A_S(l).
 *
 * a - g = A_S(l) - psi(l) = sum b_i R_i (b_i the coordinates of l in T',
 * R_i Taylor's remainder of psi from l to l_i; sum b_i (l_i - l) = 0),
 * so |a - g| <= e = 1/2 M rho^2 for l in T' (M bounds |D2 psi[d, d]|,
 * tr_curve.c; sum b_i |l_i - l|^2 <= rho^2, T''s least enclosing circle
 * squared); for l up to delta outside T' (a decoded corner's place) e
 * gains (|D A_S| + |D psi|) delta. The first term is at most |grad P| e.
 * The second is 0 for g in S; else g lies within e + |D A_S| delta of S
 * (A_S maps T' onto S) and P - Z, 0 on S, grows by at most |grad P| + G
 * per cell from it, G the steepest selected triangle of the tile (those
 * within a twentieth of a tile of it, tr_cut.c's keep_grid: the places
 * reached lie within reach |D phi| degrees of S's piece there, which
 * must be under half that). So
 *
 *   C = |grad P| e + (|grad P| + G) (e + |D A_S| delta).
 *
 * The reach e + |D A_S| delta also bounds how far inside the grid a
 * sample drawn past S's outline edge can lie (tr_bound's band). */
#include <math.h>

#include "terrain/tr_impl.h"

/* The least enclosing circle's radius squared of the triangle x, y. */
static double
enclosing(const double *x, const double *y)
{
	double l[3], h;
	int k = 0;

	for (int i = 0; i < 3; i++) {
		int a = (i + 1) % 3, b = (i + 2) % 3;
		l[i] = (x[a] - x[b]) * (x[a] - x[b]) + (y[a] - y[b]) * (y[a] -
		    y[b]);
		k = l[i] > l[k] ? i : k;
	}
	if (l[k] >= l[(k + 1) % 3] + l[(k + 2) % 3])
		return l[k] / 4; /* right or obtuse: half the longest */
	h = 2 * (l[0] * l[1] + l[1] * l[2] + l[2] * l[0]) - (l[0] * l[0] +
	    l[1] * l[1] + l[2] * l[2]);
	return dmax(l[k] / 4, l[0] * l[1] * l[2] / h);
}

/* The distance from (px, py) to the triangle x, y (0 inside). */
static double
outside(const double *x, const double *y, double px, double py)
{
	double s = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] -
	    x[0]), d = INFINITY;
	int in = 1;

	for (int i = 0; i < 3 && in; i++) { /* each side's same way */
		int j = (i + 1) % 3;
		double c = (x[j] - x[i]) * (py - y[i]) - (y[j] - y[i]) * (px -
		    x[i]);
		in = c * s >= 0;
	}
	if (in)
		return 0;
	for (int i = 0; i < 3; i++) {
		int j = (i + 1) % 3;
		double ex = x[j] - x[i], ey = y[j] - y[i];
		double qx = px - x[i], qy = py - y[i], l2 = ex * ex + ey * ey;
		double t = l2 > 0 ? dmin(1, dmax(0, (ex * qx + ey * qy) / l2)) : 0;
		qx -= t * ex, qy -= t * ey;
		d = dmin(d, qx * qx + qy * qy);
	}
	return sqrt(d);
}

/* |D A_S| (Frobenius) of selection triangle f; -1 when T' or S is
 * degenerate. */
static double
affine_norm(const tr_tri *f)
{
	double lx1 = f->x[1] - f->x[0], lx2 = f->x[2] - f->x[0];
	double ly1 = f->y[1] - f->y[0], ly2 = f->y[2] - f->y[0];
	double gx1 = f->gx[1] - f->gx[0], gx2 = f->gx[2] - f->gx[0];
	double gy1 = f->gy[1] - f->gy[0], gy2 = f->gy[2] - f->gy[0];
	double det = lx1 * ly2 - lx2 * ly1;
	/* D A = G L^-1, L = (l1 - l0, l2 - l0) by columns */
	double a = (gx1 * ly2 - gx2 * ly1) / det, b = (gx2 * lx1 - gx1 * lx2) /
	    det, c = (gy1 * ly2 - gy2 * ly1) / det, d = (gy2 * lx1 - gy1 *
	    lx2) / det;
	double n = sqrt(a * a + b * b + c * c + d * d);

	return isfinite(n) && n > 0 ? n : -1;
}

/* |grad P| of f in the grid, metres a cell; -1 when degenerate. */
static double
slope(const tr_tri *f)
{
	double x1 = f->gx[1] - f->gx[0], y1 = f->gy[1] - f->gy[0];
	double x2 = f->gx[2] - f->gx[0], y2 = f->gy[2] - f->gy[0];
	double h1 = f->h[1] - f->h[0], h2 = f->h[2] - f->h[0];
	double d = x1 * y2 - x2 * y1;
	double a = (y2 * h1 - y1 * h2) / d, b = (x1 * h2 - x2 * h1) / d;
	double n = sqrt(a * a + b * b);

	return isfinite(n) ? n : -1;
}

void
tr_crs_prep(const tr_grid *g, const tr_tri *f, double pre[3])
{
	double e = 0.5 * g->d2psi * enclosing(f->x, f->y);

	pre[0] = affine_norm(f), pre[1] = slope(f);
	pre[2] = isfinite(e) ? e : INFINITY;
}

double
tr_crs(const tr_grid *g, const tr_tri *f, const double pre[3],
    const double xd[3], const double yd[3], double gmax, double margin,
    double *reach)
{
	double da = pre[0], gp = pre[1], delta = 0, e, c;

	*reach = INFINITY;
	if (da < 0 || gp < 0)
		return INFINITY;
	for (int j = 0; j < 3; j++)
		delta = dmax(delta, outside(f->x, f->y, xd[j], yd[j]));
	e = pre[2] + (da + g->d1psi) * delta;
	*reach = e + da * delta;
	/* G holds the triangles within margin of the tile, and the places
	 * this may reach lie within reach cells of S: less than half the
	 * margin, or no bound */
	if (!(2 * *reach * g->d1phi < margin))
		return INFINITY;
	c = gp * e + (gp + gmax) * *reach;
	return isfinite(c) ? c : INFINITY;
}
