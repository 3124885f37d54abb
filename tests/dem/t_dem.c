/* t_dem.c - DEM input and georeferencing on the real DEMs of
 * ../shared/data (or $DATA) and on GDAL-made fixtures (tests/tools/mkdem.py).
 * Expected georeferencing comes from gdalinfo, metric cell sizes from
 * GeodSolve (GeographicLib's own tool), both written here as literals. */
#include <dlfcn.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "dem/dem.h"
#include "geo/georef.h"
#include "raster/oiio_plugin.h"
#include "raster/raster.h"
#include "tap.h"

/* top and fx stay below PATH_MAX; the paths built on them fit in 2x. */
static char top[PATH_MAX], data[PATH_MAX + 32], fx[PATH_MAX + 32];

static const char *
dpath(const char *name)
{
	static char p[4][2 * PATH_MAX + 64];
	static int k;

	k = (k + 1) % 4;
	snprintf(p[k], sizeof p[k], "%s/%s", data, name);
	return p[k];
}

static const char *
fpath(const char *name)
{
	static char p[4][2 * PATH_MAX + 64];
	static int k;

	k = (k + 1) % 4;
	snprintf(p[k], sizeof p[k], "%s/%s", fx, name);
	return p[k];
}

static int
near(double a, double b, double tol)
{
	return fabs(a - b) <= tol;
}

static double
now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + t.tv_nsec * 1e-9;
}

/* Everything one sequential pass over a DEM tells. */
typedef struct {
	int w, h;
	long long voids;       /* mask zeros */
	double vmin, vmax;     /* valid samples */
	int imax, jmax;        /* where vmax is (first) */
	double fmin, fmax;     /* filled voids */
	long long nonfinite;   /* any sample */
	uint64_t *rowhash;     /* per row, z and mask */
	double secs;           /* dem_open + the pass */
} stats;

static uint64_t
fnv(uint64_t h, const void *p, size_t n)
{
	const unsigned char *c = p;

	while (n--)
		h = (h ^ *c++) * 0x100000001b3ULL;
	return h;
}

static void
scan_row(stats *s, const float *z, const unsigned char *v, int j)
{
	for (int i = 0; i < s->w; i++) {
		if (!isfinite(z[i]))
			s->nonfinite++;
		if (!v[i]) {
			s->voids++;
			s->fmin = fmin(s->fmin, z[i]);
			s->fmax = fmax(s->fmax, z[i]);
			continue;
		}
		s->vmin = fmin(s->vmin, z[i]);
		if (z[i] > s->vmax)
			s->vmax = z[i], s->imax = i, s->jmax = j;
	}
	s->rowhash[j] = fnv(fnv(0xcbf29ce484222325ULL, z, s->w * sizeof *z),
	    v, (size_t)s->w);
}

static dem *
scan(const char *path, const dem_opts *o, stats *s, tl_err *e)
{
	double t0 = now();
	dem *d = dem_open(path, o, e);
	float *z;
	unsigned char *v;

	memset(s, 0, sizeof *s);
	if (d == NULL)
		return NULL;
	s->w = dem_georef(d)->width;
	s->h = dem_georef(d)->height;
	s->vmin = s->fmin = INFINITY;
	s->vmax = s->fmax = -INFINITY;
	z = malloc(s->w * sizeof *z);
	v = malloc(s->w);
	s->rowhash = calloc(s->h, sizeof *s->rowhash);
	for (int j = 0; j < s->h; j++) {
		if (dem_read_row(d, j, z, v, e) < 0) {
			dem_close(d);
			d = NULL;
			break;
		}
		scan_row(s, z, v, j);
	}
	free(z);
	free(v);
	s->secs = now() - t0;
	return d;
}

/* Rows in a scrambled order hash the same as in sequence. */
static int
random_order_same(dem *d, const stats *s)
{
	float *z = malloc(s->w * sizeof *z);
	unsigned char *v = malloc(s->w);
	uint32_t x = 12345;
	int bad = 0;
	tl_err e;

	for (int k = 0; k < s->h && !bad; k++) {
		int j;
		x = x * 1664525u + 1013904223u;
		j = (int)(x >> 8) % s->h;
		if (k % 2)
			j = s->h - 1 - k / 2; /* and every row from the end */
		bad = dem_read_row(d, j, z, v, &e) < 0 ||
		    fnv(fnv(0xcbf29ce484222325ULL, z, s->w * sizeof *z), v,
		    (size_t)s->w) != s->rowhash[j];
	}
	free(z);
	free(v);
	return !bad;
}

/* Valgrind's own memory would fail the RSS check: skip it there. */
static int
under_valgrind(void)
{
	char line[512];
	FILE *f = fopen("/proc/self/maps", "r");
	int found = 0;

	while (f != NULL && !found && fgets(line, sizeof line, f) != NULL)
		found = strstr(line, "vgpreload") != NULL;
	if (f != NULL)
		fclose(f);
	return found;
}

static long
peak_rss_kib(void)
{
	struct rusage ru;

	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss;
}

/* --- the real DEMs -------------------------------------------------- */

typedef struct {
	const char *file;
	int w, h;
	enum geo_model model;
	int epsg, point;
	double gdal_origin[2]; /* gdalinfo: corner of pixel (0,0) */
	double step;           /* gdalinfo pixel size, x; y is its negative */
	long long voids;
	double vmin, vmax;     /* data/README.md */
	double nodata;
} real;

