/* volume.c - a tile's bounding volume: its block's footprint (padding
 * included: triangles may overhang the DEM's edge) from the lowest skirt
 * to the highest vertex of its subtree, so that it holds its children's.
 * A box in the tile's east-north-up frame, or for a geographic DEM a
 * region (radians, ellipsoidal heights), fitted to a lattice of the
 * footprint's points (kept on the globe: geo_grid_crs), widened for the
 * curve between them. */
#include <math.h>

#include "tiles3d/t3_impl.h"

#define NL 17 /* lattice nodes a side */

/* Lattice point q (of NL * NL * 2) at level-0 grid position, height. */
static void
node(const t3_set *s, const t3_tile *t, int q, double *x, double *y,
    double *z)
{
	double cell = ldexp(1, t->level), span = BT_CELLS * cell;
	double pad = t->displaced ? 0.5 * cell : 0; /* QEM-3D offsets */
	double u = (double)(q % NL) / (NL - 1), v = (double)(q / NL % NL) /
	    (NL - 1);
	int top = q / (NL * NL);

	geo_grid_crs(&s->ix->geo, span * (t->bi + u) + pad * (2 * u - 1),
	    span * (t->bj + v) + pad * (2 * v - 1), x, y);
	*z = top ? s->zhi[t - s->tile] : s->zlo[t - s->tile];
}

/* Longitudes continuous over the lattice, whichever way PROJ wrapped
 * them: each node within half a turn of its neighbour (the one before
 * in its row, or above it), the first as it came. */
static void
unwrap(double *x, int n)
{
	for (int q = 1; q < n; q++) {
		int r = q % (NL * NL), ref = r % NL ? q - 1 : q - NL;
		if (r == 0)
			ref = q - NL * NL;
		x[q] += 360 * round((x[ref] - x[q]) / 360);
	}
}

/* A region from the footprint's extremes (degrees, metres): radians,
 * west and east within [-pi, pi] (west > east across the antimeridian,
 * as 3D Tiles has it; the whole turn when it spans one), south and
 * north within [-pi/2, pi/2]. */
static void
region(const double lo[3], const double hi[3], double *v)
{
	double k = floor((lo[0] + 180) / 360), w = lo[0], east = hi[0];

	if (hi[0] - lo[0] >= 360)
		w = -180, east = 180;
	else if (k != 0 || east > 180) {
		w = lo[0] - 360 * k, east = hi[0] - 360 * k;
		if (east > 180)
			east -= 360;
	}
	v[0] = w * M_PI / 180, v[2] = east * M_PI / 180;
	v[1] = fmax(-M_PI / 2, lo[1] * M_PI / 180);
	v[3] = fmin(M_PI / 2, hi[1] * M_PI / 180);
	v[4] = lo[2], v[5] = hi[2];
}

int
t3_volume(const t3_set *s, geo_proj *p, const t3_tile *t, double *v,
    tl_err *e)
{
	enum { N = NL * NL * 2 };
	double x[N], y[N], z[N], lo[3], hi[3], margin;

	for (int q = 0; q < N; q++)
		node(s, t, q, &x[q], &y[q], &z[q]);
	if (geo_proj_lonlat(p, x, y, z, N, e) < 0)
		return -1;
	if (s->region)
		unwrap(x, N);
	for (int a = 0; a < 3; a++)
		lo[a] = INFINITY, hi[a] = -INFINITY;
	for (int q = 0; q < N; q++) {
		double c[3], d[3], l[3];
		if (s->region) {
			l[0] = x[q], l[1] = y[q], l[2] = z[q];
		} else {
			geo_ecef(x[q], y[q], z[q], c);
			for (int a = 0; a < 3; a++)
				d[a] = c[a] - t->f.c[a];
			for (int a = 0; a < 3; a++)
				l[a] = t->f.r[3 * a] * d[0] +
				    t->f.r[3 * a + 1] * d[1] +
				    t->f.r[3 * a + 2] * d[2];
		}
		for (int a = 0; a < 3; a++)
			lo[a] = fmin(lo[a], l[a]), hi[a] = fmax(hi[a], l[a]);
	}
	if (s->region) {
		region(lo, hi, v);
		return 0;
	}
	/* the sagitta between nodes: (span / 16)^2 / 8R, with room */
	margin = 1 + 1e-3 * hypot(hi[0] - lo[0], hi[1] - lo[1]);
	for (int a = 0; a < 12; a++)
		v[a] = 0;
	for (int a = 0; a < 3; a++) {
		v[a] = 0.5 * (lo[a] + hi[a]);
		v[3 + 4 * a] = 0.5 * (hi[a] - lo[a]) + margin;
	}
	return 0;
}
