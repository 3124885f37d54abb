/* t3c_glb.c - a glb of the 3D Tiles terrain profile into a t3c_tile, read
 * from the glTF 2.0 specification (the binary container, the JSON, the
 * accessors) and the draft CESIUM_tile_edges: what Cesium3DTilesTerrain
 * GeometryProcessor reads (nodes[0].matrix, meshes[0].primitives[0],
 * float32 arrays packed at their offsets) and nothing else. Every offset
 * and count is checked against the bytes before use. */
#include "verify/t3c.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/json.h"

#define MAXBYTES (1u << 30)
#define GLTF_FLOAT 5126

typedef struct {
	json_t *g;
	const unsigned char *bin;
	size_t binlen;    /* the BIN chunk's bytes */
	size_t buflen;    /* buffers[0].byteLength */
} doc;

/* An accessor's data: count elements of comp components of size bytes. */
typedef struct {
	const unsigned char *p;
	size_t count;
	int ctype, size;
} acc;

static uint32_t
le32(const unsigned char *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
	    (uint32_t)p[3] << 24;
}

static float
lef(const unsigned char *p)
{
	uint32_t u = le32(p);
	float f;

	memcpy(&f, &u, sizeof f);
	return f;
}

/* A non-negative integer member (or def when absent and def >= 0). */
static int
member(json_t *o, const char *k, long long def, long long lim,
    long long *v)
{
	json_t *j = json_object_get(o, k);

	if (j == NULL && def >= 0) {
		*v = def;
		return 0;
	}
	if (!json_is_integer(j) || json_integer_value(j) < 0 ||
	    json_integer_value(j) > lim)
		return -1;
	*v = json_integer_value(j);
	return 0;
}

static int
csize(int ctype)
{
	return ctype == 5121 ? 1 : ctype == 5123 ? 2 :
	    ctype == 5125 || ctype == GLTF_FLOAT ? 4 : 0;
}

/* Accessor i of type ("VEC3", "SCALAR"), components float (want
 * GLTF_FLOAT) or unsigned integers (want 0), what naming it. */
static int
accessor(const doc *d, json_t *ji, const char *type, int want,
    const char *what, acc *a, tl_err *e)
{
	json_t *ac = json_object_get(d->g, "accessors"), *o, *v;
	long long i, bv, aoff, voff, vlen, buf, ct, count, stride;
	int comps = strcmp(type, "VEC3") ? 1 : 3;
	size_t elem;

	if (!json_is_integer(ji) || (i = json_integer_value(ji)) < 0 ||
	    (o = json_array_get(ac, (size_t)i)) == NULL)
		return tl_fail(e, "%s: no such accessor", what);
	if (json_object_get(o, "sparse") != NULL)
		return tl_fail(e, "%s: sparse accessor (not read by "
		    "CesiumJS's terrain)", what);
	if (member(o, "bufferView", -1, 1LL << 31, &bv) < 0 ||
	    (v = json_array_get(json_object_get(d->g, "bufferViews"),
	    (size_t)bv)) == NULL)
		return tl_fail(e, "%s: no buffer view", what);
	if (member(o, "byteOffset", 0, MAXBYTES, &aoff) < 0 ||
	    member(o, "componentType", -1, 99999, &ct) < 0 ||
	    member(o, "count", -1, MAXBYTES, &count) < 0 || count < 1 ||
	    !json_is_string(json_object_get(o, "type")) ||
	    strcmp(json_string_value(json_object_get(o, "type")), type))
		return tl_fail(e, "%s: not %s with componentType, count >= 1",
		    what, type);
	if (want ? ct != want : (ct == GLTF_FLOAT || csize((int)ct) == 0))
		return tl_fail(e, "%s: componentType %lld, not %s", what, ct,
		    want ? "FLOAT (5126)" : "an unsigned integer");
	if (member(v, "buffer", -1, 0, &buf) < 0 ||
	    member(v, "byteOffset", 0, MAXBYTES, &voff) < 0 ||
	    member(v, "byteLength", -1, MAXBYTES, &vlen) < 0 ||
	    voff + vlen > (long long)d->buflen)
		return tl_fail(e, "%s: buffer view %lld not within buffer 0's "
		    "%zu bytes", what, bv, d->buflen);
	elem = (size_t)csize((int)ct) * comps;
	if (member(v, "byteStride", elem, 255, &stride) < 0 ||
	    stride != (long long)elem)
		return tl_fail(e, "%s: byteStride not %zu: CesiumJS reads the "
		    "elements packed", what, elem);
	if (aoff + (long long)elem * count > vlen)
		return tl_fail(e, "truncated: %s: %lld elements of %zu bytes "
		    "at %lld, the buffer view has %lld", what, count, elem,
		    aoff, vlen);
	if ((voff + aoff) % csize((int)ct))
		return tl_fail(e, "%s: at byte %lld, not aligned to its "
		    "components", what, voff + aoff);
	a->p = d->bin + voff + aoff, a->count = (size_t)count;
	a->ctype = (int)ct, a->size = csize((int)ct);
	return 0;
}

