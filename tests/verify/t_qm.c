/* t_qm - the quantized-mesh checker (verify/qm.h) on tilesets encoded
 * here, by hand, from the quantized-mesh-1.0 specification: a tiny
 * encoder of its own (no writer's code), a good tileset over a small
 * geographic DEM that passes (with gzip'd, 32-bit and metadata tiles),
 * and one damage at a time, each failing with its own kind and message.
 * "t_qm --write DIR" writes the good tileset to DIR and exits (for
 * tests/cmd/t_qmdecode.sh, which decodes it with loaders.gl). */
#include "tap.h"
#include "tmpdir.h"

#include <math.h>
#include <stdint.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "geo/wgs84.h"
#include "verify/qm.h"

/* The DEM: a flat 100 m (ellipsoidal) over lon 1..1.1, lat 42..42.1. */
#define DW 41
#define LON0 1.0
#define LAT0 42.0
#define STEP 0.0025
#define DEMH 100.0
#define LEVELS 5

/* --- the encoder ---------------------------------------------------- */

typedef struct {
	int n, ntri;
	int *u, *v, *h;    /* 0..32767 */
	uint32_t *tri;     /* 3 ntri, vertex numbers in any order */
	double hmin, hmax;
} mesh;

enum {
	D_NONE, D_TRUNC, D_INDEX, D_EDGE, D_SPHERE, D_OCCL, D_CW, D_FLAT,
	D_HEIGHTS, D_HIGH, D_SEAM, D_HOLE
};

typedef struct {
	unsigned char *b;
	size_t n, cap;
} buf;

static void
put(buf *b, const void *p, size_t n)
{
	if (b->n + n > b->cap) {
		b->cap = 2 * (b->n + n);
		b->b = realloc(b->b, b->cap);
	}
	memcpy(b->b + b->n, p, n);
	b->n += n;
}

static void
put16(buf *b, unsigned v)
{
	unsigned char c[2] = { v & 0xff, (v >> 8) & 0xff };

	put(b, c, 2);
}

static void
put32(buf *b, uint32_t v)
{
	unsigned char c[4] = { v & 0xff, (v >> 8) & 0xff, (v >> 16) & 0xff,
	    v >> 24 };

	put(b, c, 4);
}

static void
putd(buf *b, double d)
{
	uint64_t u;

	memcpy(&u, &d, 8);
	put32(b, (uint32_t)u), put32(b, (uint32_t)(u >> 32));
}

static void
putf(buf *b, float f)
{
	uint32_t u;

	memcpy(&u, &f, 4);
	put32(b, u);
}

static void
ecef_of(const mesh *m, const double r[4], int i, double p[3])
{
	double u = m->u[i] / 32767.0, v = m->v[i] / 32767.0;
	double h = m->h[i] / 32767.0;

	geo_ecef((1 - u) * r[0] + u * r[2], (1 - v) * r[1] + v * r[3],
	    (1 - h) * m->hmin + h * m->hmax, p);
}

/* CesiumJS's horizon magnitude, written again from its description. */
static double
magnitude(const double p[3], const double d[3])
{
	const double R[3] = { 6378137.0, 6378137.0, 6356752.3142451793 };
	double s[3], len = 0, ca = 0, cr[3];

	for (int k = 0; k < 3; k++)
		s[k] = p[k] / R[k], len += s[k] * s[k];
	len = sqrt(len);
	for (int k = 0; k < 3; k++)
		s[k] /= len, ca += s[k] * d[k];
	cr[0] = s[1] * d[2] - s[2] * d[1], cr[1] = s[2] * d[0] - s[0] * d[2];
	cr[2] = s[0] * d[1] - s[1] * d[0];
	len = fmax(len, 1);
	return 1 / (ca / len - sqrt(cr[0] * cr[0] + cr[1] * cr[1] +
	    cr[2] * cr[2]) * sqrt(len * len - 1) / len);
}

