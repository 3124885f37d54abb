/* quadric.h - Garland-Heckbert error quadrics, in double: all the algebra of
 * QEM-filtering in one place.
 *
 * Q(v) = v'Av + 2b'v + c for v = (x, y, z) in metres, in the frame of the
 * vertex that owns the quadric (x along columns, y along rows, z up, origin
 * at the vertex's grid position and reference height). A is symmetric and
 * stored as a[] = a11 a12 a13 a22 a23 a33. */
#ifndef TL_QUADRIC_H
#define TL_QUADRIC_H

#include <math.h>

typedef struct {
	double a[6];
	double b[3];
	double c;
} quadric;

/* The FQM stores a quadric as its 10 Q.* channels (fqm.h). */
_Static_assert(sizeof(quadric) == 10 * sizeof(double),
    "a quadric is a[6], b[3], c");

/* The order of A's coefficients in a[]. */
enum {
	QUADRIC_A11, QUADRIC_A12, QUADRIC_A13, QUADRIC_A22, QUADRIC_A23,
	QUADRIC_A33
};

void quadric_zero(quadric *q);
/* q += w * (n.v + d)^2 */
void quadric_add_plane(quadric *q, const double n[3], double d, double w);
/* q += w * area * (plane of p0 p1 p2)^2, the Garland-Heckbert face
 * quadric; returns the area (0 for a degenerate triangle, which adds
 * nothing). Points are in q's frame. */
double quadric_add_triangle(quadric *q, const double p0[3], const double p1[3],
    const double p2[3], double w);
/* The A that quadric_add_triangle(q, p0, p1, p2, w) adds to a zero q,
 * bit for bit, from the edges e1 = p1 - p0 and e2 = p2 - p0 as it forms
 * them: all +0 for a degenerate triangle. b and c are left out (a plane
 * through the frame's origin has none), and it is inline so that a loop
 * over a grid's cells computes only what varies from cell to cell (the
 * edges' x, y parts and the products of them are loop invariants). */
static inline void
quadric_triangle_a(const double e1[3], const double e2[3], double w,
    double a[6])
{
	double n0 = e1[1] * e2[2] - e1[2] * e2[1];
	double n1 = e1[2] * e2[0] - e1[0] * e2[2];
	double n2 = e1[0] * e2[1] - e1[1] * e2[0];
	double len = sqrt(n0 * n0 + n1 * n1 + n2 * n2), s, s0, s1, s2;

	if (!(len > 0)) {
		for (int k = 0; k < 6; k++)
			a[k] = 0;
		return;
	}
	n0 /= len, n1 /= len, n2 /= len;
	s = w * 0.5 * len;
	s0 = s * n0, s1 = s * n1, s2 = s * n2;
	/* 0 + x, as quadric_add_plane adds to a zero quadric: a -0 product
	 * becomes +0 */
	a[QUADRIC_A11] = 0 + s0 * n0;
	a[QUADRIC_A12] = 0 + s0 * n1;
	a[QUADRIC_A13] = 0 + s0 * n2;
	a[QUADRIC_A22] = 0 + s1 * n1;
	a[QUADRIC_A23] = 0 + s1 * n2;
	a[QUADRIC_A33] = 0 + s2 * n2;
}
void quadric_add(quadric *q, const quadric *r, double w); /* q += w r */
/* Re-express q in a frame whose origin is point d of the old frame:
 * A' = A, b' = b + A d, c' = c + 2 b.d + d.A d. */
void quadric_translate(quadric *q, const double d[3]);
double quadric_eval(const quadric *q, const double v[3]);

/* The z minimising Q at fixed (x, y): -(b3 + a13 x + a23 y) / a33. Returns
 * -1 (z untouched) when a33 is not positive, i.e. no plane constrains z. A
 * height field's planes are never vertical, so a33 > 0 wherever any
 * triangle contributed. */
int quadric_min_z(const quadric *q, double x, double y, double *z);

/* The minimum-norm minimiser of Q (v = -A^+ b): eigen-decomposition of A,
 * eigenvalues below rel * (largest) treated as zero, so flat (rank 1) and
 * ridge-like (rank 2) quadrics keep their free directions at the frame
 * origin. Returns the rank used (0: v = 0). */
int quadric_min_3d(const quadric *q, double rel, double v[3]);

/* Eigen-decomposition of the symmetric 3x3 A (Jacobi): eigenvalues w[k],
 * unit eigenvectors in columns V[.][k]. */
void quadric_eigen(const double a[6], double w[3], double V[3][3]);

#endif
