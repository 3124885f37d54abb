/* t_t3c - the 3D Tiles terrain reader of tilecheck (verify/t3c.h) on
 * glbs built here, by hand, from the glTF 2.0 specification (no
 * writer's code): a good tile of level 14 (four triangles round a centre
 * vertex, CESIUM_tile_edges, TILE_* metadata) decodes, is placed on its
 * rectangle and passes; one damage at a time to the container, the JSON,
 * the accessors or the metadata fails, with its own message or kind. */
#include "tap.h"

#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "geo/wgs84.h"
#include "verify/t3c.h"

#define Z 14
#define X 16429   /* lon 0.494 .. 0.505 (global x, from -180) */
#define Y 12072   /* lat 42.627 .. 42.638 */
#define H 100.0

static const double radii[3] = { 6378137.0, 6378137.0, 6356752.3142451793 };

enum {
	D_NONE, D_MAGIC, D_LENGTH, D_JSONPAD, D_STRIDE, D_ALIGN, D_MINMAX,
	D_MODE, D_NOEDGES, D_MATRIX, D_SPARSE, D_NAN, D_COUNT, D_INDEX
};

/* 0 SW, 1 SE, 2 NE, 3 NW, 4 the centre; ECEF into p. */
static void
vertices(double p[5][3])
{
	double r[4], uv[5][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 },
	    { 0.5, 0.5 } };

	qm_rect(Z, X, Y, r);
	for (int i = 0; i < 5; i++)
		geo_ecef(r[0] + uv[i][0] * (r[2] - r[0]), r[1] + uv[i][1] *
		    (r[3] - r[1]), H, p[i]);
}

static void
put32(unsigned char *b, uint32_t v)
{
	for (int k = 0; k < 4; k++)
		b[k] = (v >> (8 * k)) & 0xff;
}

static json_t *
accessor(int view, int ctype, const char *type, int count)
{
	return json_pack("{s:i, s:i, s:s, s:i}", "bufferView", view,
	    "componentType", ctype, "type", type, "count", count);
}

