/* quadric.c - the quadric algebra (see quadric.h). */
#include "qem/quadric.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

void
quadric_zero(quadric *q)
{
	memset(q, 0, sizeof *q);
}

void
quadric_add_plane(quadric *q, const double n[3], double d, double w)
{
	q->a[QUADRIC_A11] += w * n[0] * n[0];
	q->a[QUADRIC_A12] += w * n[0] * n[1];
	q->a[QUADRIC_A13] += w * n[0] * n[2];
	q->a[QUADRIC_A22] += w * n[1] * n[1];
	q->a[QUADRIC_A23] += w * n[1] * n[2];
	q->a[QUADRIC_A33] += w * n[2] * n[2];
	q->b[0] += w * n[0] * d;
	q->b[1] += w * n[1] * d;
	q->b[2] += w * n[2] * d;
	q->c += w * d * d;
}

double
quadric_add_triangle(quadric *q, const double p0[3], const double p1[3],
    const double p2[3], double w)
{
	double e1[3], e2[3], n[3], len;

	for (int k = 0; k < 3; k++) {
		e1[k] = p1[k] - p0[k];
		e2[k] = p2[k] - p0[k];
	}
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
	len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	if (!(len > 0))
		return 0;
	for (int k = 0; k < 3; k++)
		n[k] /= len;
	quadric_add_plane(q, n, -(n[0] * p0[0] + n[1] * p0[1] + n[2] * p0[2]),
	    w * 0.5 * len);
	return 0.5 * len;
}

void
quadric_add(quadric *q, const quadric *r, double w)
{
	for (int k = 0; k < 6; k++)
		q->a[k] += w * r->a[k];
	for (int k = 0; k < 3; k++)
		q->b[k] += w * r->b[k];
	q->c += w * r->c;
}

/* y = A x */
static void
mul_a(const double a[6], const double x[3], double y[3])
{
	y[0] = a[QUADRIC_A11] * x[0] + a[QUADRIC_A12] * x[1] +
	    a[QUADRIC_A13] * x[2];
	y[1] = a[QUADRIC_A12] * x[0] + a[QUADRIC_A22] * x[1] +
	    a[QUADRIC_A23] * x[2];
	y[2] = a[QUADRIC_A13] * x[0] + a[QUADRIC_A23] * x[1] +
	    a[QUADRIC_A33] * x[2];
}

void
quadric_translate(quadric *q, const double d[3])
{
	double ad[3];

	mul_a(q->a, d, ad);
	q->c += 2 * (q->b[0] * d[0] + q->b[1] * d[1] + q->b[2] * d[2]) +
	    ad[0] * d[0] + ad[1] * d[1] + ad[2] * d[2];
	for (int k = 0; k < 3; k++)
		q->b[k] += ad[k];
}

double
quadric_eval(const quadric *q, const double v[3])
{
	double av[3];

	mul_a(q->a, v, av);
	return av[0] * v[0] + av[1] * v[1] + av[2] * v[2] +
	    2 * (q->b[0] * v[0] + q->b[1] * v[1] + q->b[2] * v[2]) + q->c;
}

int
quadric_min_z(const quadric *q, double x, double y, double *z)
{
	double a33 = q->a[QUADRIC_A33];

	if (!(a33 > 0) || !isfinite(a33))
		return -1;
	*z = -(q->b[2] + q->a[QUADRIC_A13] * x + q->a[QUADRIC_A23] * y) / a33;
	return isfinite(*z) ? 0 : -1;
}

void
quadric_eigen(const double a[6], double w[3], double V[3][3])
{
	double m[3][3] = {
		{ a[QUADRIC_A11], a[QUADRIC_A12], a[QUADRIC_A13] },
		{ a[QUADRIC_A12], a[QUADRIC_A22], a[QUADRIC_A23] },
		{ a[QUADRIC_A13], a[QUADRIC_A23], a[QUADRIC_A33] },
	};

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			V[i][j] = i == j;
	/* Cyclic Jacobi: exact enough after a few sweeps for 3x3. */
	for (int sweep = 0; sweep < 32; sweep++) {
		double off = fabs(m[0][1]) + fabs(m[0][2]) + fabs(m[1][2]);
		double scale = fabs(m[0][0]) + fabs(m[1][1]) + fabs(m[2][2]);
		if (off <= 1e-15 * scale || off == 0)
			break;
		for (int p = 0; p < 2; p++)
			for (int r = p + 1; r < 3; r++) {
				double t, c, s, theta;
				if (m[p][r] == 0)
					continue;
				theta = (m[r][r] - m[p][p]) / (2 * m[p][r]);
				t = (theta >= 0 ? 1 : -1) /
				    (fabs(theta) + sqrt(theta * theta + 1));
				c = 1 / sqrt(t * t + 1);
				s = t * c;
				for (int k = 0; k < 3; k++) { /* m = J' m J */
					double mkp = m[k][p], mkr = m[k][r];
					m[k][p] = c * mkp - s * mkr;
					m[k][r] = s * mkp + c * mkr;
				}
				for (int k = 0; k < 3; k++) {
					double mpk = m[p][k], mrk = m[r][k];
					m[p][k] = c * mpk - s * mrk;
					m[r][k] = s * mpk + c * mrk;
				}
				for (int k = 0; k < 3; k++) {
					double vkp = V[k][p], vkr = V[k][r];
					V[k][p] = c * vkp - s * vkr;
					V[k][r] = s * vkp + c * vkr;
				}
			}
	}
	for (int k = 0; k < 3; k++)
		w[k] = m[k][k];
}