static uint32_t
index_at(const acc *a, size_t k)
{
	const unsigned char *p = a->p + k * (size_t)a->size;

	return a->size == 1 ? p[0] : a->size == 2 ?
	    ((uint32_t)p[0] | (uint32_t)p[1] << 8) : le32(p);
}

static int
indices(const doc *d, json_t *ji, const char *what, uint32_t **out,
    uint32_t *n, tl_err *e)
{
	acc a;

	if (accessor(d, ji, "SCALAR", 0, what, &a, e) < 0)
		return -1;
	if ((*out = malloc((a.count + 1) * sizeof **out)) == NULL)
		return tl_fail(e, "%s: out of memory", what);
	for (size_t k = 0; k < a.count; k++)
		(*out)[k] = index_at(&a, k);
	*n = (uint32_t)a.count;
	return 0;
}

/* POSITION through the node's matrix (column-major), then Y up to Z up
 * (x, y, z) -> (x, -z, y): ECEF; its min and max checked. */
static int
positions(const doc *d, json_t *prim, const double m[16], t3c_tile *t,
    tl_err *e)
{
	json_t *attr = json_object_get(prim, "attributes");
	json_t *ac = json_object_get(d->g, "accessors"), *mn, *mx;
	double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3], big = 0;
	acc a;

	hi[0] = hi[1] = hi[2] = -INFINITY;
	if (accessor(d, json_object_get(attr, "POSITION"), "VEC3",
	    GLTF_FLOAT, "POSITION", &a, e) < 0)
		return -1;
	t->n = (uint32_t)a.count;
	if ((t->p = malloc(3 * a.count * sizeof *t->p)) == NULL)
		return tl_fail(e, "POSITION: out of memory");
	for (size_t i = 0; i < a.count; i++) {
		double q[3], w[3];

		for (int k = 0; k < 3; k++) {
			q[k] = lef(a.p + 12 * i + 4 * k);
			if (!isfinite(q[k]))
				return tl_fail(e, "POSITION: vertex %zu not "
				    "finite", i);
			lo[k] = fmin(lo[k], q[k]), hi[k] = fmax(hi[k], q[k]);
			big = fmax(big, fabs(q[k]));
		}
		for (int r = 0; r < 3; r++)
			w[r] = m[r] * q[0] + m[4 + r] * q[1] + m[8 + r] * q[2] +
			    m[12 + r];
		t->p[3 * i] = w[0], t->p[3 * i + 1] = -w[2];
		t->p[3 * i + 2] = w[1];
	}
	/* half an ulp per component, three of them, through a rotation */
	t->noise = 3 * ldexp(big, -24) + 1e-6;
	mn = json_object_get(json_array_get(ac, (size_t)json_integer_value(
	    json_object_get(attr, "POSITION"))), "min");
	mx = json_object_get(json_array_get(ac, (size_t)json_integer_value(
	    json_object_get(attr, "POSITION"))), "max");
	for (int k = 0; k < 3; k++)
		if ((float)json_number_value(json_array_get(mn, k)) !=
		    (float)lo[k] ||
		    (float)json_number_value(json_array_get(mx, k)) !=
		    (float)hi[k] || json_array_size(mn) != 3 ||
		    json_array_size(mx) != 3)
			return tl_fail(e, "POSITION: min, max not the "
			    "positions' extremes (glTF requires them)");
	return 0;
}

