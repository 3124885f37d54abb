/* dem_info.c - what is known of a DEM, said to a user (dem.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "dem/dem.h"
#include "geo/levels.h"

/* Ground metres per cell over the grid, min and max along x and y,
 * sampled on about 256 x 256 positions (the metric varies smoothly). */
static int
ground_range(const georef *g, double r[4], tl_err *e)
{
	int si = g->width > 256 ? g->width / 256 : 1;
	int sj = g->height > 256 ? g->height / 256 : 1;
	geo_ground m;

	if (geo_ground_init(&m, g, e) < 0)
		return -1;
	r[0] = r[2] = INFINITY, r[1] = r[3] = 0;
	for (int j = 0; j < g->height; j += sj)
		for (int i = 0; i < g->width; i += si) {
			double sx, sy;
			geo_scale(&m, i, j, &sx, &sy);
			r[0] = fmin(r[0], sx), r[1] = fmax(r[1], sx);
			r[2] = fmin(r[2], sy), r[3] = fmax(r[3], sy);
		}
	geo_ground_free(&m);
	return 0;
}

int
dem_info_print(const dem *d, FILE *f, tl_err *e)
{
	const georef *g = dem_georef(d);
	double r[4];

	if (ground_range(g, r, e) < 0)
		return -1;
	fprintf(f, "size %d %d\n", g->width, g->height);
	if (dem_voids(d) >= 0)
		fprintf(f, "voids %lld\n", dem_voids(d));
	fprintf(f, "model %s\ncrs %s\nraster %s\n"
	    "origin %.17g %.17g\nstep %.17g %.17g\n",
	    geo_model_name(g->model), g->crs[0] ? g->crs : "-",
	    g->point ? "point" : "area", g->origin[0], g->origin[1],
	    g->step[0], g->step[1]);
	if (g->vdatum[0] != '\0')
		fprintf(f, "vdatum %s\n", g->vdatum);
	if (g->has_nodata)
		fprintf(f, "nodata %.17g\n", g->nodata);
	if (g->cell[0] > 0)
		fprintf(f, "cell %.17g %.17g\n", g->cell[0], g->cell[1]);
	fprintf(f, "metric %.6f %.6f %.6f %.6f\nzunit %.17g\nlevels %d\n",
	    r[0], r[1], r[2], r[3], dem_zunit(d),
	    geo_levels(g->width, g->height));
	return fflush(f) == 0 && !ferror(f) ? 0 :
	    tl_failsys(e, "%s", f == stdout ? "stdout" : "output");
}

/* Whether name has an .aux.xml sidecar that GDAL was told not to read. */
static int
pam_off(const char *name)
{
	const char *v = getenv("GDAL_PAM_ENABLED");
	char aux[4096];

	if (v == NULL || !(strcasecmp(v, "NO") == 0 ||
	    strcasecmp(v, "FALSE") == 0 || strcasecmp(v, "OFF") == 0 ||
	    strcmp(v, "0") == 0))
		return 0;
	return (size_t)snprintf(aux, sizeof aux, "%s.aux.xml", name) <
	    sizeof aux && access(aux, F_OK) == 0;
}

int
dem_ground_note(const dem *d, const dem_opts *o, const char *name,
    char *buf, size_t n)
{
	const georef *g = dem_georef(d);

	if (g->model != GEO_NONE || g->cell[0] > 0 || o->cell[0] > 0)
		return 0;
	if (g->origin[0] == 0 && g->origin[1] == 0 && g->step[0] == 1 &&
	    g->step[1] == -1)
		snprintf(buf, n, "%s: not georeferenced: cells taken as 1 m "
		    "(set with -s)%s", name, pam_off(name) ? "; its .aux.xml "
		    "sidecar is not read while GDAL_PAM_ENABLED says NO" : "");
	else
		snprintf(buf, n, "%s: a geotransform but no CRS: its pixel size "
		    "%g x %g taken as metres (set with -s, or assign the CRS: "
		    "gdal_edit.py -a_srs)", name, g->step[0], -g->step[1]);
	return 1;
}
