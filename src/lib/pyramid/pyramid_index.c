/* pyramid_index.c - index.json of a pyramid (vgis(5)), written and read
 * with jansson (base/json.h); the reader treats the file as untrusted. */
#include "pyramid/pyramid.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/json.h"
#include "geo/levels.h"

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
	json_t *root, *levels;
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
	snprintf(path, sizeof path, "%s/" VGIS_INDEX, dir);
	r = tl_json_write(root, JSON_INDENT(1) | JSON_REAL_PRECISION(17), path,
	    e);
	json_decref(root);
	return r;
}

/* --- reading: untrusted input ----------------------------------------- */

static int
num2(json_t *o, const char *key, double v[2])
{
	json_t *a = json_object_get(o, key);

	return json_is_array(a) && json_array_size(a) == 2 &&
	    tl_json_num(json_array_get(a, 0), &v[0]) == 0 &&
	    tl_json_num(json_array_get(a, 1), &v[1]) == 0 ? 0 : -1;
}

static int
int2(json_t *o, const char *key, long long lo, long long hi, int v[2])
{
	json_t *a = json_object_get(o, key);

	return json_is_array(a) && json_array_size(a) == 2 &&
	    tl_json_int(json_array_get(a, 0), lo, hi, &v[0]) == 0 &&
	    tl_json_int(json_array_get(a, 1), lo, hi, &v[1]) == 0 ? 0 : -1;
}

/* A string that fits buf (never cut short); optional: absent gives "". */
static int
str(json_t *o, const char *key, char *buf, size_t n, int optional)
{
	json_t *x = json_object_get(o, key);

	buf[0] = '\0';
	if (x == NULL && optional)
		return 0;
	if (!json_is_string(x) || json_string_length(x) >= n ||
	    strlen(json_string_value(x)) != json_string_length(x))
		return -1;
	memcpy(buf, json_string_value(x), json_string_length(x) + 1);
	return 0;
}

/* A pixel a viewer can place: 1 micrometre to 10,000 km on the ground
 * (degrees: 1e-11 to 90), and a grid that stays on its model's world. */
static int
step_sane(const georef *g)
{
	double lo = 1e-6, hi = 1e7, m = 1;

	if (g->model == GEO_GEOGRAPHIC)
		lo = 1e-11, hi = 90;
	else
		m = g->unit;
	for (int a = 0; a < 2; a++) {
		double s = fabs(g->step[a]) * m;
		if (!(s >= lo && s <= hi))
			return -1;
	}
	return 0;
}

/* "georef": the field that is wrong, or NULL. */
static const char *
geo_of(json_t *o, georef *g)
{
	char s[32];
	json_t *x;

	memset(g, 0, sizeof *g);
	if (!json_is_object(o))
		return "georef";
	if (str(o, "model", s, sizeof s, 0) < 0 ||
	    geo_model_parse(s, &g->model) < 0)
		return "georef.model";
	if (tl_json_int(json_object_get(o, "epsg"), 0, INT_MAX, &g->epsg) < 0)
		return "georef.epsg";
	if (str(o, "crs", g->crs, sizeof g->crs, 0) < 0)
		return "georef.crs";
	if (str(o, "raster", s, sizeof s, 0) < 0 ||
	    (strcmp(s, "point") != 0 && strcmp(s, "area") != 0))
		return "georef.raster";
	g->point = strcmp(s, "point") == 0;
	if (num2(o, "origin", g->origin) < 0)
		return "georef.origin";
	if (tl_json_num(json_object_get(o, "unit"), &g->unit) < 0 ||
	    g->unit < 0 || (g->model != GEO_GEOGRAPHIC && !(g->unit > 0)))
		return "georef.unit";
	if (num2(o, "step", g->step) < 0 || step_sane(g) < 0)
		return "georef.step";
	if (str(o, "vdatum", g->vdatum, sizeof g->vdatum, 1) < 0)
		return "georef.vdatum";
	if (json_object_get(o, "cell") != NULL &&
	    (num2(o, "cell", g->cell) < 0 || !(g->cell[0] >= 1e-6) ||
	    !(g->cell[1] >= 1e-6) || g->cell[0] > 1e7 || g->cell[1] > 1e7))
		return "georef.cell";
	/* JSON has no NaN: a NaN nodata is the string "nan" */
	x = json_object_get(o, "nodata");
	if (json_is_number(x) && tl_json_num(x, &g->nodata) == 0) {
		g->has_nodata = 1;
	} else if (json_is_string(x) &&
	    strcmp(json_string_value(x), "nan") == 0) {
		g->has_nodata = 1;
		g->nodata = NAN;
	} else if (x != NULL) {
		return "georef.nodata";
	}
	return NULL;
}

