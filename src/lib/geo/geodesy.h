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
int geodesy_inverse(double lat1, double lon1, double lat2, double lon2,
    double *s12);

/* The same on any ellipsoid (equatorial radius a metres, flattening f; 0
 * for a sphere), set up once: the metric of a projected grid measures
 * thousands of steps on its CRS's own ellipsoid. NULL on bad a or f. */
typedef struct geodesy geodesy;
geodesy *geodesy_new(double a, double f);
int geodesy_distance(const geodesy *g, double lat1, double lon1, double lat2,
    double lon2, double *s12);
void geodesy_free(geodesy *g);

#ifdef __cplusplus
}
#endif

#endif
