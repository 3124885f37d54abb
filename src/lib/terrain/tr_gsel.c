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
 * near it; a grid of buckets finds the one holding g. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/tr_impl.h"

int
tr_gsel_add(tr_work *w, const double x[3], const double y[3],
    const double h[3])
{
	double *t;

	if (w->ngsel == w->cgsel) {
		int n = w->cgsel ? 2 * w->cgsel : 256;
		if ((t = realloc(w->gsel, (size_t)n * 9 * sizeof *t)) == NULL)
			return -1;
		w->gsel = t, w->cgsel = n;
	}
	t = w->gsel + 9 * (size_t)w->ngsel++;
	for (int i = 0; i < 3; i++)
		t[i] = x[i], t[3 + i] = y[i], t[6 + i] = h[i];
	return 0;
}

static int
bucket(const tr_gsel *g, double c, int k)
{
	double b = floor((c - g->o[k]) * g->s[k]);

	return b < 0 ? 0 : b >= g->nb ? g->nb - 1 : (int)b;
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
	if ((g->t = malloc((n ? n : 1) * 9 * sizeof *g->t)) == NULL ||
	    (g->start = calloc((size_t)g->nb * g->nb + 1,
	    sizeof *g->start)) == NULL)
		return -1;
	if (n)
		memcpy(g->t, w->gsel, n * 9 * sizeof *g->t);
	for (size_t i = 0; i < n; i++)
		for (int k = 0; k < 3; k++) {
			lo[0] = dmin(lo[0], g->t[9 * i + k]);
			hi[0] = dmax(hi[0], g->t[9 * i + k]);
			lo[1] = dmin(lo[1], g->t[9 * i + 3 + k]);
			hi[1] = dmax(hi[1], g->t[9 * i + 3 + k]);
		}
	for (int k = 0; k < 2 && n; k++)
		g->o[k] = lo[k], g->s[k] = g->nb / (hi[k] - lo[k] + 1);
	/* counts, then lists: each triangle in the buckets its box meets */
	for (int pass = 0; pass < 2; pass++) {
		for (size_t i = 0; i < n; i++) {
			const double *t = g->t + 9 * i;
			int b0 = bucket(g, dmin(t[0], dmin(t[1], t[2])), 0);
			int b1 = bucket(g, dmax(t[0], dmax(t[1], t[2])), 0);
			int c0 = bucket(g, dmin(t[3], dmin(t[4], t[5])), 1);
			int c1 = bucket(g, dmax(t[3], dmax(t[4], t[5])), 1);
			for (int c = c0; c <= c1; c++)
				for (int b = b0; b <= b1; b++) {
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
	g->bytes = n * 9 * sizeof *g->t + ((size_t)g->nb * g->nb + 1 +
	    (size_t)g->start[g->nb * g->nb]) * sizeof(int);
	return 0;
}

void
tr_gsel_free(tr_gsel *g)
{
	free(g->t), free(g->start), free(g->list);
	memset(g, 0, sizeof *g);
}

/* Triangle t's least barycentric coordinate of (x, y), and the other
 * two into b */
static double
least(const double *t, double x, double y, double b[2])
{
	double x1 = t[1] - t[0], y1 = t[4] - t[3];
	double x2 = t[2] - t[0], y2 = t[5] - t[3];
	double d = x1 * y2 - x2 * y1, px = x - t[0], py = y - t[3];

	b[0] = (px * y2 - x2 * py) / d, b[1] = (x1 * py - px * y1) / d;
	return dmin(1 - b[0] - b[1], dmin(b[0], b[1]));
}

double
tr_gsel_height(const tr_gsel *g, double x, double y, int *hint)
{
	int k, best = -1;
	double lb = -INFINITY, b[2], c[2];
	const double *t;

	if (g->nt == 0)
		return NAN;
	/* the previous sample's triangle when the place is inside it: no
	 * other then holds it (they do not overlap) but on its edges */
	if (*hint >= 0 && least(g->t + 9 * (size_t)*hint, x, y, c) > 1e-9) {
		best = *hint;
		b[0] = c[0], b[1] = c[1];
	} else {
		/* the triangle where the least coordinate is largest: >= 0
		 * inside; on an edge either side gives F, continuous */
		k = bucket(g, y, 1) * g->nb + bucket(g, x, 0);
		for (int i = g->start[k]; i < g->start[k + 1]; i++) {
			double v = least(g->t + 9 * (size_t)g->list[i], x, y, c);
			if (v > lb)
				lb = v, best = g->list[i], b[0] = c[0], b[1] = c[1];
		}
		if (best < 0 || lb < -1e-9)
			return NAN;
		*hint = best;
	}
	t = g->t + 9 * (size_t)best;
	return t[6] + b[0] * (t[7] - t[6]) + b[1] * (t[8] - t[6]);
}
