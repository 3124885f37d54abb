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

static void
raise(state *s, int g0, int lo, int hi, float *e, int ci, int cj)
{
	if (ci >= 0 && ci < s->P && cj >= lo && cj < hi) {
		float c = s->satband[(size_t)(cj - g0) * s->P + ci];
		if (c > *e)
			*e = c;
	}
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
			for (int gi = gi0; gi < P; gi += 2 * h) {
				float *e = &sat[(size_t)(gj - g0) * P + gi];
				raise(s, g0, lo, hi, e, gi - g, gj - g);
				raise(s, g0, lo, hi, e, gi + g, gj - g);
				raise(s, g0, lo, hi, e, gi - g, gj + g);
				raise(s, g0, lo, hi, e, gi + g, gj + g);
			}
		}
		/* square(h): children (gi +- h, gj), (gi, gj +- h) */
		for (int gj = lo; gj < hi; gj++) {
			if (gj % h != 0 || (gj / h) % 2 == 0)
				continue;
			for (int gi = h; gi < P; gi += 2 * h) {
				float *e = &sat[(size_t)(gj - g0) * P + gi];
				raise(s, g0, lo, hi, e, gi - h, gj);
				raise(s, g0, lo, hi, e, gi + h, gj);
				raise(s, g0, lo, hi, e, gi, gj - h);
				raise(s, g0, lo, hi, e, gi, gj + h);
			}
		}
	}
}
