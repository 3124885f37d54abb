/* t_wgs84.c - the DEM's CRS to WGS 84 (geo/wgs84.c): a point that is not
 * finite (a NaN height from a damaged block) is named as such, not
 * blamed on PROJ. */
#include <math.h>
#include <string.h>

#include "tap.h"
#include "geo/wgs84.h"

int
main(void)
{
	georef g;
	geo_proj p;
	tl_err e = { "" };
	double x[3] = { 138.7, 138.71, 138.72 }, y[3] = { 35.3, 35.31, 35.32 };
	double z[3] = { 1000, NAN, 1200 };

	memset(&g, 0, sizeof g);
	g.model = GEO_GEOGRAPHIC, g.epsg = 4326;
	snprintf(g.crs, sizeof g.crs, "EPSG:4326");
	if (!ok(geo_proj_open(&p, &g, &e) == 0, "EPSG:4326 to WGS 84: %s",
	    e.msg))
		return tap_done();
	ok(geo_proj_lonlat(&p, x, y, z, 3, &e) < 0 &&
	    strstr(e.msg, "vertex 1 of 3") != NULL &&
	    strstr(e.msg, "height nan") != NULL &&
	    strstr(e.msg, "not finite") != NULL &&
	    strstr(e.msg, "PROJ") == NULL, "a NaN height named: %s", e.msg);
	z[1] = 1100, x[0] = INFINITY;
	ok(geo_proj_lonlat(&p, x, y, z, 3, &e) < 0 &&
	    strstr(e.msg, "vertex 0 of 3: position inf") != NULL,
	    "an infinite position named: %s", e.msg);
	x[0] = 138.7;
	ok(geo_proj_lonlat(&p, x, y, z, 3, &e) == 0 && fabs(x[0] - 138.7) < 1e-9 &&
	    fabs(z[1] - 1100) < 1e-6, "finite points still converted");
	geo_proj_close(&p);
	return tap_done();
}
