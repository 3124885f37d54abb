/* vdatum_lattice.c - DEM heights shifted between vertical datums, row by
 * row (vdatum_apply), with the operation vdatum.c chose.
 *
 * Cost: PROJ takes 130-370 ns per point for these pipelines (its
 * unitconvert step alone ~70 ns), 2-5 s for a 3601 x 3601 DEM. So the
 * shift is computed exactly (z = 0) at a lattice of nodes every S
 * samples, S chosen so that a lattice cell measures at most LATTICE_SPAN
 * metres along x plus y on the ground, and interpolated bilinearly in
 * between; where S would be 1 every sample is transformed exactly.
 *
 * Error of the lattice: the grids PROJ applies are interpolated
 * bilinearly in longitude, latitude, so the shift is smooth inside a
 * grid cell and its slope jumps (by at most ds) across a grid line. A
 * linear interpolation over h metres that straddles one such kink errs
 * by at most h ds / 4; the bilinear one by at most (hx + hy) ds / 4 <=
 * LATTICE_SPAN ds / 4 (its cells, <= 250 m, are far smaller than any
 * geoid grid's, 1.8 km for 1' grids, so a cell meets at most one line
 * each way), plus a curvature term below 1e-4 m where the DEM's axes are
 * not parallel to the grid's (projected CRSs). For EGM96 (egm96_15.gtx)
 * ds <= 2.2e-4 (measured over the whole grid; largest at the Canaries
 * and the Bonin trench), so the error is below 1.4 cm; t_vdatum measures
 * 9.3 mm on Tenerife with the grid lines mid-cell, the worst case. A
 * grid whose slope (the deflection of the vertical, rarely above 60",
 * 3e-4) changed sign across one line would make ds 6e-4 and the bound 4
 * cm. The heights' own accuracy (SRTM: metres) and that of EGM96's 15'
 * grid against the model (decimetres) are larger. */
#include "geo/vdatum_impl.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

/* Ground metres, x plus y, of a lattice cell; see the error above. */
#define LATTICE_SPAN 250.0
#define LATTICE_MAX_STEP 64
#define EARTH_RADIUS 6371008.8

/* Ground metres of one column step and one row step, the largest over
 * the DEM's corners and centre (WGS 84 lon/lat on a sphere: a 0.5 %
 * estimate is plenty to size the lattice). */
static int
sample_size(vdatum_shift *v, double *sx, double *sy)
{
	static const double at[5][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 },
		{ 1, 1 }, { 0.5, 0.5 } };
	double x[15], y[15], i, j, c, dx, dy, rad = M_PI / 180;

	for (int k = 0; k < 5; k++) {
		i = at[k][0] * (v->g.width - 1);
		j = at[k][1] * (v->g.height - 1);
		for (int q = 0; q < 3; q++)
			geo_vertex_crs(&v->g, 0, i + (q == 1), j + (q == 2),
			    &x[3 * k + q], &y[3 * k + q]);
	}
	proj_trans_generic(v->toll, PJ_FWD, x, sizeof *x, 15, y, sizeof *y,
	    15, NULL, 0, 0, NULL, 0, 0);
	*sx = *sy = 0;
	for (int k = 0; k < 15; k++)
		if (!isfinite(x[k]) || !isfinite(y[k]))
			return -1;
	for (int k = 0; k < 15; k += 3) {
		c = cos(y[k] * rad);
		for (int q = 1; q <= 2; q++) {
			dx = remainder(x[k + q] - x[k], 360) * c;
			dy = y[k + q] - y[k];
			*(q == 1 ? sx : sy) = fmax(*(q == 1 ? sx : sy),
			    EARTH_RADIUS * rad * hypot(dx, dy));
		}
	}
	return 0;
}

/* The lattice: the largest spacing S whose cells measure at most
 * LATTICE_SPAN metres, x plus y; 1 (exact) for small grids. */
