/* plan.c - the tiles before any block is read: per level its tolerance
 * and skirt, per tile its frame and the heights of its subtree, all from
 * the index (t3_impl.h). */
#include <math.h>
#include <stdlib.h>

#include "tiles3d/t3_impl.h"

/* Smallest radius of curvature of WGS 84 (the meridian's at the
 * equator), for a sagitta's bound. */
#define R_MIN 6335439.0
/* Metres: a triangle whose chord may sag more than this and than tau
 * below the Earth's curve is split whatever its E, so that blocks the
 * size of continents (a global DEM) are not drawn as a few flat
 * triangles hundreds of kilometres under the ground. Blocks under about
 * 700 km across (padding included) never reach it: their tiles are
 * what they were. */
#define SAG_SPLIT 10000.0
#define NC 9 /* lattice nodes a side for a cell's length */

/* A frame at level-0 grid position (I, J), height z: ENU there. */
static int
frame_at(geo_proj *p, const georef *g, double I, double J, double z,
    t3_frame *f, tl_err *e)
{
	double x, y;

	geo_grid_crs(g, I, J, &x, &y);
	if (geo_proj_lonlat(p, &x, &y, &z, 1, e) < 0)
		return -1;
	geo_ecef(x, y, z, f->c);
	geo_enu(x, y, f->r);
	return 0;
}

/* The block's diagonal in metres (ECEF chord), for the sagitta term. */
static int
diagonal(geo_proj *p, const georef *g, const t3_tile *t, double *d,
    tl_err *e)
{
	double s = BT_CELLS * ldexp(1, t->level), x[2], y[2], z[2] = { 0, 0 };
	double a[3], b[3];

	geo_grid_crs(g, t->bi * s, t->bj * s, &x[0], &y[0]);
	geo_grid_crs(g, (t->bi + 1) * s, (t->bj + 1) * s, &x[1], &y[1]);
	if (geo_proj_lonlat(p, x, y, z, 2, e) < 0)
		return -1;
	geo_ecef(x[0], y[0], 0, a), geo_ecef(x[1], y[1], 0, b);
	*d = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
	    (a[2] - b[2]) * (a[2] - b[2]));
	return 0;
}

/* The longest chord of one level cell step along a row or a column of
 * tile t, from a lattice of its footprint (kept on the globe), with 5 %
 * for the arcs between nodes. */
static int
cell_length(geo_proj *p, const georef *g, const t3_tile *t, double *len,
    tl_err *e)
{
	double span = BT_CELLS * ldexp(1, t->level), x[NC * NC], y[NC * NC];
	double z[NC * NC] = { 0 }, a[3], b[3], m = 0;

	for (int q = 0; q < NC * NC; q++)
		geo_grid_crs(g, span * (t->bi + (double)(q % NC) / (NC - 1)),
		    span * (t->bj + (double)(q / NC) / (NC - 1)), &x[q], &y[q]);
	if (geo_proj_lonlat(p, x, y, z, NC * NC, e) < 0)
		return -1;
	for (int q = 0; q < NC * NC; q++) {
		geo_ecef(x[q], y[q], 0, a);
		for (int k = 0; k < 2; k++) {
			int o = k ? q + NC : q + 1;
			if ((k ? q / NC : q % NC) == NC - 1)
				continue;
			geo_ecef(x[o], y[o], 0, b);
			m = fmax(m, hypot(hypot(a[0] - b[0], a[1] - b[1]),
			    a[2] - b[2]));
		}
	}
	*len = 1.05 * m * (NC - 1) / BT_CELLS;
	return 0;
}

/* Per level: the longest cell (cl) and each tile's lmax, the hypotenuse
 * in cells whose chord sags SAG_SPLIT or tau. */
static int
curve_split(t3_set *s, geo_proj *p, double *cl, tl_err *e)
{
	for (int l = 0; l < s->ix->nlevels; l++) {
		cl[l] = 0;
		for (int k = s->first[l]; k < s->first[l + 1]; k++) {
			double c;
			if (cell_length(p, &s->ix->geo, &s->tile[k], &c, e) < 0)
				return -1;
			cl[l] = fmax(cl[l], c);
		}
		for (int k = s->first[l]; k < s->first[l + 1]; k++) {
			t3_tile *t = &s->tile[k];
			t->lmax = cl[l] > 0 ? sqrt(8 * R_MIN * fmax(t->tau,
			    SAG_SPLIT)) / cl[l] : 2 * BT_CELLS;
		}
	}
	return 0;
}

/* A bound of any tile's error on level l, from the index: unsplit
 * vertices have E <= min(tau, the block's largest), leaves the base
 * error, and flat triangles sag at most d^2 / 8R (twice, for the
 * projection's curve and float rounding), d the block's diagonal or the
 * longest hypotenuse the curve lets stand (lmax cells, or a leaf's). */