static void
header(buf *b, const mesh *m, const double r[4], int damage)
{
	const double R[3] = { 6378137.0, 6378137.0, 6356752.3142451793 };
	double c[3] = { 0, 0, 0 }, rad = 0, d[3], dl = 0, mag = 0, p[3];
	int ok = 1;

	for (int i = 0; i < m->n; i++) {
		ecef_of(m, r, i, p);
		for (int k = 0; k < 3; k++)
			c[k] += p[k] / m->n;
	}
	for (int i = 0; i < m->n; i++) {
		ecef_of(m, r, i, p);
		rad = fmax(rad, sqrt((p[0] - c[0]) * (p[0] - c[0]) +
		    (p[1] - c[1]) * (p[1] - c[1]) +
		    (p[2] - c[2]) * (p[2] - c[2])));
	}
	for (int k = 0; k < 3; k++)
		d[k] = c[k] / R[k], dl += d[k] * d[k];
	for (int k = 0; k < 3; k++)
		d[k] /= sqrt(dl);
	for (int i = 0; i < m->n; i++) {
		double g;

		ecef_of(m, r, i, p);
		g = magnitude(p, d);
		ok &= g > 0 && isfinite(g);
		mag = fmax(mag, g);
	}
	if (damage == D_OCCL)
		mag *= 0.99;
	for (int k = 0; k < 3; k++)
		putd(b, c[k]);
	putf(b, (float)m->hmin), putf(b, (float)m->hmax);
	for (int k = 0; k < 3; k++)
		putd(b, c[k]);
	putd(b, damage == D_SPHERE ? rad / 2 : rad + 1e-6);
	/* no finite point occludes a hemisphere: NaN, never culled */
	for (int k = 0; k < 3; k++)
		putd(b, ok ? d[k] * mag : NAN);
}

static unsigned
zz(int d)
{
	return ((unsigned)d << 1 ^ (unsigned)(d >> 31)) & 0xffff;
}

/* Vertices renumbered in the order the triangles first use them, so
 * that high-water marks can code them. */
static void
body(buf *b, const mesh *m, const double r[4], int damage, int normals)
{
	int *order = malloc(m->n * sizeof *order), *num = malloc(m->n *
	    sizeof *num), k = 0, big = m->n > 65536, prev[3] = { 0, 0, 0 };
	uint32_t highest = 0;

	for (int i = 0; i < m->n; i++)
		num[i] = -1;
	for (int i = 0; i < 3 * m->ntri; i++)
		if (num[m->tri[i]] < 0)
			order[k] = m->tri[i], num[m->tri[i]] = k++;
	for (int i = 0; i < m->n; i++)
		if (num[i] < 0)
			order[k] = i, num[i] = k++;
	put32(b, (uint32_t)m->n);
	for (int c = 0; c < 3; c++)
		for (int i = 0; i < m->n; i++) {
			const int *q = c == 0 ? m->u : c == 1 ? m->v : m->h;

			put16(b, zz(q[order[i]] - prev[c]));
			prev[c] = q[order[i]];
		}
	while (big && b->n % 4)
		put(b, "\0", 1);
	put32(b, (uint32_t)m->ntri);
	for (int i = 0; i < 3 * m->ntri; i++) {
		uint32_t v = (uint32_t)num[m->tri[i]], code = highest - v;

		if (v == highest)
			highest++;
		if (damage == D_INDEX && i == 3)
			code = highest + 5;
		big ? put32(b, code) : put16(b, code);
	}
	for (int s = 0; s < 4; s++) {
		uint32_t *list = malloc((m->n + 1) * sizeof *list);
		int cnt = 0, dropped = 0;

		for (int i = 0; i < m->n; i++) {
			int q = s == 0 || s == 2 ? m->u[order[i]] :
			    m->v[order[i]];

			if (q != (s < 2 ? 0 : 32767))
				continue;
			if (damage == D_EDGE && s == 0 && !dropped++)
				continue;
			list[cnt++] = (uint32_t)i;
		}
		put32(b, (uint32_t)cnt);
		for (int i = 0; i < cnt; i++)
			big ? put32(b, list[i]) : put16(b, list[i]);
		free(list);
	}
	if (normals) {
		put(b, "\1", 1);
		put32(b, 2 * (uint32_t)m->n);
		for (int i = 0; i < m->n; i++) {
			double p[3], foot[3], up[3], llh[2], s;
			double u = m->u[order[i]] / 32767.0;
			double v = m->v[order[i]] / 32767.0;
			unsigned char oct[2];

			llh[0] = (1 - u) * r[0] + u * r[2];
			llh[1] = (1 - v) * r[1] + v * r[3];
			geo_ellipsoid(llh[0], llh[1], foot, up);
			s = fabs(up[0]) + fabs(up[1]) + fabs(up[2]);
			p[0] = up[0] / s, p[1] = up[1] / s;
			if (up[2] < 0) {
				double x = p[0];

				p[0] = (1 - fabs(p[1])) * (x < 0 ? -1 : 1);
				p[1] = (1 - fabs(x)) * (p[1] < 0 ? -1 : 1);
			}
			for (int q = 0; q < 2; q++)
				oct[q] = (unsigned char)lround((p[q] * 0.5 +
				    0.5) * 255);
			put(b, oct, 2);
		}
	}
	free(order), free(num);
}