int
vdatum_lattice_open(vdatum_shift *v, tl_err *e)
{
	double sx, sy;
	int s;

	v->step = 1;
	if (v->g.width < 2 || v->g.height < 2 ||
	    sample_size(v, &sx, &sy) < 0 || !(sx + sy > 0))
		return 0;
	s = (int)fmin(floor(LATTICE_SPAN / (sx + sy)), LATTICE_MAX_STEP);
	if (s < 2)
		return 0;
	v->step = s;
	v->nx = (v->g.width - 2) / s + 2;
	v->ny = (v->g.height - 2) / s + 2;
	for (int r = 0; r < 2; r++) {
		v->rows[r].m = -1;
		if ((v->rows[r].d = tl_alloc((size_t)v->nx,
		    sizeof *v->rows[r].d, e)) == NULL)
			return -1;
	}
	return 0;
}

static int
grow(vdatum_shift *v, int n, tl_err *e)
{
	double *x, *y, *z;

	if (n <= v->cap)
		return 0;
	x = tl_alloc((size_t)n, sizeof *x, e);
	y = tl_alloc((size_t)n, sizeof *y, e);
	z = tl_alloc((size_t)n, sizeof *z, e);
	if (x == NULL || y == NULL || z == NULL) {
		free(x), free(y), free(z);
		return -1;
	}
	free(v->x), free(v->y), free(v->z);
	v->x = x, v->y = y, v->z = z, v->cap = n;
	return 0;
}

static int
fail_sample(vdatum_shift *v, int j, int i, tl_err *e)
{
	double x, y;
	int err = proj_errno(v->op);

	geo_vertex_crs(&v->g, 0, i, j, &x, &y);
	return tl_fail(e, "%s: row %d column %d (%.10g, %.10g in the DEM's "
	    "CRS): PROJ gives no height there (%s)", v->name, j, i, x, y,
	    err != 0 ? proj_context_errno_string(v->ctx, err) :
	    vdatum_why(v->log));
}

/* The n points in x, y (the DEM's CRS), z (source units) to the target;
 * HUGE_VAL where PROJ gives nothing (outside a grid). */
static void
transform(vdatum_shift *v, int n)
{
	v->log[0] = '\0';
	if (v->toll != NULL) {
		proj_errno_reset(v->toll);
		proj_trans_generic(v->toll, PJ_FWD, v->x, sizeof *v->x, n,
		    v->y, sizeof *v->y, n, NULL, 0, 0, NULL, 0, 0);
	}
	proj_errno_reset(v->op);
	proj_trans_generic(v->op, PJ_FWD, v->x, sizeof *v->x, n, v->y,
	    sizeof *v->y, n, v->z, sizeof *v->z, n, NULL, 0, 0);
}

/* Every sample through PROJ. */
static int
exact(vdatum_shift *v, int j, int i0, int n, float *z, tl_err *e)
{
	if (grow(v, n, e) < 0)
		return -1;
	for (int k = 0; k < n; k++) {
		geo_vertex_crs(&v->g, 0, i0 + k, j, &v->x[k], &v->y[k]);
		/* The operation works in the source CRS's units. */
		v->z[k] = isnan(z[k]) ? 0 : z[k] / v->fs;
	}
	transform(v, n);
	for (int k = 0; k < n; k++)
		if (!isnan(z[k]) && !isfinite(v->z[k]))
			return fail_sample(v, j, i0 + k, e);
	for (int k = 0; k < n; k++)
		if (!isnan(z[k]))
			z[k] = (float)(v->z[k] * v->ft);
	return 0;
}

/* Level-0 column of lattice column k, row of lattice row m. */
static int
node_i(const vdatum_shift *v, int k)
{
	return k * v->step < v->g.width - 1 ? k * v->step : v->g.width - 1;
}

static int
node_j(const vdatum_shift *v, int m)
{
	return m * v->step < v->g.height - 1 ? m * v->step : v->g.height - 1;
}