/* Per block: n finite numbers, those of errors >= 0 (and max_error
 * below FLT_MAX, which marks the corners). */
static int
per_block(json_t *o, const char *key, double *v, size_t n, int error,
    const char *what, int l, tl_err *e)
{
	json_t *a = json_object_get(o, key);

	if (!json_is_array(a) || json_array_size(a) != n)
		return tl_fail(e, "%s: levels[%d].%s: must list %zu numbers, "
		    "one a block", what, l, key, n);
	for (size_t k = 0; k < n; k++)
		if (tl_json_num(json_array_get(a, k), &v[k]) < 0 ||
		    (error && !(v[k] >= 0 && v[k] < FLT_MAX)))
			return tl_fail(e, "%s: levels[%d].%s[%zu]: %s", what, l,
			    key, k, error ? "not a finite error >= 0" :
			    "not a finite number");
	return 0;
}

static int
level_blocks(json_t *o, pyramid_level *L, const char *what, tl_err *e)
{
	size_t nb = (size_t)L->blocks[0] * L->blocks[1];
	int l = L->level;

	if (per_block(o, "zmin", L->zmin, nb, 0, what, l, e) < 0 ||
	    per_block(o, "zmax", L->zmax, nb, 0, what, l, e) < 0 ||
	    per_block(o, "base_error", L->base, nb, 1, what, l, e) < 0 ||
	    per_block(o, "max_error", L->emax, nb, 1, what, l, e) < 0)
		return -1;
	for (size_t k = 0; k < nb; k++)
		if (L->zmin[k] > L->zmax[k])
			return tl_fail(e, "%s: levels[%d]: block (%zu,%zu): "
			    "zmin %.9g > zmax %.9g", what, l,
			    k % (size_t)L->blocks[0], k / (size_t)L->blocks[0],
			    L->zmin[k], L->zmax[k]);
	return 0;
}

/* Entry `want` of the levels array of a size0 pyramid. */
static int
level_from_json(json_t *o, pyramid_level *L, int want, const int size0[2],
    const char *what, tl_err *e)
{
	int level, sz[2], bl[2];
	json_t *d = json_object_get(o, "displaced");
	char mode[sizeof L->mode], kernel[sizeof L->kernel];

	if (!json_is_object(o) ||
	    tl_json_int(json_object_get(o, "level"), 0, 63, &level) < 0 ||
	    int2(o, "size", 2, 1 << 26, sz) < 0 ||
	    int2(o, "blocks", 1, 1 << 26, bl) < 0 || !json_is_boolean(d) ||
	    str(o, "mode", mode, sizeof mode, 0) < 0 ||
	    str(o, "kernel", kernel, sizeof kernel, 0) < 0)
		return tl_fail(e, "%s: levels[%d]: level, size, blocks, "
		    "displaced, mode or kernel missing, out of range or not of "
		    "its type", what, want);
	if (level != want || sz[0] != geo_level_size(size0[0], level) ||
	    sz[1] != geo_level_size(size0[1], level))
		return tl_fail(e, "%s: levels[%d]: level %d, size %dx%d; level "
		    "%d of a %dx%d DEM is %dx%d", what, want, level, sz[0],
		    sz[1], want, size0[0], size0[1],
		    geo_level_size(size0[0], want),
		    geo_level_size(size0[1], want));
	if (bl[0] != pyramid_nblocks(sz[0]) || bl[1] != pyramid_nblocks(sz[1]))
		return tl_fail(e, "%s: levels[%d].blocks: %dx%d, a %dx%d level "
		    "has %dx%d", what, want, bl[0], bl[1], sz[0], sz[1],
		    pyramid_nblocks(sz[0]), pyramid_nblocks(sz[1]));
	if (pyramid_level_init(L, level, sz[0], sz[1], e) < 0)
		return tl_fail(e, "%s: levels[%d]: %zu blocks: out of memory",
		    what, want, (size_t)bl[0] * bl[1]);
	L->displaced = json_is_true(d);
	memcpy(L->mode, mode, sizeof mode);
	memcpy(L->kernel, kernel, sizeof kernel);
	return level_blocks(o, L, what, e);
}

