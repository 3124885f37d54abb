/* t_quadric_pair - quadric_min_3d2, the two-lane Jacobi of the 3D solver,
 * gives bit for bit what two quadric_min_3d calls give: on random full-rank
 * quadrics, flat (rank 1) and ridge-like (rank 2) ones, zero and diagonal
 * ones (whose pivots are 0 from the start), and pairs of one of each, so
 * that the lanes converge after different numbers of sweeps. */
#include <math.h>
#include <string.h>

#include "qem/quadric.h"
#include "tap.h"
#include "urand.h"

/* Kind 0 random planes, 1 one plane (flat), 2 two (ridge), 3 zero, 4 a
 * diagonal A, 5 four planes of one slope but for a tiny tilt. */
static void
make(quadric *q, int kind, unsigned *s)
{
	int np = kind == 0 ? 4 : kind == 1 ? 1 : kind == 2 ? 2 : 0;

	quadric_zero(q);
	for (int k = 0; k < np; k++) {
		double n[3] = { urand(s), urand(s), urand(s) + 2 }, l;
		l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int i = 0; i < 3; i++)
			n[i] /= l;
		quadric_add_plane(q, n, 10 * urand(s), 1 + urand(s));
	}
	if (kind == 4) {
		q->a[QUADRIC_A11] = 2 + urand(s), q->a[QUADRIC_A22] = 1;
		q->a[QUADRIC_A33] = 3, q->b[0] = urand(s), q->b[2] = urand(s);
	}
	for (int k = 0; kind == 5 && k < 4; k++) {
		double n[3] = { 0.6 + 1e-9 * urand(s), 0, 0.8 };
		quadric_add_plane(q, n, urand(s), 1);
	}
}

static int
same(const double a[3], const double b[3])
{
	return memcmp(a, b, 3 * sizeof *a) == 0;
}

int
main(void)
{
	unsigned s = 7;
	int n = 0, bad = 0, rank[4] = { 0 };

	for (int ka = 0; ka < 6; ka++)
		for (int kb = 0; kb < 6; kb++)
			for (int t = 0; t < 200; t++) {
				quadric q0, q1;
				double a0[3], a1[3], b0[3], b1[3];
				make(&q0, ka, &s), make(&q1, kb, &s);
				rank[quadric_min_3d(&q0, 1e-3, a0)]++;
				quadric_min_3d(&q1, 1e-3, a1);
				quadric_min_3d2(&q0, &q1, 1e-3, b0, b1);
				bad += !same(a0, b0) || !same(a1, b1);
				n++;
			}
	ok(bad == 0, "quadric_min_3d2: %d of %d pairs differ from two "
	    "quadric_min_3d calls", bad, n);
	ok(rank[0] > 0 && rank[1] > 0 && rank[2] > 0 && rank[3] > 0,
	    "the pairs hold every rank (%d %d %d %d)", rank[0], rank[1],
	    rank[2], rank[3]);
	return tap_done();
}
