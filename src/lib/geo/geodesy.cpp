// geodesy.cpp - extern "C" shim over GeographicLib; no exception leaves it.
#include "geo/geodesy.h"

#include <cmath>
#include <new>

#include <GeographicLib/Geodesic.hpp>

struct geodesy {
	GeographicLib::Geodesic g;
};

static bool
bad_points(double lat1, double lon1, double lat2, double lon2)
{
	return !std::isfinite(lat1) || !std::isfinite(lat2) ||
	    !std::isfinite(lon1) || !std::isfinite(lon2) ||
	    std::fabs(lat1) > 90 || std::fabs(lat2) > 90;
}

static int
distance(const GeographicLib::Geodesic &g, double lat1, double lon1,
    double lat2, double lon2, double *s12)
{
	if (bad_points(lat1, lon1, lat2, lon2))
		return -1;
	try {
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

extern "C" int
geodesy_inverse(double lat1, double lon1, double lat2, double lon2,
    double *s12)
{
	return distance(GeographicLib::Geodesic::WGS84(), lat1, lon1, lat2,
	    lon2, s12);
}

extern "C" geodesy *
geodesy_new(double a, double f)
{
	if (!(std::isfinite(a) && a > 0 && std::isfinite(f) && f < 1))
		return nullptr;
	try {
		return new geodesy{ GeographicLib::Geodesic(a, f) };
	} catch (...) {
		return nullptr;
	}
}

extern "C" int
geodesy_distance(const geodesy *g, double lat1, double lon1, double lat2,
    double lon2, double *s12)
{
	return distance(g->g, lat1, lon1, lat2, lon2, s12);
}

extern "C" void
geodesy_free(geodesy *g)
{
	delete g;
}
