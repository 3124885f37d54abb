/* t_ground.c - the ground embedding (georef.h) on real data: N44W072.hgt
 * of ../shared/data (or $DATA) warped by gdalwarp to Web Mercator, UTM 19N
 * and Arctic polar stereographic, and the geographic original. Distances
 * the metric gives between samples a quarter block apart (along a row, a
 * column, both diagonals) and along a whole column must agree within
 * 0.1 % with the WGS84 geodesics between the same samples: their latitude
 * and longitude from gdaltransform, the distance from GeodSolve
 * (GeographicLib's own tool). Geographic metrics must be exactly the
 * per-row geodesics they always were (the pyramids stay byte-identical). */
#include <jansson.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "geo/geodesy.h"
#include "geo/georef.h"
#include "tap.h"

#define QUARTER 32 /* level-0 samples: a quarter of a 128-cell block */
#define MAXP 64    /* sample pairs per grid */

static char data[PATH_MAX + 32], tmp[PATH_MAX];

static double
now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + t.tv_nsec * 1e-9;
}

static const char *
tpath(const char *name)
{
	static char p[4][PATH_MAX + 64];
	static int k;

	k = (k + 1) % 4;
	snprintf(p[k], sizeof p[k], "%s/%s", tmp, name);
	return p[k];
}

