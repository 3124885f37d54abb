/* volume.c - a tile's bounding volume: its block's footprint (padding
 * included: triangles may overhang the DEM's edge) from the lowest skirt
 * to the highest vertex of its subtree, so that it holds its children's.
 * A box in the tile's east-north-up frame, or for a geographic DEM a
 * region (radians, ellipsoidal heights), fitted to a lattice of the
 * footprint's points, widened for the curve between them. */
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

	geo_vertex_crs(&s->ix->geo, 0, span * (t->bi + u) + pad * (2 * u - 1),
	    span * (t->bj + v) + pad * (2 * v - 1), x, y);
	*z = top ? s->zhi[t - s->tile] : s->zlo[t - s->tile];
}

int
t3_volume(const t3_set *s, t3_proj *p, const t3_tile *t, double *v,
    tl_err *e)
{
	enum { N = NL * NL * 2 };
	double x[N], y[N], z[N], lo[3], hi[3], margin;

	for (int q = 0; q < N; q++)
		node(s, t, q, &x[q], &y[q], &z[q]);
	if (t3_proj_geo(p, x, y, z, N, e) < 0)
		return -1;
	for (int a = 0; a < 3; a++)
		lo[a] = INFINITY, hi[a] = -INFINITY;
	for (int q = 0; q < N; q++) {
		double c[3], d[3], l[3];
		if (s->region) {
			l[0] = x[q] * M_PI / 180, l[1] = y[q] * M_PI / 180;
			l[2] = z[q];
		} else {
			t3_ecef(x[q], y[q], z[q], c);
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
		/* a geographic grid's footprint is a lon/lat rectangle */
		double v6[6] = { lo[0], lo[1], hi[0], hi[1], lo[2], hi[2] };
		for (int a = 0; a < 6; a++)
			v[a] = v6[a];
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