/* quadric_min_3d from A's eigen-decomposition. */
static int
min_3d(const quadric *q, double rel, const double w[3],
    const double V[3][3], double v[3])
{
	double wmax = 0;
	int rank = 0;

	v[0] = v[1] = v[2] = 0;
	for (int k = 0; k < 3; k++)
		if (w[k] > wmax)
			wmax = w[k];
	if (!(wmax > 0) || !isfinite(wmax))
		return 0;
	/* v = -sum_k (u_k . b / w_k) u_k over the kept eigenpairs. */
	for (int k = 0; k < 3; k++) {
		double ub;
		if (!(w[k] > rel * wmax))
			continue;
		ub = V[0][k] * q->b[0] + V[1][k] * q->b[1] + V[2][k] * q->b[2];
		for (int i = 0; i < 3; i++)
			v[i] -= ub / w[k] * V[i][k];
		rank++;
	}
	return rank;
}

int
quadric_min_3d(const quadric *q, double rel, double v[3])
{
	double w[3], V[3][3];

	quadric_eigen(q->a, w, V);
	return min_3d(q, rel, w, V, v);
}

typedef quadric_v2 v2;
typedef quadric_m2 m2;

static inline v2
v2_abs(v2 x)
{
	return (v2)((m2)x & (m2){ INT64_MAX, INT64_MAX });
}

/* Lane by lane: a where k, else b. */
static inline v2
v2_sel(m2 k, v2 a, v2 b)
{
	return (v2)(((m2)a & k) | ((m2)b & ~k));
}

/* One Jacobi rotation of the pair (*x, *y) where go: c x - s y, s x + c y,
 * the scalar code's operations. */
static inline void
rot2(v2 *x, v2 *y, v2 c, v2 s, m2 go)
{
	v2 a = *x, b = *y;

	*x = v2_sel(go, c * a - s * b, a);
	*y = v2_sel(go, s * a + c * b, b);
}

/* quadric_eigen on two lanes: a lane's rotations are those of its own
 * call (a lane past its own convergence, or whose pivot is 0, keeps its
 * values), each rotation's operations those of the scalar code. */
static void
eigen2(const double *a0, const double *a1, v2 w[3], v2 V[3][3])
{
	static const int ix[3][3] = {
		{ QUADRIC_A11, QUADRIC_A12, QUADRIC_A13 },
		{ QUADRIC_A12, QUADRIC_A22, QUADRIC_A23 },
		{ QUADRIC_A13, QUADRIC_A23, QUADRIC_A33 },
	};
	v2 m[3][3];
	m2 live = { -1, -1 };

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			m[i][j] = (v2){ a0[ix[i][j]], a1[ix[i][j]] };
			V[i][j] = (v2){ i == j, i == j };
		}
	for (int sweep = 0; sweep < 32; sweep++) {
		v2 off = v2_abs(m[0][1]) + v2_abs(m[0][2]) + v2_abs(m[1][2]);
		v2 scale = v2_abs(m[0][0]) + v2_abs(m[1][1]) + v2_abs(m[2][2]);
		live &= ~((off <= 1e-15 * scale) | (off == 0));
		if (!(live[0] | live[1]))
			break;
		for (int p = 0; p < 2; p++)
			for (int r = p + 1; r < 3; r++) {
				m2 go = live & (m[p][r] != 0);
				v2 t, c, s, theta;
				if (!(go[0] | go[1]))
					continue;
				theta = (m[r][r] - m[p][p]) / (2 * m[p][r]);
				t = v2_sel(theta >= 0, (v2){ 1, 1 },
				    (v2){ -1, -1 }) / (v2_abs(theta) +
				    quadric_v2_sqrt(theta * theta + 1));
				c = 1 / quadric_v2_sqrt(t * t + 1);
				s = t * c;
				for (int k = 0; k < 3; k++) /* m = J' m J */
					rot2(&m[k][p], &m[k][r], c, s, go);
				for (int k = 0; k < 3; k++)
					rot2(&m[p][k], &m[r][k], c, s, go);
				for (int k = 0; k < 3; k++)
					rot2(&V[k][p], &V[k][r], c, s, go);
			}
	}
	for (int k = 0; k < 3; k++)
		w[k] = m[k][k];
}

void
quadric_min_3d2(const quadric *q0, const quadric *q1, double rel,
    double v0[3], double v1[3])
{
	v2 w[3], V[3][3];
	double wl[3], Vl[3][3];

	eigen2(q0->a, q1->a, w, V);
	for (int l = 0; l < 2; l++) {
		for (int i = 0; i < 3; i++) {
			wl[i] = w[i][l];
			for (int k = 0; k < 3; k++)
				Vl[i][k] = V[i][k][l];
		}
		min_3d(l ? q1 : q0, rel, wl, Vl, l ? v1 : v0);
	}
}
