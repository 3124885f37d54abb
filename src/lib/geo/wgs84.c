/* wgs84.c - the DEM's CRS to WGS84 geodetic (PROJ) and to ECEF (closed
 * form): see wgs84.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <proj_experimental.h>

#include <proj.h>

#include "geo/wgs84.h"

#define WGS84_A 6378137.0
#define WGS84_F (1 / 298.257223563)
#define DEG (M_PI / 180)

static void
quiet(void *data, int level, const char *msg)
{
	(void)data, (void)level, (void)msg;
}

/* The CRS with an ellipsoidal height axis, so that PROJ carries z as
 * the height above its ellipsoid (and through any datum shift). */
static PJ *
crs3d(PJ_CONTEXT *ctx, const georef *g)
{
	char def[32];
	const char *d = g->crs;
	PJ *crs, *c3;

	if (d[0] == '\0' && g->epsg > 0)
		snprintf(def, sizeof def, "EPSG:%d", g->epsg), d = def;
	if ((crs = proj_create(ctx, d)) == NULL || !proj_is_crs(crs)) {
		proj_destroy(crs);
		return NULL;
	}
	c3 = proj_crs_promote_to_3D(ctx, NULL, crs);
	proj_destroy(crs);
	return c3;
}

int
geo_proj_open(geo_proj *p, const georef *g, tl_err *e)
{
	PJ *src, *dst, *op;

	memset(p, 0, sizeof *p);
	if ((p->ctx = proj_context_create()) == NULL)
		return tl_fail(e, "PROJ: cannot create a context");
	proj_log_func(p->ctx, NULL, quiet);
	src = crs3d(p->ctx, g);
	dst = proj_create(p->ctx, "EPSG:4979");
	op = src && dst ? proj_create_crs_to_crs_from_pj(p->ctx, src, dst,
	    NULL, NULL) : NULL;
	p->op = op ? proj_normalize_for_visualization(p->ctx, op) : NULL;
	proj_destroy(op), proj_destroy(src), proj_destroy(dst);
	if (p->op == NULL) {
		/* PROJ fails alike when it cannot open proj.db */
		int fds = tl_fds_exhausted();
		geo_proj_close(p);
		if (fds)
			return tl_fail_fds(e, "PROJ", "its database");
		return tl_fail(e, "CRS %.200s: PROJ has no way to WGS 84 "
		    "(EPSG:4979)", g->crs);
	}
	return 0;
}

void
geo_proj_close(geo_proj *p)
{
	proj_destroy(p->op);
	if (p->ctx)
		proj_context_destroy(p->ctx);
	memset(p, 0, sizeof *p);
}

int
geo_proj_lonlat(geo_proj *p, double *x, double *y, double *z, int n, tl_err *e)
{
	size_t s = sizeof(double);
	double x0, y0;

	/* a NaN height is damage, not a CRS's limit: say which */
	for (int k = 0; k < n; k++)
		if (!isfinite(x[k]) || !isfinite(y[k]) || !isfinite(z[k]))
			return tl_fail(e, "vertex %d of %d: position %g, %g, "
			    "height %g: not finite, a damaged block or index "
			    "(tilecheck names it; rebuild the pyramid)", k, n,
			    x[k], y[k], z[k]);
	x0 = x[0], y0 = y[0];
	proj_trans_generic(p->op, PJ_FWD, x, s, (size_t)n, y, s, (size_t)n,
	    z, s, (size_t)n, NULL, 0, 0);
	for (int k = 0; k < n; k++)
		if (!isfinite(x[k]) || !isfinite(y[k]) || !isfinite(z[k]))
			return tl_fail(e, "PROJ: vertex %d of %d has no WGS 84 "
			    "position (the first is at %g, %g in the DEM's CRS): "
			    "outside the CRS's area?", k, n, x0, y0);
	return 0;
}

int
geo_proj_crs(geo_proj *p, double *x, double *y, double *z, int n)
{
	size_t s = sizeof(double);

	proj_trans_generic(p->op, PJ_INV, x, s, (size_t)n, y, s, (size_t)n,
	    z, s, (size_t)n, NULL, 0, 0);
	for (int k = 0; k < n; k++)
		if (!isfinite(x[k]) || !isfinite(y[k]))
			return -1;
	return 0;
}

void
geo_grid_crs(const georef *g, double I, double J, double *x, double *y)
{
	double x0, y0;

	geo_vertex_crs(g, 0, I, J, x, y);
	if (g->model != GEO_GEOGRAPHIC)
		return;
	geo_vertex_crs(g, 0, 0, 0, &x0, &y0);
	*y = fmax(-90, fmin(90, *y));
	*x = fmax(x0 - 360, fmin(x0 + 360, *x));
}

void
geo_ecef(double lon, double lat, double h, double out[3])
{
	double e2 = WGS84_F * (2 - WGS84_F), sl = sin(lat * DEG);
	double cl = cos(lat * DEG), n = WGS84_A / sqrt(1 - e2 * sl * sl);

	out[0] = (n + h) * cl * cos(lon * DEG);
	out[1] = (n + h) * cl * sin(lon * DEG);
	out[2] = (n * (1 - e2) + h) * sl;
}

void
geo_ellipsoid(double lon, double lat, double foot[3], double up[3])
{
	double e2 = WGS84_F * (2 - WGS84_F), sl = sin(lat * DEG);
	double cl = cos(lat * DEG), so = sin(lon * DEG), co = cos(lon * DEG);
	double n = WGS84_A / sqrt(1 - e2 * sl * sl);

	foot[0] = n * cl * co, foot[1] = n * cl * so;
	foot[2] = n * (1 - e2) * sl;
	up[0] = cl * co, up[1] = cl * so, up[2] = sl;
}

void
geo_enu(double lon, double lat, double r[9])
{
	double so = sin(lon * DEG), co = cos(lon * DEG);
	double sa = sin(lat * DEG), ca = cos(lat * DEG);

	r[0] = -so, r[1] = co, r[2] = 0;
	r[3] = -sa * co, r[4] = -sa * so, r[5] = ca;
	r[6] = ca * co, r[7] = ca * so, r[8] = sa;
}
