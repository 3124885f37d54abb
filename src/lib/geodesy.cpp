// geodesy.cpp - extern "C" shim over GeographicLib; no exception leaves it.
#include "geodesy.h"

#include <cmath>

#include <GeographicLib/Geodesic.hpp>

extern "C" int
tl_geod_inverse(double lat1, double lon1, double lat2, double lon2,
    double *s12)
{
	if (!std::isfinite(lat1) || !std::isfinite(lat2) ||
	    !std::isfinite(lon1) || !std::isfinite(lon2) ||
	    std::fabs(lat1) > 90 || std::fabs(lat2) > 90)
		return -1;
	try {
		const GeographicLib::Geodesic &g = GeographicLib::Geodesic::WGS84();
		double s;

		g.Inverse(lat1, lon1, lat2, lon2, s);
		if (!std::isfinite(s))
			return -1;
		*s12 = s;
		return 0;
	} catch (...) {
		return -1;
	}
}