static void
metadata(buf *b, const char *json)
{
	put(b, "\4", 1);
	put32(b, 4 + (uint32_t)strlen(json));
	put32(b, (uint32_t)strlen(json));
	put(b, json, strlen(json));
}

/* Heights all over 0..32767 between -50 and 3000 m instead of flat. */
static int vary;

/* A k x k grid of cells over tile z/x/y, counter-clockwise, at height h. */
static void
grid_mesh(mesh *m, int k, double h, int damage)
{
	int n = 0;

	m->n = (k + 1) * (k + 1), m->ntri = 2 * k * k;
	m->u = malloc(m->n * sizeof *m->u), m->v = malloc(m->n * sizeof *m->v);
	m->h = calloc(m->n, sizeof *m->h);
	m->tri = malloc(3 * m->ntri * sizeof *m->tri);
	m->hmin = m->hmax = h;
	for (int j = 0; j <= k; j++)
		for (int i = 0; i <= k; i++) {
			m->u[j * (k + 1) + i] = (int)lround(i * 32767.0 / k);
			m->v[j * (k + 1) + i] = (int)lround(j * 32767.0 / k);
		}
	for (int j = 0; j < k; j++)
		for (int i = 0; i < k; i++) {
			uint32_t a = j * (k + 1) + i, b = a + 1, c = b + k + 1,
			    d = a + k + 1;
			uint32_t t[6] = { a, b, c, a, c, d };

			memcpy(m->tri + n, t, sizeof t), n += 6;
		}
	if (vary) { /* the same on the west and east edges: no seam */
		m->hmin = -50, m->hmax = 3000;
		for (int j = 0; j <= k; j++)
			for (int i = 0; i <= k; i++)
				m->h[j * (k + 1) + i] = j * 7919 % 16384 +
				    (i % k ? i * 104729 % 16384 : 0);
		m->h[0] = 0, m->h[1] = 32767;
	}
	if (damage == D_SEAM) { /* one west edge vertex raised 100 m */
		m->hmax = h + 100;
		m->h[5 * (k + 1)] = 32767;
	}
	if (damage == D_CW) {
		uint32_t s = m->tri[1];

		m->tri[1] = m->tri[2], m->tri[2] = s;
	}
	if (damage == D_HOLE)
		m->ntri--; /* the last cell's upper triangle */
	if (damage == D_FLAT)
		m->tri[2] = 2; /* (0,0) (1,0) (2,0): on one line */
	if (damage == D_HEIGHTS) {
		m->hmin = h - 50;
		for (int i = 0; i < m->n; i++)
			m->h[i] = 32767;
	}
}

static int
write_file(const char *path, const void *p, size_t n)
{
	FILE *f = fopen(path, "wb");
	int r = f != NULL && fwrite(p, 1, n, f) == n ? 0 : -1;

	if (f != NULL && fclose(f) != 0)
		r = -1;
	return r;
}

static int
gzip_file(const char *path, const buf *b)
{
	z_stream z;
	unsigned char out[1 << 16];
	buf o = { NULL, 0, 0 };
	int r;

	memset(&z, 0, sizeof z);
	deflateInit2(&z, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY);
	z.next_in = b->b, z.avail_in = (uInt)b->n;
	do {
		z.next_out = out, z.avail_out = sizeof out;
		r = deflate(&z, Z_FINISH);
		put(&o, out, sizeof out - z.avail_out);
	} while (r == Z_OK);
	deflateEnd(&z);
	r = write_file(path, o.b, o.n);
	free(o.b);
	return r;
}

/* The tile of level z holding the DEM (level 0: both roots). */
static void
tile_of(int z, int *x, int *y)
{
	double d = 180 / ldexp(1, z);

	*x = (int)floor((LON0 + 180) / d), *y = (int)floor((LAT0 + 90) / d);
}

