/* dem_warp.h - a DEM put on a Web Mercator grid by GDAL's warper, and a
 * Web Mercator grid of heights written row by row: the GDAL side of
 * dem2rgb(1) (the rgb layer reaches GDAL only through these).
 *
 * A grid is a window of the global Web Mercator pixel grid of a zoom:
 * its point (i, j) is the centre of global pixel (x0 + i, y0 + j) of zoom
 * z, i.e. EPSG:3857 x = -PI R + (x0 + i + 0.5) res, y = PI R - (y0 + j +
 * 0.5) res, res = 2 PI R / (dim 2^z), R = 6378137 m (where MapLibre
 * places a raster-dem pixel's height). The files are float32 GeoTIFFs in
 * EPSG:3857 whose pixel centres are those points, voids NaN. */
#ifndef TL_DEM_WARP_H
#define TL_DEM_WARP_H

#include "base/util.h"

typedef struct {
	int z, dim;        /* zoom and tile size: res = 2 PI R / (dim 2^z) */
	long long x0, y0;  /* global pixel of grid point (0, 0) */
	int w, h;          /* points */
} dem_mgrid;

#define DEM_MERC_HALF 20037508.342789244 /* PI R, metres */

/* The grid's pixel size in metres of EPSG:3857. */
double dem_mgrid_res(const dem_mgrid *g);

/* The DEM path (any dataset GDAL opens, or a list of DEM files read as
 * the reader reads it, dem2fqm(1) MOSAICS; a source nodata, when
 * has_nodata, overriding the file's) warped by GDAL onto g, bilinear
 * (cubic: 1), its validity kept (nodata and mask: GDAL's warper weights
 * only valid samples; a vertex with none is NaN), into the GeoTIFF out,
 * on `threads` threads (the result is the same for any count). */
int dem_warp_mercator(const char *path, int has_nodata, double nodata,
    const dem_mgrid *g, int cubic, int threads, const char *out,
    tl_err *e);

/* The DEM's bounds in degrees of WGS84 (west, south, east, north), its
 * centre latitude and its cell in ground metres there (the smaller of
 * the two steps), from its header: for the zoom rule. West lies in
 * -180 .. 180; east past 180 when the DEM lies across the antimeridian
 * (its longitudes past 180 either way, or wrapping there), the grids
 * around it then running past the world's east edge (the warp takes
 * EPSG:3857 x past PI R as longitudes past 180). */
int dem_extent_wgs84(const char *path, double ll[4], double *cell,
    tl_err *e);

/* A grid written a row at a time (north first) as a GeoTIFF. */
typedef struct dem_mwriter dem_mwriter;
dem_mwriter *dem_mwriter_open(const char *out, const dem_mgrid *g,
    tl_err *e);
/* Row j (in order); NaN for a void. */
int dem_mwriter_row(dem_mwriter *w, int j, const float *z, tl_err *e);
/* Closes; 0, or -1 when a write failed (the file is then incomplete). */
int dem_mwriter_close(dem_mwriter *w, tl_err *e);

#endif
