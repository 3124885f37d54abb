/* t3t_glb.c - one tile of the 3D Tiles terrain profile as a glb (t3t.h):
 * the quantised tile's decoded ECEF vertices (w->pos, the same surface as
 * its .terrain) as float offsets from the centre of its bounding sphere,
 * the node's matrix Z_UP_TO_Y_UP * translate(centre), which
 * Cesium3DTilesTerrainGeometryProcessor undoes with Y_UP_TO_Z_UP; smooth
 * ECEF normals, as that processor reads them (untransformed); the
 * triangles (counter-clockwise); CESIUM_tile_edges' four lists in the
 * order CesiumJS's skirts walk them (west south to north, south east to
 * west, east north to south, north west to east). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/t3t.h"

/* Keys (coordinate << 32 | vertex) of the vertices with a[] == val. */
static int
cmp64(const void *a, const void *b)
{
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;

	return x < y ? -1 : x > y;
}

static int
edge(const tr_work *w, const uint16_t *a, int val, const uint16_t *along,
    int down, uint32_t *out)
{
	int n = 0;
	uint64_t *k = (uint64_t *)out; /* out has room for 2 nv words */

	for (int i = 0; i < w->m.nv; i++)
		if (a[i] == val) {
			uint64_t c = down ? QM_MAX - along[i] : along[i];
			k[n++] = c << 32 | (uint32_t)i;
		}
	qsort(k, (size_t)n, sizeof *k, cmp64);
	for (int i = 0; i < n; i++)
		out[i] = (uint32_t)(k[i] & 0xffffffffu);
	return n;
}

/* Sphere (centre, radius) and horizon point as the .terrain header's. */
static void
bounds(const tr_work *w, double *meta)
{
	int n = w->m.nv;
	double lo[3] = { INFINITY, INFINITY, INFINITY }, *c = meta + 2, r = 0;

	for (int k = 0; k < 3; k++) {
		double hi = -INFINITY;
		for (int i = 0; i < n; i++) {
			lo[k] = fmin(lo[k], w->pos[3 * i + k]);
			hi = fmax(hi, w->pos[3 * i + k]);
		}
		c[k] = 0.5 * (lo[k] + hi);
	}
	for (int i = 0; i < n; i++) {
		const double *p = w->pos + 3 * i;
		r = fmax(r, sqrt((p[0] - c[0]) * (p[0] - c[0]) +
		    (p[1] - c[1]) * (p[1] - c[1]) +
		    (p[2] - c[2]) * (p[2] - c[2])));
	}
	meta[5] = r * (1 + 1e-9) + 1e-3;
	/* a root tile has no point seeing every vertex: NaN, never
	 * culled, as qm_encode writes it */
	if (qm_horizon(c, w->pos, n, meta + 6) < 0)
		meta[6] = meta[7] = meta[8] = NAN;
}

static void
normals(const tr_work *w, float *out)
{
	double *nr = tr_area_normals(&w->m, w->pos);

	for (int i = 0; i < w->m.nv; i++) {
		const double *p = nr ? nr + 3 * i : w->pos + 3 * i;
		double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
		if (!(l > 0)) /* no triangle: radial */
			p = w->pos + 3 * i, l = sqrt(p[0] * p[0] +
			    p[1] * p[1] + p[2] * p[2]);
		for (int d = 0; d < 3; d++)
			out[3 * i + d] = (float)(p[d] / l);
	}
	free(nr);
}

/* The binary chunk's parts, each 4-aligned: positions, normals,
 * triangles, the four edges. */
typedef struct {
	size_t off[7], len[7];
	int count[7];
} layout;

static size_t
pad4(size_t n)
{
	return (n + 3) & ~(size_t)3;
}

