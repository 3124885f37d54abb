/* t_geodesy - the GeographicLib shim (geodesy.h): distances along the
 * equator and a meridian quadrant on WGS84, great circles on a sphere
 * against the haversine formula, symmetry, and bad input refused. */
#include "geo/geodesy.h"
#include "tap.h"
#include "urand.h"

#include <math.h>

#define WGS84_A 6378137.0
#define WGS84_F (1 / 298.257223563)

/* Great-circle distance on a sphere of radius r, degrees in. */
static double
haversine(double r, double lat1, double lon1, double lat2, double lon2)
{
	double d = M_PI / 180, a;

	a = pow(sin((lat2 - lat1) * d / 2), 2) +
	    cos(lat1 * d) * cos(lat2 * d) * pow(sin((lon2 - lon1) * d / 2), 2);
	return 2 * r * asin(sqrt(a));
}

static void
test_wgs84(void)
{
	double s = 0, q = 0, t = 0, u = 0;
	int r;

	r = geodesy_inverse(0, 10, 0, 11.5, &s);
	ok(r == 0 && fabs(s - WGS84_A * 1.5 * M_PI / 180) < 1e-6,
	    "along the equator: a times the longitude difference (%.6f m)", s);
	r = geodesy_inverse(0, 0, 90, 0, &q);
	ok(r == 0 && fabs(q - 10001965.7293) < 1e-3, "a meridian quadrant: "
	    "10001965.729 m (%.4f)", q);
	r = geodesy_inverse(35, 139, -33.9, 151.2, &t) |
	    geodesy_inverse(-33.9, 151.2, 35, 139, &u);
	ok(r == 0 && fabs(t - u) < 1e-6 && t > 7.7e6 && t < 7.9e6,
	    "symmetric, and Tokyo-Sydney about 7.8e6 m (%.1f)", t);
	s = -1;
	ok(geodesy_inverse(90.5, 0, 0, 0, &s) < 0 &&
	    geodesy_inverse(0, NAN, 0, 0, &s) < 0 &&
	    geodesy_inverse(0, 0, 0, INFINITY, &s) < 0 && s == -1,
	    "latitude beyond 90, NaN or infinite coordinates refused, s12 "
	    "untouched");
}

static void
test_ellipsoids(void)
{
	geodesy *w = geodesy_new(WGS84_A, WGS84_F);
	geodesy *sph = geodesy_new(6371000, 0);
	unsigned seed = 5;
	double worst = 0, a, b;
	int same = 1;

	ok(w != NULL && sph != NULL, "geodesy_new: WGS84 and a sphere");
	for (int k = 0; k < 200; k++) {
		double lat1 = 89 * urand(&seed), lon1 = 180 * urand(&seed);
		double lat2 = 89 * urand(&seed), lon2 = 180 * urand(&seed);
		geodesy_distance(sph, lat1, lon1, lat2, lon2, &a);
		b = haversine(6371000, lat1, lon1, lat2, lon2);
		worst = fmax(worst, fabs(a - b) / b);
		geodesy_distance(w, lat1, lon1, lat2, lon2, &a);
		geodesy_inverse(lat1, lon1, lat2, lon2, &b);
		same &= a == b;
	}
	ok(worst < 1e-9, "on a sphere: great circles (haversine within %.1g)",
	    worst);
	ok(same, "geodesy_new(WGS84) gives geodesy_inverse's distances");
	ok(geodesy_new(0, 0) == NULL && geodesy_new(-1, 0) == NULL &&
	    geodesy_new(NAN, 0) == NULL && geodesy_new(6e6, 1) == NULL &&
	    geodesy_new(6e6, NAN) == NULL, "geodesy_new: a <= 0, f >= 1 and "
	    "non-finite values refused");
	a = -1;
	ok(geodesy_distance(w, 0, 0, -91, 0, &a) < 0 && a == -1,
	    "geodesy_distance: a bad latitude refused");
	geodesy_free(w);
	geodesy_free(sph);
	geodesy_free(NULL);
}

int
main(void)
{
	test_wgs84();
	test_ellipsoids();
	return tap_done();
}