/* Tile z/x/y of the good tileset (with damage) into b. */
static void
encode(buf *b, int z, int x, int y, int damage)
{
	double r[4], d = 180 / ldexp(1, z);
	int k = z == LEVELS - 1 ? 256 : 16, dx, dy;
	mesh m;

	r[0] = -180 + x * d, r[1] = -90 + y * d, r[2] = r[0] + d;
	r[3] = r[1] + d;
	grid_mesh(&m, k, damage == D_HIGH ? DEMH + 2 * qm_level_error(z) :
	    DEMH, damage);
	header(b, &m, r, damage);
	body(b, &m, r, damage, 1);
	tile_of(z + 1, &dx, &dy);
	if (z == 1) {
		char js[256];

		snprintf(js, sizeof js, "{\"available\":[[{\"startX\":%d,"
		    "\"startY\":%d,\"endX\":%d,\"endY\":%d}]]}", dx, dy, dx,
		    dy);
		metadata(b, js);
	}
	if (damage == D_TRUNC)
		b->n /= 2;
	free(m.u), free(m.v), free(m.h), free(m.tri);
}

static int
write_tile(const char *dir, int z, int x, int y, int damage)
{
	char path[PATH_MAX];
	buf b = { NULL, 0, 0 };
	int st;

	encode(&b, z, x, y, damage);
	snprintf(path, sizeof path, "%s/%d", dir, z);
	mkdir(path, 0777);
	snprintf(path, sizeof path, "%s/%d/%d", dir, z, x);
	mkdir(path, 0777);
	snprintf(path, sizeof path, "%s/%d/%d/%d.terrain", dir, z, x, y);
	st = z == 2 ? gzip_file(path, &b) : write_file(path, b.b, b.n);
	free(b.b);
	return st;
}

static int
write_layer(const char *dir, int skip_z)
{
	char path[PATH_MAX];
	FILE *f;
	int x, y;

	snprintf(path, sizeof path, "%s/layer.json", dir);
	if ((f = fopen(path, "w")) == NULL)
		return -1;
	fprintf(f, "{\"tilejson\":\"2.1.0\",\"name\":\"t_qm\","
	    "\"description\":\"hand-made\",\"version\":\"1.0.0\","
	    "\"format\":\"quantized-mesh-1.0\",\"scheme\":\"tms\","
	    "\"tiles\":[\"{z}/{x}/{y}.terrain?v={version}\"],"
	    "\"projection\":\"EPSG:4326\",\"bounds\":[-180,-90,180,90],"
	    "\"minzoom\":0,\"maxzoom\":%d,"
	    "\"extensions\":[\"octvertexnormals\",\"metadata\"],"
	    "\"available\":[[{\"startX\":0,\"startY\":0,\"endX\":1,"
	    "\"endY\":0}]", LEVELS - 1);
	for (int z = 1; z < LEVELS; z++) {
		tile_of(z, &x, &y);
		if (z == skip_z)
			fprintf(f, ",[]");
		else
			fprintf(f, ",[{\"startX\":%d,\"startY\":%d,\"endX\":%d,"
			    "\"endY\":%d}]", x, y, x, y);
	}
	fprintf(f, "]}\n");
	return fclose(f);
}

/* The good tileset, but for damage on tile 3/x/y. */
static int
write_set(const char *dir, int damage)
{
	int x, y, st = 0;

	mkdir(dir, 0777);
	st |= write_tile(dir, 0, 0, 0, D_NONE);
	st |= write_tile(dir, 0, 1, 0, damage == D_SEAM ? D_SEAM : D_NONE);
	for (int z = 1; z < LEVELS; z++) {
		tile_of(z, &x, &y);
		st |= write_tile(dir, z, x, y, (damage == D_HIGH ?
		    z == LEVELS - 1 : z == 3 && damage != D_SEAM) ? damage :
		    D_NONE);
	}
	return st | write_layer(dir, -1);
}

/* An Esri grid of DW x DW samples of DEMH (one void) whose first sample
 * centre is (x0, y0) south-west, step apart; with prj, a WGS 84 .prj. */