static int
json(char *j, size_t cap, const layout *l, int wide, const double c[3],
    const float lo[3], const float hi[3], size_t nbin)
{
	int ct = wide ? 5125 : 5123, n;

	n = snprintf(j, cap, "{\"asset\":{\"version\":\"2.0\",\"generator\":"
	    "\"vgis2terrain\"},\"extensionsUsed\":[\"CESIUM_tile_edges\"],"
	    "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,"
	    "\"matrix\":[1,0,0,0,0,0,-1,0,0,1,0,0,%.17g,%.17g,%.17g,1]}],"
	    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,"
	    "\"NORMAL\":1},\"indices\":2,\"mode\":4,\"extensions\":"
	    "{\"CESIUM_tile_edges\":{\"left\":3,\"bottom\":4,\"right\":5,"
	    "\"top\":6}}}]}],\"buffers\":[{\"byteLength\":%zu}],"
	    "\"bufferViews\":[", c[0], c[2], -c[1], nbin);
	for (int k = 0; k < 7 && n > 0 && (size_t)n < cap; k++)
		n += snprintf(j + n, cap - (size_t)n, "%s{\"buffer\":0,"
		    "\"byteOffset\":%zu,\"byteLength\":%zu%s}", k ? "," : "",
		    l->off[k], l->len[k], k < 2 ? ",\"target\":34962" :
		    k == 2 ? ",\"target\":34963" : "");
	if (n > 0 && (size_t)n < cap)
		n += snprintf(j + n, cap - (size_t)n, "],\"accessors\":[{"
		    "\"bufferView\":0,\"componentType\":5126,\"count\":%d,"
		    "\"type\":\"VEC3\",\"min\":[%.17g,%.17g,%.17g],\"max\":"
		    "[%.17g,%.17g,%.17g]},{\"bufferView\":1,\"componentType\":"
		    "5126,\"count\":%d,\"type\":\"VEC3\"}", l->count[0],
		    (double)lo[0], (double)lo[1], (double)lo[2], (double)hi[0],
		    (double)hi[1], (double)hi[2], l->count[1]);
	for (int k = 2; k < 7 && n > 0 && (size_t)n < cap; k++)
		n += snprintf(j + n, cap - (size_t)n, ",{\"bufferView\":%d,"
		    "\"componentType\":%d,\"count\":%d,\"type\":\"SCALAR\"}", k,
		    ct, l->count[k]);
	if (n > 0 && (size_t)n < cap)
		n += snprintf(j + n, cap - (size_t)n, "]}");
	return n > 0 && (size_t)n < cap ? n : -1;
}

static void
put32(unsigned char *b, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		b[i] = (unsigned char)(v >> (8 * i));
}

/* Indices a[0 .. n) into b as 16 or 32 bits, little-endian. */
static void
put_index(unsigned char *b, const uint32_t *a, int n, int wide)
{
	for (int i = 0; i < n; i++)
		if (wide)
			put32(b + 4 * i, a[i]);
		else
			b[2 * i] = (unsigned char)a[i],
			b[2 * i + 1] = (unsigned char)(a[i] >> 8);
}

/* Positions and normals (float, little-endian) into bin; their extremes. */
static void
put_vertices(const tr_work *w, const double c[3], const float *nrm,
    unsigned char *bin, const layout *l, float lo[3], float hi[3])
{
	for (int k = 0; k < 3; k++)
		lo[k] = INFINITY, hi[k] = -INFINITY;
	for (int i = 0; i < w->m.nv; i++)
		for (int k = 0; k < 3; k++) {
			float f = (float)(w->pos[3 * i + k] - c[k]);
			uint32_t b;
			lo[k] = fminf(lo[k], f), hi[k] = fmaxf(hi[k], f);
			memcpy(&b, &f, 4);
			put32(bin + l->off[0] + 12 * (size_t)i + 4 * k, b);
			memcpy(&b, nrm + 3 * i + k, 4);
			put32(bin + l->off[1] + 12 * (size_t)i + 4 * k, b);
		}
}

