/* pyramid.c - index.json (jansson) and block files (raster.h). */
#include "pyramid/pyramid.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/fqm.h"

int
pyramid_nblocks(int n)
{
	int b = (n - 1 + BT_CELLS - 1) / BT_CELLS;

	return b < 1 ? 1 : b;
}

int
pyramid_level_init(pyramid_level *L, int level, int w, int h, tl_err *e)
{
	size_t nb;

	memset(L, 0, sizeof *L);
	L->level = level;
	L->size[0] = w, L->size[1] = h;
	L->blocks[0] = pyramid_nblocks(w), L->blocks[1] = pyramid_nblocks(h);
	nb = (size_t)L->blocks[0] * L->blocks[1];
	L->zmin = tl_alloc(nb, sizeof *L->zmin, e);
	L->zmax = tl_alloc(nb, sizeof *L->zmax, e);
	L->base = tl_alloc(nb, sizeof *L->base, e);
	L->emax = tl_alloc(nb, sizeof *L->emax, e);
	if (!L->zmin || !L->zmax || !L->base || !L->emax)
		return -1;
	return 0;
}

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

void
pyramid_block_path(char *buf, size_t n, const char *dir, int level, int bi, int bj)
{
	snprintf(buf, n, "%s/%d/%d_%d.exr", dir, level, bj, bi);
}