static int
write_asc(const char *path, double x0, double y0, double step, int prj)
{
	char name[PATH_MAX];
	FILE *f = fopen(path, "w");

	if (f == NULL)
		return -1;
	fprintf(f, "ncols %d\nnrows %d\nxllcorner %.6f\nyllcorner %.6f\n"
	    "cellsize %.6f\nNODATA_value -9999\n", DW, DW, x0 - step / 2,
	    y0 - step / 2, step);
	for (int j = 0; j < DW; j++)
		for (int i = 0; i < DW; i++)
			fprintf(f, "%s%s", i == 7 && j == 9 ? "-9999" : "100",
			    i == DW - 1 ? "\n" : " ");
	fclose(f);
	if (!prj)
		return 0;
	snprintf(name, sizeof name, "%.*s.prj", (int)strlen(path) - 4, path);
	if ((f = fopen(name, "w")) == NULL)
		return -1;
	fprintf(f, "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\","
	    "6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\","
	    "0.0174532925199433]]\n");
	return fclose(f);
}

static int
write_dem(const char *path)
{
	return write_asc(path, LON0, LAT0, STEP, 1);
}

/* --- the checks ----------------------------------------------------- */

static char top[PATH_MAX - 64];

static const char *
tmp(const char *name)
{
	return tmpdir_join(top, name);
}

static int
check(const char *dir, const char *dem_path, qm_report *r)
{
	qm_set s;
	tl_err e;
	dem_opts o;
	int st;

	memset(&o, 0, sizeof o);
	st = qm_check(dir, dem_path, &o, &s, r, &e);
	if (st < 0)
		printf("# cannot check: %s\n", e.msg);
	qm_set_free(&s);
	return st;
}

static void
show(const qm_report *r)
{
	for (int i = 0; i < r->nissue; i++)
		printf("#   %d/%d/%d: %s: %s\n", r->issue[i].z, r->issue[i].x,
		    r->issue[i].y, qm_kind_name(r->issue[i].kind),
		    r->issue[i].text);
}

static int
has(const qm_report *r, int kind, const char *text)
{
	for (int i = 0; i < r->nissue; i++)
		if (r->issue[i].kind == kind && strstr(r->issue[i].text, text))
			return 1;
	return 0;
}

/* dir fails with violations of kind, one saying text, and of no other
 * kind but hole when also (a triangle damaged opens or folds the mesh
 * too). */
static void
expect2(const char *dir, const char *dem_path, const char *what, int kind,
    const char *text, int also)
{
	qm_report r;
	int st = check(dir, dem_path, &r);
	long long other = r.total - r.count[kind] -
	    (also ? r.count[QM_HOLE] : 0);

	if (!ok(st == 0 && r.count[kind] > 0 && other == 0 &&
	    has(&r, kind, text), "%s: %s violations (%lld of %lld%s), "
	    "saying \"%s\"", what, qm_kind_name(kind), r.count[kind], r.total,
	    also ? ", the others holes" : "", text))
		show(&r);
	qm_report_free(&r);
}

static void
expect(const char *dir, const char *dem_path, const char *what, int kind,
    const char *text)
{
	expect2(dir, dem_path, what, kind, text, 0);
}

static void
expect_pass(const char *dir)
{
	qm_report r;

	write_set(dir, D_NONE);
	if (!ok(check(dir, NULL, &r) == 0 && r.total == 0, "heights all "
	    "over 0..32767: passes (%lld violations)", r.total))
		show(&r);
	qm_report_free(&r);
}

static void
good(const char *dir, const char *dem_path)
{
	qm_report r;
	int st = check(dir, NULL, &r), x, y;

	if (!ok(st == 0 && r.total == 0, "the hand-encoded tileset passes "
	    "(%lld violations)", r.total))
		show(&r);
	ok(r.maxz == LEVELS - 1 && r.lev[0].tiles == 2 &&
	    r.lev[LEVELS - 1].vertices == 257 * 257 &&
	    r.lev[LEVELS - 1].triangles == 2 * 256 * 256,
	    "levels 0..%d, both roots, a tile of %lld vertices (32-bit "
	    "indices)", r.maxz, r.lev[LEVELS - 1].vertices);
	ok(r.lev[2].gzip == 1, "the gzip'd tile of level 2 inflated");
	qm_report_free(&r);
	st = check(dir, dem_path, &r);
	if (!ok(st == 0 && r.total == 0, "against its DEM: within E_L at "
	    "every level (%lld violations)", r.total))
		show(&r);
	for (int z = 0; z < LEVELS; z++) {
		qm_level *L = &r.lev[z];
		double mx = 0;

		for (long i = 0; i < L->nratio; i++)
			mx = fmax(mx, L->ratio[i]);
		tile_of(z, &x, &y);
		ok(L->nratio == 1 && L->samples == DW * DW - 1 && mx > 0 &&
		    mx <= 1, "level %d: %lld valid samples (one void) in one "
		    "tile, error / E_L %.4f (the sag of flat chords)", z,
		    L->samples, mx);
	}
	qm_report_free(&r);
}

