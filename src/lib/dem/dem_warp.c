/* dem_warp.c - the GDAL side of dem2rgb(1) (dem_warp.h): a DEM warped
 * onto a Web Mercator zoom's pixel grid (the pixel centres), its extent in WGS84, and a grid
 * of heights written as a GeoTIFF a row at a time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cpl_conv.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include "dem/dem_gdal.h"
#include "dem/dem_impl.h"
#include "dem/dem_warp.h"

double
dem_mgrid_res(const dem_mgrid *g)
{
	return 2 * DEM_MERC_HALF / ((double)g->dim * ldexp(1, g->z));
}

/* The geotransform whose pixels are g's: zoom z's own pixels, so a
 * file's pixel centres are the tiles' pixel centres (MapLibre's). */
static void
mgrid_gt(const dem_mgrid *g, double gt[6])
{
	double r = dem_mgrid_res(g);

	gt[0] = -DEM_MERC_HALF + (double)g->x0 * r;
	gt[1] = r, gt[2] = 0;
	gt[3] = DEM_MERC_HALF - (double)g->y0 * r;
	gt[4] = 0, gt[5] = -r;
}

int
dem_warp_mercator(const char *path, int has_nodata, double nodata,
    const dem_mgrid *g, int cubic, int threads, const char *out, tl_err *e)
{
	char te[4][40], ts[2][24], nd[40], nt[40];
	double gt[6];
	dem_gdal_msg m;
	GDALDatasetH src, dst = NULL;
	GDALWarpAppOptions *wo;
	int usage = 0;

	dem_gdal_init();
	mgrid_gt(g, gt);
	snprintf(te[0], sizeof te[0], "%.17g", gt[0]);
	snprintf(te[1], sizeof te[1], "%.17g", gt[3] + g->h * gt[5]);
	snprintf(te[2], sizeof te[2], "%.17g", gt[0] + g->w * gt[1]);
	snprintf(te[3], sizeof te[3], "%.17g", gt[3]);
	snprintf(ts[0], sizeof ts[0], "%d", g->w);
	snprintf(ts[1], sizeof ts[1], "%d", g->h);
	snprintf(nd, sizeof nd, "%.17g", nodata);
	snprintf(nt, sizeof nt, "NUM_THREADS=%d", threads < 1 ? 1 : threads);
	const char *argv[] = { "-t_srs", "EPSG:3857", "-te", te[0], te[1],
	    te[2], te[3], "-ts", ts[0], ts[1], "-r",
	    cubic ? "cubic" : "bilinear", "-ot", "Float32", "-dstnodata",
	    "nan", "-of", "GTiff", "-co", "TILED=YES", "-co",
	    "COMPRESS=NONE", "-co", "BIGTIFF=IF_SAFER", "-wm", "16", "-et", "0",
	    "-multi", "-wo", nt, "-q",
	    has_nodata ? "-srcnodata" : NULL, nd, NULL };
	/* a list: its tiles' overlaps compared, as its reading does */
	if ((src = dem_warp_open(path, &(dem_opts){ .has_nodata = has_nodata,
	    .nodata = nodata }, 1, e)) == NULL)
		return -1;
	dem_gdal_catch(&m);
	wo = GDALWarpAppOptionsNew((char **)argv, NULL);
	if (wo != NULL)
		dst = GDALWarp(out, NULL, 1, &src, wo, &usage);
	GDALWarpAppOptionsFree(wo);
	if (dst != NULL) {
		GDALClose(dst);
		if (m.msg[0] != '\0') /* a failure while flushing */
			dst = NULL;
	}
	GDALClose(src);
	dem_gdal_release();
	if (dst == NULL)
		return tl_fail(e, "%s: warp to Web Mercator: %s", path,
		    m.msg[0] ? m.msg : "GDAL failed");
	return 0;
}

