/* glb.c - a binary glTF 2.0 of one indexed triangle mesh: POSITION and
 * NORMAL (float32, interleaving none), uint16 indices, one grey material
 * lit by its normals, drawn from both sides (skirts). Little-endian hosts
 * (the file is little-endian). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/json.h"
#include "tiles3d/t3_impl.h"

#define GLB_MAGIC 0x46546C67u
#define CHUNK_JSON 0x4E4F534Au
#define CHUNK_BIN 0x004E4942u

static json_t *
view(size_t off, size_t len, int target)
{
	return json_pack("{s:i, s:I, s:I, s:i}", "buffer", 0, "byteOffset",
	    (json_int_t)off, "byteLength", (json_int_t)len, "target", target);
}

static json_t *
vec3(int view, int n, const float *v)
{
	json_t *a = json_pack("{s:i, s:i, s:i, s:s}", "bufferView", view,
	    "componentType", 5126, "count", n, "type", "VEC3");
	json_t *lo = json_array(), *hi = json_array();

	for (int q = 0; q < 3; q++) {
		float mn = INFINITY, mx = -INFINITY;
		for (int k = 0; k < n; k++)
			mn = fminf(mn, v[3 * k + q]), mx = fmaxf(mx, v[3 * k + q]);
		json_array_append_new(lo, json_real(mn));
		json_array_append_new(hi, json_real(mx));
	}
	json_object_set_new(a, "min", lo);
	json_object_set_new(a, "max", hi);
	return a;
}

static json_t *
gltf(int nv, const float *pos, int ni, size_t bin)
{
	size_t vb = (size_t)nv * 12;
	json_t *j = json_pack("{s:{s:s, s:s}, s:i, s:[{s:[i]}], s:[{s:i}],"
	    "s:[{s:[{s:{s:i, s:i}, s:i, s:i, s:i}]}],"
	    "s:[{s:{s:[f, f, f, f], s:f, s:f}, s:b}], s:[{s:I}]}",
	    "asset", "version", "2.0", "generator", "vgis2tiles",
	    "scene", 0, "scenes", "nodes", 0, "nodes", "mesh", 0,
	    "meshes", "primitives", "attributes", "POSITION", 0, "NORMAL", 1,
	    "indices", 2, "material", 0, "mode", 4,
	    "materials", "pbrMetallicRoughness", "baseColorFactor", 0.8, 0.8,
	    0.8, 1.0, "metallicFactor", 0.0, "roughnessFactor", 1.0,
	    "doubleSided", 1, "buffers", "byteLength", (json_int_t)bin);

	if (j == NULL)
		return NULL;
	json_object_set_new(j, "bufferViews", json_pack("[o, o, o]",
	    view(0, vb, 34962), view(vb, vb, 34962),
	    view(2 * vb, (size_t)ni * 2, 34963)));
	json_object_set_new(j, "accessors", json_pack("[o, o, {s:i, s:i, "
	    "s:i, s:s}]", vec3(0, nv, pos), json_pack("{s:i, s:i, s:i, s:s}",
	    "bufferView", 1, "componentType", 5126, "count", nv, "type",
	    "VEC3"), "bufferView", 2, "componentType", 5123, "count", ni,
	    "type", "SCALAR"));
	return j;
}

static int
put32(FILE *f, uint32_t v)
{
	return fwrite(&v, 4, 1, f) == 1 ? 0 : -1;
}

int
t3_glb_write(FILE *f, const float *pos, const float *nrm, int nv,
    const uint16_t *idx, int ni, long long *bytes, tl_err *e)
{
	size_t vb = (size_t)nv * 12, ib = (size_t)ni * 2;
	size_t bin = (2 * vb + ib + 3) & ~(size_t)3, jl, total;
	static const char pad[4] = { 0, 0, 0, 0 }, sp[4] = "   ";
	json_t *j = gltf(nv, pos, ni, bin);
	char *js = j ? json_dumps(j, JSON_COMPACT | JSON_SORT_KEYS) : NULL;
	int r = -1;

	json_decref(j);
	if (js == NULL)
		return tl_fail(e, "glTF: out of memory for its JSON");
	jl = strlen(js);
	total = 12 + 8 + ((jl + 3) & ~(size_t)3) + 8 + bin;
	if (put32(f, GLB_MAGIC) || put32(f, 2) || put32(f, (uint32_t)total) ||
	    put32(f, (uint32_t)((jl + 3) & ~(size_t)3)) ||
	    put32(f, CHUNK_JSON) || fwrite(js, 1, jl, f) != jl ||
	    fwrite(sp, 1, ((jl + 3) & ~(size_t)3) - jl, f) !=
	    ((jl + 3) & ~(size_t)3) - jl || put32(f, (uint32_t)bin) ||
	    put32(f, CHUNK_BIN) || fwrite(pos, 4, 3 * (size_t)nv, f) !=
	    3 * (size_t)nv || fwrite(nrm, 4, 3 * (size_t)nv, f) !=
	    3 * (size_t)nv || fwrite(idx, 2, (size_t)ni, f) != (size_t)ni ||
	    fwrite(pad, 1, bin - 2 * vb - ib, f) != bin - 2 * vb - ib)
		tl_failsys(e, "write");
	else
		r = 0, *bytes = (long long)total;
	free(js);
	return r;
}
