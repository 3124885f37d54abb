/* tr_curve.c - how far a projected DEM's map bends: bounds, over the
 * DEM, of the first and second derivatives of psi, the map from
 * longitude, latitude (degrees) to level-0 grid places, for the bound of
 * the CRS term (tr_bound.c: a triangle drawn straight in longitude and
 * latitude against the selection straight in the grid).
 *
 * phi = psi^-1 (grid to degrees, PROJ) is sampled on a lattice of step s
 * cells over the grid and one step past it; at each inner node its first
 * and second derivatives come from central differences (second
 * differences at s >= 8 cells: the roundings of the degrees, about 1e-14,
 * against a signal 64 times the second derivative), and psi's from
 * them exactly as the inverse map's (D psi = (D phi)^-1, D2 psi[a, b] =
 * -D psi D2 phi[D psi a, D psi b]). A map PROJ computes is smooth on the
 * scale of the Earth's radius, a million cells of most DEMs: its second
 * derivatives change by a part in 10^4 between nodes, so twice the
 * largest at the nodes bounds them everywhere between, with a floor of a
 * thousandth of the sphere's (|D psi| pi / 180) where they vanish. A
 * lattice that PROJ cannot convert, that reaches a pole (89 degrees) or
 * the antimeridian (a step of 90 degrees), or whose estimates are not
 * finite leaves d2psi INFINITY: the tiles are measured. */
#include <math.h>
#include <stdlib.h>

#include "terrain/tr_impl.h"

#define NODES 256 /* at most a side, about */

/* The largest |v^T M v| over unit v of the symmetric 2x2 M = (a, b; b,
 * c), bounded by that of the matrix of their magnitudes. */
static double
quad(double a, double b, double c)
{
	a = fabs(a), b = fabs(b), c = fabs(c);
	return 0.5 * (a + c) + sqrt(0.25 * (a - c) * (a - c) + b * b);
}

/* psi's bounds at node (i, j) of the nx-wide lattice x (longitudes), y
 * (latitudes) of step s: *d0 |D phi|, *d1 |D psi| (Frobenius norms), *d2
 * the largest |D2 psi[d, d]|; -1 where the map folds there. */
static int
node(const double *x, const double *y, int nx, int i, int j, double s,
    double *d0, double *d1, double *d2)
{
	const double *v[2] = { x, y };
	double J[2][2], H[2][3], K[2][2];
	int k = j * nx + i;

	for (int c = 0; c < 2; c++) {
		const double *f = v[c];
		J[c][0] = (f[k + 1] - f[k - 1]) / (2 * s);
		J[c][1] = (f[k + nx] - f[k - nx]) / (2 * s);
		H[c][0] = (f[k + 1] - 2 * f[k] + f[k - 1]) / (s * s);
		H[c][2] = (f[k + nx] - 2 * f[k] + f[k - nx]) / (s * s);
		H[c][1] = (f[k + nx + 1] - f[k + nx - 1] - f[k - nx + 1] +
		    f[k - nx - 1]) / (4 * s * s);
	}
	double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
	*d0 = sqrt(J[0][0] * J[0][0] + J[0][1] * J[0][1] + J[1][0] *
	    J[1][0] + J[1][1] * J[1][1]);
	if (!(fabs(det) > 0) || !isfinite(det))
		return -1;
	K[0][0] = J[1][1] / det, K[0][1] = -J[0][1] / det;
	K[1][0] = -J[1][0] / det, K[1][1] = J[0][0] / det;
	*d1 = sqrt(K[0][0] * K[0][0] + K[0][1] * K[0][1] + K[1][0] *
	    K[1][0] + K[1][1] * K[1][1]);
	/* T_c = D2 phi_c[K e_a, K e_b]: the second form pulled back */
	double T[2][3];
	for (int c = 0; c < 2; c++) {
		double a = H[c][0], b = H[c][1], d = H[c][2];
		for (int p = 0, q = 0; p < 2; p++)
			for (int r = p; r < 2; r++, q++) {
				double u0 = K[0][p], u1 = K[1][p];
				double w0 = K[0][r], w1 = K[1][r];
				T[c][q] = a * u0 * w0 + b * (u0 * w1 + u1 * w0) +
				    d * u1 * w1;
			}
	}
	double m[2];
	for (int o = 0; o < 2; o++) { /* component o of D2 psi */
		double e[3];
		for (int q = 0; q < 3; q++)
			e[q] = -(K[o][0] * T[0][q] + K[o][1] * T[1][q]);
		m[o] = quad(e[0], e[1], e[2]);
	}
	*d2 = sqrt(m[0] * m[0] + m[1] * m[1]);
	return isfinite(*d0) && isfinite(*d1) && isfinite(*d2) ? 0 : -1;
}

void
tr_curve(tr_grid *g, geo_proj *p, const georef *geo)
{
	int big = g->w0 > g->h0 ? g->w0 : g->h0;
	int s = big / NODES + 1, nx, ny, n;
	double *x, *y, *h = NULL, d0 = 0, d1 = 0, d2 = 0, lat = 0;
	tl_err ignored;

	g->d1phi = g->d1psi = g->d2psi = INFINITY;
	s = s < 8 ? 8 : s;
	nx = (g->w0 - 1) / s + 4, ny = (g->h0 - 1) / s + 4, n = nx * ny;
	x = malloc((size_t)n * sizeof *x), y = malloc((size_t)n * sizeof *y);
	if (x == NULL || y == NULL || (h = calloc((size_t)n, sizeof *h)) ==
	    NULL)
		goto done;
	/* as tr_lonlat converts a projected grid's places */
	for (int j = 0; j < ny; j++)
		for (int i = 0; i < nx; i++)
			geo_grid_crs(geo, (double)(i - 1) * s, (double)(j - 1) * s,
			    &x[j * nx + i], &y[j * nx + i]);
	if (geo_proj_lonlat(p, x, y, h, n, &ignored) < 0)
		goto done;
	for (int k = 0; k < n; k++) {
		lat = fmax(lat, fabs(y[k]));
		if (k % nx > 0 && fabs(x[k] - x[k - 1]) > 90)
			goto done;
		if (k >= nx && fabs(x[k] - x[k - nx]) > 90)
			goto done;
	}
	if (!(lat < 89))
		goto done;
	for (int j = 1; j + 1 < ny; j++)
		for (int i = 1; i + 1 < nx; i++) {
			double a, b, c;
			if (node(x, y, nx, i, j, s, &c, &a, &b) < 0)
				goto done;
			d0 = fmax(d0, c), d1 = fmax(d1, a), d2 = fmax(d2, b);
		}
	/* between nodes: D psi within its change over a step, D2 psi
	 * twice its largest, floored */
	g->d1phi = 1.25 * d0, g->d1psi = 1.25 * d1;
	g->d2psi = fmax(2 * d2, 1e-3 * g->d1psi * M_PI / 180);
	if (!isfinite(g->d1phi) || !isfinite(g->d1psi) ||
	    !isfinite(g->d2psi))
		g->d1phi = g->d1psi = g->d2psi = INFINITY;
done:
	free(x), free(y), free(h);
}