/* What the index of a w x h pyramid can hold: its blocks (all levels),
 * and at most how many bytes its text needs (the writer's indented
 * numbers take about 30 bytes; 48 allowed, 2 KiB a level, 64 KiB for the
 * rest: a CRS string of 4 KiB escaped included). */
static void
index_need(int w, int h, long long *blocks, long long *bytes)
{
	int nl = geo_levels(w, h);

	*blocks = 0;
	for (int l = 0; l < nl; l++)
		*blocks += (long long)pyramid_nblocks(geo_level_size(w, l)) *
		    pyramid_nblocks(geo_level_size(h, l));
	*bytes = (64 << 10) + (2 << 10) * (long long)nl + 4 * 48 * *blocks;
}

#define PYRAMID_INDEX_SMALL (1 << 20)

/* "[ a , b ]" of integers at t[i..n) (blanks allowed); -1 if not. */
static int
int_pair_at(const char *t, size_t n, size_t i, long v[2])
{
	const char *want = ":[,]";

	for (int k = 0; k < 4; k++) {
		while (i < n && strchr(" \t\r\n", t[i]) != NULL)
			i++;
		if (k == 2 || k == 3) {
			long x = 0;
			size_t i0 = i;
			for (; i < n && t[i] >= '0' && t[i] <= '9' &&
			    x <= (1L << 30); i++)
				x = 10 * x + (t[i] - '0');
			if (i == i0)
				return -1;
			v[k - 2] = x;
			while (i < n && strchr(" \t\r\n", t[i]) != NULL)
				i++;
		}
		if (i >= n || t[i] != want[k])
			return -1;
		i++;
	}
	return 0;
}

/* Before jansson builds anything: the root's "size0" (by a scan that
 * knows strings and nesting; there once), and how many values the text
 * holds at most (its commas outside strings). */
static int
prescan(const char *t, size_t n, int size0[2], long long *commas)
{
	int depth = 0, found = 0;
	long v[2];

	*commas = 0;
	for (size_t i = 0; i < n; i++) {
		if (t[i] == '"') {
			size_t j = i + 1;
			while (j < n && t[j] != '"')
				j += t[j] == '\\' ? 2 : 1;
			if (depth == 1 && j == i + 6 && j < n &&
			    memcmp(t + i, "\"size0\"", 7) == 0) {
				if (found++ ||
				    int_pair_at(t, n, j + 1, v) < 0 ||
				    v[0] < 3 || v[1] < 3 || v[0] > (1 << 26) ||
				    v[1] > (1 << 26))
					return -1;
				size0[0] = (int)v[0], size0[1] = (int)v[1];
			}
			i = j;
		} else if (t[i] == '{' || t[i] == '[') {
			depth++;
		} else if (t[i] == '}' || t[i] == ']') {
			depth--;
		} else if (t[i] == ',') {
			(*commas)++;
		}
	}
	return found ? 0 : -1;
}

/* The text's size and values against what its size0 claims: never more
 * than that pyramid's index needs, never fewer values than its blocks. */
int
pyramid_index_bounded(const char *text, size_t n, const char *what,
    tl_err *e)
{
	int s0[2];
	long long commas, nb, need;

	/* no size0 to go by: what is refused anyway, once parsed, may be
	 * parsed if small, so that its message names the field */
	if (prescan(text, n, s0, &commas) < 0)
		return n <= PYRAMID_INDEX_SMALL ? 0 : tl_fail(e, "%s: %zu "
		    "bytes without a size0 (two integers 3 .. 2^26, in the "
		    "root, once): not a pyramid index", what, n);
	index_need(s0[0], s0[1], &nb, &need);
	if ((long long)n > need)
		return tl_fail(e, "%s: %zu bytes, more than the index of a "
		    "%dx%d pyramid (%lld blocks) can need (%lld): damaged or "
		    "forged", what, n, s0[0], s0[1], nb, need);
	if (commas > 4 * nb + 64 * geo_levels(s0[0], s0[1]) + 256 ||
	    commas < 4 * nb - 4)
		return tl_fail(e, "%s: %lld values, the index of a %dx%d "
		    "pyramid (%lld blocks) holds 4 a block: damaged or forged",
		    what, commas, s0[0], s0[1], nb);
	return 0;
}

/* jansson's reason, never empty ("line -1: " said nothing). */
static int
json_failed(const json_error_t *je, int oom, size_t n, const char *what,
    tl_err *e)
{
	if (oom)
		return tl_fail(e, "%s: out of memory parsing its %zu bytes",
		    what, n);
	if (json_error_code(je) == json_error_duplicate_key)
		return tl_fail(e, "%s: line %d: %s (each key once)", what,
		    je->line, je->text);
	return tl_fail(e, "%s: not JSON: line %d column %d: %s", what,
	    je->line, je->column, je->text);
}