static int
run(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

static int
run(const char *fmt, ...)
{
	char cmd[4 * PATH_MAX];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(cmd, sizeof cmd, fmt, ap);
	va_end(ap);
	return system(cmd) == 0 ? 0 : -1;
}

/* A georef from gdalinfo -json of a north-up GeoTIFF (pixel is area). */
static int
grid_of(const char *file, const char *crs, enum geo_model model, georef *g,
    char *wkt, size_t nwkt)
{
	char cmd[2 * PATH_MAX];
	json_t *j, *gt, *size, *w;
	FILE *f;
	int r = -1;

	snprintf(cmd, sizeof cmd, "gdalinfo -json '%s'", file);
	if ((f = popen(cmd, "r")) == NULL)
		return -1;
	j = json_loadf(f, 0, NULL);
	pclose(f);
	gt = json_object_get(j, "geoTransform");
	size = json_object_get(j, "size");
	w = json_object_get(json_object_get(j, "coordinateSystem"), "wkt");
	memset(g, 0, sizeof *g);
	if (json_array_size(gt) == 6 && json_array_size(size) == 2 &&
	    json_real_value(json_array_get(gt, 5)) < 0) {
		g->model = model;
		snprintf(g->crs, sizeof g->crs, "%s", crs);
		g->origin[0] = json_real_value(json_array_get(gt, 0));
		g->origin[1] = json_real_value(json_array_get(gt, 3));
		g->step[0] = json_real_value(json_array_get(gt, 1));
		g->step[1] = json_real_value(json_array_get(gt, 5));
		g->unit = model == GEO_GEOGRAPHIC ? 0 : 1;
		g->width = (int)json_integer_value(json_array_get(size, 0));
		g->height = (int)json_integer_value(json_array_get(size, 1));
		if (wkt != NULL)
			snprintf(wkt, nwkt, "%s", json_string_value(w) ?
			    json_string_value(w) : "");
		r = 0;
	}
	json_decref(j);
	return r;
}

/* Two samples (level-0 columns and rows) and what lies between them. */
typedef struct {
	double I0, J0, I1, J1;
	const char *kind;
	double metric, geodesic;
} pair;

/* Metres the metric puts between the pair's samples: along the row, along
 * the column, else through the local frame of the first one. */
static double
ground_distance(const geo_ground *m, const pair *p)
{
	double q[2];

	if (p->J0 == p->J1)
		return fabs(geo_x(m, p->I0, p->I1, p->J0));
	if (p->I0 == p->I1)
		return fabs(geo_y(m, p->I0, p->J1) - geo_y(m, p->I0, p->J0));
	geo_local(m, p->I0, p->J0, p->I1, p->J1, q);
	return hypot(q[0], q[1]);
}

/* Quarter-block pairs from a few places, and a whole middle column. */
static int
make_pairs(const georef *g, pair *p)
{
	static const double at[][2] = { { 0.2, 0.2 }, { 0.5, 0.5 },
		{ 0.8, 0.3 }, { 0.3, 0.8 } };
	static const struct {
		int di, dj;
		const char *kind;
	} d[] = { { QUARTER, 0, "row" }, { 0, QUARTER, "column" },
		{ QUARTER, QUARTER, "diagonal" }, { QUARTER, -QUARTER,
		"diagonal" } };
	int n = 0;

	for (size_t a = 0; a < sizeof at / sizeof at[0]; a++)
		for (size_t k = 0; k < sizeof d / sizeof d[0]; k++) {
			double I = floor(at[a][0] * (g->width - 1 - QUARTER));
			double J = floor(at[a][1] * (g->height - 1 - QUARTER)) +
			    (d[k].dj < 0 ? QUARTER : 0);
			p[n++] = (pair){ I, J, I + d[k].di, J + d[k].dj,
				d[k].kind, 0, 0 };
		}
	p[n++] = (pair){ g->width / 2, 0, g->width / 2, g->height - 1,
		"whole column", 0, 0 };
	return n;
}

/* WGS84 geodesics between the pairs' sample centres: gdaltransform for
 * latitude and longitude (unless the grid is in degrees), GeodSolve -i. */
static int
geodesics(const georef *g, pair *p, int n)
{
	FILE *f;
	double ll[2 * MAXP][2];

	if ((f = fopen(tpath("xy"), "w")) == NULL)
		return -1;
	for (int k = 0; k < n; k++)
		for (int e = 0; e < 2; e++) {
			double I = e ? p[k].I1 : p[k].I0;
			double J = e ? p[k].J1 : p[k].J0;
			fprintf(f, "%.17g %.17g\n", g->origin[0] + (I + 0.5) *
			    g->step[0], g->origin[1] + (J + 0.5) * g->step[1]);
		}
	fclose(f);
	if (g->model == GEO_GEOGRAPHIC ? run("cp '%s' '%s'", tpath("xy"),
	    tpath("ll")) < 0 : run("gdaltransform -s_srs '%s' -t_srs "
	    "EPSG:4326 < '%s' > '%s'", g->crs, tpath("xy"), tpath("ll")) < 0)
		return -1;
	if ((f = fopen(tpath("ll"), "r")) == NULL)
		return -1;
	for (int k = 0; k < 2 * n; k++)
		if (fscanf(f, "%lf %lf%*[^\n]", &ll[k][0], &ll[k][1]) != 2) {
			fclose(f);
			return -1;
		}
	fclose(f);
	if ((f = fopen(tpath("in"), "w")) == NULL)
		return -1;
	for (int k = 0; k < n; k++) /* GeodSolve: lat1 lon1 lat2 lon2 */
		fprintf(f, "%.15f %.15f %.15f %.15f\n", ll[2 * k][1],
		    ll[2 * k][0], ll[2 * k + 1][1], ll[2 * k + 1][0]);
	fclose(f);
	if (run("GeodSolve -i -p 9 < '%s' > '%s'", tpath("in"),
	    tpath("out")) < 0 || (f = fopen(tpath("out"), "r")) == NULL)
		return -1;
	for (int k = 0; k < n; k++)
		if (fscanf(f, "%*f %*f %lf", &p[k].geodesic) != 1) {
			fclose(f);
			return -1;
		}
	fclose(f);
	return 0;
}

/* The metric of grid g against geodesics: the worst |ratio - 1| of each
 * kind of pair; naive_expect > 0: what CRS units alone would give. */
static void
check_grid(const char *name, const georef *g, double naive_expect)
{
	pair p[MAXP];
	geo_ground m;
	tl_err e = { "" };
	int n = make_pairs(g, p);
	double worst[4] = { 0 }, naive = 0;
	double lo[4] = { INFINITY, INFINITY, INFINITY, INFINITY };
	double hi[4] = { 0 };
	static const char *kinds[4] = { "row", "column", "diagonal",
		"whole column" };

	if (!ok(geo_ground_init(&m, g, &e) == 0, "%s: metric %s", name,
	    e.msg))
		return;
	if (!ok(geodesics(g, p, n) == 0, "%s: gdaltransform and GeodSolve",
	    name)) {
		geo_ground_free(&m);
		return;
	}
	for (int k = 0; k < n; k++) {
		double r = ground_distance(&m, &p[k]) / p[k].geodesic - 1;
		int t = 0;
		while (t < 3 && strcmp(kinds[t], p[k].kind) != 0)
			t++;
		worst[t] = fmax(worst[t], fabs(r));
		lo[t] = fmin(lo[t], 1 + r), hi[t] = fmax(hi[t], 1 + r);
		if (p[k].J0 == p[k].J1) /* the old metric: CRS units */
			naive = fabs(p[k].I1 - p[k].I0) * fabs(g->step[0]) *
			    g->unit / p[k].geodesic;
	}
	printf("# %s: metric / geodesic:", name);
	for (int t = 0; t < 4; t++)
		printf(" %s %.7f..%.7f,", kinds[t], lo[t], hi[t]);
	printf(" CRS units / geodesic %.4f\n", naive);
	for (int t = 0; t < 4; t++)
		ok(worst[t] < 1e-3, "%s: %s distances within %.2g %% of WGS84 "
		    "geodesics (0.1 %% allowed)", name, kinds[t],
		    100 * worst[t]);
	if (naive_expect > 0)
		ok(fabs(naive / naive_expect - 1) < 0.02, "%s: the CRS's units "
		    "alone would give %.4f x the ground distance, the metric "
		    "1 +- %.1e", name, naive, fmax(worst[0], worst[2]));
	geo_ground_free(&m);
}

/* fqm_y as it was: rows past the last continue its spacing. */
static double
old_y(const double *y, int H, long J)
{
	return J < H ? y[J] : y[H - 1] + (double)(J - H + 1) * (y[H - 1] -
	    y[H - 2]);
}

/* The per-row geodesics the metric always had for geographic grids,
 * recomputed here as it did, with fqm_grid_scale's row spacing; rows past
 * the end continue the last spacing, fractional rows interpolate (the
 * viewer's world). */
static void
check_geographic_exact(const georef *g)
{
	geo_ground m;
	tl_err e = { "" };
	int H = g->height, bad = 0;
	double *dx = calloc(H, sizeof *dx), *y = calloc(H, sizeof *y);
	double sx = fabs(g->step[0]);

	for (int j = 0; j < H; j++) {
		double lat = g->origin[1] + (j + 0.5) * g->step[1], d;
		double next = g->origin[1] + (j + 1.5) * g->step[1];
		geodesy_inverse(lat, 0, lat, sx, &dx[j]);
		if (j + 1 < H && geodesy_inverse(lat, 0, next, 0, &d) == 0)
			y[j + 1] = y[j] + d;
	}
	if (!ok(geo_ground_init(&m, g, &e) == 0, "geographic: metric %s",
	    e.msg))
		goto done;
	for (long j = 0; j < H + 300; j += j < H ? 1 : 7)
		for (double I = -3; I < g->width + 5; I += 397.25) {
			double s, t, sy = j > 0 ? (old_y(y, H, j + 1) -
			    old_y(y, H, j - 1)) / 2 : y[1] - y[0];
			geo_scale(&m, I, j, &s, &t);
			bad += geo_sx(&m, I, j) != dx[j < H ? j : H - 1] ||
			    geo_y(&m, I, j) != old_y(y, H, j) ||
			    s != dx[j < H ? j : H - 1] || t != sy;
		}
	for (double J = 0.25; J < H - 1; J += 97.5) {
		long j0 = (long)floor(J);
		double f = J - j0;
		bad += geo_y(&m, 7, J) != (1 - f) * y[j0] + f * y[j0 + 1] ||
		    geo_x(&m, 600, 3.5, J) != (3.5 - 600) * ((1 - f) * dx[j0] +
		    f * dx[j0 + 1]);
	}
	ok(bad == 0, "geographic: geo_sx, geo_y, geo_scale, geo_x are the "
	    "per-row geodesics dx[J], y[J] exactly, at any column, past the "
	    "last row and between rows (%d differ)", bad);
	geo_ground_free(&m);
done:
	free(dx), free(y);
}

/* The user's cell size overrides any CRS. */
static void
check_cell(const georef *g0)
{
	georef g = *g0;
	geo_ground m;
	int bad = 0;

	g.cell[0] = 25, g.cell[1] = 20;
	if (!ok(geo_ground_init(&m, &g, NULL) == 0, "cell size: metric"))
		return;
	for (int j = 0; j < g.height + 50; j += 13)
		bad += geo_sx(&m, j, j) != 25 ||
		    geo_y(&m, 3 * j, j) != j * 20.0;
	ok(bad == 0 && m.per_row, "geo:cell 25 x 20 on EPSG:3857: constant "
	    "metric, the CRS ignored");
	geo_ground_free(&m);
}

/* The same CRS as an EPSG code, WKT2 and a PROJ string: one metric. */
static void
check_crs_forms(const georef *g0, const char *wkt)
{
	const char *forms[] = { wkt, "+proj=utm +zone=19 +datum=WGS84 "
		"+units=m +no_defs" };
	geo_ground a, b;
	georef g = *g0;
	tl_err e = { "" };

	if (!ok(geo_ground_init(&a, g0, &e) == 0, "UTM 19N as EPSG:32619: "
	    "metric %s", e.msg))
		return;
	for (int k = 0; k < 2; k++) {
		double worst = 0;
		snprintf(g.crs, sizeof g.crs, "%s", forms[k]);
		if (!ok(geo_ground_init(&b, &g, &e) == 0, "UTM 19N as %s: "
		    "metric %s", k ? "a PROJ string" : "WKT2", e.msg))
			continue;
		for (int j = 0; j < g.height; j += 111)
			for (int i = 0; i < g.width; i += 97)
				worst = fmax(worst, fabs(geo_y(&a, i, j) -
				    geo_y(&b, i, j)) + fabs(geo_sx(&a, i, j) -
				    geo_sx(&b, i, j)));
		ok(worst < 1e-9, "UTM 19N as %s: the EPSG:32619 metric (max "
		    "dev %.2g m)", k ? "a PROJ string" : "WKT2", worst);
		geo_ground_free(&b);
	}
	geo_ground_free(&a);
}

/* A CRS PROJ does not know: a message, nothing printed. */
static void
check_bad_crs(const georef *g0)
{
	georef g = *g0;
	geo_ground m;
	tl_err e = { "" };
	off_t printed;
	int fd = dup(2), out = open(tpath("stderr"), O_CREAT | O_TRUNC |
	    O_WRONLY, 0600), r;

	snprintf(g.crs, sizeof g.crs, "EPSG:999999");
	fflush(stderr);
	dup2(out, 2);
	r = geo_ground_init(&m, &g, &e);
	fflush(stderr);
	dup2(fd, 2);
	printed = lseek(out, 0, SEEK_END);
	close(fd), close(out);
	ok(r < 0 && strncmp(e.msg, "CRS EPSG:999999: cannot", 23) == 0,
	    "unknown CRS: \"%s\"", e.msg);
	ok(printed == 0, "unknown CRS: PROJ prints nothing (%lld bytes)",
	    (long long)printed);
	g.crs[0] = '\0', g.epsg = 0;
	r = geo_ground_init(&m, &g, &e);
	ok(r < 0 && strncmp(e.msg, "CRS unknown: cannot", 19) == 0,
	    "projected grid without a CRS: \"%s\"", e.msg);
}

/* Init cost on an 8193 x 8193 UTM grid: the lattice is 257 x 257. */
static void
check_big(const georef *g0)
{
	georef g = *g0;
	geo_ground m;
	double t = now();

	g.width = g.height = 8193;
	g.step[0] = 10, g.step[1] = -10;
	if (!ok(geo_ground_init(&m, &g, NULL) == 0, "8193 x 8193 UTM metric"))
		return;
	t = now() - t;
	ok(m.nx <= 257 && m.ny <= 257 && t < 5, "8193 x 8193 UTM grid: %d x "
	    "%d lattice every %d samples, init %.3f s", m.nx, m.ny, m.cs, t);
	geo_ground_free(&m);
}

static void
setup(void)
{
	const char *d = getenv("DATA");
	char self[PATH_MAX];
	ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);

	if (d != NULL)
		snprintf(data, sizeof data, "%s", d);
	else if (n > 0 && (self[n] = '\0', strstr(self, "/build/tests/"))) {
		*strstr(self, "/build/tests/") = '\0';
		snprintf(data, sizeof data, "%s/../shared/data", self);
	} else
		snprintf(data, sizeof data, "../shared/data");
	snprintf(tmp, sizeof tmp, "%s/tmetric.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
}

int
main(void)
{
	static const struct {
		const char *crs, *name;
		double naive; /* the old metric's ratio to the ground */
	} crs[] = { { "EPSG:3857", "Web Mercator", 1.4 },
		{ "EPSG:32619", "UTM 19N", 0 },
		{ "EPSG:3995", "Arctic polar stereographic", 0 } };
	char src[PATH_MAX + 64], wkt[4096] = "";
	georef g = { 0 }, utm;

	setup();
	snprintf(src, sizeof src, "%s/N44W072.hgt", data);
	if (access(src, R_OK) != 0 || mkdtemp(tmp) == NULL) {
		ok(1, "# SKIP %s not readable", src);
		return tap_done();
	}
	if (ok(grid_of(src, "EPSG:4326", GEO_GEOGRAPHIC, &g, NULL, 0) == 0,
	    "N44W072.hgt: gdalinfo")) {
		check_grid("geographic", &g, 0);
		check_geographic_exact(&g);
	}
	for (size_t k = 0; k < sizeof crs / sizeof crs[0]; k++) {
		char name[32];
		const char *out = (snprintf(name, sizeof name, "%s.tif",
		    crs[k].crs + 5), tpath(name));
		int r = run("gdalwarp -q -overwrite -t_srs %s '%s' '%s'",
		    crs[k].crs, src, out) == 0 ? grid_of(out, crs[k].crs,
		    GEO_PROJECTED, &g, wkt, sizeof wkt) : -1;
		if (!ok(r == 0, "N44W072.hgt warped to %s: %d x %d, %.2f m "
		    "pixels", crs[k].crs, g.width, g.height, g.step[0]))
			continue;
		check_grid(crs[k].name, &g, crs[k].naive);
		if (k == 0) {
			check_cell(&g);
			check_bad_crs(&g);
		}
		if (k == 1) {
			utm = g;
			check_crs_forms(&utm, wkt);
			check_big(&utm);
		}
	}
	run("rm -rf '%s'", tmp);
	return tap_done();
}
