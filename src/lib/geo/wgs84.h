/* wgs84.h - the DEM's CRS to WGS84 longitude, latitude and ellipsoidal
 * height (PROJ), and those to ECEF (closed form): what every exporter
 * to a globe (3D Tiles, terrain) places its vertices with. */
#ifndef TL_GEO_WGS84_H
#define TL_GEO_WGS84_H

#include "geo/georef.h"

/* One thread's PROJ: the DEM's CRS, heights ellipsoidal (promoted to
 * 3D), to EPSG:4979 longitude, latitude (degrees), height. */
typedef struct {
	void *ctx; /* PJ_CONTEXT, PROJ's only in wgs84.c */
	void *op;  /* PJ */
} geo_proj;

int geo_proj_open(geo_proj *p, const georef *g, tl_err *e);
void geo_proj_close(geo_proj *p);
/* n points in place: x, y (CRS), z (m) in; lon, lat (deg), h (m) out. */
int geo_proj_lonlat(geo_proj *p, double *x, double *y, double *z, int n,
    tl_err *e);

/* The inverse, n points in place: lon, lat (deg), h (m) in; x, y (CRS),
 * z out; -1 when one has no place in the CRS. */
int geo_proj_crs(geo_proj *p, double *x, double *y, double *z, int n);

/* Level-0 grid place (I, J) in the DEM's CRS (geo_vertex_crs), kept on
 * the globe for a geographic DEM: padding past a pole stops at the pole,
 * padding past a full turn of longitude from column 0 stops a turn away
 * (where the DEM's column 0 comes round again). Any other place, and
 * every place of a projected DEM, is geo_vertex_crs's. */
void geo_grid_crs(const georef *g, double I, double J, double *x, double *y);

/* WGS84 (EPSG:4979 -> EPSG:4978), closed form. */
void geo_ecef(double lon, double lat, double h, double out[3]);
/* The point of height 0 at (lon, lat) and the unit normal there: the
 * point of height h is foot + h up. */
void geo_ellipsoid(double lon, double lat, double foot[3], double up[3]);
/* The east, north, up unit vectors at (lon, lat), rows of r (9). */
void geo_enu(double lon, double lat, double r[9]);

#endif