/* Transforms n points of ds's CRS to WGS84 degrees (lon, lat). */
static int
to_wgs84(GDALDatasetH ds, double *x, double *y, int n)
{
	OGRSpatialReferenceH s, t;
	OGRCoordinateTransformationH ct = NULL;
	const char *wkt = GDALGetProjectionRef(ds);
	int ok = 0;

	if (wkt == NULL || *wkt == '\0')
		return -1;
	s = OSRNewSpatialReference(wkt);
	t = OSRNewSpatialReference(NULL);
	OSRImportFromEPSG(t, 4326);
	OSRSetAxisMappingStrategy(s, OAMS_TRADITIONAL_GIS_ORDER);
	OSRSetAxisMappingStrategy(t, OAMS_TRADITIONAL_GIS_ORDER);
	ct = OCTNewCoordinateTransformation(s, t);
	if (ct != NULL)
		ok = OCTTransform(ct, n, x, y, NULL);
	OCTDestroyCoordinateTransformation(ct);
	OSRDestroySpatialReference(s);
	OSRDestroySpatialReference(t);
	return ok ? 0 : -1;
}

static void
box(const double *x, const double *y, int n, double ll[4])
{
	ll[0] = ll[1] = HUGE_VAL, ll[2] = ll[3] = -HUGE_VAL;
	for (int i = 0; i < n; i++) {
		ll[0] = fmin(ll[0], x[i]), ll[2] = fmax(ll[2], x[i]);
		ll[1] = fmin(ll[1], y[i]), ll[3] = fmax(ll[3], y[i]);
	}
}

/* The outline's longitudes (n points a side, the sides interleaved:
 * point k of side s at k 4 + s, each side starting where the one before
 * ends) made continuous around it, then moved whole by 360 so that its
 * west lies in -180 .. 180; the 3 centre points after them moved by 360
 * to lie nearest the outline's middle. */
static void
unwrap(double *x, int n)
{
	double prev = x[0], lo = HUGE_VAL, hi = -HUGE_VAL, d = 0;

	for (int s = 0; s < 4; s++)
		for (int k = 0; k < n; k++) {
			double *p = &x[k * 4 + s];
			*p += 360 * round((prev - *p) / 360);
			prev = *p, lo = fmin(lo, *p), hi = fmax(hi, *p);
		}
	while (lo + d < -180)
		d += 360;
	while (lo + d >= 180)
		d -= 360;
	for (int i = 0; i < n * 4; i++)
		x[i] += d;
	for (int i = n * 4; i < n * 4 + 3; i++)
		x[i] += 360 * round(((lo + hi) / 2 + d - x[i]) / 360);
}

/* The outline's bounds: clamped to the world (a global grid a half cell
 * past its seam too); a DEM across the antimeridian (longitudes jumping
 * there between neighbours, a CRS whose longitudes wrap there, or past
 * 180 either way) unwrapped: its west in -180 .. 180, its east past
 * 180, the points moved with it. */
static int
bounds(const char *path, double *x, const double *y, int n, double ll[4],
    tl_err *e)
{
	int jumps = 0, past = 0;

	for (int k = 0; k < n * 4; k++) {
		jumps |= k + 4 < n * 4 && fabs(x[k] - x[k + 4]) > 180;
		past |= fabs(x[k]) > 180 + 1e-9;
	}
	box(x, y, n * 4, ll);
	if (!jumps && (!past || ll[2] - ll[0] >= 359.9)) {
		ll[0] = fmax(ll[0], -180), ll[2] = fmin(ll[2], 180);
		return 0;
	}
	unwrap(x, n);
	box(x, y, n * 4, ll);
	if (ll[2] - ll[0] >= 359.9)
		return tl_fail(e, "%s: spans the whole world across the "
		    "antimeridian (180 degrees): not supported; give it in a "
		    "CRS whose longitudes run -180 .. 180", path);
	return 0;
}

