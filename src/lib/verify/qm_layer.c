/* qm_layer.c - a quantized-mesh tileset as a whole: layer.json's fields
 * (read with jansson, as cesium-native's layer schema and CesiumJS's
 * CesiumTerrainProvider need them), the tile files present, the tiles
 * "available" announces, and the quadtree: every ancestor of a tile, up
 * to the two roots, present. */
#include "verify/qm.h"

#include <dirent.h>
#include "base/json.h"
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAXANNOUNCED (1L << 26) /* tiles enumerated from rectangles */

typedef struct {
	qm_key *k;
	long n, cap;
} keys;

static int
push(keys *s, qm_key k)
{
	if (s->n == s->cap) {
		long cap = s->cap ? 2 * s->cap : 1024;
		qm_key *p = realloc(s->k, (size_t)cap * sizeof *p);

		if (p == NULL)
			return -1;
		s->k = p, s->cap = cap;
	}
	s->k[s->n++] = k;
	return 0;
}

static int
cmpkey(const void *a, const void *b)
{
	qm_key x = *(const qm_key *)a, y = *(const qm_key *)b;

	return x < y ? -1 : x > y;
}

static void
sort_unique(keys *s)
{
	long m = 0;

	qsort(s->k, (size_t)s->n, sizeof *s->k, cmpkey);
	for (long i = 0; i < s->n; i++)
		if (m == 0 || s->k[i] != s->k[m - 1])
			s->k[m++] = s->k[i];
	s->n = m;
}

int
qm_set_has(const qm_set *s, qm_key k)
{
	return s->n > 0 && bsearch(&k, s->key, (size_t)s->n, sizeof k,
	    cmpkey) != NULL;
}

/* A decimal number without sign or leading zero, below lim; -1 if not. */
static long
number(const char *s, const char *end, long lim)
{
	long v = 0;

	if (s == end || (s[0] == '0' && end - s > 1))
		return -1;
	for (; s < end; s++) {
		if (*s < '0' || *s > '9' || v > lim)
			return -1;
		v = v * 10 + (*s - '0');
	}
	return v < lim ? v : -1;
}

static int
isdir(const char *path)
{
	struct stat st;

	return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* dir/z/x/y.terrain for each x of level z. */
static int
scan_level(const char *dir, int z, keys *s, qm_report *r)
{
	char path[4096];
	DIR *dx, *dy;
	struct dirent *a, *b;

	snprintf(path, sizeof path, "%s/%d", dir, z);
	if ((dx = opendir(path)) == NULL)
		return 0;
	while ((a = readdir(dx)) != NULL) {
		long x = number(a->d_name, a->d_name + strlen(a->d_name),
		    2L << z);

		snprintf(path, sizeof path, "%s/%d/%s", dir, z, a->d_name);
		if (x < 0 || !isdir(path) || (dy = opendir(path)) == NULL)
			continue;
		while ((b = readdir(dy)) != NULL) {
			const char *dot = strrchr(b->d_name, '.');
			long y = dot == NULL || strcmp(dot, ".terrain") ? -1 :
			    number(b->d_name, dot, 1L << z);

			if (y < 0)
				continue;
			if (push(s, QM_KEY(z, x, y)) < 0) {
				closedir(dy), closedir(dx);
				return -1;
			}
		}
		closedir(dy);
	}
	closedir(dx);
	(void)r;
	return 0;
}

static int
scan(const char *dir, keys *s, qm_report *r, tl_err *e)
{
	DIR *d = opendir(dir);
	struct dirent *a;

	if (d == NULL)
		return tl_failsys(e, "%s", dir);
	while ((a = readdir(d)) != NULL) {
		long z = number(a->d_name, a->d_name + strlen(a->d_name),
		    1000);

		if (z > QM_MAXZ)
			qm_issue_add(r, QM_UNANNOUNCED, -1, 0, 0, "level "
			    "directory %ld: deeper than %d, not read", z,
			    QM_MAXZ);
		else if (z >= 0 && scan_level(dir, (int)z, s, r) < 0) {
			closedir(d);
			return tl_fail(e, "%s: out of memory", dir);
		}
	}
	closedir(d);
	sort_unique(s);
	return 0;
}

static int
rect_int(json_t *o, const char *k, long lim, long *v)
{
	json_t *j = json_object_get(o, k);

	if (!json_is_integer(j) || json_integer_value(j) < 0 ||
	    json_integer_value(j) >= lim)
		return -1;
	*v = (long)json_integer_value(j);
	return 0;
}

/* Rectangles {startX, startY, endX, endY} (inclusive) of level z into
 * s; what names them in messages. -1: not rectangles of that level. */
static int
rects(json_t *a, int z, keys *s, long *budget, const char *what,
    qm_report *r)
{
	size_t i;
	json_t *o;

	if (!json_is_array(a)) {
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "%s level %d: not an "
		    "array of rectangles", what, z);
		return -1;
	}
	json_array_foreach(a, i, o) {
		long x0, y0, x1, y1;

		if (rect_int(o, "startX", 2L << z, &x0) < 0 ||
		    rect_int(o, "startY", 1L << z, &y0) < 0 ||
		    rect_int(o, "endX", 2L << z, &x1) < 0 ||
		    rect_int(o, "endY", 1L << z, &y1) < 0 || x1 < x0 ||
		    y1 < y0) {
			qm_issue_add(r, QM_LAYER, -1, 0, 0, "%s level %d, "
			    "rectangle %zu: startX startY endX endY not "
			    "integers of the level, start <= end", what, z, i);
			return -1;
		}
		if ((*budget -= (x1 - x0 + 1) * (y1 - y0 + 1)) < 0) {
			qm_issue_add(r, QM_LAYER, -1, 0, 0, "%s: over %ld "
			    "tiles announced, not enumerated", what,
			    MAXANNOUNCED);
			return -1;
		}
		for (long x = x0; x <= x1; x++)
			for (long y = y0; y <= y1; y++)
				if (push(s, QM_KEY(z, x, y)) < 0)
					return -1;
	}
	return 0;
}

