/* geodesy.h - the few geodesic computations the toolchain needs, through
 * GeographicLib (C++: geodesy.cpp is the shim). */
#ifndef TL_GEODESY_H
#define TL_GEODESY_H

#ifdef __cplusplus
extern "C" {
#endif

/* Geodesic distance s12 in metres between (lat1, lon1) and (lat2, lon2),
 * degrees, on WGS84. Returns 0, or -1 on bad input (latitude beyond +-90,
 * not finite) or any library failure. */
int tl_geod_inverse(double lat1, double lon1, double lat2, double lon2,
    double *s12);

/* The same on any ellipsoid (equatorial radius a metres, flattening f; 0
 * for a sphere), set up once: the metric of a projected grid measures
 * thousands of steps on its CRS's own ellipsoid. NULL on bad a or f. */
typedef struct tl_geod tl_geod;
tl_geod *tl_geod_new(double a, double f);
int tl_geod_distance(const tl_geod *g, double lat1, double lon1, double lat2,
    double lon2, double *s12);
void tl_geod_free(tl_geod *g);

#ifdef __cplusplus
}
#endif

#endif
