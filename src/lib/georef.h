/* georef.h - georeferencing carried from the DEM to every output, and the
 * metric embedding of the grid (cell sizes in metres, never degrees). */
#ifndef TL_GEOREF_H
#define TL_GEOREF_H

#include "raster.h"
#include "util.h"

enum geo_model { GEO_NONE, GEO_PROJECTED, GEO_GEOGRAPHIC };

typedef struct {
	enum geo_model model;
	int epsg;        /* horizontal CRS EPSG code, 0 if none or unknown */
	char crs[4096];  /* "EPSG:32611" when the CRS is one EPSG code, else
	                  * its WKT2 (one line), "" for GEO_NONE */
	int point;       /* 1 PixelIsPoint, 0 PixelIsArea */
	double origin[2]; /* CRS coords of raster point (0,0): the corner of
	                   * pixel (0,0) (area) or its centre (point), exactly
	                   * as the file's tie point gives it */
	double step[2];  /* level-0 pixel size in CRS units, signed as in a
	                  * GDAL geotransform (y < 0 for north-up) */
	double unit;     /* metres per CRS unit; 1 for GEO_NONE (cells given
	                  * in metres), 0 for GEO_GEOGRAPHIC (degrees) */
	char vdatum[256]; /* vertical datum as declared ("EPSG:5773", a
	                   * citation, "EGM96 (SRTM)"), "" when not declared */
	double cell[2];  /* metres per column and per row step given by the
	                  * user (-s) on a georeferenced DEM, overriding the
	                  * CRS's metric; 0 0 = the metric comes from the CRS */
	int has_nodata;
	double nodata;   /* as declared by the file (may be NaN) */
	int width, height; /* level-0 size */
} georef;

/* Writes / reads the geo:* attributes documented in fqm(5). */
int geo_to_header(const georef *g, rs_header *h, tl_err *e);
int geo_from_header(georef *g, const rs_header *h, tl_err *e);

/* CRS coordinates of the centre of vertex (i, j) of a level: level-0
 * position (i*2^level, j*2^level). */
void geo_vertex_crs(const georef *g, int level, double i, double j,
    double *x, double *y);

/* The metric embedding of the level-0 grid, per row J: dx[J] is the width
 * of a cell in metres along row J, y[J] the distance in metres from row 0
 * along the grid's y axis (y[0] = 0, increasing with J). Vertex (I, J) seen
 * from vertex (I0, J0) sits at ((I - I0) * dx[J], y[J] - y[J0]). Projected
 * and ungeoreferenced grids: constant dx, y[J] = J * dy. Geographic grids:
 * geodesic distances on WGS84 (GeographicLib) along the parallel of row J
 * and along the meridian between rows. */
typedef struct {
	int height;
	double *dx;
	double *y;
} geo_metric;

int geo_metric_init(geo_metric *m, const georef *g, tl_err *e);
void geo_metric_free(geo_metric *m);

/* For dem.c and programs that build a georef by hand. */

/* GEO_NONE: origin (0,0), step (cx, -cy) in metres, unit 1, point 1. */
void geo_init_none(georef *g, double cx, double cy);

#endif
