/* t_measure_bary.c - the measure's barycentric decisions taken on the
 * near coordinates (terrain/tr_bary.h) against the exact ones, the
 * quotients the measure always took, bit for bit: on random triangles
 * of the u, v lattice and points inside, outside, on their vertices, on
 * their edges and within a hair of the hint's threshold 1e-9; on a
 * jittered lattice mesh (shared edges: ties) the bucket's choice; and
 * the selection's height, skipped only where the exact one could not
 * raise the largest distance. Each counts the cases the exact path had
 * to decide, so that both paths are seen. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "tap.h"
#include "terrain/tr_bary.h"

static uint64_t seed = 0x9e3779b97f4a7c15ull;

static double
rnd(void) /* 0 .. 1 */
{
	seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
	return (double)(seed >> 11) / 9007199254740992.0;
}

/* Terms of the triangle a b c (tr_bary.h), heights h (or NULL), as
 * tr_measure.c's planes() sets them; 0 when it has no area. */
static int
terms(double *t, const double a[2], const double b[2], const double c[2],
    const double *h)
{
	t[0] = a[0], t[1] = a[1];
	t[2] = b[0] - t[0], t[3] = b[1] - t[1];
	t[4] = c[0] - t[0], t[5] = c[1] - t[1];
	t[6] = t[2] * t[5] - t[4] * t[3], t[7] = 1 / t[6];
	if (h)
		t[8] = h[0], t[9] = h[1] - h[0], t[10] = h[2] - h[0];
	return t[6] > 0;
}

static void
lattice_tri(double *t)
{
	double p[3][2];

	do {
		for (int i = 0; i < 3; i++) {
			double s = rnd() < 0.5 ? 32767 : 40;
			p[i][0] = floor(rnd() * s), p[i][1] = floor(rnd() * s);
		}
	} while (!terms(t, p[0], p[1], p[2], NULL));
}

/* A point by barycentric coordinates (b1, b2) of t. */
static void
at(const double *t, double b1, double b2, double *x, double *y)
{
	*x = t[0] + b1 * t[2] + b2 * t[4];
	*y = t[1] + b1 * t[3] + b2 * t[5];
}

static void
above(void)
{
	int bad = 0, open = 0, n = 400000;
	double t[8], x, y, lim = 1e-9;

	for (int i = 0; i < n; i++) {
		double b1 = rnd(), b2 = rnd() * (1 - b1), k = rnd();
		lattice_tri(t);
		if (k < 0.3) /* a hair from the threshold */
			b1 = lim + (rnd() - 0.5) * (rnd() < 0.5 ? 1e-11 : 1e-15),
			b2 = rnd() * 0.9;
		else if (k < 0.5) /* on an edge or a vertex */
			b1 = 0, b2 = floor(rnd() * 5) / 4;
		else if (k < 0.6) /* outside */
			b1 = -rnd() * 100, b2 = rnd() * 300;
		at(t, b1, b2, &x, &y);
		double v = tr_bary_near_least(t, x, y);
		if (!(v > lim + 5 * TR_BARY_SLACK || v + tr_bary_slack(v) <= lim))
			open++;
		if (tr_bary_above(t, x, y, lim) != (tr_bary_least(t, x, y) > lim))
			bad++;
	}
	ok(bad == 0, "least > 1e-9 as the quotients decide it: %d of %d "
	    "differ", bad, n);
	ok(open > 100 && open < n / 4, "the exact path decided %d of %d "
	    "(near the threshold only)", open, n);
}

/* The bucket's choice as tr_measure.c took it: largest exact least,
 * the first of equals. */
static int
best_exact(const double *bq, const int *list, int n, double x, double y)
{
	int best = -1;
	double bv = -INFINITY;

	for (int i = 0; i < n; i++) {
		double v = tr_bary_least(bq + TR_BARY_TERMS * list[i], x, y);
		if (v > bv)
			bv = v, best = list[i];
	}
	return best;
}

/* A 6 x 6 lattice of jittered integer vertices, two triangles a cell
 * (either diagonal); points on vertices, edges, inside, outside. */