static int
normals(const doc *d, json_t *prim, t3c_tile *t, tl_err *e)
{
	acc a;

	if (accessor(d, json_object_get(json_object_get(prim, "attributes"),
	    "NORMAL"), "VEC3", GLTF_FLOAT, "NORMAL", &a, e) < 0)
		return -1;
	if (a.count != t->n)
		return tl_fail(e, "NORMAL: %zu normals, %u positions",
		    a.count, t->n);
	if ((t->nrm = malloc(3 * a.count * sizeof *t->nrm)) == NULL)
		return tl_fail(e, "NORMAL: out of memory");
	for (size_t i = 0; i < 3 * a.count; i++)
		t->nrm[i] = lef(a.p + 4 * i);
	return 0;
}

/* extensionsUsed names CESIUM_tile_edges; nodes[0].matrix into m. */
static int
frame(json_t *g, double m[16], tl_err *e)
{
	json_t *used = json_object_get(g, "extensionsUsed"), *j, *mat;
	size_t i;
	int has = 0;

	json_array_foreach(used, i, j)
		has |= json_is_string(j) &&
		    !strcmp(json_string_value(j), "CESIUM_tile_edges");
	if (!has)
		return tl_fail(e, "extensionsUsed lacks CESIUM_tile_edges");
	if (json_array_size(json_object_get(g, "meshes")) != 1 ||
	    json_array_size(json_object_get(json_array_get(json_object_get(g,
	    "meshes"), 0), "primitives")) != 1)
		return tl_fail(e, "not one mesh of one primitive");
	mat = json_object_get(json_array_get(json_object_get(g, "nodes"), 0),
	    "matrix");
	if (json_array_size(mat) != 16)
		return tl_fail(e, "nodes[0] has no matrix of 16 numbers "
		    "(CesiumJS's terrain reads it)");
	for (int k = 0; k < 16; k++)
		if (tl_json_num(json_array_get(mat, k), &m[k]) < 0)
			return tl_fail(e, "nodes[0].matrix: not 16 finite "
			    "numbers");
	return 0;
}

static int
gltf(const doc *d, t3c_tile *t, tl_err *e)
{
	static const char *name[4] = { "left", "bottom", "right", "top" };
	json_t *prim = json_array_get(json_object_get(json_array_get(
	    json_object_get(d->g, "meshes"), 0), "primitives"), 0), *edges;
	json_t *mode = json_object_get(prim, "mode");
	double m[16];
	uint32_t ni;
	char what[64];

	if (frame(d->g, m, e) < 0)
		return -1;
	if (mode != NULL && (!json_is_integer(mode) ||
	    json_integer_value(mode) != 4))
		return tl_fail(e, "primitive mode not triangles (4)");
	if (positions(d, prim, m, t, e) < 0 || normals(d, prim, t, e) < 0 ||
	    indices(d, json_object_get(prim, "indices"), "indices", &t->idx,
	    &ni, e) < 0)
		return -1;
	if (ni % 3)
		return tl_fail(e, "indices: %u, not triangles", ni);
	t->ntri = ni / 3;
	edges = json_object_get(json_object_get(prim, "extensions"),
	    "CESIUM_tile_edges");
	if (!json_is_object(edges))
		return tl_fail(e, "the primitive has no CESIUM_tile_edges");
	for (int k = 0; k < 4; k++) {
		snprintf(what, sizeof what, "CESIUM_tile_edges %s", name[k]);
		if (indices(d, json_object_get(edges, name[k]), what,
		    &t->edge[k], &t->nedge[k], e) < 0)
			return -1;
	}
	return 0;
}

