/* plan.c - the tiles before any block is read: per level its tolerance
 * and skirt, per tile its frame and the heights of its subtree, all from
 * the index (t3_impl.h). */
#include <math.h>
#include <stdlib.h>

#include "tiles3d/t3_impl.h"

/* Smallest radius of curvature of WGS 84 (the meridian's at the
 * equator), for a sagitta's bound. */
#define R_MIN 6335439.0

/* A frame at level-0 grid position (I, J), height z: ENU there. */
static int
frame_at(t3_proj *p, const georef *g, double I, double J, double z,
    t3_frame *f, tl_err *e)
{
	double x, y;

	geo_vertex_crs(g, 0, I, J, &x, &y);
	if (t3_proj_geo(p, &x, &y, &z, 1, e) < 0)
		return -1;
	t3_ecef(x, y, z, f->c);
	t3_enu(x, y, f->r);
	return 0;
}

/* The block's diagonal in metres (ECEF chord), for the sagitta term. */
static int
diagonal(t3_proj *p, const georef *g, const t3_tile *t, double *d,
    tl_err *e)
{
	double s = BT_CELLS * ldexp(1, t->level), x[2], y[2], z[2] = { 0, 0 };
	double a[3], b[3];

	geo_vertex_crs(g, 0, t->bi * s, t->bj * s, &x[0], &y[0]);
	geo_vertex_crs(g, 0, (t->bi + 1) * s, (t->bj + 1) * s, &x[1], &y[1]);
	if (t3_proj_geo(p, x, y, z, 2, e) < 0)
		return -1;
	t3_ecef(x[0], y[0], 0, a), t3_ecef(x[1], y[1], 0, b);
	*d = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
	    (a[2] - b[2]) * (a[2] - b[2]));
	return 0;
}

/* A bound of any tile's error on level l, from the index: unsplit
 * vertices have E <= min(tau, the block's largest), leaves the base
 * error, and flat triangles sag at most diag^2 / 8R (twice, for the
 * projection's curve and float rounding). */
static int
level_bounds(const t3_set *s, t3_proj *p, double *ub, tl_err *e)
{
	for (int l = 0; l < s->ix->nlevels; l++) {
		const pyramid_level *L = &s->ix->lev[l];
		ub[l] = 0;
		for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++) {
			t3_tile *t = &s->tile[s->first[l] + k];
			double d, b = fmax(fmin(t->tau, L->emax[k]), L->base[k]);
			if (diagonal(p, &s->ix->geo, t, &d, e) < 0)
				return -1;
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
t3_plan(t3_set *s, const pyramid_index *ix, double tau0, t3_proj *p,
    tl_err *e)
{
	int n = 0, nl = ix->nlevels, r = -1;
	double *ub = NULL;

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
	    (ub = tl_alloc(nl, sizeof *ub, e)) == NULL)
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
	if (level_bounds(s, p, ub, e) < 0)
		goto done;
	skirts(s, ub);
	heights(s);
	r = 0;
done:
	free(ub);
	return r;
}

void
t3_set_free(t3_set *s)
{
	free(s->first), free(s->tile), free(s->zlo), free(s->zhi);
	s->first = NULL, s->tile = NULL, s->zlo = s->zhi = NULL;
}
