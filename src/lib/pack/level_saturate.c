/* level_saturate.c - saturation: a block row's errors nested, each
 * vertex's E the largest of its local error and its children's E, over
 * the saturation band (SAT_BAND rows) so that it crosses block borders.
 * This is the error saturation of Pajarola ("Large scale terrain
 * visualization using the restricted quadtree triangulation", IEEE
 * Visualization 98; the survey in ../shared/papers, section 3.6) and
 * the nested errors of Lindstrom and Pascucci (IEEE TVCG 2002): with it,
 * selecting every vertex whose E exceeds a tolerance is already a
 * matching triangulation. */
#include "pack/level_impl.h"

#include <assert.h>
#include <string.h>

/* e raised to c: the order of raises kept, though no error is NaN */
static inline float
up(float e, float c)
{
	return c > e ? c : e;
}

/* Row r's E at columns gi0, gi0 + 2h, ... raised by their children in
 * rows a and b (NULL: outside the band) at columns gi - d and gi + d
 * (those inside the row), in that order: a's two, then b's. */
static void
raise_row(float *r, const float *a, const float *b, int gi0, int h, int d,
    int P)
{
	for (int gi = gi0; gi < P; gi += 2 * h) {
		float e = r[gi];
		int lo = gi - d >= 0, hi = gi + d < P;
		if (a != NULL) {
			if (lo)
				e = up(e, a[gi - d]);
			if (hi)
				e = up(e, a[gi + d]);
		}
		if (b != NULL) {
			if (lo)
				e = up(e, b[gi - d]);
			if (hi)
				e = up(e, b[gi + d]);
		}
		r[gi] = e;
	}
}

/* Row r's E at columns h, 3h, ... raised by rows a and b's (NULL:
 * outside the band) at the same columns, a's then b's. */
static void
raise_col(float *r, const float *a, const float *b, int h, int P)
{
	for (int gi = h; gi < P; gi += 2 * h) {
		float e = r[gi];
		if (a != NULL)
			e = up(e, a[gi]);
		if (b != NULL)
			e = up(e, b[gi]);
		r[gi] = e;
	}
}

/* Band row gj, or NULL outside [lo, hi). */
static inline float *
band(float *sat, int P, int g0, int lo, int hi, int gj)
{
	return gj >= lo && gj < hi ? sat + (size_t)(gj - g0) * P : NULL;
}

/* E = max(local, E of children), children first: edge(1), square(1),
 * edge(2), ..., square(64), over the saturation band, rows g0 ..
 * g0+SAT_BAND-1. */
void
lv_saturate(state *s, int bj)
{
	int g0 = bj * BT_CELLS - REACH, P = s->P;
	float *sat = s->satband;
	int lo = g0 > 0 ? g0 : 0;
	int hi = g0 + SAT_BAND < s->Q ? g0 + SAT_BAND : s->Q;

	assert(lo >= g0 && hi <= g0 + SAT_BAND && lo < hi);
	for (int gj = lo; gj < hi; gj++)
		memcpy(sat + (size_t)(gj - g0) * P, s->acc + eslot(s, gj),
		    (size_t)P * sizeof *sat);
	for (int h = 1; h <= BT_MAXH; h *= 2) {
		int g = h / 2;
		/* edge(h), h > 1: children (gi +- h/2, gj +- h/2) */
		for (int gj = lo; h > 1 && gj < hi; gj++) {
			int gi0 = gj % (2 * h) == 0 ? h : gj % h == 0 &&
			    (gj / h) % 2 ? 0 : -1;
			if (gi0 < 0)
				continue;
			raise_row(band(sat, P, g0, lo, hi, gj), band(sat, P, g0,
			    lo, hi, gj - g), band(sat, P, g0, lo, hi, gj + g),
			    gi0, h, g, P);
		}
		/* square(h): children (gi +- h, gj), then (gi, gj +- h) */
		for (int gj = lo; gj < hi; gj++) {
			float *r = band(sat, P, g0, lo, hi, gj);
			if (gj % h != 0 || (gj / h) % 2 == 0)
				continue;
			raise_row(r, r, NULL, h, h, h, P);
			raise_col(r, band(sat, P, g0, lo, hi, gj - h),
			    band(sat, P, g0, lo, hi, gj + h), h, P);
		}
	}
}