static const real reals[] = {
	{ "N48W125.hgt", 3601, 3601, GEO_GEOGRAPHIC, 4326, 1,
	    { -125.00013888888888, 49.00013888888889 }, 0.0002777777777778,
	    6483876, -13, 1095, -32768 },
	{ "N48W125.tif", 3601, 3601, GEO_GEOGRAPHIC, 4326, 1,
	    { -125.00013888888888, 49.00013888888889 }, 0.0002777777777778,
	    6483876, -13, 1095, -32768 },
	{ "N42E001.hgt", 1201, 1201, GEO_GEOGRAPHIC, 4326, 1,
	    { 0.9995833333333334, 43.000416666666666 }, 0.0008333333333333,
	    7652, 349, 3100, -32768 },
	{ "N42E001.tif", 1201, 1201, GEO_GEOGRAPHIC, 4326, 1,
	    { 0.9995833333333334, 43.000416666666666 }, 0.0008333333333333,
	    7652, 349, 3100, -32768 },
	{ "N44W072.hgt", 1201, 1201, GEO_GEOGRAPHIC, 4326, 1,
	    { -72.00041666666667, 45.000416666666666 }, 0.0008333333333333,
	    0, 115, 1908, -32768 },
	{ "N44W072.tif", 1201, 1201, GEO_GEOGRAPHIC, 4326, 1,
	    { -72.00041666666667, 45.000416666666666 }, 0.0008333333333333,
	    0, 115, 1908, -32768 },
	{ "bigtujunga.tif", 1197, 643, GEO_PROJECTED, 32611, 0,
	    { 376313.6554542635, 3807917.8276283755 }, 30,
	    0, 315, 2295, 32767 },
};

static void
check_georef(const real *r, const georef *g)
{
	double half = r->point ? 0.5 : 0;
	double ox = g->origin[0] - half * g->step[0];
	double oy = g->origin[1] - half * g->step[1];
	char crs[32];

	snprintf(crs, sizeof crs, "EPSG:%d", r->epsg);
	ok(g->width == r->w && g->height == r->h, "%s: size %d x %d",
	    r->file, g->width, g->height);
	ok(g->model == r->model && g->epsg == r->epsg &&
	    strcmp(g->crs, crs) == 0, "%s: model %d, %s", r->file, g->model,
	    g->crs);
	ok(g->point == r->point, "%s: pixel is %s", r->file,
	    g->point ? "point" : "area");
	ok(near(ox, r->gdal_origin[0], 1e-9) && near(oy, r->gdal_origin[1],
	    1e-9), "%s: origin - step/2 = gdalinfo origin (%.12g, %.12g)",
	    r->file, ox, oy);
	ok(near(g->step[0], r->step, 1e-13) && near(g->step[1], -r->step,
	    1e-13), "%s: pixel size %.16g x %.16g", r->file, g->step[0],
	    g->step[1]);
	ok(g->unit == (r->model == GEO_GEOGRAPHIC ? 0 : 1), "%s: unit %g",
	    r->file, g->unit);
	ok(g->has_nodata && g->nodata == r->nodata, "%s: nodata %g", r->file,
	    g->nodata);
	if (strstr(r->file, ".hgt"))
		ok(strcmp(g->vdatum, "EPSG:5773") == 0, "%s: vertical datum "
		    "EGM96 (EPSG:5773)", r->file);
}

static void
check_real(const real *r, stats *keep)
{
	tl_err e = { "" };
	stats s;
	dem *d = scan(dpath(r->file), NULL, &s, &e);

	if (!ok(d != NULL, "%s: opens and reads (%.2f s)", r->file, s.secs)) {
		printf("#   %s\n", e.msg);
		return;
	}
	printf("# %s: dem_open + all rows %.3f s\n", r->file, s.secs);
	check_georef(r, dem_georef(d));
	ok(dem_voids(d) == r->voids && s.voids == r->voids,
	    "%s: %lld voids (mask %lld)", r->file, dem_voids(d), s.voids);
	ok(s.vmin == r->vmin && s.vmax == r->vmax, "%s: valid %g .. %g",
	    r->file, s.vmin, s.vmax);
	ok(s.nonfinite == 0, "%s: every sample finite after filling", r->file);
	if (r->voids > 0)
		ok(s.fmin >= s.vmin && s.fmax <= s.vmax, "%s: filled voids "
		    "%g .. %g within the valid range", r->file, s.fmin, s.fmax);
	ok(random_order_same(d, &s), "%s: rows in random order = in sequence",
	    r->file);
	dem_close(d);
	if (keep != NULL)
		*keep = s;
	else
		free(s.rowhash);
}

static int
same_rows(const stats *a, const stats *b)
{
	return a->w == b->w && a->h == b->h &&
	    memcmp(a->rowhash, b->rowhash, a->h * sizeof *a->rowhash) == 0;
}

static void
check_pairs(void)
{
	stats hgt, tif;

	for (size_t k = 0; k + 1 < sizeof reals / sizeof reals[0]; k += 2) {
		check_real(&reals[k], &hgt);
		check_real(&reals[k + 1], &tif);
		ok(same_rows(&hgt, &tif), "%s and %s: identical rows and masks",
		    reals[k].file, reals[k + 1].file);
		if (k == 0 && (under_valgrind() || TAP_SANITIZED))
			ok(1, "# SKIP peak RSS under valgrind or ASan");
		else if (k == 0)
			/* GDAL costs ~44 MiB by being linked and registered
			 * (measured: 35 + 9); its block cache is 4 MiB */
			ok(peak_rss_kib() < 72 * 1024, "peak RSS after reading "
			    "N48W125 .hgt and .tif: %ld KiB < 72 MiB",
			    peak_rss_kib());
		free(hgt.rowhash);
		free(tif.rowhash);
	}
	check_real(&reals[6], NULL);
}

/* --- metric embedding (GeodSolve -i -p 9 literals) ------------------- */

