/* world.c - the pyramid in metres (see world.h). */
#include "play/world.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

int
world_open(world *w, const char *dir, tl_err *e)
{
	memset(w, 0, sizeof *w);
	snprintf(w->dir, sizeof w->dir, "%s", dir);
	if (pyramid_index_read(dir, &w->ix, e) < 0)
		return -1;
	if (pyramid_levels_probe(dir, &w->ix, e) < 0 ||
	    geo_ground_init(&w->m, &w->ix.geo, e) < 0) {
		pyramid_index_free(&w->ix);
		return -1;
	}
	w->ci = (w->ix.size0[0] - 1) / 2.0;
	w->cj = (w->ix.size0[1] - 1) / 2.0;
	w->zmin = INFINITY, w->zmax = -INFINITY;
	for (int l = 0; l < w->ix.nlevels; l++) {
		pyramid_level *L = &w->ix.lev[l];
		for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++) {
			w->zmin = fmin(w->zmin, L->zmin[k]);
			w->zmax = fmax(w->zmax, L->zmax[k]);
		}
	}
	if (!(w->zmin <= w->zmax))
		w->zmin = w->zmax = 0;
	/* skirts hang to a floor under everything */
	w->base = w->zmin - 0.02 * (w->zmax - w->zmin) - 1;
	return 0;
}

void
world_close(world *w)
{
	pyramid_index_free(&w->ix);
	geo_ground_free(&w->m);
}

/* World x: metres along row J from the centre column (for a per-row
 * metric (I - ci) * dx at the fractional row J); world y: metres along
 * column I from the centre row, northward (rows run south). */
void
world_pos(const world *w, double I, double J, double X, double Y, double z,
    double out[3])
{
	out[0] = geo_x(&w->m, w->ci, I, J) + X;
	out[1] = -(geo_y(&w->m, I, J) - geo_y(&w->m, I, w->cj)) - Y;
	out[2] = z;
}

int
world_block_exists(const world *w, int l, int bi, int bj)
{
	const pyramid_level *L;

	if (l < 0 || l >= w->ix.nlevels)
		return 0;
	L = &w->ix.lev[l];
	return bi >= 0 && bj >= 0 && bi < L->blocks[0] && bj < L->blocks[1];
}

int
world_block_curved(const world *w, int l, int bi, int bj)
{
	double span = BT_CELLS * ldexp(1, l), lo = INFINITY, hi = 0;
	double last = w->ix.size0[1] - 1;

	(void)bi;
	for (int k = 0; k <= 8; k++) {
		double J = fmin(last, (bj + k / 8.0) * span);
		double sx = geo_sx(&w->m, 0, J);
		lo = fmin(lo, sx), hi = fmax(hi, sx);
	}
	return lo < 0.5 * hi;
}

void
world_block_box(const world *w, int level, int bi, int bj, double lo[3],
    double hi[3])
{
	const pyramid_level *L = &w->ix.lev[level];
	double s = (double)(1L << level), span = BT_CELLS * s;
	double pad = L->displaced ? 0.5 * s : 0;
	int k = bj * L->blocks[0] + bi;

	assert(world_block_exists(w, level, bi, bj));
	lo[0] = lo[1] = INFINITY, hi[0] = hi[1] = -INFINITY;
	for (int c = 0; c < 4; c++) {
		double p[3];
		double I = bi * span + (c & 1 ? span + pad : -pad);
		double J = bj * span + (c & 2 ? span + pad : -pad);
		world_pos(w, I, J, 0, 0, 0, p);
		for (int a = 0; a < 2; a++)
			lo[a] = fmin(lo[a], p[a]), hi[a] = fmax(hi[a], p[a]);
	}
	lo[2] = L->zmin[k], hi[2] = L->zmax[k];
}

int
world_blocks(const world *w)
{
	int n = 0;

	for (int l = 0; l < w->ix.nlevels; l++)
		n += w->ix.lev[l].blocks[0] * w->ix.lev[l].blocks[1];
	return n;
}

void
world_box(const world *w, double lo[3], double hi[3])
{
	double p[3], q[3];

	world_pos(w, 0, 0, 0, 0, 0, p);
	world_pos(w, w->ix.size0[0] - 1, w->ix.size0[1] - 1, 0, 0, 0, q);
	lo[0] = fmin(p[0], q[0]), hi[0] = fmax(p[0], q[0]);
	lo[1] = fmin(p[1], q[1]), hi[1] = fmax(p[1], q[1]);
	lo[2] = w->zmin, hi[2] = w->zmax;
	/* a geographic DEM is widest on its row nearest the equator, not on
	 * its first or last (a pole's is a point) */
	for (int k = 1; k < 16; k++) {
		world_pos(w, 0, k * (w->ix.size0[1] - 1) / 16.0, 0, 0, 0, p);
		world_pos(w, w->ix.size0[0] - 1, k * (w->ix.size0[1] - 1) /
		    16.0, 0, 0, 0, q);
		lo[0] = fmin(lo[0], fmin(p[0], q[0]));
		hi[0] = fmax(hi[0], fmax(p[0], q[0]));
	}
}
