/* georef.c - georeferencing to and from the geo:* header attributes, and
 * grid positions in CRS coordinates. Reading it from the DEM is dem.c's
 * job, from and to a raster's header raster/rs_georef.c's; the metric
 * embedding of the grid is ground.c's. */
#include "geo/georef.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


void
geo_init_none(georef *g, double cx, double cy)
{
	memset(g, 0, sizeof *g);
	g->model = GEO_NONE;
	g->point = 1;
	g->step[0] = cx > 0 ? cx : 1;
	g->step[1] = -(cy > 0 ? cy : g->step[0]);
	g->unit = 1;
}

/* --- header attributes -------------------------------------------------- */

static const char *const model_names[] = { "none", "projected", "geographic" };

const char *
geo_model_name(enum geo_model m)
{
	assert((unsigned)m <= GEO_GEOGRAPHIC);
	return model_names[m];
}

int
geo_model_parse(const char *s, enum geo_model *m)
{
	for (int k = 0; k <= GEO_GEOGRAPHIC; k++)
		if (strcmp(s, model_names[k]) == 0) {
			*m = (enum geo_model)k;
			return 0;
		}
	return -1;
}

const char *
geo_differs(const georef *a, const georef *b)
{
	if (a->model != b->model)
		return "model";
	if (a->epsg != b->epsg || strcmp(a->crs, b->crs) != 0)
		return "crs";
	if (a->point != b->point)
		return "raster";
	if (a->origin[0] != b->origin[0] || a->origin[1] != b->origin[1])
		return "origin";
	if (a->step[0] != b->step[0] || a->step[1] != b->step[1])
		return "step";
	if (a->unit != b->unit)
		return "unit";
	if (a->cell[0] != b->cell[0] || a->cell[1] != b->cell[1])
		return "cell";
	if (strcmp(a->vdatum, b->vdatum) != 0)
		return "vdatum";
	if (a->has_nodata != b->has_nodata || (a->has_nodata &&
	    a->nodata != b->nodata && !(isnan(a->nodata) && isnan(b->nodata))))
		return "nodata";
	return NULL;
}

/* --- grid geometry ------------------------------------------------------ */

void
geo_vertex_crs(const georef *g, int level, double i, double j, double *x,
    double *y)
{
	double s = ldexp(1, level), c = g->point ? 0 : 0.5;

	*x = g->origin[0] + (i * s + c) * g->step[0];
	*y = g->origin[1] + (j * s + c) * g->step[1];
}