static void
check_ground_file(const char *file, const int *rows, const double *dx,
    int drow, double dy, double ytotal)
{
	tl_err e = { "" };
	dem *d = dem_open(dpath(file), NULL, &e);
	geo_ground m;
	int n;

	if (!ok(d != NULL && geo_ground_init(&m, dem_georef(d), &e) == 0,
	    "%s: metric", file)) {
		printf("#   %s\n", e.msg);
		dem_close(d);
		return;
	}
	n = m.height - 1;
	for (int k = 0; k < 3; k++)
		ok(near(m.dx[rows[k]], dx[k], 1e-6), "%s: dx[%d] = %.9f m "
		    "(GeodSolve %.9f)", file, rows[k], m.dx[rows[k]], dx[k]);
	ok(near(m.y[drow + 1] - m.y[drow], dy, 1e-6), "%s: y[%d] - y[%d] = "
	    "%.9f m (GeodSolve %.9f)", file, drow + 1, drow,
	    m.y[drow + 1] - m.y[drow], dy);
	ok(m.y[0] == 0 && near(m.y[n], ytotal, 1e-5), "%s: y[%d] = %.9f m, "
	    "the meridian arc (GeodSolve %.9f)", file, n, m.y[n], ytotal);
	geo_ground_free(&m);
	dem_close(d);
}

static void
check_ground(void)
{
	static const int r1[] = { 0, 600, 1200 }, r3[] = { 0, 1800, 3600 };
	static const double dx1[] = { 67.950806464, 68.499176504, 69.042301321 };
	static const double dx3[] = { 20.325498153, 20.528169672, 20.729264878 };
	tl_err e = { "" };
	dem *d;
	geo_ground m;

	check_ground_file("N42E001.hgt", r1, dx1, 600, 92.569161377,
	    111083.004469900);
	check_ground_file("N42E001.tif", r1, dx1, 1199, 92.561076401,
	    111083.004469900);
	check_ground_file("N48W125.hgt", r3, dx3, 1800, 30.888899250,
	    111200.036762378);
	d = dem_open(dpath("bigtujunga.tif"), NULL, &e);
	if (ok(d != NULL && geo_ground_init(&m, dem_georef(d), &e) == 0,
	    "bigtujunga.tif: metric")) {
		/* ground metres: the 30 m grid step over UTM's scale factor
		 * (t_ground checks them against geodesics) */
		double sx = geo_sx(&m, 600, 642), y = geo_y(&m, 600, 642);
		ok(sx != 30 && fabs(sx / 30 - 1) < 1e-3 &&
		    fabs(y / (642 * 30.0) - 1) < 1e-3, "bigtujunga.tif: "
		    "projected: a 30 m step is %.6f m, y[642] = %.3f m", sx, y);
		geo_ground_free(&m);
	}
	dem_close(d);
}

/* --- georeferencing helpers ------------------------------------------ */

static void
check_vertex_crs(void)
{
	tl_err e;
	dem *d = dem_open(dpath("N42E001.hgt"), NULL, &e);
	double x, y;

	geo_vertex_crs(dem_georef(d), 0, 0, 0, &x, &y);
	ok(x == 1 && y == 43, "N42E001: vertex (0,0) at (1, 43) exactly");
	geo_vertex_crs(dem_georef(d), 2, 300, 300, &x, &y);
	ok(near(x, 2, 1e-12) && near(y, 42, 1e-12), "N42E001: level 2 vertex "
	    "(300,300) at (%.15g, %.15g)", x, y);
	dem_close(d);
	d = dem_open(dpath("bigtujunga.tif"), NULL, &e);
	geo_vertex_crs(dem_georef(d), 1, 1, 2, &x, &y);
	ok(near(x, 376313.6554542635 + 75, 1e-7) &&
	    near(y, 3807917.8276283755 - 135, 1e-7), "bigtujunga: level 1 "
	    "vertex (1,2) is the centre of pixel (2,4)");
	dem_close(d);
}

static void
check_header_roundtrip(void)
{
	tl_err e = { "" };
	dem *d = dem_open(dpath("N42E001.hgt"), NULL, &e);
	georef g = *dem_georef(d), back;
	rs_header h;
	int r;

	rs_header_init(&h, 10, 10);
	r = rs_put_georef(&g, &h, &e) == 0 &&
	    rs_set_v2i(&h, "fqm:size0", g.width, g.height, &e) == 0 &&
	    rs_get_georef(&back, &h, &e) == 0;
	ok(r && memcmp(&g, &back, sizeof g) == 0, "rs_put_georef then "
	    "rs_get_georef gives the same georef %s", e.msg);
	ok(strcmp(rs_get_string(&h, "geo:model"), "geographic") == 0 &&
	    strcmp(rs_get_string(&h, "geo:raster"), "point") == 0 &&
	    strcmp(rs_get_string(&h, "geo:vdatum"), "EPSG:5773") == 0,
	    "geo:model, geo:raster, geo:vdatum attributes");
	g.has_nodata = 0;
	g.vdatum[0] = '\0';
	rs_put_georef(&g, &h, &e);
	ok(rs_get_string(&h, "geo:vdatum") == NULL &&
	    rs_get_double(&h, "geo:nodata", &g.nodata) < 0,
	    "geo:vdatum and geo:nodata only when declared");
	rs_set_string(&h, "geo:model", "sideways", &e);
	ok(rs_get_georef(&back, &h, &e) < 0 && strstr(e.msg, "geo:model"),
	    "unknown geo:model fails: %s", e.msg);
	rs_header_free(&h);
	dem_close(d);
}

/* --- fuji.png: Terrain-RGB through the OpenImageIO plugin ------------- */

