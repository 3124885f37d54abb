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

/* The A that quadric_add_triangle(q, p0, p1, p2, w) adds to a zero q,
 * for two triangles a lane each, bit for bit: from the edges
 * e1 = p1 - p0 and e2 = p2 - p0 as it forms them, b and c left out (a
 * plane through the frame's origin has none). A lane comes out +0, as
 * the zero q, where the triangle is degenerate (the function adds
 * nothing) or keep is 0 (a triangle not to add). Inline, so that a loop
 * over a grid's cells keeps the edges' x, y parts, which depend on the
 * grid only, out of the loop. */
static inline void
quadric_triangle_a2(const quadric_v2 e1[3], const quadric_v2 e2[3],
    quadric_m2 keep, double w, quadric_v2 a[6])
{
	quadric_v2 n0 = e1[1] * e2[2] - e1[2] * e2[1];
	quadric_v2 n1 = e1[2] * e2[0] - e1[0] * e2[2];
	quadric_v2 n2 = e1[0] * e2[1] - e1[1] * e2[0];
	quadric_v2 len = quadric_v2_sqrt(n0 * n0 + n1 * n1 + n2 * n2);
	quadric_v2 s, s0, s1, s2;
	quadric_m2 m = keep & (quadric_m2)(len > 0);

	/* a dropped lane may divide by 0: computed, then masked to +0 (all
	 * zero bits) */
	n0 /= len, n1 /= len, n2 /= len;
	s = w * 0.5 * len;
	s0 = s * n0, s1 = s * n1, s2 = s * n2;
	/* 0 + x, as quadric_add_plane adds to the zero q: -0 becomes +0 */
	a[QUADRIC_A11] = (quadric_v2)((quadric_m2)(0 + s0 * n0) & m);
	a[QUADRIC_A12] = (quadric_v2)((quadric_m2)(0 + s0 * n1) & m);
	a[QUADRIC_A13] = (quadric_v2)((quadric_m2)(0 + s0 * n2) & m);
	a[QUADRIC_A22] = (quadric_v2)((quadric_m2)(0 + s1 * n1) & m);
	a[QUADRIC_A23] = (quadric_v2)((quadric_m2)(0 + s1 * n2) & m);
	a[QUADRIC_A33] = (quadric_v2)((quadric_m2)(0 + s2 * n2) & m);
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