/* --- index.json ------------------------------------------------------- */

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
	    "terrain-lod vgis",
	    "version", PYRAMID_VERSION, "block", BT_SIZE, "size0", ix->size0[0],
	    ix->size0[1], "georef", geo_json(&ix->geo), "levels", levels);
	if (root == NULL)
		return tl_fail(e, "%s/index.json: cannot build the index", dir);
	text = json_dumps(root, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	json_decref(root);
	if (text == NULL)
		return tl_fail(e, "%s/index.json: out of memory", dir);
	snprintf(path, sizeof path, "%s/index.json", dir);
	r = tl_out_begin(&o, path, e);
	if (r == 0 && (r = tl_pwrite(o.fd, text, strlen(text), 0, path, e)) == 0)
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
	snprintf(path, sizeof path, "%s/index.json", dir);
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
	if (ix->version != PYRAMID_VERSION) {
		tl_fail(e, "%s: version %d, this program reads %d", path,
		    ix->version, PYRAMID_VERSION);
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

/* --- blocks ----------------------------------------------------------- */

int
pyramid_block_alloc(pyramid_block *b, int displaced, tl_err *e)
{
	memset(b, 0, sizeof *b);
	b->displaced = displaced;
	b->z = tl_alloc(PYRAMID_N, sizeof *b->z, e);
	b->e = tl_alloc(PYRAMID_N, sizeof *b->e, e);
	if (displaced) {
		b->x = tl_alloc(PYRAMID_N, sizeof *b->x, e);
		b->y = tl_alloc(PYRAMID_N, sizeof *b->y, e);
	}
	if (!b->z || !b->e || (displaced && (!b->x || !b->y))) {
		pyramid_block_free(b);
		return -1;
	}
	return 0;
}

void
pyramid_block_free(pyramid_block *b)
{
	free(b->z), free(b->e), free(b->x), free(b->y);
	b->z = b->e = b->x = b->y = NULL;
}

/* Channel order in the file (sorted): E X Y Z, or E Z. */
static float **
planes(pyramid_block *b, float *p[4], int *n)
{
	*n = 0;
	p[(*n)++] = b->e;
	if (b->displaced) {
		p[(*n)++] = b->x;
		p[(*n)++] = b->y;
	}
	p[(*n)++] = b->z;
	return p;
}

int
pyramid_block_write(const char *path, const pyramid_block *b, const rs_header *attrs,
    tl_err *e)
{
	rs_header h;
	rs_writer *w;
	float row[4 * BT_SIZE], *p[4];
	int n, r = -1;

	if (rs_header_copy(&h, attrs, e) < 0)
		return -1;
	h.width = h.height = BT_SIZE;
	rs_clear_channels(&h);
	planes((pyramid_block *)b, p, &n);
	if (rs_add_channel(&h, "E", e) < 0 || rs_add_channel(&h, "Z", e) < 0 ||
	    (b->displaced && (rs_add_channel(&h, "X", e) < 0 ||
	    rs_add_channel(&h, "Y", e) < 0)) ||
	    rs_set_int(&h, VGIS_ATTR_VERSION, PYRAMID_VERSION, e) < 0 ||
	    rs_set_int(&h, VGIS_ATTR_LEVEL, b->level, e) < 0 ||
	    rs_set_v2i(&h, VGIS_ATTR_BLOCK, b->bi, b->bj, e) < 0 ||
	    rs_set_v2i(&h, VGIS_ATTR_ORIGIN, b->bi * BT_CELLS, b->bj * BT_CELLS,
	    e) < 0 ||
	    rs_set_double(&h, VGIS_ATTR_BASE_ERROR, b->base, e) < 0 ||
	    rs_set_v2d(&h, VGIS_ATTR_ZRANGE, b->zmin, b->zmax, e) < 0)
		goto done;
	if ((w = rs_create(path, &h, RS_ZIP, e)) == NULL)
		goto done;
	for (int j = 0; j < BT_SIZE; j++) {
		for (int c = 0; c < n; c++)
			memcpy(row + c * BT_SIZE, p[c] + j * BT_SIZE,
			    BT_SIZE * sizeof *row);
		if (rs_write_row(w, row, e) < 0) {
			rs_abort(w);
			goto done;
		}
	}
	r = rs_finish(w, e);
done:
	rs_header_free(&h);
	return r;
}

int
pyramid_block_read(const char *path, pyramid_block *b, tl_err *e)
{
	rs_reader *r;
	float row[4 * BT_SIZE], *p[4];
	int n, level, blk[2], ret = -1;
	double zr[2];

	if ((r = rs_open(path, e)) == NULL)
		return -1;
	const rs_header *h = rs_header_of(r);
	planes(b, p, &n);
	if (h->width != BT_SIZE || h->height != BT_SIZE) {
		tl_fail(e, "%s: %dx%d, a block is %dx%d", path, h->width,
		    h->height, BT_SIZE, BT_SIZE);
		goto done;
	}
	if (h->nch != n || rs_channel(h, "E") != 0 ||
	    rs_channel(h, "Z") != n - 1 ||
	    (b->displaced && (rs_channel(h, "X") != 1 ||
	    rs_channel(h, "Y") != 2))) {
		tl_fail(e, "%s: channels must be %s", path,
		    b->displaced ? "E X Y Z" : "E Z");
		goto done;
	}
	if (rs_get_int(h, VGIS_ATTR_LEVEL, &level) < 0 ||
	    rs_get_v2i(h, VGIS_ATTR_BLOCK, blk) < 0 ||
	    rs_get_double(h, VGIS_ATTR_BASE_ERROR, &b->base) < 0 ||
	    rs_get_v2d(h, VGIS_ATTR_ZRANGE, zr) < 0) {
		tl_fail(e, "%s: vgis:level, vgis:block, vgis:base_error or "
		    "vgis:zrange missing", path);
		goto done;
	}
	if (level != b->level || blk[0] != b->bi || blk[1] != b->bj) {
		tl_fail(e, "%s: says level %d block (%d,%d), expected level %d "
		    "block (%d,%d)", path, level, blk[0], blk[1], b->level,
		    b->bi, b->bj);
		goto done;
	}
	b->zmin = zr[0], b->zmax = zr[1];
	for (int j = 0; j < BT_SIZE; j++) {
		if (rs_read_row(r, row, e) < 0)
			goto done;
		for (int c = 0; c < n; c++)
			memcpy(p[c] + j * BT_SIZE, row + c * BT_SIZE,
			    BT_SIZE * sizeof *row);
	}
	ret = 0;
done:
	rs_close(r);
	return ret;
}