static void
check_fuji(void)
{
	tl_err e = { "" };
	stats s;
	dem *d = scan(dpath("fuji.png"), NULL, &s, &e);

	if (!ok(d != NULL, "fuji.png: opens through the plugin")) {
		printf("#   %s\n", e.msg);
		return;
	}
	printf("# fuji.png: dem_open + all rows %.3f s\n", s.secs);
	ok(s.w == 512 && s.h == 512 && s.voids == 0, "fuji.png: 512 x 512, "
	    "no voids");
	ok(near(s.vmin, 13.7, 1e-4) && near(s.vmax, 3751.0, 1e-4),
	    "fuji.png: Terrain-RGB %g .. %g", s.vmin, s.vmax);
	ok(s.jmax == 178 && s.imax == 308, "fuji.png: maximum at row %d, col "
	    "%d", s.jmax, s.imax);
	ok(dem_georef(d)->model == GEO_NONE && dem_georef(d)->step[0] == 1,
	    "fuji.png: ungeoreferenced, 1 m cells by default");
	dem_close(d);
	free(s.rowhash);
}

/* --- stdin ------------------------------------------------------------ */

static dem *
open_stdin(const char *file, const dem_opts *o, stats *s, tl_err *e)
{
	int saved = dup(0), fd = open(file, O_RDONLY);
	dem *d;

	dup2(fd, 0);
	close(fd);
	d = scan("-", o, s, e);
	dup2(saved, 0);
	close(saved);
	return d;
}

static void
check_stdin(void)
{
	dem_opts o = { .hgt_name = "N42E001.hgt" };
	tl_err e = { "" };
	stats a, b;
	dem *da = scan(dpath("N42E001.hgt"), NULL, &a, &e);
	dem *db = open_stdin(dpath("N42E001.hgt"), &o, &b, &e);

	ok(db != NULL && same_rows(&a, &b) && memcmp(dem_georef(da),
	    dem_georef(db), sizeof(georef)) == 0, "N42E001.hgt on stdin with "
	    "its name: same rows and georef %s", e.msg);
	dem_close(db), free(b.rowhash);
	db = open_stdin(dpath("N42E001.hgt"), NULL, &b, &e);
	ok(db == NULL && strstr(e.msg, "-n NAME") != NULL, "N42E001.hgt on "
	    "stdin without a name: refused, pointing at -n: %s", e.msg);
	dem_close(da), dem_close(db), free(a.rowhash), free(b.rowhash);

	da = scan(dpath("bigtujunga.tif"), NULL, &a, &e);
	db = open_stdin(dpath("bigtujunga.tif"), NULL, &b, &e);
	ok(db != NULL && same_rows(&a, &b) && memcmp(dem_georef(da),
	    dem_georef(db), sizeof(georef)) == 0, "bigtujunga.tif on stdin: "
	    "same rows and georef");
	dem_close(da), dem_close(db), free(a.rowhash), free(b.rowhash);

	da = scan(dpath("fuji.png"), NULL, &a, &e);
	db = open_stdin(dpath("fuji.png"), NULL, &b, &e);
	ok(db != NULL && same_rows(&a, &b), "fuji.png on stdin: same rows %s",
	    db ? "" : e.msg);
	dem_close(da), dem_close(db), free(a.rowhash), free(b.rowhash);
}

/* --- fixtures ----------------------------------------------------------- */

static void
write_file(const char *path, const void *p, size_t n)
{
	FILE *f = fopen(path, "wb");

	fwrite(p, 1, n, f);
	fclose(f);
}

/* Every sample of a fixture against its formula; voids must be NaN-free. */
static int
matches(const char *file, const dem_opts *o, double (*f)(int, int),
    int w, int h, tl_err *e)
{
	dem *d = dem_open(fpath(file), o, e);
	float *z = malloc(w * sizeof *z);
	unsigned char *v = malloc(w);
	int good = d != NULL && dem_georef(d)->width == w &&
	    dem_georef(d)->height == h;

	for (int j = 0; good && j < h; j++) {
		good = dem_read_row(d, j, z, v, e) == 0;
		for (int i = 0; good && i < w; i++)
			good = !v[i] || z[i] == (float)f(i, j);
	}
	free(z), free(v);
	dem_close(d);
	return good;
}

static double f_tiled(int i, int j) { return (float)(100 + 0.5 * i + 0.25 * j); }
static double f_u16(int i, int j) { return i == 49 && j == 39 ? 65535 :
    j == 10 ? 0 : i * 1000 + j * 7; }
static double f_grey(int i, int j) { return i * 1000 + j; }
static double f_trgb(int i, int j) { return (65536.0 + 256 * i + j) / 10 - 10000; }
static double f_terrarium(int i, int j) { return 256 + i + j / 256.0 - 32768; }
static double f_planar(int i, int j) { return i - 100 * j; }
static double f_f64(int i, int j) { return (float)(0.001 * i + j); }
static double f_half(int i, int j) { return 0.5 * i + j; }
static double f_i8(int i, int j) { return i - 16; }
static double f_one(int i, int j) { return 1; }
static double f_exr(int i, int j) { return i * 0.25 - j * 3; }

static void
check_voids(const char *file, long long want, double lo, double hi)
{
	tl_err e = { "" };
	stats s;
	dem *d = scan(fpath(file), NULL, &s, &e);

	ok(d != NULL && dem_voids(d) == want && s.voids == want &&
	    s.nonfinite == 0 && s.fmin >= lo && s.fmax <= hi, "%s: %lld voids, "
	    "filled %g .. %g within %g .. %g %s", file, s.voids, s.fmin, s.fmax,
	    lo, hi, e.msg);
	dem_close(d);
	free(s.rowhash);
}

/* Every sample, void or not, within tol of f: 1/d weights between two
 * samples on opposite sides interpolate linearly, so filling reproduces a
 * linear surface. */