/* The same flat DEM in UTM zone 31 (10 km square near 1 E, 42 N): its
 * samples through PROJ, rows that are not parallels. */
static void
utm(const char *dir)
{
	char cmd[3 * PATH_MAX];
	const char *asc = tmp("utm.asc"), *tif = tmp("utm.tif");
	qm_report r;
	int st;

	if (system("gdal_translate --version >/dev/null 2>&1") != 0) {
		ok(1, "# SKIP no gdal_translate");
		return;
	}
	write_asc(asc, 340000, 4655000, 250, 0);
	snprintf(cmd, sizeof cmd, "gdal_translate -q -a_srs EPSG:32631 '%s' "
	    "'%s'", asc, tif);
	ok(system(cmd) == 0, "a flat UTM DEM (EPSG:32631)");
	st = check(dir, tif, &r);
	if (!ok(st == 0 && r.total == 0, "against it: within E_L (%lld "
	    "violations)", r.total))
		show(&r);
	st = 1;
	for (int z = 0; z < LEVELS; z++)
		st &= r.lev[z].nratio == 1 && r.lev[z].samples == DW * DW - 1 &&
		    r.lev[z].ratio[0] > 0 && r.lev[z].ratio[0] <= 1;
	ok(st, "every level: %d valid samples in one tile, 0 < error / E_L "
	    "<= 1", DW * DW - 1);
	qm_report_free(&r);
}

static void
damages(const char *dem_path)
{
	static const struct {
		int damage, kind;
		const char *what, *text;
	} d[] = {
		{ D_TRUNC, QM_DECODE, "a tile cut in half", "truncated" },
		{ D_INDEX, QM_INDEX, "a high-water-mark code above the highest",
		  "high-water-mark" },
		{ D_EDGE, QM_EDGES, "a vertex left out of the west list",
		  "on the west edge but not in its list" },
		{ D_SPHERE, QM_SPHERE, "the bounding sphere halved",
		  "outside the bounding sphere" },
		{ D_OCCL, QM_OCCLUSION, "the occlusion point 1% low",
		  "below vertex" },
		{ D_CW, QM_WINDING, "a clockwise triangle", "is clockwise" },
		{ D_FLAT, QM_DEGENERATE, "a triangle on a line", "no area" },
		{ D_HEIGHTS, QM_HEIGHTS, "a minimum height below every vertex",
		  "no vertex at height 0" },
		{ D_SEAM, QM_SEAM, "a west edge vertex of 0/1/0 raised 100 m",
		  "east edge at 10240: height 100.0000 m, 200.0000 m in 0/1/0" },
		{ D_HOLE, QM_HOLE, "a triangle left out",
		  "2 edges inside the tile belong to one triangle only" },
	};
	static const char *name[] = { "d0", "d1", "d2", "d3", "d4", "d5", "d6",
	    "d7", "d8", "d9" };
	const char *dir;

	for (size_t i = 0; i < sizeof d / sizeof d[0]; i++) {
		dir = tmp(name[i]);
		if (write_set(dir, d[i].damage) < 0)
			ok(0, "write %s", dir);
		expect2(dir, NULL, d[i].what, d[i].kind, d[i].text,
		    d[i].damage == D_INDEX || d[i].damage == D_CW ||
		    d[i].damage == D_FLAT);
	}
	dir = tmp("high");
	write_set(dir, D_HIGH);
	expect(dir, dem_path, "the deepest tile 2 E_L above the DEM",
	    QM_ERROR, "over E_4");
}

