/* t3t_tileset.c - the 3D Tiles terrain profile's tree (t3t.h): the
 * directories and paths of the two roots, each tile's metadata until the
 * end, then per root the subtree files (3D Tiles 1.1 implicit tiling:
 * "subt" header, JSON, binary; availability bitstreams in Morton order,
 * a property table of the class "tile" over the available tiles, in that
 * order) and tileset.json with the metadata schema the provider reads by
 * semantic. Availability is each level's rectangle, as layer.json's. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "terrain/t3t.h"

#define NMETA 9

struct t3t_set {
	int maxz;
	int av[TR_MAXZ + 1][4];
	double *meta[TR_MAXZ + 1];
};

t3t_set *
t3t_new(int maxz, const int (*av)[4], tl_err *e)
{
	t3t_set *s = tl_alloc(1, sizeof *s, e);

	if (s == NULL)
		return NULL;
	s->maxz = maxz;
	for (int z = 0; z <= maxz; z++) {
		size_t n = (size_t)(av[z][2] - av[z][0] + 1) *
		    (size_t)(av[z][3] - av[z][1] + 1);
		memcpy(s->av[z], av[z], sizeof s->av[z]);
		if ((s->meta[z] = tl_alloc(n * NMETA, sizeof(double), e)) ==
		    NULL) {
			t3t_free(s);
			return NULL;
		}
	}
	return s;
}

void
t3t_free(t3t_set *s)
{
	if (s == NULL)
		return;
	for (int z = 0; z <= s->maxz; z++)
		free(s->meta[z]);
	free(s);
}

double *
t3t_meta(t3t_set *s, int z, int x, int y)
{
	const int *a = s->av[z];

	return s->meta[z] + NMETA * ((size_t)(y - a[1]) *
	    (size_t)(a[2] - a[0] + 1) + (size_t)(x - a[0]));
}

void
t3t_path(char *p, size_t n, const char *tmp, int z, int x, int y)
{
	snprintf(p, n, "%s/r%d/%d/%d/%d.glb", tmp, x >> z, z,
	    x & ((1 << z) - 1), y);
}

static int
mk(const char *p, tl_err *e)
{
	if (mkdir(p, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", p);
	return 0;
}

int
t3t_dirs(const char *tmp, int z, const int av[4], tl_err *e)
{
	char p[4096];

	for (int x = av[0]; x <= av[2]; x++) {
		int r = x >> z;
		snprintf(p, sizeof p, "%s/r%d", tmp, r);
		if (mk(p, e) < 0)
			return -1;
		snprintf(p, sizeof p, "%s/r%d/%d", tmp, r, z);
		if (mk(p, e) < 0)
			return -1;
		snprintf(p, sizeof p, "%s/r%d/%d/%d", tmp, r, z,
		    x & ((1 << z) - 1));
		if (mk(p, e) < 0)
			return -1;
	}
	return 0;
}

/* Is tile (z, local x, y) of root r written? */
static int
avail(const t3t_set *s, int r, int z, int x, int y)
{
	const int *a;

	if (z > s->maxz)
		return 0;
	a = s->av[z];
	x += r << z;
	return x >= a[0] && x <= a[2] && y >= a[1] && y <= a[3];
}

static uint32_t
unmorton(uint32_t m, int odd)
{
	uint32_t v = 0;

	for (int b = 0; b < 16; b++)
		v |= ((m >> (2 * b + odd)) & 1) << b;
	return v;
}

/* A subtree's availability: bits, how many set, of how many. */
typedef struct {
	unsigned char *bits;
	size_t n, set;
} bitset;

/* "constant": 0 or 1 when every bit agrees, else bitstream view v. */
static int
avail_json(char *j, size_t cap, const bitset *b, int v)
{
	if (b->set == 0 || b->set == b->n)
		return snprintf(j, cap, "{\"constant\":%d}", b->set != 0);
	return snprintf(j, cap, "{\"bitstream\":%d,\"availableCount\":%zu}", v,
	    b->set);
}

static void
put_u64(unsigned char *b, uint64_t v)
{
	for (int i = 0; i < 8; i++)
		b[i] = (unsigned char)(v >> (8 * i));
}

/* The bytes of the subtree: views of the two bitstreams (when not
 * constant) and the four metadata columns, each 8-aligned. */