static int
filled_like(const char *file, double (*f)(int, int), double tol,
    tl_err *e)
{
	dem *d = dem_open(fpath(file), NULL, e);
	int w = d ? dem_georef(d)->width : 0, good = d != NULL;
	float *z = malloc((w + 1) * sizeof *z);

	for (int j = 0; good && j < dem_georef(d)->height; j++) {
		good = dem_read_row(d, j, z, NULL, e) == 0;
		for (int i = 0; good && i < w; i++)
			good = fabs(z[i] - f(i, j)) <= tol;
	}
	free(z);
	dem_close(d);
	return good;
}

static double f_cross(int i, int j) { return 10 * i + j; }
/* Corner voids have neighbours on two sides only: the mean of those. */
static double f_tiled_filled(int i, int j) { return i == 0 && j == 0 ?
    (100.5 + 100.25) / 2 : i == 299 && j == 199 ? (298.75 + 299) / 2 :
    f_tiled(i, j); }

static void
check_fill(void)
{
	tl_err e = { "" };
	dem *d;
	float z[4];
	unsigned char v[4];

	ok(filled_like("tiled_f32.tif", f_tiled_filled, 1e-4, &e), "filling "
	    "reproduces the linear surface in tiled_f32.tif %s", e.msg);
	ok(filled_like("cross.tif", f_cross, 1e-5, &e), "a void row crossing "
	    "a void column: filled, the crossing from its row %s", e.msg);
	d = dem_open(fpath("idw.tif"), NULL, &e);
	if (d == NULL || dem_read_row(d, 1, z, v, &e) < 0)
		memset(z, 0, sizeof z), memset(v, 0, sizeof v);
	ok(d != NULL && dem_voids(d) == 2 && near(z[1], 26.0 / 7, 1e-6) && near(z[2], 12.0 / 7, 1e-6) &&
	    z[0] == 8 && z[3] == 2 && v[0] && !v[1] && !v[2] && v[3],
	    "inverse-distance weights: (8/1 + 2/2 + 0/1 + 4/1) / 3.5 = %g, "
	    "(8/2 + 2/1 + 0 + 0) / 3.5 = %g", z[1], z[2]);
	dem_close(d);
}

/* --- a window of columns (dem_open_cols) -------------------------------- */

/* Columns x0 .. x1-1 of path, row by row against the whole DEM: the same
 * validity, the same heights where valid, NaN where not; a span reaching
 * out of the window refused. */
static int
same_cols(const char *path, int x0, int x1, tl_err *e)
{
	dem *a = dem_open(path, NULL, e), *b = NULL;
	int w, h, n = x1 - x0, r = 0;
	float *za = NULL, *zb = NULL;
	unsigned char *va = NULL, *vb = NULL;

	if (a == NULL || (b = dem_open_cols(path, NULL, x0, x1, e)) == NULL)
		goto out;
	w = dem_georef(a)->width, h = dem_georef(a)->height;
	za = malloc((size_t)w * sizeof *za), zb = malloc((size_t)n * sizeof *zb);
	va = malloc((size_t)w), vb = malloc((size_t)n);
	r = dem_georef(b)->width == w && dem_georef(b)->height == h &&
	    memcmp(dem_georef(a), dem_georef(b), sizeof(georef)) == 0;
	for (int j = 0; j < h && r; j++) {
		if (dem_read_row(a, j, za, va, e) < 0 ||
		    dem_read_span(b, j, x0, n, zb, vb, e) < 0) {
			r = 0;
			break;
		}
		for (int i = 0; i < n && r; i++)
			r = va[x0 + i] == vb[i] && (vb[i] ? za[x0 + i] == zb[i] :
			    isnan(zb[i]));
	}
	if (r && x0 > 0)
		r = dem_read_span(b, 0, x0 - 1, 2, zb, vb, e) < 0;
	if (r && x1 < w)
		r = dem_read_span(b, h - 1, x1 - 1, 2, zb, vb, e) < 0;
	if (r)
		e->msg[0] = '\0'; /* the refusals asked for */
out:
	dem_close(a);
	dem_close(b);
	free(za), free(zb), free(va), free(vb);
	return r;
}

static void
check_cols(void)
{
	static const struct { const char *file; int x0, x1; } c[] = {
		{ "tiled_f32.tif", 0, 37 }, { "tiled_f32.tif", 120, 300 },
		{ "cross.tif", 2, 5 }, { "u16_be.tif", 10, 41 },
		{ "planar_i32.tif", 5, 33 },
	};
	tl_err e = { "" };
	dem *d;

	for (size_t k = 0; k < sizeof c / sizeof c[0]; k++)
		ok(same_cols(fpath(c[k].file), c[k].x0, c[k].x1, &e), "%s: "
		    "columns %d .. %d alone: the whole DEM's, voids NaN %s",
		    c[k].file, c[k].x0, c[k].x1 - 1, e.msg);
	ok(same_cols(dpath("N44W072.hgt"), 1000, 1201, &e), "N44W072.hgt: "
	    "its last 201 columns alone %s", e.msg);
	d = dem_open_cols(fpath("cross.tif"), NULL, 5, 500, &e);
	ok(d == NULL && strstr(e.msg, "outside") != NULL, "columns past the "
	    "DEM refused: %s", e.msg);
	dem_close(d);
}