static void
files(void)
{
	const char *dir;
	char a[PATH_MAX + 64];
	int x, y;

	dir = tmp("unannounced");
	write_set(dir, D_NONE);
	tile_of(3, &x, &y);
	ok(write_tile(dir, 3, x + 1, y, D_NONE) == 0, "a good tile 3/%d/%d "
	    "beside 3/%d/%d", x + 1, y, x, y);
	expect(dir, NULL, "a tile available does not announce", QM_UNANNOUNCED,
	    "does not announce");

	dir = tmp("missing");
	write_set(dir, D_NONE);
	tile_of(LEVELS - 1, &x, &y);
	snprintf(a, sizeof a, "%s/%d/%d/%d.terrain", dir, LEVELS - 1, x, y);
	unlink(a);
	expect(dir, NULL, "an announced tile removed", QM_MISSING, "no file");

	dir = tmp("ancestor");
	write_set(dir, D_NONE);
	tile_of(3, &x, &y);
	snprintf(a, sizeof a, "%s/3/%d/%d.terrain", dir, x, y);
	unlink(a);
	write_layer(dir, 3);
	expect(dir, NULL, "a level-3 tile neither present nor announced",
	    QM_ANCESTOR, "its parent 3/");

	dir = tmp("nolayer");
	write_set(dir, D_NONE);
	snprintf(a, sizeof a, "%s/layer.json", dir);
	unlink(a);
	{
		qm_report r;

		ok(check(dir, NULL, &r) < 0, "no layer.json: cannot check");
		qm_report_free(&r);
	}
}

/* Every prefix of a tile and bytes changed at random: decoded or refused
 * with a reason, never read past (make check-asan), and whatever
 * decodes checked without harm. */
static void
hostile(void)
{
	buf b = { NULL, 0, 0 };
	size_t edges = 0, refused = 0, decoded = 0;
	unsigned seed = 12345;
	qm_report r;

	encode(&b, 1, 2, 1, D_NONE); /* normals, metadata */
	for (size_t n = 0; n < b.n; n++) {
		unsigned char *p = malloc(n + 1);
		qm_tile t;
		tl_err e;

		memcpy(p, b.b, n);
		if (qm_decode(p, n, &t, &e) < 0)
			refused += strstr(e.msg, "truncated") != NULL;
		else
			edges = n; /* the tile without its extensions */
		qm_free(&t);
		free(p);
	}
	ok(refused == b.n - 2, "each of %zu prefixes refused as truncated "
	    "but two complete ones (without extensions; without the "
	    "metadata, %zu bytes)", b.n, edges);
	qm_report_init(&r);
	for (int k = 0; k < 2000; k++) {
		unsigned char *p = malloc(b.n);
		qm_tile t;
		tl_err e;

		memcpy(p, b.b, b.n);
		for (int m = 0; m < 1 + k % 4; m++) {
			seed = seed * 1103515245 + 12345;
			p[(seed >> 8) % b.n] ^= (unsigned char)(1 + (seed >> 20) % 255);
		}
		if (qm_decode(p, b.n, &t, &e) == 0) {
			decoded++;
			qm_tile_check(&t, 1, 2, 1, 1, &r);
		}
		qm_free(&t);
		free(p);
	}
	ok(decoded > 0 && r.total > 0, "2000 damaged copies: %zu decode, "
	    "%lld violations found in them, no crash", decoded, r.total);
	qm_report_free(&r);
	free(b.b);
}

int
main(int argc, char **argv)
{
	char dir[PATH_MAX], dem_path[PATH_MAX], cmd[PATH_MAX + 16];

	if (argc == 3 && !strcmp(argv[1], "--write")) {
		vary = 1;
		return write_set(argv[2], D_NONE) < 0;
	}
	if (tmpdir_make(top, sizeof top, "t_qm") < 0)
		return ok(0, "scratch directory"), tap_done();
	strcpy(dir, tmp("good"));
	strcpy(dem_path, tmp("dem.asc"));
	ok(write_set(dir, D_NONE) == 0 && write_dem(dem_path) == 0,
	    "a tileset of %d levels and its DEM encoded by hand", LEVELS);
	good(dir, dem_path);
	utm(dir);
	vary = 1;
	expect_pass(tmp("vary"));
	vary = 0;
	damages(dem_path);
	files();
	hostile();
	if (tap_failed == 0) {
		snprintf(cmd, sizeof cmd, "rm -rf '%s'", top);
		system(cmd);
	} else
		printf("# kept %s\n", top);
	return tap_done();
}
