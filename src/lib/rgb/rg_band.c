/* rg_band.c - which columns and tiles are a plan's part's (rg_impl.h):
 * the split work's bands of the grid's columns (rg_split.c), and -m
 * average's ranges of every zoom's tiles. */
#include <string.h>

#include "rgb/rg_impl.h"
#include "geo/levels.h"

static long long
floordiv(long long a, long long b)
{
	return a >= 0 ? a / b : -((-a + b - 1) / b);
}

/* The split work's owner of tile t of zoom zz's band: that of its
 * column, or where the whole grid (j->wrap) has the same tile a world
 * east or west, theirs when the same, else the gather's (-1). */
static int
owner(const rg_job *j, const rg_zoom *zz, int t)
{
	const rg_band *b = j->band;
	int l = b->maxz - zz->g.z, o;
	long long x = zz->tx0 + t, n = 1LL << zz->g.z;
	long long c0 = b->gx0 >> l, c1 = c0 + geo_level_size(b->gw, l) - 1;
	long long t0 = floordiv(c0, b->dim), t1 = floordiv(c1, b->dim);

	o = rg_band_owner(b, l, x);
	if (j->wrap && x + n <= t1 && rg_band_owner(b, l, x + n) != o)
		return -1;
	if (j->wrap && x - n >= t0 && rg_band_owner(b, l, x - n) != o)
		return -1;
	return o;
}

/* The zoom's tiles numbered row by row, cut into nparts ranges (-m
 * average's parts); the split work's parts, by the band's rule. */
int
rg_part_owns(const rg_job *j, const rg_zoom *zz, int t)
{
	const rg_args *a = j->a;
	long long ty0, nty, T, i;

	if (j->band != NULL)
		return owner(j, zz, t) == j->band->k;
	if (a->work == NULL || a->nparts <= 1)
		return 1;
	ty0 = floordiv(zz->g.y0, a->dim);
	nty = floordiv(zz->g.y0 + zz->g.h - 1, a->dim) - ty0 + 1;
	T = nty * zz->ntx, i = (zz->ty - ty0) * zz->ntx + t;
	return i >= T * a->part / a->nparts &&
	    i < T * (a->part + 1) / a->nparts;
}

/* The first level-0 column of part k: that of its range of the deepest
 * zoom's tile columns, ntx k / n .. ntx (k + 1) / n - 1. */
static long long
first(const rg_band *b, int k)
{
	long long c;

	if (k <= 0)
		return 0;
	if (k >= b->n)
		return b->gw;
	c = (b->T0 + (long long)b->ntx * k / b->n) * b->dim - b->gx0;
	return c < 0 ? 0 : c > b->gw ? b->gw : c;
}

/* Part k's columns of level l: those whose level-0 column is its (the
 * last part's also those past the grid's last column). */
static void
cols(const rg_band *b, int k, int l, int *lo, int *hi)
{
	long long s = (1LL << l) - 1;

	*lo = (int)((first(b, k) + s) >> l);
	*hi = k == b->n - 1 ? geo_level_size(b->gw, l) :
	    (int)((first(b, k + 1) + s) >> l);
}

int
rg_band_owner(const rg_band *b, int l, long long t)
{
	long long o = b->gx0 >> l, wl = geo_level_size(b->gw, l);
	long long c0 = t * b->dim - o, c1 = c0 + b->dim;
	int lo, hi;

	c0 = c0 < 0 ? 0 : c0, c1 = c1 > wl ? wl : c1;
	for (int k = 0; k < b->n; k++) { /* its first column's part */
		cols(b, k, l, &lo, &hi);
		if (c0 >= lo && c0 < hi)
			return c1 <= hi ? k : -1;
	}
	return -1;
}

/* Part k of n of segment 0 (nl levels) on grid g: its columns of each
 * level, its window. */
void
rg_band_of(rg_band *b, const dem_mgrid *g, int maxz, int nl, int k, int n)
{
	long long x0, x1 = 0;

	memset(b, 0, sizeof *b);
	b->k = k, b->n = n, b->maxz = maxz, b->nl = nl, b->dim = g->dim;
	b->gx0 = g->x0, b->gw = g->w, b->nfd = -1;
	b->T0 = floordiv(g->x0, g->dim);
	b->ntx = (int)(floordiv(g->x0 + g->w - 1, g->dim) - b->T0 + 1);
	for (int l = 0; l < nl; l++) {
		b->fd[l] = -1;
		cols(b, k, l, &b->lo[l], &b->hi[l]);
		if (((long long)b->hi[l] << l) > x1)
			x1 = (long long)b->hi[l] << l;
	}
	if (k < 0 || b->hi[0] == b->lo[0])
		return; /* owns nothing: x0 = x1 = 0 */
	/* the centres of level l reach vertex hi[l] */
	x0 = first(b, k) - RG_HALO(nl - 1);
	x1 += RG_HALO(nl - 1) + 1;
	x0 = x0 < 0 ? 0 : x0 >> (nl - 1) << (nl - 1);
	b->x0 = (int)x0, b->x1 = (int)(x1 > g->w ? g->w : x1);
}