static void
check_formats(void)
{
	dem_opts terrarium = { .encoding = DEM_ENC_TERRARIUM };
	dem_opts grey = { .encoding = DEM_ENC_GREY };
	dem_opts nd7 = { .has_nodata = 1, .nodata = 7 };
	tl_err e = { "" };
	stats s;
	dem *d;

	ok(matches("tiled_f32.tif", NULL, f_tiled, 300, 200, &e),
	    "tiled float32 DEFLATE predictor-3 GeoTIFF %s", e.msg);
	check_voids("tiled_f32.tif", 803, 100.25, 299);
	ok(matches("u16_be.tif", NULL, f_u16, 50, 40, &e),
	    "big-endian uint16 GeoTIFF, 65535 stays 65535 %s", e.msg);
	check_voids("u16_be.tif", 51, 7, 65535);
	d = scan(fpath("u16_be.tif"), &nd7, &s, &e);
	ok(d != NULL && s.voids == 1 && dem_georef(d)->nodata == 0,
	    "nodata override 7: 1 void, the file's nodata still reported");
	dem_close(d), free(s.rowhash);
	ok(matches("grey16.png", NULL, f_grey, 64, 48, &e),
	    "16-bit grey PNG, native values %s", e.msg);
	ok(matches("trgb.tif", NULL, f_trgb, 40, 30, &e) &&
	    matches("trgb.png", NULL, f_trgb, 40, 30, &e),
	    "8-bit RGB TIFF (libtiff) and PNG (plugin): Terrain-RGB %s", e.msg);
	ok(matches("trgb.png", &terrarium, f_terrarium, 40, 30, &e),
	    "Terrarium encoding on request %s", e.msg);
	ok(matches("trgb.tif", &grey, f_one, 40, 30, &e),
	    "grey encoding on request reads the first channel %s", e.msg);
	ok(matches("planar_i32.tif", NULL, f_planar, 33, 21, &e),
	    "int32, separate planes: the first %s", e.msg);
	ok(matches("f64_be.tif", NULL, f_f64, 33, 21, &e),
	    "big-endian float64 %s", e.msg);
	ok(matches("half.tif", NULL, f_half, 33, 21, &e),
	    "16-bit float TIFF %s", e.msg);
	ok(matches("i8.tif", NULL, f_i8, 33, 21, &e), "signed 8-bit %s", e.msg);
	write_file(fpath("S01W001.hgt"), "\0\1\xff\xfe\x80\0\0\4", 8);
	d = scan(fpath("S01W001.hgt"), NULL, &s, &e);
	ok(d == NULL && strstr(e.msg, "tile name") != NULL, "a 2 x 2 .hgt "
	    "(no SRTM size) is refused with a message: %s", e.msg);
	dem_close(d);
	d = scan(fpath("one.tif"), NULL, &s, &e);
	ok(d != NULL && s.w == 1 && s.h == 1 && s.vmax == 42.5 && s.voids == 0,
	    "1 x 1 DEM reads 42.5");
	dem_close(d), free(s.rowhash);
}

static void
check_fixture_georef(void)
{
	tl_err e = { "" };
	dem *d;
	const georef *g;

	d = dem_open(fpath("tiled_f32.tif"), NULL, &e);
	g = dem_georef(d);
	ok(g->model == GEO_PROJECTED && g->epsg == 32632 && !g->point &&
	    g->origin[0] == 500000 && g->origin[1] == 5200000 &&
	    g->step[0] == 30 && g->step[1] == -30 && g->unit == 1,
	    "tiled_f32.tif: EPSG:32632, area, origin and step");
	dem_close(d);
	d = dem_open(fpath("point.tif"), NULL, &e);
	g = dem_georef(d);
	ok(g->point && g->origin[0] == 700000 && g->origin[1] == 5100000,
	    "PixelIsPoint projected: origin is pixel (0,0)'s centre");
	dem_close(d);
	d = dem_open(fpath("compound.tif"), NULL, &e);
	g = dem_georef(d);
	ok(g->model == GEO_GEOGRAPHIC && g->epsg == 4326 &&
	    strcmp(g->vdatum, "EPSG:5773") == 0, "EPSG:4326+5773: vertical "
	    "datum %s", g->vdatum);
	dem_close(d);
	d = dem_open(fpath("userdef.tif"), NULL, &e);
	g = dem_georef(d);
	ok(g->model == GEO_PROJECTED && g->epsg == 0 &&
	    strncmp(g->crs, "PROJCRS[", 8) == 0 &&
	    strstr(g->crs, "Transverse Mercator") != NULL &&
	    strstr(g->crs, "13.5") != NULL && strchr(g->crs, '\n') == NULL,
	    "user-defined CRS: one-line WKT2 %.60s...", g->crs);
	dem_close(d);
	d = dem_open(fpath("grey16.png"), &(dem_opts){ .cell = { 2.5, 0 } },
	    &e);
	g = dem_georef(d);
	ok(g->model == GEO_NONE && g->step[0] == 2.5 && g->step[1] == -2.5 &&
	    g->unit == 1, "ungeoreferenced: --cell 2.5 gives 2.5 m cells");
	dem_close(d);
}

static void
fails(const char *path, const char *want, const char *what)
{
	tl_err e = { "" };
	dem *d = dem_open(path, NULL, &e);

	ok(d == NULL && strstr(e.msg, want) != NULL &&
	    strncmp(e.msg, path, strlen(path)) == 0, "%s fails: %s", what,
	    e.msg);
	dem_close(d);
}

static void
check_failures(void)
{
	char head[200];
	FILE *f = fopen(fpath("whole.tif"), "rb");

	fails(fpath("allvoid.tif"), "no valid samples", "all-void DEM");
	fails(fpath("notraster.txt"), "not a raster", "a text file");
	fails(fpath("trunc.tif"), "truncated or corrupt", "truncated TIFF");
	fread(head, 1, sizeof head, f);
	fclose(f);
	write_file(fpath("head.tif"), head, sizeof head);
	fails(fpath("head.tif"), "truncated or corrupt", "TIFF cut in its IFD");
	write_file(fpath("head.png"), "\x89PNG\r\n\x1a\n\0\0", 10);
	fails(fpath("head.png"), "head.png: ", "PNG cut after its magic");
	write_file(fpath("bad.hgt"), head, 100);
	fails(fpath("bad.hgt"), "not an SRTM .hgt", "an .hgt of 100 bytes");
	fails(fpath("rotated.tif"), "rotated or sheared", "rotated GeoTIFF");
	fails(fpath("huge.tif"), "unsupported size", "a TIFF 2^26 + 1 wide");
	fails(fpath("missing.tif"), "cannot open", "a missing file");
	fails(fx, "is a directory", "a directory");
	write_file(fpath("empty"), "", 0);
	fails(fpath("empty"), "empty", "an empty file");
}