static int
subtree_write(FILE *f, const bitset *tb, const bitset *cb, const double *md,
    size_t na, tl_err *e)
{
	size_t len[6] = { tb->set % tb->n ? (tb->n + 7) / 8 : 0,
		cb->set % cb->n ? (cb->n + 7) / 8 : 0, 8 * na, 8 * na,
		32 * na, 24 * na }, off[6], nbin = 0;
	const int col[4] = { 0, 1, 2, 6 }, width[4] = { 1, 1, 4, 3 };
	int view[6], nview = 0, nj;
	char j[2048], ta[64], ca[64];
	unsigned char *bin, h[24];

	for (int k = 0; k < 6; k++) {
		view[k] = len[k] ? nview++ : -1;
		off[k] = nbin, nbin += (len[k] + 7) & ~(size_t)7;
	}
	if ((bin = calloc(1, nbin + 1)) == NULL)
		return tl_fail(e, "subtree: out of memory");
	memcpy(bin + off[0], tb->bits, len[0]);
	memcpy(bin + off[1], cb->bits, len[1]);
	for (int c = 0; c < 4; c++)
		for (size_t t = 0; t < na; t++)
			for (int k = 0; k < width[c]; k++) {
				uint64_t v;
				memcpy(&v, md + NMETA * t + col[c] + k, 8);
				put_u64(bin + off[2 + c] + 8 * (width[c] * t +
				    (size_t)k), v);
			}
	avail_json(ta, sizeof ta, tb, view[0]);
	avail_json(ca, sizeof ca, cb, view[1]);
	nj = snprintf(j, sizeof j, "{\"buffers\":[{\"byteLength\":%zu}],"
	    "\"bufferViews\":[", nbin);
	for (int k = 0; k < 6; k++)
		if (len[k])
			nj += snprintf(j + nj, sizeof j - (size_t)nj, "%s{"
			    "\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":"
			    "%zu}", view[k] ? "," : "", off[k], len[k]);
	nj += snprintf(j + nj, sizeof j - (size_t)nj, "],\"propertyTables\":"
	    "[{\"class\":\"tile\",\"count\":%zu,\"properties\":{"
	    "\"minimumHeight\":{\"values\":%d},\"maximumHeight\":{\"values\":"
	    "%d},\"boundingSphere\":{\"values\":%d},\"horizonOcclusionPoint\":"
	    "{\"values\":%d}}}],\"tileAvailability\":%s,\"contentAvailability\""
	    ":[%s],\"childSubtreeAvailability\":%s,\"tileMetadata\":0}", na,
	    view[2], view[3], view[4], view[5], ta, ta, ca);
	while (nj % 8)
		j[nj++] = ' ';
	memcpy(h, "subt", 4), h[4] = 1, h[5] = h[6] = h[7] = 0;
	put_u64(h + 8, (uint64_t)nj), put_u64(h + 16, nbin);
	if (fwrite(h, 1, 24, f) != 24 || fwrite(j, 1, (size_t)nj, f) !=
	    (size_t)nj || fwrite(bin, 1, nbin, f) != nbin) {
		free(bin);
		return tl_fail(e, "subtree: write failed");
	}
	free(bin);
	return 0;
}

/* Subtree (s, sx, sy) of root r into dir/r{r}/{s}/{sx}/{sy}.subtree. */
static int
subtree(t3t_set *s, const char *dir, int r, int lv, int sx, int sy,
    tl_err *e)
{
	const int K = T3T_SUBLEVELS;
	bitset tb = { NULL, ((size_t)1 << 2 * K) / 3, 0 };
	bitset cb = { NULL, (size_t)1 << 2 * K, 0 };
	double *md = malloc(NMETA * sizeof *md * tb.n);
	char p[4096];
	FILE *f;
	int rc = -1;

	tb.bits = calloc(1, tb.n / 8 + 1), cb.bits = calloc(1, cb.n / 8 + 1);
	if (md == NULL || tb.bits == NULL || cb.bits == NULL) {
		tl_fail(e, "subtree: out of memory");
		goto done;
	}
	for (size_t i = 0, d = 0, first = 0; i < tb.n; i++) {
		uint32_t m;
		int x, y;
		if (i == first + ((size_t)1 << 2 * d))
			first = i, d++;
		m = (uint32_t)(i - first);
		x = (sx << d) + (int)unmorton(m, 0);
		y = (sy << d) + (int)unmorton(m, 1);
		if (!avail(s, r, lv + (int)d, x, y))
			continue;
		tb.bits[i / 8] |= (unsigned char)(1 << i % 8);
		memcpy(md + NMETA * tb.set++, t3t_meta(s, lv + (int)d,
		    x + (r << (lv + (int)d)), y), NMETA * sizeof *md);
	}
	for (size_t i = 0; i < cb.n; i++)
		if (avail(s, r, lv + K, (sx << K) + (int)unmorton((uint32_t)i,
		    0), (sy << K) + (int)unmorton((uint32_t)i, 1)))
			cb.bits[i / 8] |= (unsigned char)(1 << i % 8), cb.set++;
	snprintf(p, sizeof p, "%s/r%d/%d/%d/%d.subtree", dir, r, lv, sx, sy);
	if ((f = fopen(p, "wb")) == NULL) {
		tl_failsys(e, "%s", p);
		goto done;
	}
	rc = subtree_write(f, &tb, &cb, md, tb.set, e);
	if (fclose(f) != 0 && rc == 0)
		rc = tl_failsys(e, "%s", p);
done:
	free(md), free(tb.bits), free(cb.bits);
	return rc;
}

