/* rs_georef.c - a grid's georeferencing (geo/georef.h) in a raster's
 * header, as the geo:* attributes documented in fqm(5). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "raster/attr_names.h"
#include "raster/raster.h"

int
rs_put_georef(const georef *g, rs_header *h, tl_err *e)
{
	if ((unsigned)g->model > GEO_GEOGRAPHIC)
		return tl_fail(e, "georeferencing: bad model %d", (int)g->model);
	if (rs_set_string(h, GEO_ATTR_MODEL, geo_model_name(g->model), e) < 0 ||
	    rs_set_int(h, GEO_ATTR_EPSG, g->epsg, e) < 0 ||
	    rs_set_string(h, GEO_ATTR_CRS, g->crs, e) < 0 ||
	    rs_set_string(h, GEO_ATTR_RASTER, g->point ? "point" : "area", e) < 0 ||
	    rs_set_v2d(h, GEO_ATTR_ORIGIN, g->origin[0], g->origin[1], e) < 0 ||
	    rs_set_v2d(h, GEO_ATTR_STEP, g->step[0], g->step[1], e) < 0 ||
	    rs_set_double(h, GEO_ATTR_UNIT, g->unit, e) < 0)
		return -1;
	rs_unset(h, GEO_ATTR_VDATUM);
	if (g->vdatum[0] != '\0' &&
	    rs_set_string(h, GEO_ATTR_VDATUM, g->vdatum, e) < 0)
		return -1;
	rs_unset(h, GEO_ATTR_CELL);
	if (g->cell[0] > 0 &&
	    rs_set_v2d(h, GEO_ATTR_CELL, g->cell[0], g->cell[1], e) < 0)
		return -1;
	rs_unset(h, GEO_ATTR_NODATA);
	if (g->has_nodata && rs_set_double(h, GEO_ATTR_NODATA, g->nodata, e) < 0)
		return -1;
	return 0;
}

static int
copy_string(char *dst, size_t n, const char *s, const char *name, tl_err *e)
{
	if (s == NULL)
		return 0;
	if (strlen(s) >= n)
		return tl_fail(e, "%s: too long (%zu bytes)", name, strlen(s));
	memcpy(dst, s, strlen(s) + 1);
	return 0;
}

int
rs_get_georef(georef *g, const rs_header *h, tl_err *e)
{
	const char *s;
	int size[2];

	geo_init_none(g, 1, 1);
	if ((s = rs_get_string(h, GEO_ATTR_MODEL)) != NULL) {
		if (geo_model_parse(s, &g->model) < 0)
			return tl_fail(e, "geo:model: unknown value \"%s\"", s);
	}
	if ((s = rs_get_string(h, GEO_ATTR_RASTER)) != NULL) {
		if (strcmp(s, "point") != 0 && strcmp(s, "area") != 0)
			return tl_fail(e, "geo:raster: unknown value \"%s\"", s);
		g->point = strcmp(s, "point") == 0;
	}
	rs_get_int(h, GEO_ATTR_EPSG, &g->epsg);
	rs_get_v2d(h, GEO_ATTR_ORIGIN, g->origin);
	rs_get_v2d(h, GEO_ATTR_STEP, g->step);
	rs_get_double(h, GEO_ATTR_UNIT, &g->unit);
	if (rs_get_v2d(h, GEO_ATTR_CELL, g->cell) == 0 &&
	    !(g->cell[0] > 0 && g->cell[1] > 0 && isfinite(g->cell[0]) &&
	    isfinite(g->cell[1])))
		return tl_fail(e, "geo:cell: invalid cell size %g x %g",
		    g->cell[0], g->cell[1]);
	if (copy_string(g->crs, sizeof g->crs, rs_get_string(h, GEO_ATTR_CRS),
	    GEO_ATTR_CRS, e) < 0 ||
	    copy_string(g->vdatum, sizeof g->vdatum,
	    rs_get_string(h, GEO_ATTR_VDATUM), GEO_ATTR_VDATUM, e) < 0)
		return -1;
	g->has_nodata = rs_get_double(h, GEO_ATTR_NODATA, &g->nodata) == 0;
	if (rs_get_v2i(h, FQM_ATTR_SIZE0, size) == 0)
		g->width = size[0], g->height = size[1];
	if (!isfinite(g->step[0]) || !isfinite(g->step[1]) ||
	    g->step[0] == 0 || g->step[1] == 0)
		return tl_fail(e, "geo:step: invalid pixel size %g x %g",
		    g->step[0], g->step[1]);
	if (g->model != GEO_GEOGRAPHIC && !(g->unit > 0 && isfinite(g->unit)))
		return tl_fail(e, "geo:unit: invalid value %g", g->unit);
	return 0;
}