/* The plugin reads a tiled TIFF with read_tiles (read_scanlines would
 * kill OpenImageIO 2.4.7): same samples as libtiff. */
/* A VRT over a real DEM declaring w x h samples (GDAL scales it). */
static void
write_vrt(const char *path, const char *src, int w, int h)
{
	char buf[2 * PATH_MAX + 512];
	int n = snprintf(buf, sizeof buf, "<VRTDataset rasterXSize=\"%d\" "
	    "rasterYSize=\"%d\">\n  <VRTRasterBand dataType=\"Int16\" "
	    "band=\"1\">\n    <SimpleSource><SourceFilename "
	    "relativeToVRT=\"0\">%s</SourceFilename><SourceBand>1"
	    "</SourceBand></SimpleSource>\n  </VRTRasterBand>\n"
	    "</VRTDataset>\n", w, h, src);

	write_file(path, buf, (size_t)n);
}

/* Sizes no DEM can have are refused before anything is read or
 * allocated; dem_open_info reads the header only, at once whatever the
 * size, and says what dem_open says. */
static void
check_sizes(void)
{
	const char *hgt = dpath("N44W072.hgt");
	tl_err e = { "" };
	dem_opts o = { 0 };
	dem *d, *full;
	float z[4];
	double t;
	int same;

	write_vrt(fpath("big.vrt"), hgt, 1 << 21, 1 << 21);
	fails(fpath("big.vrt"), "2097152 x 2097152 samples, more than 2^40: "
	    "refused before reading", "a VRT of 2^21 x 2^21 samples");
	d = dem_open_info(fpath("big.vrt"), NULL, &e);
	ok(d == NULL && strstr(e.msg, "more than 2^40") != NULL,
	    "dem_open_info refuses it too: %s", e.msg);
	write_vrt(fpath("huge.vrt"), hgt, 100000, 100000);
	t = now();
	d = dem_open_info(fpath("huge.vrt"), NULL, &e);
	t = now() - t;
	ok(d != NULL && dem_georef(d)->width == 100000 &&
	    dem_georef(d)->height == 100000 && dem_voids(d) == -1 && t < 10,
	    "dem_open_info: a VRT of 10^10 samples in %.3f s, voids unknown "
	    "%s", t, d == NULL ? e.msg : "");
	ok(d != NULL && dem_read_row(d, 0, z, NULL, &e) < 0 &&
	    strstr(e.msg, "header only") != NULL, "dem_read_row on it fails: "
	    "%s", e.msg);
	dem_close(d);
	o.heights = "ellipsoid";
	d = dem_open_info(hgt, &o, &e);
	full = dem_open(hgt, &o, &e);
	same = d != NULL && full != NULL &&
	    memcmp(dem_georef(d), dem_georef(full), sizeof(georef)) == 0 &&
	    dem_zunit(d) == dem_zunit(full);
	ok(same && strcmp(dem_georef(d)->vdatum, "EPSG:4979") == 0,
	    "N44W072.hgt -H ellipsoid: dem_open_info's georeferencing and "
	    "unit are dem_open's (%s)", d ? dem_georef(d)->vdatum : e.msg);
	dem_close(d), dem_close(full);
	d = dem_open_info(fpath("rotated.tif"), NULL, &e);
	ok(d == NULL && strstr(e.msg, "rotated or sheared") != NULL,
	    "dem_open_info refuses what dem_open refuses: %s", e.msg);
	d = dem_open_info(fpath("z.exr"), NULL, &e);
	ok(d != NULL && dem_georef(d)->width == 7 && dem_voids(d) == -1,
	    "dem_open_info on an EXR (the plugin): %s", d ? "7 wide" : e.msg);
	dem_close(d);
}

static void
check_plugin_tiled(void)
{
	const char *so = getenv("TL_OIIO_PLUGIN");
	void *h = dlopen(so, RTLD_NOW | RTLD_LOCAL);
	tl_oiio_entry_fn entry;
	const tl_oiio_api *api;
	tl_oiio_info info;
	tl_oiio_img *img;
	char err[256] = "";
	float *buf;
	int good;

	if (!ok(h != NULL, "plugin %s loads", so))
		return;
	*(void **)&entry = dlsym(h, TL_OIIO_ENTRY);
	api = entry();
	img = api->open(fpath("tiled_f32.tif"), &info, err, sizeof err);
	if (!ok(img != NULL && info.chunk == 64 && info.type == TL_PX_F32,
	    "plugin opens the tiled TIFF, chunk %d rows %s", img ? info.chunk :
	    0, err))
		return;
	buf = malloc(300 * 64 * sizeof *buf);
	good = api->read_rows(img, 128, 192, 1, buf, err, sizeof err) == 0;
	for (int k = 0; good && k < 300 * 64; k++) {
		int i = k % 300, j = 128 + k / 300;
		good = buf[k] == (float)f_tiled(i, j) || (i == 299 && j == 199);
	}
	ok(good, "plugin: tile row 128..191 by read_tiles matches %s", err);
	good = api->read_rows(img, 192, 200, 1, buf, err, sizeof err) == 0 &&
	    buf[0] == (float)f_tiled(0, 192);
	ok(good, "plugin: the last, partial tile row %s", err);
	api->close(img);
	free(buf);
}