/* The glb, with damage d; *len its bytes. */
static unsigned char *
glb(int d, size_t *len)
{
	double p[5][3], c[3] = { 0, 0, 0 };
	float bin[128];
	uint16_t *ix = (uint16_t *)(bin + 30);
	static const uint16_t tri[12] = { 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4 };
	static const uint16_t edges[8] = { 0, 3, 1, 0, 2, 1, 3, 2 };
	json_t *g, *acc, *views, *m, *prim, *pos;
	float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3];
	char *js;
	size_t jl, bl = 30 * 4 + 12 * 2 + 8 * 2;
	unsigned char *out;

	vertices(p);
	for (int i = 0; i < 5; i++)
		for (int k = 0; k < 3; k++)
			c[k] += p[i][k] / 5;
	hi[0] = hi[1] = hi[2] = -INFINITY;
	for (int i = 0; i < 5; i++) {
		double q[3] = { p[i][0] - c[0], p[i][2] - c[2],
		    -(p[i][1] - c[1]) }, f[3], n[3];

		geo_ellipsoid(0.5, 42.632, f, n);
		for (int k = 0; k < 3; k++) {
			bin[3 * i + k] = (float)q[k];
			lo[k] = fminf(lo[k], bin[3 * i + k]);
			hi[k] = fmaxf(hi[k], bin[3 * i + k]);
			bin[15 + 3 * i + k] = (float)n[k];
		}
	}
	if (d == D_NAN)
		bin[4] = NAN;
	memcpy(ix, tri, sizeof tri);
	if (d == D_INDEX)
		ix[5] = 9;
	memcpy(ix + 12, edges, sizeof edges);
	views = json_array();
	json_array_append_new(views, json_pack("{s:i, s:i, s:i}", "buffer", 0,
	    "byteOffset", 0, "byteLength", 60));
	json_array_append_new(views, json_pack("{s:i, s:i, s:i}", "buffer", 0,
	    "byteOffset", 60, "byteLength", 60));
	json_array_append_new(views, json_pack("{s:i, s:i, s:i}", "buffer", 0,
	    "byteOffset", 120, "byteLength", 40));
	acc = json_array();
	json_array_append_new(acc, pos = accessor(0, 5126, "VEC3", d ==
	    D_COUNT ? 6 : 5));
	json_object_set_new(pos, "min", json_pack("[f, f, f]", lo[0],
	    lo[1] + (d == D_MINMAX), lo[2]));
	json_object_set_new(pos, "max", json_pack("[f, f, f]", hi[0], hi[1],
	    hi[2]));
	if (d == D_STRIDE)
		json_object_set_new(json_array_get(views, 0), "byteStride",
		    json_integer(16));
	if (d == D_ALIGN) {
		json_object_set_new(pos, "byteOffset", json_integer(2));
		json_object_set_new(json_array_get(views, 0), "byteLength",
		    json_integer(62));
	}
	if (d == D_SPARSE)
		json_object_set_new(pos, "sparse", json_object());
	json_array_append_new(acc, accessor(1, 5126, "VEC3", 5));
	json_array_append_new(acc, accessor(2, 5123, "SCALAR", 12));
	for (int k = 0; k < 4; k++) {
		json_t *a = accessor(2, 5123, "SCALAR", 2);

		json_object_set_new(a, "byteOffset", json_integer(24 + 4 * k));
		json_array_append_new(acc, a);
	}
	prim = json_pack("{s:{s:i, s:i}, s:i, s:i}", "attributes", "POSITION",
	    0, "NORMAL", 1, "indices", 2, "mode", d == D_MODE ? 1 : 4);
	if (d != D_NOEDGES)
		json_object_set_new(prim, "extensions", json_pack("{s:{s:i, s:i,"
		    " s:i, s:i}}", "CESIUM_tile_edges", "left", 3, "bottom", 4,
		    "right", 5, "top", 6));
	m = json_pack("[i,i,i,i, i,i,i,i, i,i,i,i, f,f,f,i]", 1, 0, 0, 0,
	    0, 1, 0, 0, 0, 0, 1, 0, c[0], c[2], -c[1], 1);
	g = json_pack("{s:{s:s}, s:[s], s:i, s:[{s:[i]}], s:[{s:i, s:o}], "
	    "s:[{s:[o]}], s:[{s:i}], s:o, s:o}", "asset", "version", "2.0",
	    "extensionsUsed", "CESIUM_tile_edges", "scene", 0, "scenes",
	    "nodes", 0, "nodes", "mesh", 0, "matrix", d == D_MATRIX ?
	    json_array() : m, "meshes", "primitives", prim, "buffers",
	    "byteLength", (int)bl, "bufferViews", views, "accessors", acc);
	if (d == D_MATRIX)
		json_decref(m);
	js = json_dumps(g, JSON_COMPACT);
	json_decref(g);
	jl = strlen(js);
	if (d != D_JSONPAD)
		jl = (jl + 3) & ~(size_t)3;
	*len = 28 + jl + bl;
	out = calloc(1, *len);
	memcpy(out, d == D_MAGIC ? "gltf" : "glTF", 4);
	put32(out + 4, 2);
	put32(out + 8, (uint32_t)*len + (d == D_LENGTH));
	put32(out + 12, (uint32_t)jl);
	memcpy(out + 16, "JSON", 4);
	memset(out + 20, ' ', jl);
	memcpy(out + 20, js, strlen(js));
	put32(out + 20 + jl, (uint32_t)bl);
	memcpy(out + 24 + jl, "BIN", 4);
	memcpy(out + 28 + jl, bin, bl);
	free(js);
	return out;
}

/* The tile's metadata from its vertices: the truth. */
static void
meta(t3c_meta *m)
{
	double p[5][3], d[3], l = 0, best = 0;

	vertices(p);
	m->hmin = m->hmax = H;
	memset(m->sphere, 0, sizeof m->sphere);
	for (int i = 0; i < 5; i++)
		for (int k = 0; k < 3; k++)
			m->sphere[k] += p[i][k] / 5;
	for (int i = 0; i < 5; i++)
		m->sphere[3] = fmax(m->sphere[3], sqrt(pow(p[i][0] -
		    m->sphere[0], 2) + pow(p[i][1] - m->sphere[1], 2) +
		    pow(p[i][2] - m->sphere[2], 2)) + 1e-3);
	for (int k = 0; k < 3; k++)
		d[k] = m->sphere[k] / radii[k], l += d[k] * d[k];
	for (int k = 0; k < 3; k++)
		d[k] /= sqrt(l);
	for (int i = 0; i < 5; i++)
		best = fmax(best, qm_horizon_magnitude(p[i], d, radii));
	for (int k = 0; k < 3; k++)
		m->hop[k] = d[k] * best * 1.0001;
}

