/* bound.c - how far a tile's stored triangles stand from the surface the
 * pyramid's errors are about.
 *
 * The pyramid bounds the DEM's distance from triangles that are linear in
 * the grid (height interpolated over the grid's cells). A renderer draws
 * flat triangles in ECEF, through float32 vertices: these sag below the
 * grid-linear surface by about d^2/8R (the Earth's curvature; 70 m for a
 * 60 km triangle) and move by the float rounding. The difference, the
 * height along the ellipsoid's normal of the drawn triangle minus the
 * grid-linear height, is a smooth function over the triangle, at vertex
 * i d_i (rounding), quadratic to the leading order: d = sum l_i d_i +
 * sum_{i<j} c_ij l_i l_j in barycentric l, c_ij / 4 being its value at
 * the midpoint of edge ij less (d_i + d_j) / 2. So |d| <= max |d_i| +
 * max |q| over the triangle, q = sum c_ij l_i l_j: on an edge at most
 * |c_ij| / 4, inside at its critical point (quad_max); d_i and c_ij
 * measured at the vertices and midpoints, exactly (PROJ, the WGS 84
 * closed form). */
#include <math.h>
#include <string.h>

#include "tiles3d/t3_impl.h"

/* Height along the normal u through the ellipsoid's point s where it
 * meets the plane through a with normal n, less h: how far the drawn
 * triangle stands above the point of height h. A plane within 6
 * degrees of the normal (a wall, steeper than any DEM's triangle: the
 * row of a pole, whose vertices all meet in one point at their several
 * heights, or padding kept on the globe) meets it far away or never;
 * there the distance from the point to the plane, how far the wall
 * stands from the point; a triangle of no area draws nothing. */
static double
plane_height(const double s[3], const double u[3], const double a[3],
    const double n[3], double h)
{
	double num = 0, den = 0, nn = 0;

	for (int q = 0; q < 3; q++) {
		num += (a[q] - s[q]) * n[q], den += u[q] * n[q];
		nn += n[q] * n[q];
	}
	nn = sqrt(nn);
	if (fabs(den) >= 0.1 * nn && fabs(den) > 0)
		return num / den - h;
	return nn > 0 ? (num - h * den) / nn : 0;
}

/* Largest |q| over the triangle, q = c0 l0 l1 + c1 l1 l2 + c2 l2 l0:
 * the edges' midpoints (|c| / 4), and the critical point of q on
 * l0 + l1 + l2 = 1 when it lies inside, where q = mu / 2 (q is
 * homogeneous of degree 2). Gaussian elimination with pivoting. */
static double
quad_max(const double c[3])
{
	double m[4][5] = {
		{ 0, c[0], c[2], -1, 0 }, { c[0], 0, c[1], -1, 0 },
		{ c[2], c[1], 0, -1, 0 }, { 1, 1, 1, 0, 1 },
	};
	double best = fmax(fabs(c[0]), fmax(fabs(c[1]), fabs(c[2]))) / 4;
	double x[4], scale = 4 * best + 1e-300;

	for (int k = 0; k < 4; k++) {
		int p = k;
		for (int i = k + 1; i < 4; i++)
			if (fabs(m[i][k]) > fabs(m[p][k]))
				p = i;
		if (fabs(m[p][k]) < 1e-12 * scale)
			return best; /* no single critical point */
		for (int j = 0; j < 5; j++) {
			double t = m[k][j];
			m[k][j] = m[p][j], m[p][j] = t;
		}
		for (int i = k + 1; i < 4; i++) {
			double f = m[i][k] / m[k][k];
			for (int j = k; j < 5; j++)
				m[i][j] -= f * m[k][j];
		}
	}
	for (int k = 3; k >= 0; k--) {
		x[k] = m[k][4];
		for (int j = k + 1; j < 4; j++)
			x[k] -= m[k][j] * x[j];
		x[k] /= m[k][k];
	}
	if (x[0] >= 0 && x[1] >= 0 && x[2] >= 0)
		best = fmax(best, fabs(x[3]) / 2);
	return best;
}

/* The ellipsoid's point and normal under the midpoint of grid vertices
 * a and b in level-0 grid places: a grid vertex's, or through PROJ
 * (leaves, QEM-3D levels). */
static int
midpoint(t3_work *w, const georef *g, const t3_tile *t, int a, int b,
    double s[3], double u[3], tl_err *e)
{
	int sc = a % BT_SIZE + b % BT_SIZE, sr = a / BT_SIZE + b / BT_SIZE;
	double lon, lat, z = 0;

	if (!t->displaced && !((sc | sr) & 1)) {
		int k = sr / 2 * BT_SIZE + sc / 2;
		memcpy(s, &w->foot[3 * k], 3 * sizeof *s);
		memcpy(u, &w->up[3 * k], 3 * sizeof *u);
		return 0;
	}
	geo_grid_crs(g, 0.5 * (w->px[a] + w->px[b]),
	    0.5 * (w->py[a] + w->py[b]), &lon, &lat);
	if (geo_proj_lonlat(&w->proj, &lon, &lat, &z, 1, e) < 0)
		return -1;
	geo_ellipsoid(lon, lat, s, u);
	return 0;
}

int
t3_flat_bound(t3_work *w, const georef *g, const t3_tile *t,
    const uint16_t k[3], const double p[3][3], double *out, tl_err *e)
{
	double n[3], u[3], v[3], d[3], c[3], dmax = 0;

	for (int q = 0; q < 3; q++)
		u[q] = p[1][q] - p[0][q], v[q] = p[2][q] - p[0][q];
	n[0] = u[1] * v[2] - u[2] * v[1];
	n[1] = u[2] * v[0] - u[0] * v[2];
	n[2] = u[0] * v[1] - u[1] * v[0];
	for (int q = 0; q < 3; q++) {
		d[q] = plane_height(&w->foot[3 * k[q]], &w->up[3 * k[q]], p[0],
		    n, w->h[k[q]]);
		dmax = fmax(dmax, fabs(d[q]));
	}
	for (int q = 0; q < 3; q++) {
		int a = k[q], b = k[(q + 1) % 3];
		double s[3], up[3], dm;
		if (midpoint(w, g, t, a, b, s, up, e) < 0)
			return -1;
		dm = plane_height(s, up, p[0], n, 0.5 * (w->h[a] + w->h[b]));
		c[q] = 4 * (dm - 0.5 * (d[q] + d[(q + 1) % 3]));
	}
	*out = dmax + quad_max(c);
	return 0;
}