/* The container: header, JSON chunk, BIN chunk, buffers[0]. */
static int
container(const unsigned char *b, size_t len, doc *d, tl_err *e)
{
	json_error_t je;
	uint32_t jl, bl;
	int oom;
	long long blen;
	json_t *b0;

	if (len < 20)
		return tl_fail(e, "truncated: %zu bytes, no glb header and "
		    "JSON chunk header", len);
	if (memcmp(b, "glTF", 4) || le32(b + 4) != 2)
		return tl_fail(e, "not a glb of glTF 2 (magic, version)");
	if (le32(b + 8) != len)
		return tl_fail(e, "truncated: the header says %u bytes, the "
		    "file has %zu", le32(b + 8), len);
	jl = le32(b + 12);
	if (memcmp(b + 16, "JSON", 4) || jl > len - 20 || jl % 4)
		return tl_fail(e, "JSON chunk: %u bytes (of %zu left, padded "
		    "to 4)", jl, len - 20);
	if (len - 20 - jl < 8)
		return tl_fail(e, "truncated: no BIN chunk");
	bl = le32(b + 20 + jl);
	if (memcmp(b + 24 + jl, "BIN\0", 4) || bl > len - 28 - jl || bl % 4)
		return tl_fail(e, "truncated: BIN chunk of %u bytes, %zu left "
		    "(padded to 4)", bl, len - 28 - jl);
	d->g = tl_json_parse((const char *)b + 20, jl, &je, &oom);
	if (d->g == NULL)
		return tl_fail(e, "JSON chunk: %s", oom ? "out of memory" :
		    je.text);
	d->bin = b + 28 + jl, d->binlen = bl;
	b0 = json_array_get(json_object_get(d->g, "buffers"), 0);
	if (member(b0, "byteLength", -1, MAXBYTES, &blen) == 0 &&
	    (size_t)blen > bl)
		return tl_fail(e, "truncated: buffers[0] has %lld bytes, the "
		    "BIN chunk %u", blen, bl);
	if (member(b0, "byteLength", -1, MAXBYTES, &blen) < 0 ||
	    json_object_get(b0, "uri") != NULL || bl - (size_t)blen > 3)
		return tl_fail(e, "buffers[0]: not the BIN chunk's %u bytes "
		    "(byteLength up to 3 less, no uri)", bl);
	d->buflen = (size_t)blen;
	return 0;
}

int
t3c_decode(const unsigned char *b, size_t len, t3c_tile *t, tl_err *e)
{
	doc d = { NULL, NULL, 0, 0 };
	int r;

	memset(t, 0, sizeof *t);
	r = container(b, len, &d, e) < 0 || gltf(&d, t, e) < 0 ? -1 : 0;
	json_decref(d.g);
	return r;
}

int
t3c_read(const char *path, t3c_tile *t, tl_err *e)
{
	struct stat st;
	unsigned char *b;
	ssize_t got;
	size_t n = 0;
	int fd, r;

	memset(t, 0, sizeof *t);
	if ((fd = tl_open_regular(path, e)) < 0)
		return -1;
	if (fstat(fd, &st) < 0 || st.st_size > MAXBYTES ||
	    (b = malloc((size_t)st.st_size + 1)) == NULL) {
		close(fd);
		return tl_fail(e, "%s: unreadable, over 1 GiB or out of "
		    "memory", path);
	}
	while (n < (size_t)st.st_size &&
	    (got = read(fd, b + n, (size_t)st.st_size - n)) > 0)
		n += (size_t)got;
	close(fd);
	r = t3c_decode(b, n, t, e);
	free(b);
	return r;
}

void
t3c_free(t3c_tile *t)
{
	free(t->p), free(t->nrm), free(t->idx);
	for (int k = 0; k < 4; k++)
		free(t->edge[k]);
	memset(t, 0, sizeof *t);
}