static int
assemble(tr_work *w, const double *meta, const uint32_t *ix,
    uint32_t *const ed[4], const int ne[4], const float *nrm, tl_err *e)
{
	int nv = w->m.nv, wide = nv > 65535, isz = wide ? 4 : 2, nj;
	layout l = { { 0 }, { 0 }, { nv, nv, 3 * w->m.nt, ne[0], ne[1], ne[2],
	    ne[3] } };
	size_t nbin = 0, total;
	char j[4096];
	float lo[3], hi[3];
	unsigned char *bin, *b;

	for (int k = 0; k < 7; k++) {
		l.off[k] = nbin;
		l.len[k] = (size_t)l.count[k] * (k < 2 ? 12 : (size_t)isz);
		nbin += pad4(l.len[k]);
	}
	if ((bin = calloc(1, nbin)) == NULL)
		return tl_fail(e, "tile: out of memory");
	put_vertices(w, meta + 2, nrm, bin, &l, lo, hi);
	put_index(bin + l.off[2], ix, l.count[2], wide);
	for (int k = 0; k < 4; k++)
		put_index(bin + l.off[3 + k], ed[k], ne[k], wide);
	if ((nj = json(j, sizeof j, &l, wide, meta + 2, lo, hi, nbin)) < 0) {
		free(bin);
		return tl_fail(e, "tile: glTF JSON too long");
	}
	total = 12 + 8 + pad4((size_t)nj) + 8 + nbin;
	if (total > w->cbuf && (b = realloc(w->buf, total)) != NULL)
		w->buf = b, w->cbuf = total;
	if (total > w->cbuf) {
		free(bin);
		return tl_fail(e, "tile: out of memory");
	}
	b = w->buf;
	memcpy(b, "glTF", 4), put32(b + 4, 2), put32(b + 8, (uint32_t)total);
	put32(b + 12, (uint32_t)pad4((size_t)nj)), memcpy(b + 16, "JSON", 4);
	memset(b + 20, ' ', pad4((size_t)nj)), memcpy(b + 20, j, (size_t)nj);
	b += 20 + pad4((size_t)nj);
	put32(b, (uint32_t)nbin), memcpy(b + 4, "BIN", 4), b[7] = 0;
	memcpy(b + 8, bin, nbin);
	w->nbuf = total;
	free(bin);
	return 0;
}

int
t3t_glb(tr_work *w, t3t_set *s, int z, int x, int y, float minh, float maxh,
    tl_err *e)
{
	int nv = w->m.nv, ne[4], r = -1;
	double *meta = t3t_meta(s, z, x, y);
	uint32_t *ix = malloc((3 * (size_t)w->m.nt + 1) * sizeof *ix);
	uint32_t *ed = malloc(4 * 2 * ((size_t)nv + 1) * sizeof *ed);
	float *nrm = malloc(3 * ((size_t)nv + 1) * sizeof *nrm);
	uint32_t *edp[4];

	if (ix == NULL || ed == NULL || nrm == NULL) {
		tl_fail(e, "tile: out of memory");
		goto done;
	}
	meta[0] = minh, meta[1] = maxh;
	bounds(w, meta);
	normals(w, nrm);
	for (int i = 0; i < 3 * w->m.nt; i++)
		ix[i] = (uint32_t)w->m.tri[i];
	for (int k = 0; k < 4; k++)
		edp[k] = ed + 2 * ((size_t)nv + 1) * (size_t)k;
	ne[0] = edge(w, w->u, 0, w->v, 0, edp[0]);
	ne[1] = edge(w, w->v, 0, w->u, 1, edp[1]);
	ne[2] = edge(w, w->u, QM_MAX, w->v, 1, edp[2]);
	ne[3] = edge(w, w->v, QM_MAX, w->u, 0, edp[3]);
	if (nv == 0 || w->m.nt == 0 || !ne[0] || !ne[1] || !ne[2] || !ne[3]) {
		tl_fail(e, "tile %d/%d/%d: no mesh or an edge without vertices",
		    z, x, y);
		goto done;
	}
	r = assemble(w, meta, ix, edp, ne, nrm, e);
done:
	free(ix), free(ed), free(nrm);
	return r;
}