static void
check_exr(void)
{
	rs_header h;
	rs_writer *w;
	tl_err e = { "" };
	float row[7];
	int r;

	georef g, back;
	rs_reader *rd;

	geo_init_none(&g, 2.5, 0);
	g.width = 7, g.height = 5;
	rs_header_init(&h, 7, 5);
	r = rs_add_channel(&h, "Z", &e) == 0 && rs_put_georef(&g, &h, &e) == 0 &&
	    rs_set_v2i(&h, "fqm:size0", 7, 5, &e) == 0 &&
	    (w = rs_create(fpath("z.exr"), &h, RS_ZIP, &e)) != NULL;
	for (int j = 0; r && j < 5; j++) {
		for (int i = 0; i < 7; i++)
			row[i] = (float)f_exr(i, j);
		r = rs_write_row(w, row, &e) == 0;
	}
	r = r && rs_finish(w, &e) == 0;
	rs_header_free(&h);
	if (!ok(r, "an EXR fixture written by raster.c %s", e.msg))
		return;
	rd = rs_open(fpath("z.exr"), &e);
	ok(rd != NULL && rs_get_georef(&back, rs_header_of(rd), &e) == 0 &&
	    memcmp(&g, &back, sizeof g) == 0, "geo:* attributes survive an EXR "
	    "file %s", e.msg);
	rs_close(rd);
	ok(matches("z.exr", NULL, f_exr, 7, 5, &e), "float EXR through the "
	    "plugin %s", e.msg);
}

static int
make_fixtures(void)
{
	char cmd[3 * PATH_MAX + 256];

	snprintf(fx, sizeof fx, "%s/tdem.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(fx) == NULL)
		return -1;
	snprintf(cmd, sizeof cmd, "/usr/bin/python3 '%s/tests/tools/mkdem.py' "
	    "'%s'", top, fx);
	return system(cmd) == 0 ? 0 : -1;
}

static void
remove_fixtures(void)
{
	char cmd[PATH_MAX + 64];

	if (strstr(fx, "/tdem.") == NULL)
		return;
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", fx);
	system(cmd);
}

/* This program is TOP/BUILD/tests/dem/t_dem, BUILD any build directory
 * (make B=...): the plugin is BUILD's, the data beside TOP. */
static void
find_top(void)
{
	ssize_t n = readlink("/proc/self/exe", top, sizeof top - 1);
	char so[PATH_MAX + 32], *t, *slash;

	if (n > 0)
		top[n] = '\0';
	if (n <= 0 || (t = strstr(top, "/tests/")) == NULL ||
	    (*t = '\0', slash = strrchr(top, '/')) == NULL) {
		if (getcwd(top, sizeof top) == NULL)
			snprintf(top, sizeof top, ".");
		snprintf(so, sizeof so, "%s/build/tl_oiio.so", top);
	} else {
		snprintf(so, sizeof so, "%s/tl_oiio.so", top);
		*slash = '\0';
	}
	/* a build directory outside the tree: the tree is where we run */
	snprintf(data, sizeof data, "%s/tests/tap.h", top);
	if (access(data, F_OK) != 0 && getcwd(top, sizeof top) == NULL)
		snprintf(top, sizeof top, ".");
	if (getenv("DATA"))
		snprintf(data, sizeof data, "%s", getenv("DATA"));
	else
		snprintf(data, sizeof data, "%s/../shared/data", top);
	setenv("TL_OIIO_PLUGIN", so, 0);
}

/* dem_open_streamed: the rows dem_open gives, bit for bit, read in order
 * while the fill goes on, or last row first (which waits for the whole
 * fill); closed at once, it stops the fill. */
static void
check_streamed(void)
{
	const char *path = dpath("N48W125.hgt");
	tl_err e = { "" };
	dem *a = dem_open(path, NULL, &e), *b;
	int w, h, same = 1;
	float *za, *zb;
	unsigned char *va, *vb;

	if (!ok(a != NULL, "streamed: N48W125 opens (%s)", e.msg))
		return;
	w = dem_georef(a)->width, h = dem_georef(a)->height;
	za = malloc((size_t)w * 4), zb = malloc((size_t)w * 4);
	va = malloc((size_t)w), vb = malloc((size_t)w);
	for (int pass = 0; pass < 2; pass++) {
		if ((b = dem_open_streamed(path, NULL, &e)) == NULL) {
			same = 0;
			break;
		}
		for (int k = 0; k < h && same; k++) {
			int j = pass == 0 ? k : h - 1 - k;
			same = dem_read_row(a, j, za, va, &e) == 0 &&
			    dem_read_row(b, j, zb, vb, &e) == 0 &&
			    memcmp(za, zb, (size_t)w * 4) == 0 &&
			    memcmp(va, vb, (size_t)w) == 0;
		}
		dem_close(b);
	}
	ok(same, "streamed: every row and mask as dem_open's, in order and "
	    "last first");
	b = dem_open_streamed(path, NULL, &e);
	dem_close(b);
	ok(b != NULL, "streamed: closed at once, the fill stopped");
	free(za), free(zb), free(va), free(vb);
	dem_close(a);
}

int
main(void)
{
	find_top();
	check_pairs();  /* first: the RSS check must precede the plugin */
	check_ground();
	check_vertex_crs();
	check_header_roundtrip();
	check_fuji();
	check_stdin();
	check_streamed();
	if (make_fixtures() == 0) {
		check_formats();
		check_fill();
		check_cols();
		check_fixture_georef();
		check_failures();
		check_plugin_tiled();
		check_exr();
		check_sizes(); /* after check_exr: its z.exr */
	} else {
		ok(1, "# SKIP GDAL fixtures: /usr/bin/python3 with python3-gdal "
		    "and python3-numpy not available");
	}
	remove_fixtures();
	return tap_done();
}