/* The root's fields but the levels; the field that is wrong, or NULL. */
static const char *
root_of(json_t *root, pyramid_index *ix)
{
	char fmt[64];
	int block;

	if (!json_is_object(root))
		return "not an object";
	if (str(root, "format", fmt, sizeof fmt, 0) < 0 ||
	    strcmp(fmt, VGIS_FORMAT) != 0)
		return "format";
	if (tl_json_int(json_object_get(root, "version"), INT_MIN, INT_MAX,
	    &ix->version) < 0)
		return "version";
	if (tl_json_int(json_object_get(root, "block"), INT_MIN, INT_MAX,
	    &block) < 0 || block != BT_SIZE)
		return "block";
	if (int2(root, "size0", 3, 1 << 26, ix->size0) < 0)
		return "size0: two integers 3 .. 2^26";
	if (!json_is_array(json_object_get(root, "levels")))
		return "levels";
	return geo_of(json_object_get(root, "georef"), &ix->geo);
}

int
pyramid_index_parse(const char *text, size_t n, const char *what,
    pyramid_index *ix, tl_err *e)
{
	json_error_t je;
	json_t *root, *levels;
	const char *bad;
	int r = -1, oom;

	memset(ix, 0, sizeof *ix);
	if (pyramid_index_bounded(text, n, what, e) < 0)
		return -1;
	if ((root = tl_json_parse(text, n, &je, &oom)) == NULL)
		return json_failed(&je, oom, n, what, e);
	levels = json_object_get(root, "levels");
	if ((bad = root_of(root, ix)) != NULL) {
		tl_fail(e, "%s: not a pyramid index (%s)", what, bad);
		goto done;
	}
	if (ix->version != VGIS_VERSION) {
		tl_fail(e, "%s: version %d, this program reads %d", what,
		    ix->version, VGIS_VERSION);
		goto done;
	}
	ix->geo.width = ix->size0[0], ix->geo.height = ix->size0[1];
	if (json_array_size(levels) !=
	    (size_t)geo_levels(ix->size0[0], ix->size0[1])) {
		tl_fail(e, "%s: levels: %zu, a %dx%d pyramid has %d", what,
		    json_array_size(levels), ix->size0[0], ix->size0[1],
		    geo_levels(ix->size0[0], ix->size0[1]));
		goto done;
	}
	if ((ix->lev = tl_alloc(json_array_size(levels), sizeof *ix->lev,
	    e)) == NULL) {
		tl_fail(e, "%s: levels: out of memory", what);
		goto done;
	}
	for (size_t l = 0; l < json_array_size(levels); l++, ix->nlevels++)
		if (level_from_json(json_array_get(levels, l), &ix->lev[l],
		    (int)l, ix->size0, what, e) < 0) {
			ix->nlevels++; /* its arrays freed too */
			goto done;
		}
	r = 0;
done:
	json_decref(root);
	if (r < 0)
		pyramid_index_free(ix);
	return r;
}

char *
pyramid_index_load(const char *path, size_t *n, tl_err *e)
{
	struct stat st;
	char *text = NULL;
	int fd;

	if ((fd = tl_open_regular(path, e)) < 0)
		return NULL;
	if (fstat(fd, &st) < 0) {
		tl_failsys(e, "%s", path);
	} else if (st.st_size > (1LL << 40) || (text = malloc((size_t)
	    st.st_size + 1)) == NULL) {
		/* bounded() then refuses what its size0 cannot need */
		tl_fail(e, "%s: %lld bytes: cannot hold it in memory", path,
		    (long long)st.st_size);
	} else if (tl_pread(fd, text, (size_t)st.st_size, 0, path, e) < 0) {
		free(text);
		text = NULL;
	} else {
		text[st.st_size] = '\0';
		*n = (size_t)st.st_size;
	}
	close(fd);
	return text;
}

int
pyramid_index_read(const char *dir, pyramid_index *ix, tl_err *e)
{
	char path[4096], *text;
	size_t n;
	int r;

	memset(ix, 0, sizeof *ix);
	snprintf(path, sizeof path, "%s/" VGIS_INDEX, dir);
	if ((text = pyramid_index_load(path, &n, e)) == NULL)
		return -1;
	r = pyramid_index_parse(text, n, path, ix, e);
	free(text);
	return r;
}
