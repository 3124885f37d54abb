/* geodesy.h - the few geodesic computations the toolchain needs, on the
 * WGS84 ellipsoid, through GeographicLib (C++: geodesy.cpp is the shim). */
#ifndef TL_GEODESY_H
#define TL_GEODESY_H

#ifdef __cplusplus
extern "C" {
#endif

/* Geodesic distance s12 in metres between (lat1, lon1) and (lat2, lon2),
 * degrees. Returns 0, or -1 on bad input (latitude beyond +-90, not
 * finite) or any library failure. */
int tl_geod_inverse(double lat1, double lon1, double lat2, double lon2,
    double *s12);

#ifdef __cplusplus
}
#endif

#endif
