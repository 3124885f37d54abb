/* pyramid_index.c - index.json of a pyramid (vgis(5)), written and read
 * with jansson; the reader treats the file as untrusted. */
#include "pyramid/pyramid.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/outfile.h"
#include "core/fqm.h"

void
pyramid_index_free(pyramid_index *ix)
{
	for (int l = 0; l < ix->nlevels && ix->lev; l++) {
		pyramid_level *L = &ix->lev[l];
		free(L->zmin), free(L->zmax), free(L->base), free(L->emax);
	}
	free(ix->lev);
	ix->lev = NULL;
	ix->nlevels = 0;
}

static json_t *
pair(double a, double b)
{
	return json_pack("[ff]", a, b);
}

static json_t *
geo_json(const georef *g)
{
	json_t *o = json_pack("{s:s, s:i, s:s, s:s, s:o, s:o, s:f}", "model",
	    geo_model_name(g->model),
	    "epsg", g->epsg, "crs", g->crs, "raster",
	    g->point ? "point" : "area", "origin",
	    pair(g->origin[0], g->origin[1]), "step",
	    pair(g->step[0], g->step[1]), "unit", g->unit);

	if (o != NULL && g->vdatum[0] != '\0')
		json_object_set_new(o, "vdatum", json_string(g->vdatum));
	if (o != NULL && g->cell[0] > 0)
		json_object_set_new(o, "cell", pair(g->cell[0], g->cell[1]));
	/* JSON has no NaN: a NaN nodata is the string "nan" */
	if (o != NULL && g->has_nodata)
		json_object_set_new(o, "nodata", isnan(g->nodata) ?
		    json_string("nan") : json_real(g->nodata));
	return o;
}

static json_t *
doubles(const double *v, size_t n)
{
	json_t *a = json_array();

	for (size_t k = 0; a != NULL && k < n; k++)
		json_array_append_new(a, json_real(v[k]));
	return a;
}

static json_t *
level_json(const pyramid_level *L)
{
	size_t nb = (size_t)L->blocks[0] * L->blocks[1];

	return json_pack("{s:i, s:[ii], s:[ii], s:b, s:s, s:s, s:o, s:o, s:o, "
	    "s:o}", "level",
	    L->level, "size", L->size[0], L->size[1], "blocks", L->blocks[0],
	    L->blocks[1], "displaced", L->displaced, "mode", L->mode,
	    "kernel", L->kernel, "zmin", doubles(L->zmin, nb), "zmax",
	    doubles(L->zmax, nb), "base_error", doubles(L->base, nb),
	    "max_error", doubles(L->emax, nb));
}

