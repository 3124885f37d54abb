/* tr_gsel.c - a projected DEM's selection in its own grid, for the
 * measure (tr_measure.c).
 *
 * The pyramid bounds the selection F against the DEM at each sample's
 * grid place g: F there is the plane, in the grid, of the selected
 * triangle holding g. The tile draws each selected triangle straight
 * between the images of its vertices in longitude and latitude, so the
 * piece of the tile over the sample's place s = Phi(g) is not that plane
 * at g: the map Phi bends straight grid lines, and the sample may even
 * lie under a neighbour's piece. The measure therefore compares the drawn
 * surface at s with F(g) itself, found here: the difference then holds
 * the CRS mapping with every other term. The tile keeps the selected
 * triangles (level-0 grid places, heights) whose footprint part lies
 * near it, in tr_bary.h's terms (the mesh's locator's decisions and
 * plane, on grid places); a grid of buckets finds the one holding g. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/tr_bary.h"
#include "terrain/tr_impl.h"

#define GT (TR_BARY_TERMS + 3) /* doubles a triangle: tr_bary_flat's */

int
tr_gsel_add(tr_work *w, const double x[3], const double y[3],
    const double h[3])
{
	double *t;

	if (w->ngsel == w->cgsel) {
		int n = w->cgsel ? 2 * w->cgsel : 256;
		if ((t = realloc(w->gsel, (size_t)n * GT * sizeof *t)) == NULL)
			return -1;
		w->gsel = t, w->cgsel = n;
	}
	t = w->gsel + GT * (size_t)w->ngsel++;
	t[0] = x[0], t[1] = y[0];
	t[2] = x[1] - x[0], t[3] = y[1] - y[0];
	t[4] = x[2] - x[0], t[5] = y[2] - y[0];
	t[6] = t[2] * t[5] - t[4] * t[3], t[7] = 1 / t[6];
	t[8] = h[0], t[9] = h[1] - h[0], t[10] = h[2] - h[0];
	return 0;
}

static int
bucket(const tr_gsel *g, double c, int k)
{
	return tr_bucket(c, g->o[k], g->s[k], g->nb);
}

void
tr_gsel_box(const double *t, int k, double *lo, double *hi)
{
	double a = t[k], b = t[k] + t[2 + k], c = t[k] + t[4 + k];

	*lo = dmin(a, dmin(b, c)), *hi = dmax(a, dmax(b, c));
}

int
tr_gsel_init(tr_gsel *g, const tr_work *w)
{
	size_t n = (size_t)w->ngsel;
	double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
	int nb = (int)ceil(sqrt((double)n));

	memset(g, 0, sizeof *g);
	g->nt = w->ngsel;
	g->nb = nb < 1 ? 1 : nb > 512 ? 512 : nb;
	if ((g->t = malloc((n ? n : 1) * GT * sizeof *g->t)) == NULL ||
	    (g->start = calloc((size_t)g->nb * g->nb + 1,
	    sizeof *g->start)) == NULL)
		return -1;
	if (n)
		memcpy(g->t, w->gsel, n * GT * sizeof *g->t);
	for (size_t i = 0; i < n; i++)
		for (int k = 0; k < 2; k++) {
			double a, b;
			tr_gsel_box(g->t + GT * i, k, &a, &b);
			lo[k] = dmin(lo[k], a), hi[k] = dmax(hi[k], b);
		}
	for (int k = 0; k < 2 && n; k++)
		g->o[k] = lo[k], g->s[k] = g->nb / (hi[k] - lo[k] + 1);
	/* counts, then lists: each triangle in the buckets its box meets */
	for (int pass = 0; pass < 2; pass++) {
		for (size_t i = 0; i < n; i++) {
			double x0, x1, y0, y1;
			tr_gsel_box(g->t + GT * i, 0, &x0, &x1);
			tr_gsel_box(g->t + GT * i, 1, &y0, &y1);
			for (int c = bucket(g, y0, 1); c <= bucket(g, y1, 1); c++)
				for (int b = bucket(g, x0, 0); b <= bucket(g, x1, 0);
				    b++) {
					int *s = &g->start[c * g->nb + b];
					if (pass == 0)
						s[1]++;
					else
						g->list[s[0]++] = (int)i;
				}
		}
		if (pass == 0) {
			int m = g->nb * g->nb;
			for (int i = 0; i < m; i++)
				g->start[i + 1] += g->start[i];
			if ((g->list = malloc((size_t)(g->start[m] ? g->start[m] :
			    1) * sizeof *g->list)) == NULL)
				return -1;
		} else {
			for (int i = g->nb * g->nb; i > 0; i--)
				g->start[i] = g->start[i - 1];
			g->start[0] = 0;
		}
	}
	g->bytes = n * GT * sizeof *g->t + ((size_t)g->nb * g->nb + 1 +
	    (size_t)g->start[g->nb * g->nb]) * sizeof(int);
	return 0;
}

void
tr_gsel_free(tr_gsel *g)
{
	free(g->t), free(g->start), free(g->list);
	memset(g, 0, sizeof *g);
}

const double *
tr_gsel_find(const tr_gsel *g, double x, double y, int *hint)
{
	int k, best = -1;
	double lb = -INFINITY;

	if (g->nt == 0)
		return NULL;
	/* the previous sample's triangle when the place is inside it: no
	 * other then holds it (they do not overlap) but on its edges */
	if (*hint >= 0 && tr_bary_above(g->t + GT * (size_t)*hint, x, y,
	    1e-9))
		best = *hint;
	else {
		/* the triangle where the least coordinate is largest: >= 0
		 * inside; on an edge either side gives F, continuous */
		k = bucket(g, y, 1) * g->nb + bucket(g, x, 0);
		for (int i = g->start[k]; i < g->start[k + 1]; i++) {
			double v = tr_bary_least(g->t + GT * (size_t)g->list[i],
			    x, y);
			if (v > lb)
				lb = v, best = g->list[i];
		}
		if (best < 0 || !(lb >= -1e-9))
			return NULL;
		*hint = best;
	}
	return g->t + GT * (size_t)best;
}