static void
need_string(json_t *L, const char *k, const char *want, qm_report *r)
{
	json_t *j = json_object_get(L, k);

	if (!json_is_string(j))
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: %s missing "
		    "or not a string", k);
	else if (want != NULL && strcmp(json_string_value(j), want))
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: %s \"%s\", "
		    "not \"%s\"", k, json_string_value(j), want);
}

static void
check_fields(json_t *L, qm_set *s, qm_report *r)
{
	json_t *t = json_object_get(L, "tiles"), *b, *x, *j;
	const char *tmpl;
	size_t i;

	need_string(L, "tilejson", NULL, r);
	need_string(L, "name", NULL, r);
	need_string(L, "description", NULL, r);
	need_string(L, "version", NULL, r);
	need_string(L, "format", "quantized-mesh-1.0", r);
	need_string(L, "scheme", "tms", r);
	need_string(L, "projection", "EPSG:4326", r);
	tmpl = json_string_value(json_array_get(t, 0));
	if (tmpl == NULL || strncmp(tmpl, "{z}/{x}/{y}.terrain", 19) ||
	    (tmpl[19] != '\0' && tmpl[19] != '?'))
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: tiles[0] "
		    "\"%s\": not {z}/{x}/{y}.terrain (with ?v={version} or "
		    "no query), the only layout read", tmpl ? tmpl : "");
	b = json_object_get(L, "bounds");
	if (json_array_size(b) != 4 || !json_is_number(json_array_get(b, 0))
	    || json_number_value(json_array_get(b, 0)) >=
	    json_number_value(json_array_get(b, 2)) ||
	    json_number_value(json_array_get(b, 1)) >=
	    json_number_value(json_array_get(b, 3)))
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: bounds not "
		    "[west, south, east, north]");
	j = json_object_get(L, "minzoom");
	x = json_object_get(L, "maxzoom");
	s->maxzoom = (int)json_integer_value(x);
	if (!json_is_integer(j) || !json_is_integer(x) ||
	    json_integer_value(j) < 0 || json_integer_value(j) >
	    json_integer_value(x) || json_integer_value(x) > QM_MAXZ)
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: minzoom, "
		    "maxzoom not levels 0 <= minzoom <= maxzoom <= %d",
		    QM_MAXZ);
	x = json_object_get(L, "extensions");
	if (!json_is_array(x))
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: extensions "
		    "missing or not an array");
	json_array_foreach(x, i, j)
		if (json_is_string(j) &&
		    !strcmp(json_string_value(j), "octvertexnormals"))
			s->normals = 1;
}