static int
level_bounds(const t3_set *s, geo_proj *p, const double *cl, double *ub,
    tl_err *e)
{
	for (int l = 0; l < s->ix->nlevels; l++) {
		const pyramid_level *L = &s->ix->lev[l];
		ub[l] = 0;
		for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++) {
			t3_tile *t = &s->tile[s->first[l] + k];
			double d, b = fmax(fmin(t->tau, L->emax[k]), L->base[k]);
			if (diagonal(p, &s->ix->geo, t, &d, e) < 0)
				return -1;
			d = fmin(d, fmax(t->lmax, M_SQRT2) * cl[l]);
			ub[l] = fmax(ub[l], b + 2 * d * d / (8 * R_MIN));
		}
	}
	return 0;
}

/* Skirts reach the gap to a neighbour up to two levels coarser: both
 * surfaces lie within their errors of the DEM along the shared edge. */
static void
skirts(t3_set *s, const double *ub)
{
	int top = s->ix->nlevels - 1;

	for (int l = 0; l <= top; l++) {
		double m = 0;
		for (int k = l; k <= l + 2 && k <= top; k++)
			m = fmax(m, ub[k]);
		for (int k = s->first[l]; k < s->first[l + 1]; k++)
			s->tile[k].skirt = fmax(2 * m, 1);
	}
}

/* Heights of each tile's subtree, bottom skirt included. */
static void
heights(t3_set *s)
{
	for (int l = 0; l < s->ix->nlevels; l++) {
		const pyramid_level *L = &s->ix->lev[l];
		for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++) {
			int id = s->first[l] + k, bi = k % L->blocks[0];
			int bj = k / L->blocks[0];
			s->zlo[id] = L->zmin[k] - s->tile[id].skirt;
			s->zhi[id] = L->zmax[k];
			for (int q = 0; l > 0 && q < 4; q++) {
				const pyramid_level *C = &s->ix->lev[l - 1];
				int ci = 2 * bi + (q & 1), cj = 2 * bj + q / 2;
				if (ci >= C->blocks[0] || cj >= C->blocks[1])
					continue;
				int c = s->first[l - 1] + cj * C->blocks[0] + ci;
				s->zlo[id] = fmin(s->zlo[id], s->zlo[c]);
				s->zhi[id] = fmax(s->zhi[id], s->zhi[c]);
			}
		}
	}
}

int
t3_plan(t3_set *s, const pyramid_index *ix, double tau0, geo_proj *p,
    tl_err *e)
{
	int n = 0, nl = ix->nlevels, r = -1;
	double *ub = NULL, *cl = NULL;

	s->ix = ix;
	s->region = ix->geo.model == GEO_GEOGRAPHIC;
	if ((s->first = tl_alloc(nl + 1, sizeof *s->first, e)) == NULL)
		return -1;
	for (int l = 0; l < nl; l++)
		s->first[l] = n, n += ix->lev[l].blocks[0] * ix->lev[l].blocks[1];
	s->first[nl] = n;
	s->tile = tl_alloc(n, sizeof *s->tile, e);
	s->zlo = tl_alloc(n, sizeof *s->zlo, e);
	s->zhi = tl_alloc(n, sizeof *s->zhi, e);
	if (!s->tile || !s->zlo || !s->zhi ||
	    (ub = tl_alloc(nl, sizeof *ub, e)) == NULL ||
	    (cl = tl_alloc(nl, sizeof *cl, e)) == NULL)
		goto done;
	for (int l = 0; l < nl; l++) {
		const pyramid_level *L = &ix->lev[l];
		double span = BT_CELLS * ldexp(1, l);
		for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++) {
			t3_tile *t = &s->tile[s->first[l] + k];
			t->level = l, t->bi = k % L->blocks[0];
			t->bj = k / L->blocks[0];
			t->displaced = L->displaced;
			t->cmax = L->size[0] - 1 - BT_CELLS * t->bi;
			t->rmax = L->size[1] - 1 - BT_CELLS * t->bj;
			/* the bound is max(tau, base error): a tau under
			 * the base error adds triangles, not accuracy */
			t->tau = fmax(tau0 * ldexp(1, l), L->base[k]);
			if (frame_at(p, &ix->geo, (t->bi + 0.5) * span,
			    (t->bj + 0.5) * span, 0.5 * (L->zmin[k] + L->zmax[k]),
			    &t->f, e) < 0)
				goto done;
		}
	}
	if (curve_split(s, p, cl, e) < 0 || level_bounds(s, p, cl, ub, e) < 0)
		goto done;
	skirts(s, ub);
	heights(s);
	r = 0;
done:
	free(ub), free(cl);
	return r;
}

void
t3_set_free(t3_set *s)
{
	free(s->first), free(s->tile), free(s->zlo), free(s->zhi);
	s->first = NULL, s->tile = NULL, s->zlo = s->zhi = NULL;
}