static void
best(void)
{
	enum { G = 7, NT = 2 * (G - 1) * (G - 1) };
	double p[G][G][2], bq[NT * TR_BARY_TERMS];
	int list[NT], bad = 0, tie = 0, n = 0, rounds = 2000;

	for (int r = 0; r < rounds; r++) {
		int nt = 0;
		for (int j = 0; j < G; j++)
			for (int i = 0; i < G; i++) {
				p[j][i][0] = i * 100 + floor(rnd() * 60);
				p[j][i][1] = j * 100 + floor(rnd() * 60);
			}
		for (int j = 0; j + 1 < G; j++)
			for (int i = 0; i + 1 < G; i++) {
				double *a = p[j][i], *b = p[j][i + 1];
				double *c = p[j + 1][i + 1], *d = p[j + 1][i];
				int diag = rnd() < 0.5;
				nt += terms(bq + TR_BARY_TERMS * nt, a, b, diag ? c : d,
				    NULL);
				nt += diag ? terms(bq + TR_BARY_TERMS * nt, a, c, d,
				    NULL) : terms(bq + TR_BARY_TERMS * nt, b, c, d, NULL);
			}
		for (int k = 0; k < 200; k++) {
			int m = 1 + (int)(rnd() * nt), o = (int)(rnd() * (nt - m + 1));
			const double *t = bq + TR_BARY_TERMS *
			    (int)(rnd() * nt);
			double x, y, w = rnd();
			if (w < 0.4) /* on an edge or a vertex */
				at(t, floor(rnd() * 3) / 2, 0, &x, &y);
			else if (w < 0.8)
				at(t, rnd() * 0.5, rnd() * 0.5, &x, &y);
			else
				x = rnd() * 800 - 100, y = rnd() * 800 - 100;
			for (int i = 0; i < m; i++)
				list[i] = o + i;
			int e = best_exact(bq, list, m, x, y);
			double v1 = -INFINITY, v2 = -INFINITY;
			for (int i = 0; i < m; i++) {
				double v = tr_bary_near_least(bq + TR_BARY_TERMS *
				    list[i], x, y);
				v > v1 ? (v2 = v1, v1 = v) : v > v2 ? (v2 = v) : 0;
			}
			tie += m > 1 && !(v1 - tr_bary_slack(v1) > v2 +
			    tr_bary_slack(v2));
			bad += tr_bary_best(bq, list, m, x, y) != e;
			n++;
		}
	}
	ok(bad == 0, "the bucket's triangle as the quotients choose it: %d "
	    "of %d differ", bad, n);
	ok(tie > 1000 && tie < n / 2, "ties and near ties the exact path "
	    "decided: %d of %d", tie, n);
}

/* The selection's height: near, with its slack, skipped only where the
 * exact |hs - flat| is below d. */
static void
flat(void)
{
	int bad = 0, skip = 0, n = 300000;
	double t[11];

	for (int i = 0; i < n; i++) {
		double p[3][2], h[3], x, y, s;
		double lon = -180 + rnd() * 359, lat = -80 + rnd() * 159;
		double wd = rnd() < 0.5 ? 1e-3 : 1e-5;
		for (int k = 0; k < 3; k++) {
			p[k][0] = lon + rnd() * wd, p[k][1] = lat + rnd() * wd;
			h[k] = rnd() * 9000 - 400;
		}
		if (!terms(t, p[0], p[1], p[2], h) && !terms(t, p[0], p[2],
		    p[1], h))
			continue;
		at(t, rnd() * 1.2 - 0.1, rnd() * 1.2 - 0.1, &x, &y);
		double e = tr_bary_flat(t, x, y), hs = e + (rnd() - 0.5) *
		    (rnd() < 0.5 ? 1e-9 : 10), ex = fabs(hs - e);
		/* the largest so far: just above, at, or just below it */
		double w = rnd(), d = w < 0.3 ? ex : w < 0.5 ? nextafter(ex,
		    INFINITY) : w < 0.6 ? nextafter(ex, 0) : ex + (rnd() - 0.2) *
		    1e-8;
		double v = fabs(hs - tr_bary_near_flat(t, x, y, hs, &s));
		if (v + s < d) {
			skip++;
			bad += !(ex < d);
		}
	}
	ok(bad == 0, "the selection's height skipped only below the largest "
	    "distance: %d wrong of %d", bad, n);
	ok(skip > n / 20, "skipped %d of %d", skip, n);
}

int
main(void)
{
	above();
	best();
	flat();
	return tap_done();
}