static void
root_json(FILE *f, int r, int maxz, const double h[2])
{
	fprintf(f, "{\"boundingVolume\":{\"region\":[%.17g,%.17g,%.17g,%.17g,"
	    "%.17g,%.17g]},\"geometricError\":%.2f,\"refine\":\"REPLACE\","
	    "\"content\":{\"uri\":\"r%d/{level}/{x}/{y}.glb\"},"
	    "\"implicitTiling\":{\"subdivisionScheme\":\"QUADTREE\","
	    "\"subtreeLevels\":%d,\"availableLevels\":%d,\"subtrees\":{\"uri\":"
	    "\"r%d/{level}/{x}/{y}.subtree\"}}}", r ? 0 : -M_PI, -M_PI / 2,
	    r ? M_PI : 0, M_PI / 2, h[0], h[1], T3T_E0, r, T3T_SUBLEVELS,
	    maxz + 1, r);
}

static const char schema[] =
    "{\"id\":\"terrain\",\"classes\":{\"tile\":{\"properties\":{"
    "\"minimumHeight\":{\"type\":\"SCALAR\",\"componentType\":\"FLOAT64\","
    "\"semantic\":\"TILE_MINIMUM_HEIGHT\"},\"maximumHeight\":{\"type\":"
    "\"SCALAR\",\"componentType\":\"FLOAT64\",\"semantic\":"
    "\"TILE_MAXIMUM_HEIGHT\"},\"boundingSphere\":{\"type\":\"SCALAR\","
    "\"componentType\":\"FLOAT64\",\"array\":true,\"count\":4,\"semantic\":"
    "\"TILE_BOUNDING_SPHERE\"},\"horizonOcclusionPoint\":{\"type\":"
    "\"VEC3\",\"componentType\":\"FLOAT64\",\"semantic\":"
    "\"TILE_HORIZON_OCCLUSION_POINT\"}}}}}";

/* s as a JSON string's characters. */
static void
put_str(FILE *f, const char *s)
{
	for (; *s; s++)
		if (*s == '"' || *s == '\\')
			fprintf(f, "\\%c", *s);
		else if ((unsigned char)*s < 0x20)
			fprintf(f, "\\u%04x", (unsigned char)*s);
		else
			fputc(*s, f);
}

static int
tileset(t3t_set *s, const char *dir, const tr_args *a, const char *datum,
    tl_err *e)
{
	double h[2] = { 0, 0 }; /* the ellipsoid past the DEM: height 0 */
	char p[4096];
	FILE *f;
	int bad;

	for (int z = 0; z <= s->maxz; z++) {
		const int *v = s->av[z];
		size_t n = (size_t)(v[2] - v[0] + 1) * (size_t)(v[3] - v[1] + 1);
		for (size_t t = 0; t < n; t++)
			h[0] = fmin(h[0], s->meta[z][NMETA * t]),
			h[1] = fmax(h[1], s->meta[z][NMETA * t + 1]);
	}
	snprintf(p, sizeof p, "%s/tileset.json", dir);
	if ((f = fopen(p, "w")) == NULL)
		return tl_failsys(e, "%s", p);
	fputs("{\"asset\":{\"version\":\"1.1\",\"generator\":"
	    "\"vgis2terrain\"},\"extras\":{\"description\":\"heights: ", f);
	put_str(f, datum);
	fputs("; every tile of level L within 77067.34 m / 2^L of every "
	    "valid DEM sample\"", f);
	if (a->attrib) {
		fputs(",\"attribution\":\"", f);
		put_str(f, a->attrib);
		fputc('"', f);
	}
	fprintf(f, "},\"schema\":%s,\"geometricError\":%.2f,\"root\":{"
	    "\"boundingVolume\":{\"region\":[%.17g,%.17g,%.17g,%.17g,%.17g,"
	    "%.17g]},\"geometricError\":%.2f,\"refine\":\"REPLACE\","
	    "\"children\":[", schema,
	    2 * T3T_E0, -M_PI, -M_PI / 2, M_PI, M_PI / 2, h[0], h[1],
	    2 * T3T_E0);
	root_json(f, 0, s->maxz, h);
	fputc(',', f);
	root_json(f, 1, s->maxz, h);
	fputs("]}}\n", f);
	bad = ferror(f);
	if (fclose(f) != 0 || bad)
		return tl_failsys(e, "%s", p);
	return 0;
}

int
t3t_finish(t3t_set *s, const char *dir, const tr_args *a, const char *datum,
    tl_err *e)
{
	for (int lv = 0; lv <= s->maxz; lv += T3T_SUBLEVELS)
		for (int r = 0; r < 2; r++)
			for (int y = s->av[lv][1]; y <= s->av[lv][3]; y++)
				for (int x = s->av[lv][0]; x <= s->av[lv][2];
				    x++)
					if (x >> lv == r && subtree(s, dir, r,
					    lv, x & ((1 << lv) - 1), y, e) < 0)
						return -1;
	return tileset(s, dir, a, datum, e);
}