static void
refused(int d, const char *what, const char *want)
{
	size_t len;
	unsigned char *b = glb(d, &len);
	t3c_tile t;
	tl_err e;
	int r = t3c_decode(b, len, &t, &e);

	ok(r < 0 && strstr(e.msg, want) != NULL, "%s: refused, \"%s\"",
	    what, r < 0 ? e.msg : "(decoded)");
	t3c_free(&t);
	free(b);
}

/* The good glb checked with metadata m (or damage dd): kind found. */
static void
flagged(const t3c_meta *m, int dd, int kind, const char *what)
{
	size_t len;
	unsigned char *b = glb(dd, &len);
	t3c_tile t;
	tl_err e;
	qm_report r;

	qm_report_init(&r);
	if (t3c_decode(b, len, &t, &e) == 0)
		t3c_tile_check(&t, m, Z, X, Y, &r);
	ok(r.count[kind] > 0, "%s: a %s violation (%lld in all)", what,
	    qm_kind_name(kind), r.total);
	qm_report_free(&r);
	t3c_free(&t);
	free(b);
}

int
main(void)
{
	size_t len;
	unsigned char *b = glb(D_NONE, &len);
	double uv[10], h[5];
	unsigned char pole[5];
	t3c_tile t;
	t3c_meta m, bad;
	qm_report r;
	tl_err e;
	int placed = 1;

	ok(fabs(t3c_level_error(0) - 78271.52) < 1e-9 &&
	    t3c_level_error(14) == 78271.52 / 16384, "E_L = 78271.52 m / 2^L");
	ok(t3c_decode(b, len, &t, &e) == 0 && t.n == 5 && t.ntri == 4 &&
	    t.nedge[QM_WEST] == 2 && t.nedge[QM_NORTH] == 2,
	    "a good glb decodes: 5 vertices, 4 triangles, edges of 2");
	t3c_place(&t, Z, X, Y, uv, h, pole);
	for (int i = 0; i < 4; i++)
		placed &= (uv[2 * i] == 0 || uv[2 * i] == QM_MAXQ) &&
		    (uv[2 * i + 1] == 0 || uv[2 * i + 1] == QM_MAXQ) &&
		    fabs(h[i] - H) < 1e-3 && !pole[i];
	ok(placed && fabs(uv[8] - QM_MAXQ / 2.0) < 0.01 && fabs(uv[9] -
	    QM_MAXQ / 2.0) < 0.01, "placed: corners on the rectangle's "
	    "corners, the centre at its middle, heights %.4f m", h[4]);
	meta(&m);
	qm_report_init(&r);
	t3c_tile_check(&t, &m, Z, X, Y, &r);
	ok(r.total == 0, "it passes every check (%lld violations%s%s)",
	    r.total, r.nissue ? ": " : "", r.nissue ? r.issue[0].text : "");
	qm_report_free(&r);
	t3c_free(&t);
	free(b);

	refused(D_MAGIC, "magic gltf", "not a glb");
	refused(D_LENGTH, "a length one past the file", "truncated");
	refused(D_JSONPAD, "a JSON chunk not padded to 4", "JSON chunk");
	refused(D_STRIDE, "POSITION's byteStride 16", "byteStride");
	refused(D_ALIGN, "POSITION at byte 2", "aligned");
	refused(D_MINMAX, "POSITION's min off by 1 m", "min, max");
	refused(D_MODE, "lines, not triangles", "mode");
	refused(D_NOEDGES, "no CESIUM_tile_edges", "CESIUM_tile_edges");
	refused(D_MATRIX, "no node matrix", "matrix");
	refused(D_SPARSE, "a sparse POSITION", "sparse");
	refused(D_NAN, "a position NaN", "not finite");
	refused(D_COUNT, "6 positions in a view of 5", "truncated");

	flagged(&m, D_INDEX, QM_INDEX, "an index past the vertices");
	bad = m, bad.hmin = H - 5;
	flagged(&bad, D_NONE, QM_HEIGHTS, "TILE_MINIMUM_HEIGHT 5 m low");
	bad = m, bad.sphere[3] -= 1;
	flagged(&bad, D_NONE, QM_SPHERE, "the sphere 1 m short");
	bad = m;
	for (int k = 0; k < 3; k++)
		bad.hop[k] = m.hop[k] / 1.0001 * (1 - 1e-7);
	flagged(&bad, D_NONE, QM_OCCLUSION, "the occlusion point 0.6 m under "
	    "a vertex's horizon");
	bad = m, bad.hmax = NAN;
	flagged(&bad, D_NONE, QM_HEADER, "a NaN maximum height");
	return tap_done();
}