int
pyramid_index_write(const char *dir, const pyramid_index *ix, tl_err *e)
{
	char path[4096];
	tl_outfile o;
	json_t *root, *levels;
	char *text;
	int r;

	levels = json_array();
	for (int l = 0; levels != NULL && l < ix->nlevels; l++)
		json_array_append_new(levels, level_json(&ix->lev[l]));
	root = json_pack("{s:s, s:i, s:i, s:[ii], s:o, s:o}", "format",
	    VGIS_FORMAT,
	    "version", VGIS_VERSION, "block", BT_SIZE, "size0", ix->size0[0],
	    ix->size0[1], "georef", geo_json(&ix->geo), "levels", levels);
	if (root == NULL)
		return tl_fail(e, "%s/" VGIS_INDEX ": cannot build the index",
		    dir);
	text = json_dumps(root, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	json_decref(root);
	if (text == NULL)
		return tl_fail(e, "%s/" VGIS_INDEX ": out of memory", dir);
	snprintf(path, sizeof path, "%s/" VGIS_INDEX, dir);
	r = tl_out_begin(&o, path, e);
	if (r == 0 &&
	    (r = tl_pwrite(o.fd, text, strlen(text), 0, path, e)) == 0)
		r = tl_pwrite(o.fd, "\n", 1, (long long)strlen(text), path, e);
	free(text);
	if (r != 0) {
		tl_out_abort(&o);
		return -1;
	}
	return tl_out_commit(&o, e);
}

static int
get_pair(json_t *o, const char *key, double v[2])
{
	json_t *a = json_object_get(o, key);

	if (!json_is_array(a) || json_array_size(a) != 2 ||
	    !json_is_number(json_array_get(a, 0)) ||
	    !json_is_number(json_array_get(a, 1)))
		return -1;
	v[0] = json_number_value(json_array_get(a, 0));
	v[1] = json_number_value(json_array_get(a, 1));
	return 0;
}

static int
geo_from_json(json_t *o, georef *g)
{
	const char *model, *crs, *raster, *vdatum = NULL;
	json_t *nodata = json_object_get(o, "nodata");
	int epsg;

	memset(g, 0, sizeof *g);
	if (json_unpack(o, "{s:s, s:i, s:s, s:s, s:F, s?s}", "model", &model,
	    "epsg", &epsg, "crs", &crs, "raster", &raster, "unit", &g->unit,
	    "vdatum", &vdatum) != 0 || get_pair(o, "origin", g->origin) < 0 ||
	    get_pair(o, "step", g->step) < 0)
		return -1;
	if (geo_model_parse(model, &g->model) < 0)
		return -1;
	g->epsg = epsg;
	g->point = strcmp(raster, "point") == 0;
	snprintf(g->crs, sizeof g->crs, "%s", crs);
	if (vdatum != NULL)
		snprintf(g->vdatum, sizeof g->vdatum, "%s", vdatum);
	if (json_is_number(nodata)) {
		g->has_nodata = 1;
		g->nodata = json_number_value(nodata);
	} else if (json_is_string(nodata) &&
	    strcmp(json_string_value(nodata), "nan") == 0) {
		g->has_nodata = 1;
		g->nodata = NAN;
	}
	if (json_object_get(o, "cell") != NULL &&
	    (get_pair(o, "cell", g->cell) < 0 || !(g->cell[0] > 0) ||
	    !(g->cell[1] > 0)))
		return -1;
	return 0;
}

static int
get_doubles(json_t *o, const char *key, double *v, size_t n)
{
	json_t *a = json_object_get(o, key);

	if (!json_is_array(a) || json_array_size(a) != n)
		return -1;
	for (size_t k = 0; k < n; k++) {
		json_t *x = json_array_get(a, k);
		if (!json_is_number(x))
			return -1;
		v[k] = json_number_value(x);
	}
	return 0;
}

/* Entry `want` of the levels array of a size0 pyramid. */
static int
level_from_json(json_t *o, pyramid_level *L, int want, const int size0[2],
    const char *what, tl_err *e)
{
	int level, w, h, bx, by, displaced;
	const char *mode, *kernel;
	size_t nb;

	if (json_unpack(o, "{s:i, s:[ii], s:[ii], s:b, s:s, s:s}", "level",
	    &level, "size", &w, &h, "blocks", &bx, &by, "displaced",
	    &displaced, "mode", &mode, "kernel", &kernel) != 0)
		return tl_fail(e, "%s: a level lacks level/size/blocks/"
		    "displaced/mode/kernel", what);
	if (w < 2 || h < 2 || w > (1 << 26) || h > (1 << 26))
		return tl_fail(e, "%s: level %d: bad size %dx%d", what, level,
		    w, h);
	if (level != want || w != fqm_level_size(size0[0], level) ||
	    h != fqm_level_size(size0[1], level))
		return tl_fail(e, "%s: level %d (entry %d): size %dx%d, level "
		    "%d of a %dx%d DEM is %dx%d", what, level, want, w, h, want,
		    size0[0], size0[1], fqm_level_size(size0[0], want),
		    fqm_level_size(size0[1], want));
	if (pyramid_level_init(L, level, w, h, e) < 0)
		return -1;
	if (L->blocks[0] != bx || L->blocks[1] != by)
		return tl_fail(e, "%s: level %d: %dx%d blocks, a %dx%d level "
		    "has %dx%d", what, level, bx, by, w, h, L->blocks[0],
		    L->blocks[1]);
	L->displaced = displaced;
	snprintf(L->mode, sizeof L->mode, "%s", mode);
	snprintf(L->kernel, sizeof L->kernel, "%s", kernel);
	nb = (size_t)bx * by;
	if (get_doubles(o, "zmin", L->zmin, nb) < 0 ||
	    get_doubles(o, "zmax", L->zmax, nb) < 0 ||
	    get_doubles(o, "base_error", L->base, nb) < 0 ||
	    get_doubles(o, "max_error", L->emax, nb) < 0)
		return tl_fail(e, "%s: level %d: zmin/zmax/base_error/"
		    "max_error must list %zu numbers", what, level, nb);
	return 0;
}

int
pyramid_index_read(const char *dir, pyramid_index *ix, tl_err *e)
{
	char path[4096];
	json_error_t je;
	json_t *root, *levels;
	int r = -1;

	memset(ix, 0, sizeof *ix);
	snprintf(path, sizeof path, "%s/" VGIS_INDEX, dir);
	if ((root = json_load_file(path, 0, &je)) == NULL) {
		if (access(path, R_OK) != 0)
			return tl_failsys(e, "%s", path);
		return tl_fail(e, "%s: line %d: %s", path, je.line, je.text);
	}
	levels = json_object_get(root, "levels");
	if (json_unpack(root, "{s:i, s:[ii]}", "version", &ix->version,
	    "size0", &ix->size0[0], &ix->size0[1]) != 0 ||
	    !json_is_array(levels) ||
	    geo_from_json(json_object_get(root, "georef"), &ix->geo) < 0) {
		tl_fail(e, "%s: not a pyramid index (version, size0, georef, "
		    "levels)", path);
		goto done;
	}
	if (ix->version != VGIS_VERSION) {
		tl_fail(e, "%s: version %d, this program reads %d", path,
		    ix->version, VGIS_VERSION);
		goto done;
	}
	ix->geo.width = ix->size0[0], ix->geo.height = ix->size0[1];
	/* an untrusted file: sizes checked before anything is allocated */
	if (ix->size0[0] < 3 || ix->size0[1] < 3 || ix->size0[0] > (1 << 26) ||
	    ix->size0[1] > (1 << 26)) {
		tl_fail(e, "%s: size0 %dx%d outside 3 .. 2^26", path,
		    ix->size0[0], ix->size0[1]);
		goto done;
	}
	if (json_array_size(levels) !=
	    (size_t)fqm_levels(ix->size0[0], ix->size0[1])) {
		tl_fail(e, "%s: %zu levels, a %dx%d pyramid has %d", path,
		    json_array_size(levels), ix->size0[0], ix->size0[1],
		    fqm_levels(ix->size0[0], ix->size0[1]));
		goto done;
	}
	ix->nlevels = (int)json_array_size(levels);
	ix->lev = tl_alloc(ix->nlevels, sizeof *ix->lev, e);
	if (ix->lev == NULL)
		goto done;
	for (int l = 0; l < ix->nlevels; l++)
		if (level_from_json(json_array_get(levels, l), &ix->lev[l], l,
		    ix->size0, path, e) < 0)
			goto done;
	r = 0;
done:
	json_decref(root);
	if (r < 0)
		pyramid_index_free(ix);
	return r;
}

