/* tr_bary.h - a sample's barycentric coordinates in a tile's triangle,
 * as the measure (tr_measure.c) takes its decisions on them.
 *
 * Contract: a triangle's terms t are x0 y0 x1-x0 y1-y0 x2-x0 y2-y0, D
 * (twice its signed area, > 0 for the triangles measured), 1/D, then for
 * tr_bary_flat three heights h0 h1-h0 h2-h0. The exact values are the
 * quotients by D (tr_bary_least, tr_bary_flat: those the measure has
 * always used, bit for bit); the near ones (tr_bary_near_*) take the
 * product by 1/D instead, no division, within a slack (tr_bary_slack,
 * or *s) of the exact value with a margin over 100 (the roundings of the
 * quotients, the products and the sums, below 10 units of the last
 * place of the terms' sizes, against 1e-13 of them).
 * tr_bary_above and tr_bary_best decide on the near values and fall back
 * to the exact ones only where the slack leaves the decision open: their
 * answers are the exact ones' always. Built with -ffp-contract=off
 * semantics (ISO C, no FMA): the same expressions round alike. */
#ifndef TL_TR_BARY_H
#define TL_TR_BARY_H

#include <math.h>

#define TR_BARY_TERMS 8 /* per triangle: the 2 lattices' terms */
#define TR_BARY_SLACK 1e-13

static inline double
tr_bary_min(double a, double b)
{
	return b < a ? b : a;
}

/* The least of the three coordinates of (x, y), exactly. */
static inline double
tr_bary_least(const double *t, double x, double y)
{
	double px = x - t[0], py = y - t[1];
	double b1 = (px * t[5] - t[4] * py) / t[6];
	double b2 = (t[2] * py - px * t[3]) / t[6];

	return tr_bary_min(1 - b1 - b2, tr_bary_min(b1, b2));
}

/* The same near: within tr_bary_slack of it (the three coordinates sum
 * to 1 and the least is v, so each is within 1 + 2 |v| of 0). */
static inline double
tr_bary_near_least(const double *t, double x, double y)
{
	double px = x - t[0], py = y - t[1];
	double b1 = (px * t[5] - t[4] * py) * t[7];
	double b2 = (t[2] * py - px * t[3]) * t[7];

	return tr_bary_min(1 - b1 - b2, tr_bary_min(b1, b2));
}

static inline double
tr_bary_slack(double v)
{
	return TR_BARY_SLACK * (3 + 4 * fabs(v));
}

/* Whether tr_bary_least(t, x, y) > lim, 0 <= lim < 0.3 (a positive
 * least is at most 1/3: its slack below 5 TR_BARY_SLACK). */
static inline int
tr_bary_above(const double *t, double x, double y, double lim)
{
	double v = tr_bary_near_least(t, x, y);

	if (v > lim + 5 * TR_BARY_SLACK)
		return 1;
	if (v + tr_bary_slack(v) <= lim)
		return 0;
	return tr_bary_least(t, x, y) > lim;
}

/* Of the n triangles list[] (terms at bq + TR_BARY_TERMS list[i]), the
 * one where the least coordinate of (x, y) is largest, the first of
 * equals; -1 when n is 0. */
static inline int
tr_bary_best(const double *bq, const int *list, int n, double x, double y)
{
	int best = -1;
	double bv = -INFINITY, next = -INFINITY, v;

	for (int i = 0; i < n; i++) {
		v = tr_bary_near_least(bq + TR_BARY_TERMS * list[i], x, y);
		if (v > bv)
			next = bv, bv = v, best = list[i];
		else if (v > next)
			next = v;
	}
	/* v + slack(v) grows with v: the second's bound is every other's */
	if (best < 0 || next == -INFINITY ||
	    bv - tr_bary_slack(bv) > next + tr_bary_slack(next))
		return best; /* above every other: the exact maximum, alone */
	best = -1, bv = -INFINITY;
	for (int i = 0; i < n; i++) {
		v = tr_bary_least(bq + TR_BARY_TERMS * list[i], x, y);
		if (v > bv)
			bv = v, best = list[i];
	}
	return best;
}

/* The height at (x, y) of the plane through the triangle's heights
 * (terms f: TR_BARY_TERMS, then 3), exactly. */
static inline double
tr_bary_flat(const double *f, double x, double y)
{
	double px = x - f[0], py = y - f[1];
	double b1 = (px * f[5] - f[4] * py) / f[6];
	double b2 = (f[2] * py - px * f[3]) / f[6];

	return f[8] + b1 * f[9] + b2 * f[10];
}

/* The same near, within *s (beside a height hs: |hs - flat| is within
 * *s of |hs - near|, the subtraction's rounding included). */
static inline double
tr_bary_near_flat(const double *f, double x, double y, double hs, double *s)
{
	double px = x - f[0], py = y - f[1];
	double a = (px * f[5] - f[4] * py) * f[7] * f[9];
	double b = (f[2] * py - px * f[3]) * f[7] * f[10];

	*s = TR_BARY_SLACK * (fabs(hs) + fabs(f[8]) + fabs(a) + fabs(b));
	return f[8] + a + b;
}

#endif
