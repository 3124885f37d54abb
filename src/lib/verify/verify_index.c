/* verify_index.c - the checker's own reader of index.json (jansson,
 * through base/json.h's strict parse and checked numbers).
 *
 * It shares no reading of fields with the viewer's and the exporters'
 * reader (pyramid_index.c): a pyramid whose index that reader misreads is
 * then caught by the checks against the block files rather than read the
 * same wrong way twice. It shares only the guards that read no field for
 * use: a regular file, and a text no larger than its size0 can need.
 * It reads the fields vgis(5) documents and the checker needs, and
 * refuses an index
 * it cannot check against (not JSON, a field missing or of the wrong
 * type, block counts that do not fit the level's size). */
#include "verify/verify.h"
#include "base/json.h"
#include "pyramid/pyramid.h"
#include "pyramid/vgis.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VF_BLOCK 129 /* vertices a block side, vgis(5) */

/* Two numbers: [a, b]. */
static int
num2(json_t *parent, const char *key, double v[2])
{
	json_t *a = json_object_get(parent, key);

	if (json_array_size(a) != 2)
		return -1;
	for (size_t k = 0; k < 2; k++) {
		if (tl_json_num(json_array_get(a, k), &v[k]) < 0)
			return -1;
	}
	return 0;
}

/* Two integers: [a, b]. */
static int
int2(json_t *parent, const char *key, int v[2])
{
	json_t *a = json_object_get(parent, key);

	if (json_array_size(a) != 2)
		return -1;
	for (size_t k = 0; k < 2; k++) {
		if (tl_json_int(json_array_get(a, k), -(1 << 30), 1 << 30,
		    &v[k]) < 0)
			return -1;
	}
	return 0;
}

static int
int1(json_t *parent, const char *key, int *v)
{
	return tl_json_int(json_object_get(parent, key), -(1 << 30), 1 << 30,
	    v);
}

/* A string into buf; NULL json (optional, absent) gives "". */
static int
str(json_t *parent, const char *key, char *buf, size_t n, int optional)
{
	json_t *x = json_object_get(parent, key);

	buf[0] = '\0';
	if (x == NULL && optional)
		return 0;
	if (!json_is_string(x) || strlen(json_string_value(x)) >= n)
		return -1;
	memcpy(buf, json_string_value(x), strlen(json_string_value(x)) + 1);
	return 0;
}

/* "georef": the level-0 georeferencing, as georef.h holds it. */
static const char *
georef_of(json_t *o, georef *g)
{
	char s[32];
	json_t *x;

	memset(g, 0, sizeof *g);
	if (!json_is_object(o))
		return "georef";
	if (str(o, "model", s, sizeof s, 0) < 0 ||
	    geo_model_parse(s, &g->model) < 0)
		return "georef.model";
	if (int1(o, "epsg", &g->epsg) < 0)
		return "georef.epsg";
	if (str(o, "crs", g->crs, sizeof g->crs, 0) < 0)
		return "georef.crs";
	if (str(o, "raster", s, sizeof s, 0) < 0 ||
	    (strcmp(s, "point") != 0 && strcmp(s, "area") != 0))
		return "georef.raster";
	g->point = strcmp(s, "point") == 0;
	if (num2(o, "origin", g->origin) < 0)
		return "georef.origin";
	if (num2(o, "step", g->step) < 0)
		return "georef.step";
	if (tl_json_num(json_object_get(o, "unit"), &g->unit) < 0)
		return "georef.unit";
	if (str(o, "vdatum", g->vdatum, sizeof g->vdatum, 1) < 0)
		return "georef.vdatum";
	if (json_object_get(o, "cell") != NULL &&
	    (num2(o, "cell", g->cell) < 0 || !(g->cell[0] > 0) ||
	    !(g->cell[1] > 0)))
		return "georef.cell";
	/* JSON has no NaN: vgis(5) writes a NaN nodata as "nan" */
	x = json_object_get(o, "nodata");
	if (tl_json_num(x, &g->nodata) == 0) {
		g->has_nodata = 1;
	} else if (json_is_string(x) && strcmp(json_string_value(x),
	    "nan") == 0) {
		g->has_nodata = 1;
		g->nodata = NAN;
	} else if (x != NULL) {
		return "georef.nodata";
	}
	return NULL;
}

/* One per block: an array of nb numbers. */
static double *
per_block(json_t *o, const char *key, size_t nb)
{
	json_t *a = json_object_get(o, key);
	double *v;

	if (!json_is_array(a) || json_array_size(a) != nb ||
	    (v = malloc((nb ? nb : 1) * sizeof *v)) == NULL)
		return NULL;
	for (size_t k = 0; k < nb; k++) {
		if (tl_json_num(json_array_get(a, k), &v[k]) < 0) {
			free(v);
			return NULL;
		}
	}
	return v;
}

