/* t_quadric - the quadric algebra (quadric.h): plane and triangle
 * quadrics, translation, evaluation, the eigen-decomposition and the
 * minimisers, on random quadrics and on flat and ridge-like ones. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "qem/quadric.h"
#include "tap.h"
#include "urand.h"

static void
rand_quadric(quadric *q, unsigned *s)
{
	quadric_zero(q);
	for (int k = 0; k < 4; k++) {
		double n[3] = { urand(s), urand(s), urand(s) + 2 }, l;
		l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int i = 0; i < 3; i++)
			n[i] /= l;
		quadric_add_plane(q, n, 10 * urand(s), 1 + urand(s));
	}
}

static void
test_algebra(void)
{
	unsigned s = 1;
	double worst = 0, worst2 = 0, worst3 = 0;

	/* A plane quadric is the squared, weighted distance to the plane. */
	for (int t = 0; t < 1000; t++) {
		quadric q;
		double n[3] = { 0.6, 0, 0.8 }, v[3] = { urand(&s), urand(&s),
			urand(&s) }, d = urand(&s), w = 3;
		double dist = n[0] * v[0] + n[1] * v[1] + n[2] * v[2] + d;
		quadric_zero(&q);
		quadric_add_plane(&q, n, d, w);
		worst = fmax(worst, fabs(quadric_eval(&q, v) - w * dist * dist));
	}
	ok(worst < 1e-12, "plane quadric = w * distance^2 (max dev %.2g)",
	    worst);

	/* Translation: Q'(v - d) = Q(v) for every v. */
	for (int t = 0; t < 1000; t++) {
		quadric q, r;
		double d[3], v[3], vd[3];
		rand_quadric(&q, &s);
		for (int k = 0; k < 3; k++) {
			d[k] = 100 * urand(&s), v[k] = 100 * urand(&s);
			vd[k] = v[k] - d[k];
		}
		r = q;
		quadric_translate(&r, d);
		worst2 = fmax(worst2, fabs(quadric_eval(&r, vd) - quadric_eval(&q, v)) /
		    (1 + fabs(quadric_eval(&q, v))));
	}
	ok(worst2 < 1e-12, "translation identity Q'(v-d) = Q(v) "
	    "(max rel dev %.2g)", worst2);

	/* Triangle quadric: zero at its corners, area * dist^2 off it. */
	{
		quadric q;
		double p0[3] = { 0, 0, 0 }, p1[3] = { 30, 0, 3 },
		       p2[3] = { 0, 20, -4 }, area, n[3], l, off[3];
		quadric_zero(&q);
		area = quadric_add_triangle(&q, p0, p1, p2, 1);
		/* n = (p1 - p0) x (p2 - p0) */
		n[0] = 0 * (-4) - 3 * 20;
		n[1] = 3 * 0 - 30 * (-4);
		n[2] = 30 * 20 - 0 * 0;
		l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int k = 0; k < 3; k++)
			off[k] = 5 * n[k] / l;
		ok(fabs(area - l / 2) < 1e-9 && fabs(quadric_eval(&q, p1)) < 1e-9 &&
		    fabs(quadric_eval(&q, p2)) < 1e-9 &&
		    fabs(quadric_eval(&q, off) - area * 25) < 1e-6 * area,
		    "triangle quadric: 0 at corners, area*d^2 at distance d");
	}

	/* Eigen-decomposition reconstructs A; the 3D minimiser solves
	 * A v = -b for full rank. */
	for (int t = 0; t < 1000; t++) {
		quadric q;
		double w[3], V[3][3], v[3], g[3], a[3][3];
		rand_quadric(&q, &s);
		quadric_eigen(q.a, w, V);
		a[0][0] = q.a[0], a[0][1] = a[1][0] = q.a[1];
		a[0][2] = a[2][0] = q.a[2], a[1][1] = q.a[3];
		a[1][2] = a[2][1] = q.a[4], a[2][2] = q.a[5];
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++) {
				double r = 0;
				for (int k = 0; k < 3; k++)
					r += V[i][k] * w[k] * V[j][k];
				worst3 = fmax(worst3, fabs(r - a[i][j]));
			}
		quadric_min_3d(&q, 1e-9, v);
		for (int i = 0; i < 3; i++)
			g[i] = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2] +
			    q.b[i];
		worst3 = fmax(worst3, fabs(g[0]) + fabs(g[1]) + fabs(g[2]));
	}
	ok(worst3 < 1e-9, "eigen reconstruction and full-rank minimiser "
	    "(max dev %.2g)", worst3);

	/* Flat terrain: rank 1, the minimiser keeps x = y = 0. */
	{
		quadric q;
		double n[3] = { 0, 0, 1 }, v[3];
		int rank;
		quadric_zero(&q);
		quadric_add_plane(&q, n, -7, 2);
		rank = quadric_min_3d(&q, 1e-3, v);
		ok(rank == 1 && v[0] == 0 && v[1] == 0 && fabs(v[2] - 7) < 1e-12,
		    "flat quadric: rank 1, x = y = 0, z on the plane");
	}
	/* Ridge: rank 2, the vertex stays on its line along the ridge. */
	{
		quadric q;
		double n1[3] = { 0.6, 0, 0.8 }, n2[3] = { -0.6, 0, 0.8 }, v[3];
		int rank;
		quadric_zero(&q);
		/* planes z = -0.75 (x - 2) and z = 0.75 (x - 2): ridge x = 2 */
		quadric_add_plane(&q, n1, -0.6 * 2, 1);
		quadric_add_plane(&q, n2, 0.6 * 2, 1);
		rank = quadric_min_3d(&q, 1e-3, v);
		ok(rank == 2 && fabs(v[0] - 2) < 1e-12 && fabs(v[1]) < 1e-12 &&
		    fabs(v[2]) < 1e-12, "ridge quadric: rank 2, on the crest, "
		    "y free and kept at 0 (v = %g %g %g)", v[0], v[1], v[2]);
	}
}

int
main(void)
{
	test_algebra();
	return tap_done();
}