int
dem_extent_wgs84(const char *path, double ll[4], double *cell, tl_err *e)
{
	enum { N = 9 };
	double gt[6], x[N * 4 + 3], y[N * 4 + 3], w, h;
	dem_gdal_msg m;
	GDALDatasetH ds;
	enum dem_input kind;
	int k = 0, r;

	/* a FIFO or a device refused at once, as the reader does */
	if (strncmp(path, "/vsi", 4) != 0 && dem_check_file(path, &kind, e) < 0)
		return -1;
	if (kind == DEM_IN_EXR)
		return tl_fail(e, "%s: an EXR carries no georeferencing GDAL "
		    "reads: dem2rgb needs a DEM GDAL opens, with a CRS", path);
	/* the header only: -N (not known here) changes no place, and the
	 * tiles' nodata is checked by the reading of its header that
	 * follows (rg_warp_opts) */
	if ((ds = dem_warp_open(path, &(dem_opts){ .has_nodata = 1 }, 0,
	    e)) == NULL)
		return -1;
	dem_gdal_catch(&m);
	w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
	r = GDALGetGeoTransform(ds, gt) == CE_None ? 0 : -1;
	/* the outline (N points a side) and the centre cell's steps */
	for (int i = 0; i < N; i++) {
		double t = (double)i / (N - 1);
		double px[4] = { t * w, w, w - t * w, 0 };
		double py[4] = { 0, t * h, h, h - t * h };
		for (int s = 0; s < 4; s++, k++)
			x[k] = gt[0] + px[s] * gt[1] + py[s] * gt[2],
			y[k] = gt[3] + px[s] * gt[4] + py[s] * gt[5];
	}
	for (int s = 0; s < 3; s++, k++) {
		double px = w / 2 + (s == 1), py = h / 2 + (s == 2);
		x[k] = gt[0] + px * gt[1] + py * gt[2];
		y[k] = gt[3] + px * gt[4] + py * gt[5];
	}
	if (r == 0)
		r = to_wgs84(ds, x, y, k);
	GDALClose(ds);
	dem_gdal_release();
	if (r < 0)
		return tl_fail(e, "%s: no georeferencing GDAL can take to "
		    "WGS84 (dem2rgb needs a CRS)", path);
	if (bounds(path, x, y, N, ll, e) < 0)
		return -1;
	/* ground metres on a sphere of the mean radius: only for the rule */
	{
		const double R = 6371008.8, d = M_PI / 180;
		double c = cos(y[N * 4] * d);
		double sx = hypot((x[N * 4 + 1] - x[N * 4]) * c,
		    y[N * 4 + 1] - y[N * 4]) * d * R;
		double sy = hypot((x[N * 4 + 2] - x[N * 4]) * c,
		    y[N * 4 + 2] - y[N * 4]) * d * R;
		*cell = fmin(sx, sy);
	}
	return 0;
}

struct dem_mwriter {
	GDALDatasetH ds;
	int w, failed;
};

dem_mwriter *
dem_mwriter_open(const char *out, const dem_mgrid *g, tl_err *e)
{
	const char *co[] = { "TILED=NO", "COMPRESS=NONE", NULL };
	OGRSpatialReferenceH s;
	dem_mwriter *w;
	char *wkt = NULL;
	double gt[6];
	dem_gdal_msg m;
	GDALDriverH drv;

	dem_gdal_init();
	if ((w = tl_alloc(1, sizeof *w, e)) == NULL)
		return NULL;
	drv = GDALGetDriverByName("GTiff");
	dem_gdal_catch(&m);
	w->ds = drv ? GDALCreate(drv, out, g->w, g->h, 1, GDT_Float32,
	    (char **)co) : NULL;
	dem_gdal_release();
	if (w->ds == NULL) {
		free(w);
		tl_fail(e, "%s: %s", out, m.msg[0] ? m.msg :
		    "GDAL cannot create it");
		return NULL;
	}
	mgrid_gt(g, gt);
	s = OSRNewSpatialReference(NULL);
	OSRImportFromEPSG(s, 3857);
	OSRExportToWkt(s, &wkt);
	GDALSetProjection(w->ds, wkt);
	CPLFree(wkt);
	OSRDestroySpatialReference(s);
	GDALSetGeoTransform(w->ds, gt);
	GDALSetRasterNoDataValue(GDALGetRasterBand(w->ds, 1), NAN);
	w->w = g->w;
	return w;
}

int
dem_mwriter_row(dem_mwriter *w, int j, const float *z, tl_err *e)
{
	if (GDALRasterIO(GDALGetRasterBand(w->ds, 1), GF_Write, 0, j, w->w,
	    1, (void *)z, w->w, 1, GDT_Float32, 0, 0) != CE_None) {
		w->failed = 1;
		return tl_fail(e, "row %d: GDAL cannot write it", j);
	}
	return 0;
}

int
dem_mwriter_close(dem_mwriter *w, tl_err *e)
{
	dem_gdal_msg m;
	int bad;

	if (w == NULL)
		return 0;
	dem_gdal_catch(&m);
	GDALClose(w->ds);
	dem_gdal_release();
	bad = w->failed || m.msg[0] != '\0';
	free(w);
	return bad ? tl_fail(e, "GDAL could not finish a grid file") : 0;
}
