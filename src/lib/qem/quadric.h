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
#ifdef __SSE2__
#include <emmintrin.h>
#endif

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

/* Two doubles, or two masks, a lane each: GCC's and Clang's generic
 * vectors. Their +, -, *, / and comparisons work lane by lane in IEEE
 * double, exactly as on scalars, so code written on them gives each
 * lane the bits the scalar code would, two at a time. */
typedef double quadric_v2 __attribute__((vector_size(2 * sizeof(double))));
typedef long long quadric_m2
    __attribute__((vector_size(2 * sizeof(long long))));

/* Correctly rounded square roots, lane by lane (sqrt is): one
 * instruction for both lanes where there is one. */
static inline quadric_v2
quadric_v2_sqrt(quadric_v2 x)
{
#ifdef __SSE2__
	return (quadric_v2)_mm_sqrt_pd((__m128d)x);
#else
	return (quadric_v2){ sqrt(x[0]), sqrt(x[1]) };
#endif
}

/* The x, y parts of two triangles' edges e1 = p1 - p0 and e2 = p2 - p0 (a
 * triangle a lane), with the terms of their quadrics that depend on them
 * only: the z of e1 x e2 and its square. Triangles that differ in their
 * heights only, as a grid's cells along a row do, share one. */
typedef struct {
	quadric_v2 x1, y1, x2, y2;
	quadric_v2 n2, n2n2; /* x1 y2 - y1 x2, its square */
} quadric_xy2;

static inline void
quadric_xy2_init(quadric_xy2 *t, quadric_v2 x1, quadric_v2 y1,
    quadric_v2 x2, quadric_v2 y2)
{
	t->x1 = x1, t->y1 = y1, t->x2 = x2, t->y2 = y2;
	t->n2 = x1 * y2 - y1 * x2;
	t->n2n2 = t->n2 * t->n2;
}

/* The A that quadric_add_triangle(q, p0, p1, p2, w) adds to a zero q, for
 * two triangles a lane each: the x, y parts t and the z parts z1, z2 of
 * their edges, formed as it forms them. b and c are left out (a plane
 * through the frame's origin has none). Bit for bit, operation for
 * operation, but for the sign of zero: quadric_add_triangle adds each
 * coefficient to q's +0, which turns a -0 product into +0, and this
 * leaves the -0. A sum begun at +0 does not tell them apart (x + -0 and
 * x + +0 differ only for x = -0, which such a sum never is), nor does
 * subtracting them from one. Returns the triangles' len (twice their
 * area): a lane whose len is not > 0 is degenerate (quadric_add_triangle
 * adds nothing) and its A is junk. Inline, so that a loop over a grid's
 * cells computes t once. */
static inline quadric_v2
quadric_triangle_a2(const quadric_xy2 *t, quadric_v2 z1, quadric_v2 z2,
    double w, quadric_v2 a[6])
{
	quadric_v2 n0 = t->y1 * z2 - z1 * t->y2;
	quadric_v2 n1 = z1 * t->x2 - t->x1 * z2;
	quadric_v2 n2 = t->n2;
	quadric_v2 len = quadric_v2_sqrt(n0 * n0 + n1 * n1 + t->n2n2);
	quadric_v2 s, s0, s1, s2;

	n0 /= len, n1 /= len, n2 /= len;
	s = w * 0.5 * len;
	s0 = s * n0, s1 = s * n1, s2 = s * n2;
	a[QUADRIC_A11] = s0 * n0;
	a[QUADRIC_A12] = s0 * n1;
	a[QUADRIC_A13] = s0 * n2;
	a[QUADRIC_A22] = s1 * n1;
	a[QUADRIC_A23] = s1 * n2;
	a[QUADRIC_A33] = s2 * n2;
	return len;
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
/* quadric_min_3d of two quadrics at once (a Jacobi sweep on both lanes):
 * the very values of two calls. */
void quadric_min_3d2(const quadric *q0, const quadric *q1, double rel,
    double v0[3], double v1[3]);

#endif
