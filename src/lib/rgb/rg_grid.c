/* rg_grid.c - the Web Mercator grids: the zoom rule, the deepest zoom's
 * pixel grid around a DEM's bounds (its origin aligned for a segment of the
 * chain), the grid of the next segment (rgb.h, rg_impl.h). */
#include <math.h>

#include "rgb/rg_impl.h"
#include "geo/levels.h"

#define LAT_MAX 85.0511287798066

int
rg_maxzoom(double lat, double cell, int dim)
{
	double c = 2 * DEM_MERC_HALF * cos(lat * M_PI / 180) / dim;

	for (int z = 0; z < RG_MAXZOOM; z++)
		if (ldexp(c, -z) < cell)
			return z;
	return RG_MAXZOOM;
}

/* Global pixel-corner coordinate (fractional) of longitude / latitude:
 * pixel k's centre is at k + 0.5. */
double
rg_merc_x(double lon, double res)
{
	return (lon * M_PI / 180 * 6378137.0 + DEM_MERC_HALF) / res;
}

double
rg_merc_y(double lat, double res)
{
	double p = fmax(-LAT_MAX, fmin(LAT_MAX, lat)) * M_PI / 180;

	return (DEM_MERC_HALF - 6378137.0 * log(tan(M_PI / 4 + p / 2))) / res;
}

static long long
align_down(long long v, int s)
{
	long long a = 1LL << s;

	return v >= 0 ? v / a * a : -((-v + a - 1) / a) * a;
}

/* g's pixel centres enclose the bounds ll at zoom z, with a margin of
 * half a pixel of zoom z - s before them (the first centre of zoom z - l,
 * at 2^(l-1) - 1/2 pixels from the origin, lies before the first sample
 * for every l <= s), its origin a multiple of 2^s, at least 3 x 3
 * pixels; pad gets the columns and rows added before the bounds. */
void
rg_grid_of(dem_mgrid *g, int z, int dim, const double ll[4], int s,
    long long pad[2])
{
	double res;
	long long x1, y1, xa, ya, m = s > 0 ? 1LL << (s - 1) : 0;

	g->z = z, g->dim = dim;
	res = dem_mgrid_res(g);
	xa = (long long)floor(rg_merc_x(ll[0], res) - 0.5);
	x1 = (long long)ceil(rg_merc_x(ll[2], res) - 0.5);
	ya = (long long)floor(rg_merc_y(ll[3], res) - 0.5);
	y1 = (long long)ceil(rg_merc_y(ll[1], res) - 0.5);
	/* never west of the world's first pixel (nor north) */
	g->x0 = xa - m > 0 ? align_down(xa - m, s) : 0;
	g->y0 = ya - m > 0 ? align_down(ya - m, s) : 0;
	pad[0] = xa - g->x0, pad[1] = ya - g->y0;
	g->w = (int)(x1 - g->x0 + 1), g->h = (int)(y1 - g->y0 + 1);
	g->w = g->w < 3 ? 3 : g->w, g->h = g->h < 3 ? 3 : g->h;
}

/* The next segment's grid: level s of g (its vertices, the deepest
 * zoom's centres i 2^s), its origin aligned down to a multiple of 2^s2
 * with the same margin as rg_grid_of's; pad gets the columns and rows
 * added before it. */
void
rg_grid_next(dem_mgrid *n, const dem_mgrid *g, int s, int s2,
    long long pad[2])
{
	long long x = g->x0 >> s, y = g->y0 >> s;
	long long m = s2 > 0 ? 1LL << (s2 - 1) : 0;

	n->z = g->z - s, n->dim = g->dim;
	n->x0 = x - m > 0 ? align_down(x - m, s2) : 0;
	n->y0 = y - m > 0 ? align_down(y - m, s2) : 0;
	pad[0] = x - n->x0, pad[1] = y - n->y0;
	n->w = geo_level_size(g->w, s) + (int)pad[0];
	n->h = geo_level_size(g->h, s) + (int)pad[1];
	n->w = n->w < 3 ? 3 : n->w, n->h = n->h < 3 ? 3 : n->h;
}