static int
level_of(json_t *o, vf_ilevel *L, int l, const char *path, tl_err *e)
{
	json_t *d = json_object_get(o, "displaced");
	size_t nb;
	int need[2];

	if (!json_is_object(o) || int1(o, "level", &L->level) < 0 ||
	    int2(o, "size", L->size) < 0 || int2(o, "blocks", L->blocks) < 0 ||
	    !json_is_boolean(d) ||
	    str(o, "mode", L->mode, sizeof L->mode, 0) < 0 ||
	    str(o, "kernel", L->kernel, sizeof L->kernel, 0) < 0)
		return tl_fail(e, "%s: levels[%d]: level, size, blocks, "
		    "displaced, mode or kernel missing or not of its type",
		    path, l);
	L->displaced = json_is_true(d);
	if (L->size[0] < 2 || L->size[1] < 2 || L->size[0] > (1 << 26) ||
	    L->size[1] > (1 << 26))
		return tl_fail(e, "%s: levels[%d]: bad size %dx%d", path, l,
		    L->size[0], L->size[1]);
	/* blocks share borders: ceil((n - 1) / 128) of them, at least one */
	for (int a = 0; a < 2; a++) {
		need[a] = (L->size[a] - 1 + VF_BLOCK - 2) / (VF_BLOCK - 1);
		if (need[a] < 1)
			need[a] = 1;
	}
	if (L->blocks[0] != need[0] || L->blocks[1] != need[1])
		return tl_fail(e, "%s: levels[%d]: %dx%d blocks, a %dx%d level "
		    "has %dx%d", path, l, L->blocks[0], L->blocks[1],
		    L->size[0], L->size[1], need[0], need[1]);
	nb = (size_t)L->blocks[0] * L->blocks[1];
	if ((L->zmin = per_block(o, "zmin", nb)) == NULL ||
	    (L->zmax = per_block(o, "zmax", nb)) == NULL ||
	    (L->base = per_block(o, "base_error", nb)) == NULL ||
	    (L->emax = per_block(o, "max_error", nb)) == NULL)
		return tl_fail(e, "%s: levels[%d]: zmin, zmax, base_error and "
		    "max_error must list %zu numbers", path, l, nb);
	return 0;
}

int
vf_index_read(const char *dir, vf_index *ix, tl_err *e)
{
	char path[4096], fmt[64];
	const char *bad = NULL;
	json_error_t je;
	json_t *root, *levels;
	int version, block, r = -1, oom;
	char *text;
	size_t n;

	memset(ix, 0, sizeof *ix);
	snprintf(path, sizeof path, "%s/" VGIS_INDEX, dir);
	/* a regular file (a FIFO never blocks), and no larger than its size0
	 * can need: the guards are shared, the reading of fields is not */
	if ((text = pyramid_index_load(path, &n, e)) == NULL)
		return -1;
	if (pyramid_index_bounded(text, n, path, e) < 0) {
		free(text);
		return -1;
	}
	root = tl_json_parse(text, n, &je, &oom);
	free(text);
	if (root == NULL && oom)
		return tl_fail(e, "%s: out of memory parsing its %zu bytes",
		    path, n);
	if (root == NULL)
		return tl_fail(e, "%s: not JSON: line %d: %s", path, je.line,
		    je.text);
	levels = json_object_get(root, "levels");
	if (!json_is_object(root))
		bad = "an object";
	else if (str(root, "format", fmt, sizeof fmt, 0) < 0 ||
	    strcmp(fmt, VGIS_FORMAT) != 0)
		bad = "format";
	else if (int1(root, "version", &version) < 0)
		bad = "version";
	else if (int1(root, "block", &block) < 0)
		bad = "block";
	else if (int2(root, "size0", ix->size0) < 0 || ix->size0[0] < 2 ||
	    ix->size0[1] < 2)
		bad = "size0";
	else if (!json_is_array(levels) || json_array_size(levels) < 1 ||
	    json_array_size(levels) > 64)
		bad = "levels";
	else
		bad = georef_of(json_object_get(root, "georef"), &ix->geo);
	if (bad != NULL) {
		tl_fail(e, "%s: not a pyramid index (%s)", path, bad);
		goto done;
	}
	if (version != VGIS_VERSION || block != VF_BLOCK) {
		tl_fail(e, "%s: version %d, blocks of %d: the checker reads "
		    "version %d, blocks of %d", path, version, block,
		    VGIS_VERSION, VF_BLOCK);
		goto done;
	}
	ix->geo.width = ix->size0[0], ix->geo.height = ix->size0[1];
	ix->nlevels = (int)json_array_size(levels);
	if ((ix->lev = calloc((size_t)ix->nlevels, sizeof *ix->lev)) == NULL) {
		tl_fail(e, "%s: out of memory", path);
		goto done;
	}
	for (int l = 0; l < ix->nlevels; l++)
		if (level_of(json_array_get(levels, l), &ix->lev[l], l, path,
		    e) < 0)
			goto done;
	r = 0;
done:
	json_decref(root);
	if (r < 0)
		vf_index_free(ix);
	return r;
}

void
vf_index_free(vf_index *ix)
{
	for (int l = 0; l < ix->nlevels && ix->lev != NULL; l++) {
		vf_ilevel *L = &ix->lev[l];
		free(L->zmin), free(L->zmax), free(L->base), free(L->emax);
	}
	free(ix->lev);
	memset(ix, 0, sizeof *ix);
}