/* Node row m with nodes k0..k1 computed, in the slot not holding node
 * row `keep`. The shift at a node is that of a height 0: the grids'
 * shifts do not depend on the height (a Helmert step's scale would, by
 * parts per million of it). */
static const double *
node_row(vdatum_shift *v, int m, int keep, int k0, int k1, tl_err *e)
{
	vdatum_nodes *r;
	int c = 0;

	assert(m >= 0 && m < v->ny && keep != m);
	assert(k0 >= 0 && k0 <= k1 && k1 < v->nx);
	r = &v->rows[v->rows[0].m == m ? 0 : v->rows[1].m == m ? 1 :
	    v->rows[0].m == keep ? 1 : 0];
	assert(r->m == m || r->m != keep); /* never the other row's slot */
	if (r->m != m) {
		r->m = m;
		for (int k = 0; k < v->nx; k++)
			r->d[k] = NAN;
	}
	if (grow(v, k1 - k0 + 1, e) < 0)
		return NULL;
	for (int k = k0; k <= k1; k++)
		if (isnan(r->d[k])) {
			geo_vertex_crs(&v->g, 0, node_i(v, k), node_j(v, m),
			    &v->x[c], &v->y[c]);
			v->z[c++] = 0;
		}
	if (c == 0)
		return r->d;
	transform(v, c);
	c = 0;
	for (int k = k0; k <= k1; k++)
		if (isnan(r->d[k])) {
			r->d[k] = isfinite(v->z[c]) ? v->z[c] * v->ft :
			    INFINITY;
			c++;
		}
	return r->d;
}

/* Bilinear between the lattice nodes around the samples. Returns 1,
 * z untouched, when a node has no shift (a grid's edge crosses the
 * cell): the caller goes exact then. */
static int
lattice(vdatum_shift *v, int j, int i0, int n, float *z, tl_err *e)
{
	const double *a, *b;
	double u, t, d;
	int m, k, k0, k1, s = v->step;

	m = j / s < v->ny - 2 ? j / s : v->ny - 2;
	k0 = i0 / s < v->nx - 2 ? i0 / s : v->nx - 2;
	k1 = (i0 + n - 1) / s + 1 < v->nx - 1 ? (i0 + n - 1) / s + 1 :
	    v->nx - 1;
	assert(m >= 0 && node_j(v, m) <= j && j <= node_j(v, m + 1));
	if ((a = node_row(v, m, m + 1, k0, k1, e)) == NULL ||
	    (b = node_row(v, m + 1, m, k0, k1, e)) == NULL)
		return -1;
	for (k = k0; k <= k1; k++)
		if (!isfinite(a[k]) || !isfinite(b[k]))
			return 1;
	u = (double)(j - node_j(v, m)) / (node_j(v, m + 1) - node_j(v, m));
	for (int q = 0; q < n; q++) {
		if (isnan(z[q]))
			continue;
		k = (i0 + q) / s < v->nx - 2 ? (i0 + q) / s : v->nx - 2;
		/* only nodes k0..k1 were computed */
		assert(k >= k0 && k + 1 <= k1);
		assert(node_i(v, k) <= i0 + q && i0 + q <= node_i(v, k + 1));
		t = (double)(i0 + q - node_i(v, k)) /
		    (node_i(v, k + 1) - node_i(v, k));
		d = (1 - u) * ((1 - t) * a[k] + t * a[k + 1]) +
		    u * ((1 - t) * b[k] + t * b[k + 1]);
		z[q] = (float)(z[q] + d);
	}
	return 0;
}

int
vdatum_apply(vdatum_shift *v, int j, int i0, int n, float *z, tl_err *e)
{
	int rc;

	if (v->op == NULL || n <= 0)
		return 0;
	/* The lattice covers the grid; anything else goes exact. */
	if (v->step > 1 && j >= 0 && j < v->g.height && i0 >= 0 &&
	    n <= v->g.width - i0) {
		if ((rc = lattice(v, j, i0, n, z, e)) <= 0)
			return rc;
	}
	return exact(v, j, i0, n, z, e);
}