static int
announced(json_t *L, qm_set *s, qm_report *r)
{
	json_t *av = json_object_get(L, "available"), *lev;
	keys k = { NULL, 0, 0 };
	long budget = MAXANNOUNCED;
	size_t z;

	if (!json_is_array(av) || json_array_size(av) == 0) {
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: available "
		    "missing or empty");
		return -1;
	}
	if (json_array_size(av) != (size_t)s->maxzoom + 1)
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "layer.json: available "
		    "has %zu levels, maxzoom %d", json_array_size(av),
		    s->maxzoom);
	json_array_foreach(av, z, lev) {
		if (z > QM_MAXZ || rects(lev, (int)z, &k, &budget,
		    "layer.json: available", r) < 0) {
			free(k.k);
			return -1;
		}
	}
	sort_unique(&k);
	s->avail = k.k, s->navail = k.n;
	return 0;
}

/* Both lists sorted: announced without a file, a file not announced. */
static void
compare(const qm_set *s, qm_report *r)
{
	long i = 0, j = 0;

	while (i < s->navail || j < s->n) {
		qm_key a = i < s->navail ? s->avail[i] : UINT64_MAX;
		qm_key b = j < s->n ? s->key[j] : UINT64_MAX;

		if (a == b)
			i++, j++;
		else if (a < b) {
			qm_issue_add(r, QM_MISSING, QM_KZ(a), QM_KX(a),
			    QM_KY(a), "announced by layer.json's available, "
			    "no file");
			i++;
		} else {
			qm_issue_add(r, QM_UNANNOUNCED, QM_KZ(b), QM_KX(b),
			    QM_KY(b), "a file layer.json's available does not "
			    "announce");
			j++;
		}
	}
}

static void
ancestors(const qm_set *s, qm_report *r)
{
	for (int x = 0; x < 2; x++)
		if (!qm_set_has(s, QM_KEY(0, x, 0)))
			qm_issue_add(r, QM_ANCESTOR, -1, 0, 0, "root tile "
			    "0/%d/0 missing: CesiumJS asks for both", x);
	for (long i = 0; i < s->n; i++) {
		qm_key k = s->key[i];
		int z = QM_KZ(k);

		if (z > 0 && !qm_set_has(s, QM_KEY(z - 1, QM_KX(k) / 2,
		    QM_KY(k) / 2)))
			qm_issue_add(r, QM_ANCESTOR, z, QM_KX(k), QM_KY(k),
			    "its parent %d/%d/%d is missing", z - 1,
			    QM_KX(k) / 2, QM_KY(k) / 2);
	}
}

int
qm_set_read(const char *dir, qm_set *s, qm_report *r, tl_err *e)
{
	char path[4096];
	json_error_t je;
	json_t *L;
	keys k = { NULL, 0, 0 };

	memset(s, 0, sizeof *s);
	snprintf(path, sizeof path, "%s/layer.json", dir);
	if (!isdir(dir))
		return tl_fail(e, "%s: not a directory", dir);
	if (access(path, R_OK) < 0)
		return tl_failsys(e, "%s", path);
	L = json_load_file(path, JSON_REJECT_DUPLICATES, &je);
	if (L == NULL)
		return tl_fail(e, "%s: line %d: %s", path, je.line, je.text);
	if (!json_is_object(L)) {
		json_decref(L);
		return tl_fail(e, "%s: not a JSON object", path);
	}
	if (scan(dir, &k, r, e) < 0) {
		json_decref(L);
		free(k.k);
		return -1;
	}
	s->key = k.k, s->n = k.n;
	check_fields(L, s, r);
	if (announced(L, s, r) == 0)
		compare(s, r);
	ancestors(s, r);
	json_decref(L);
	return 0;
}

void
qm_set_free(qm_set *s)
{
	free(s->key), free(s->avail);
	memset(s, 0, sizeof *s);
}

void
qm_metadata_check(const qm_set *s, const qm_tile *t, int z, int x, int y,
    qm_report *r)
{
	json_t *j = t->metadata ? json_loads(t->metadata, 0, NULL) : NULL;
	json_t *av = json_object_get(j, "available"), *lev;
	keys k = { NULL, 0, 0 };
	long budget = MAXANNOUNCED;
	size_t i;

	json_array_foreach(av, i, lev)
		if (z + 1 + (int)i > QM_MAXZ || rects(lev, z + 1 + (int)i, &k,
		    &budget, "metadata (4) available", r) < 0)
			break;
	for (long n = 0; n < k.n; n++)
		if (!qm_set_has(s, k.k[n]))
			qm_issue_add(r, QM_MISSING, z, x, y, "its metadata "
			    "announces %d/%d/%d, no file", QM_KZ(k.k[n]),
			    QM_KX(k.k[n]), QM_KY(k.k[n]));
	free(k.k);
	json_decref(j);
}
