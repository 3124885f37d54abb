/* t_vdatum - heights converted between vertical datums through PROJ:
 * EGM96 undulations against cs2cs / gdaltransform on the SRTM tiles'
 * grids and bigtujunga's UTM grid, both directions; refusals (a missing
 * geoid grid, a ballpark-only operation, no declared datum, no CRS,
 * a target in feet, no height from PROJ); units of vertical CRSs;
 * identity and NaN; the lattice against PROJ at every sample of whole
 * rows, where EGM96 bends most; rows in pieces; the cost per sample of
 * 3601-wide rows (not asserted). Assumes Debian's proj-data: EGM96
 * (egm96_15.gtx) present, EGM2008 and the US geoids absent. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <proj.h>

#include "geo/vdatum.h"
#include "tap.h"

/* A SRTM tile's grid: EPSG:4326, PixelIsPoint, origin at its NW sample. */
static georef
srtm(double lon, double lat, int n)
{
	georef g;

	memset(&g, 0, sizeof g);
	g.model = GEO_GEOGRAPHIC;
	g.epsg = 4326;
	strcpy(g.crs, "EPSG:4326");
	g.point = 1;
	g.origin[0] = lon, g.origin[1] = lat;
	g.step[0] = 1.0 / (n - 1), g.step[1] = -1.0 / (n - 1);
	g.width = g.height = n;
	return g;
}

/* bigtujunga.tif (gdalinfo): EPSG:32611, PixelIsArea, 30 m. */
static georef
bigtujunga(void)
{
	georef g;

	memset(&g, 0, sizeof g);
	g.model = GEO_PROJECTED;
	g.epsg = 32611;
	strcpy(g.crs, "EPSG:32611");
	g.point = 0;
	g.origin[0] = 376313.655454263498541;
	g.origin[1] = 3807917.827628375496715;
	g.step[0] = 30, g.step[1] = -30;
	g.unit = 1;
	g.width = 1197, g.height = 643;
	return g;
}

static double
now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + t.tv_nsec * 1e-9;
}

static int
has(const char *msg, const char *s)
{
	return strstr(msg, s) != NULL;
}

/* The height vdatum_apply gives sample (i, j) whose height is h. */
static double
shifted(vdatum_shift *v, int i, int j, float h)
{
	tl_err e = { "" };

	if (vdatum_apply(v, j, i, 1, &h, &e) < 0) {
		printf("# %s\n", e.msg);
		return NAN;
	}
	return h;
}

/* Oracle undulations N (EGM96 height 0 -> ellipsoidal height N), from
 *   echo "LAT LON 0" | cs2cs -d 6 EPSG:4326+5773 EPSG:4979
 *   echo "LON LAT 0" | gdaltransform -s_srs EPSG:4326+5773 -t_srs EPSG:4979
 * and for the UTM points
 *   echo "E N 0" | cs2cs -d 6 EPSG:32611+5773 EPSG:4979
 *   echo "E N 0" | gdaltransform -s_srs EPSG:32611+5773 -t_srs EPSG:4979
 * (PROJ 9.1.1, GDAL 3.6, proj-data's egm96_15.gtx; both tools agree to
 * the digits shown). */
static const struct {
	const char *what;
	double lon0, lat0; /* the tile's NW corner */
	int n, i, j;       /* grid size, sample */
	double N;
} geo_pts[] = {
	/* lon -71.5 lat 44.5: cs2cs -27.622223, gdaltransform -27.6222229 */
	{ "N44W072 centre", -72, 45, 1201, 600, 600, -27.622223 },
	/* lon 1.25 lat 42.25: cs2cs 51.541721, gdaltransform 51.5417213 */
	{ "N42E001 (300, 900)", 1, 43, 1201, 300, 900, 51.541721 },
	/* lon -124.65722222222222 lat 48.34861111111111:
	 * cs2cs -20.546155, gdaltransform -20.5461545 */
	{ "N48W125 (1234, 2345)", -125, 49, 3601, 1234, 2345, -20.546155 },
};

static const struct {
	int i, j;
	double N;
} utm_pts[] = {
	/* E 394268.6554542635 N 3798272.8276283755 (lon -118.149229,
	 * lat 34.320334): cs2cs -33.303748, gdaltransform -33.3037478 */
	{ 598, 321, -33.303748 },
	/* E 406328.6554542635 N 3804902.8276283755 (lon -118.018887,
	 * lat 34.381277): cs2cs -32.878993, gdaltransform -32.8789934 */
	{ 1000, 100, -32.878993 },
};

static void
test_egm96(void)
{
	tl_err e = { "" };
	vdatum_shift *v, *back;
	georef g;
	double h;

	for (size_t k = 0; k < sizeof geo_pts / sizeof geo_pts[0]; k++) {
		g = srtm(geo_pts[k].lon0, geo_pts[k].lat0, geo_pts[k].n);
		v = vdatum_open(&g, "EPSG:5773", "ellipsoid", &e);
		back = vdatum_open(&g, "ellipsoid", "EPSG:5773", &e);
		if (!ok(v != NULL && back != NULL, "%s: EGM96 <-> ellipsoid "
		    "opens", geo_pts[k].what)) {
			printf("# %s\n", e.msg);
			vdatum_close(v);
			continue;
		}
		if (k == 0)
			printf("# EGM96 -> ellipsoid: \"%s\"; back: \"%s\"\n",
			    vdatum_operation_name(v), vdatum_operation_name(back));
		h = shifted(v, geo_pts[k].i, geo_pts[k].j, 250);
		ok(fabs(h - 250 - geo_pts[k].N) < 0.05, "%s: 250 m EGM96 = "
		    "%.4f m ellipsoidal (cs2cs: N = %.4f)", geo_pts[k].what, h,
		    geo_pts[k].N);
		h = shifted(back, geo_pts[k].i, geo_pts[k].j, 250);
		ok(fabs(h - 250 + geo_pts[k].N) < 0.05, "%s: 250 m "
		    "ellipsoidal = %.4f m EGM96", geo_pts[k].what, h);
		ok(strcmp(vdatum_target_name(v), "EPSG:4979") == 0 &&
		    strcmp(vdatum_target_name(back), "EPSG:5773") == 0,
		    "%s: targets named %s, %s", geo_pts[k].what,
		    vdatum_target_name(v), vdatum_target_name(back));
		vdatum_close(v);
		vdatum_close(back);
	}
}

static void
test_utm(void)
{
	tl_err e = { "" };
	georef g = bigtujunga();
	vdatum_shift *v = vdatum_open(&g, "EPSG:5773", "ellipsoid", &e);
	vdatum_shift *back = vdatum_open(&g, "ellipsoid", "EPSG:5773", &e);
	double h;

	if (!ok(v != NULL && back != NULL, "UTM 11N: EGM96 <-> ellipsoid "
	    "opens")) {
		printf("# %s\n", e.msg);
		vdatum_close(v);
		return;
	}
	printf("# UTM: \"%s\"; back: \"%s\"\n", vdatum_operation_name(v),
	    vdatum_operation_name(back));
	for (size_t k = 0; k < sizeof utm_pts / sizeof utm_pts[0]; k++) {
		h = shifted(v, utm_pts[k].i, utm_pts[k].j, 1000);
		ok(fabs(h - 1000 - utm_pts[k].N) < 0.05, "UTM (%d, %d): 1000 "
		    "m EGM96 = %.4f m ellipsoidal (cs2cs: N = %.4f)",
		    utm_pts[k].i, utm_pts[k].j, h, utm_pts[k].N);
		h = shifted(back, utm_pts[k].i, utm_pts[k].j, 1000);
		ok(fabs(h - 1000 + utm_pts[k].N) < 0.05, "UTM (%d, %d): 1000 "
		    "m ellipsoidal = %.4f m EGM96", utm_pts[k].i,
		    utm_pts[k].j, h);
	}
	vdatum_close(v);
	vdatum_close(back);
}

/* The exact heights, straight from PROJ (crs_to_crs picks the EGM96
 * grid operation when the grid is there), for rows j of g. */
typedef struct {
	PJ_CONTEXT *ctx;
	PJ *op;
} oracle;

static int
oracle_open(oracle *o, const char *src)
{
	PJ *op;

	o->ctx = proj_context_create();
	op = proj_create_crs_to_crs(o->ctx, src, "EPSG:4979", NULL);
	o->op = op != NULL ? proj_normalize_for_visualization(o->ctx, op) :
	    NULL;
	proj_destroy(op);
	return o->op != NULL ? 0 : -1;
}

static void
oracle_close(oracle *o)
{
	proj_destroy(o->op);
	proj_context_destroy(o->ctx);
}

static void
oracle_row(oracle *o, const georef *g, int j, const float *z, double *x,
    double *y, double *h)
{
	for (int i = 0; i < g->width; i++) {
		geo_vertex_crs(g, 0, i, j, &x[i], &y[i]);
		h[i] = z[i];
	}
	proj_trans_generic(o->op, PJ_FWD, x, sizeof *x, g->width, y,
	    sizeof *y, g->width, h, sizeof *h, g->width, NULL, 0, 0);
}

/* Largest |vdatum_apply - PROJ| over every every-th row of g and every row
 * within 12 of row `near` (whole rows, heights 0..999 with NaN between).
 * Also the exact cost per sample. */
static double
lattice_error(const georef *g, const char *src, int every, int near,
    double *ns, int *nan_ok)
{
	tl_err e = { "" };
	vdatum_shift *v = vdatum_open(g, "EPSG:5773", "ellipsoid", &e);
	float *z = calloc(g->width, sizeof *z);
	double *x = calloc(g->width, sizeof *x), *y, *h, worst = 0, t = 0,
	    t0;
	oracle o;
	int rows = 0;

	y = calloc(g->width, sizeof *y), h = calloc(g->width, sizeof *h);
	*nan_ok = 1;
	if (v == NULL || z == NULL || x == NULL || y == NULL || h == NULL ||
	    oracle_open(&o, src) < 0) {
		printf("# %s\n", v == NULL ? e.msg : "no memory or PROJ");
		return INFINITY;
	}
	for (int j = 0; j < g->height; j++) {
		if (j % every != 0 && abs(j - near) > 12)
			continue;
		rows++;
		for (int i = 0; i < g->width; i++)
			z[i] = (float)((i * 7 + j) % 1000);
		t0 = now();
		oracle_row(&o, g, j, z, x, y, h);
		t += now() - t0;
		for (int i = 0; i < g->width; i++)
			z[i] = i % 11 == 5 ? NAN : z[i];
		if (vdatum_apply(v, j, 0, g->width, z, &e) < 0) {
			printf("# %s\n", e.msg);
			worst = INFINITY;
			break;
		}
		for (int i = 0; i < g->width; i++)
			if (i % 11 == 5)
				*nan_ok &= isnan(z[i]);
			else
				worst = fmax(worst, fabs(z[i] - h[i]));
	}
	*ns = t / ((double)rows * g->width) * 1e9;
	oracle_close(&o);
	vdatum_close(v);
	free(z), free(x), free(y), free(h);
	return worst;
}

/* The lattice against PROJ at every sample of whole rows. Tenerife, 1"
 * samples: EGM96's slope jumps most there (2.2e-4 across the grid line
 * at 28.25N; 2.0e-4 across -16.75); the tile is moved by 2 samples so
 * that these lines fall mid-cell of the lattice (on SRTM's own grid they
 * fall on nodes, 900 samples apart, and cost nothing): the worst case,
 * about h ds / 4 = 124 m * 2.2e-4 / 4 = 7 mm. Then N48W125 (1") and
 * bigtujunga (UTM). The bound: 1.4 cm (vdatum.c), plus the float
 * rounding of heights up to 1000 m (3e-5). */
static void
test_lattice(void)
{
	static const struct {
		const char *what, *src;
		double lon, lat;
		int every, near;
	} tiles[] = {
		{ "Tenerife (1\", lines mid-cell)", "EPSG:4326+5773",
		    -17 - 2 / 3600.0, 29 + 2 / 3600.0, 7, 2702 },
		{ "N48W125", "EPSG:4326+5773", -125, 49, 3, -100 },
		{ "bigtujunga (UTM 11N)", "EPSG:32611+5773", 0, 0, 1, -100 },
	};
	georef g;
	double err, ns = 0;
	int nan_ok;

	for (size_t k = 0; k < sizeof tiles / sizeof tiles[0]; k++) {
		g = k < 2 ? srtm(tiles[k].lon, tiles[k].lat, 3601) :
		    bigtujunga();
		err = lattice_error(&g, tiles[k].src, tiles[k].every,
		    tiles[k].near, &ns, &nan_ok);
		ok(err < 0.014, "%s: lattice within %.4f m of PROJ at every "
		    "sample (bound 0.014)", tiles[k].what, err);
		ok(nan_ok, "%s: NaN samples stay NaN", tiles[k].what);
		printf("# %s: PROJ exact costs %.1f ns per sample\n",
		    tiles[k].what, ns);
	}
}

/* Pieces of a row, in any order, give what the whole row gives. */
static void
test_pieces(void)
{
	tl_err e = { "" };
	georef g = srtm(-125, 49, 3601);
	vdatum_shift *v = vdatum_open(&g, "EPSG:5773", "ellipsoid", &e);
	float whole[3601], part[3601];
	int same = 1;

	if (!ok(v != NULL, "N48W125: opens")) {
		printf("# %s\n", e.msg);
		return;
	}
	for (int j = 3600; j >= 0; j -= 97) {
		for (int i = 0; i < 3601; i++)
			whole[i] = part[i] = (float)(i % 500);
		vdatum_apply(v, j, 0, 3601, whole, &e);
		for (int i1 = 3601, i0; i1 > 0; i1 = i0) {
			i0 = i1 > 301 ? i1 - 301 : 0;
			vdatum_apply(v, j, i0, i1 - i0, part + i0, &e);
		}
		same &= memcmp(whole, part, sizeof whole) == 0;
	}
	ok(same, "rows converted in pieces, bottom up, = whole rows");
	/* Past the grid: PROJ, exactly. */
	ok(fabs(shifted(v, -5, 3700, 0) - shifted(v, 0, 3600, 0)) < 0.5,
	    "samples past the grid still convert");
	vdatum_close(v);
}

/* Where PROJ gives HUGE_VAL (here latitude 2826 degrees), vdatum_apply fails
 * rather than store it; NaN samples there need nothing. */
static void
test_huge(void)
{
	tl_err e = { "" };
	georef g = srtm(-125, 49, 3601);
	vdatum_shift *v = vdatum_open(&g, "EPSG:5773", "ellipsoid", &e);
	float z[2] = { 100, 200 }, w[2] = { NAN, NAN };

	if (!ok(v != NULL, "N48W125: opens")) {
		printf("# %s\n", e.msg);
		return;
	}
	ok(vdatum_apply(v, -10000000, 0, 2, z, &e) < 0 &&
	    has(e.msg, "no height") && z[0] == 100 && z[1] == 200,
	    "no height from PROJ: refused, heights untouched");
	printf("# %s\n", e.msg);
	ok(vdatum_apply(v, -10000000, 0, 2, w, &e) == 0 && isnan(w[0]),
	    "no height needed for NaN");
	vdatum_close(v);
}

/* The DEM's CRS as WKT2 (what GDAL gives for a CRS without one code)
 * works as its code does. */
static void
test_wkt(void)
{
	PJ_CONTEXT *ctx = proj_context_create();
	PJ *crs = proj_create(ctx, "EPSG:32611");
	const char *opts[] = { "MULTILINE=NO", NULL }, *wkt;
	tl_err e = { "" };
	georef g = bigtujunga();
	vdatum_shift *v;
	double h;

	wkt = proj_as_wkt(ctx, crs, PJ_WKT2_2019, opts);
	snprintf(g.crs, sizeof g.crs, "%s", wkt != NULL ? wkt : "");
	g.epsg = 0;
	v = vdatum_open(&g, "EPSG:5773", "EPSG:4979", &e);
	if (ok(v != NULL, "UTM 11N as WKT2: opens")) {
		h = shifted(v, utm_pts[0].i, utm_pts[0].j, 1000);
		ok(fabs(h - 1000 - utm_pts[0].N) < 0.05, "UTM 11N as WKT2: "
		    "1000 m EGM96 = %.4f m ellipsoidal", h);
	} else
		printf("# %s\n", e.msg);
	vdatum_close(v);
	proj_destroy(crs);
	proj_context_destroy(ctx);
}

static void
test_refusals(void)
{
	tl_err e = { "" };
	georef g = srtm(-72, 45, 1201), sp = srtm(1, 43, 1201), none;
	vdatum_shift *v;

	v = vdatum_open(&g, "EPSG:5773", "EPSG:3855", &e);
	ok(v == NULL && has(e.msg, "egm08") && has(e.msg, "PROJ_DATA"),
	    "EGM96 -> EGM2008 refused, naming the missing grid");
	printf("# %s\n", e.msg);
	vdatum_close(v);

	v = vdatum_open(&g, "EPSG:3855", "ellipsoid", &e);
	ok(v == NULL && has(e.msg, "egm08") &&
	    has(e.msg, "EPSG:3855 to EPSG:4979"),
	    "EGM2008 -> ellipsoid refused, naming the missing grid");

	/* NAVD88 in Vermont: only geoid grids Debian lacks (GEOID99..18). */
	v = vdatum_open(&g, "EPSG:5703", "ellipsoid", &e);
	ok(v == NULL && has(e.msg, "needs the grid") && has(e.msg, "us_noaa"),
	    "NAVD88 -> ellipsoid in the US refused, naming a NOAA geoid grid");
	printf("# %s\n", e.msg);

	/* NAVD88 in the Pyrenees: PROJ has only its ballpark (zero). */
	v = vdatum_open(&sp, "EPSG:5703", "ellipsoid", &e);
	ok(v == NULL && has(e.msg, "ballpark"), "NAVD88 in Spain refused: "
	    "only a ballpark operation");
	printf("# %s\n", e.msg);

	v = vdatum_open(&g, NULL, "ellipsoid", &e);
	ok(v == NULL && has(e.msg, "declares no vertical datum") &&
	    has(e.msg, "-D EPSG:5773"), "no declared datum: the -D hint");
	v = vdatum_open(&g, "", "EPSG:5773", &e);
	ok(v == NULL && has(e.msg, "-D"), "empty declared datum: the -D hint");
	printf("# %s\n", e.msg);

	v = vdatum_open(&g, "EGM96 (SRTM)", "ellipsoid", &e);
	ok(v == NULL && has(e.msg, "not a vertical CRS"), "a citation is "
	    "not a vertical CRS");
	v = vdatum_open(&g, "EPSG:4326", "ellipsoid", &e);
	ok(v == NULL && has(e.msg, "not a vertical CRS"), "EPSG:4326 is "
	    "not a vertical CRS");

	v = vdatum_open(&g, "EPSG:5703", "EPSG:6360", &e);
	ok(v == NULL && has(e.msg, "metres"), "a target in feet refused");

	geo_init_none(&none, 30, 30);
	v = vdatum_open(&none, "EPSG:5773", "ellipsoid", &e);
	ok(v == NULL && has(e.msg, "no horizontal CRS"), "no CRS: refused");
	printf("# %s\n", e.msg);
}

static void
test_units(void)
{
	tl_err e = { "" };

	ok(fabs(vdatum_unit_of("EPSG:6360", &e) - 1200.0 / 3937) < 1e-12,
	    "EPSG:6360 (NAVD88 ftUS): %.15g m", vdatum_unit_of("EPSG:6360", &e));
	ok(fabs(vdatum_unit_of("EPSG:8228", &e) - 0.3048) < 1e-12,
	    "EPSG:8228 (NAVD88 ft): %.15g m", vdatum_unit_of("EPSG:8228", &e));
	ok(vdatum_unit_of("EPSG:5773", &e) == 1, "EPSG:5773: 1 m");
	ok(vdatum_unit_of("ellipsoid", &e) == 1, "ellipsoid: 1 m");
	ok(vdatum_unit_of("EPSG:4326+5773", &e) == 1, "a compound CRS: its "
	    "vertical part");
	ok(vdatum_unit_of("EPSG:32611", &e) < 0 && has(e.msg, "not a vertical"),
	    "EPSG:32611 has no height unit");
	ok(vdatum_unit_of(NULL, &e) < 0, "NULL has no height unit");
}

/* Same datum, units aside: heights in metres need nothing. */
static void
test_identity(void)
{
	static const char *pairs[][2] = {
		{ "EPSG:5773", "EPSG:5773" }, { "ellipsoid", "EPSG:4979" },
		{ "EPSG:6360", "EPSG:5703" }, { "EPSG:4326+5773", "EPSG:5773" },
	};
	tl_err e = { "" };
	georef g = srtm(-72, 45, 1201), none;
	float z[4] = { 1.5f, NAN, -3, 1e6f }, w[4];
	vdatum_shift *v;

	geo_init_none(&none, 30, 30);
	for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
		v = vdatum_open(k == 0 ? &none : &g, pairs[k][0], pairs[k][1], &e);
		memcpy(w, z, sizeof w);
		ok(v != NULL && vdatum_apply(v, 5, 7, 4, w, &e) == 0 &&
		    memcmp(w, z, sizeof w) == 0 &&
		    strcmp(vdatum_operation_name(v), "identity") == 0,
		    "%s -> %s: identity, nothing changes", pairs[k][0],
		    pairs[k][1]);
		if (v == NULL)
			printf("# %s\n", e.msg);
		vdatum_close(v);
	}
}

/* A source in feet: vdatum_apply takes metres, the operation feet. A WKT
 * vertical CRS on the EGM96 datum in feet (not in EPSG). */
static void
test_feet(void)
{
	static const char *wkt = "VERTCRS[\"EGM96 height (ft)\","
	    "VDATUM[\"EGM96 geoid\"],CS[vertical,1],"
	    "AXIS[\"gravity-related height (H)\",up,"
	    "LENGTHUNIT[\"foot\",0.3048]]]";
	tl_err e = { "" };
	georef g = srtm(-72, 45, 1201);
	vdatum_shift *v;
	double h;

	ok(fabs(vdatum_unit_of(wkt, &e) - 0.3048) < 1e-12, "EGM96 in feet: "
	    "0.3048 m");
	v = vdatum_open(&g, wkt, "ellipsoid", &e);
	if (!ok(v != NULL, "EGM96 (ft) -> ellipsoid opens")) {
		printf("# %s\n", e.msg);
		return;
	}
	printf("# EGM96 (ft): \"%s\"\n", vdatum_operation_name(v));
	h = shifted(v, 600, 600, 250);
	ok(fabs(h - 250 - geo_pts[0].N) < 0.05, "250 m (given in metres) "
	    "EGM96 = %.4f m ellipsoidal", h);
	vdatum_close(v);
}

/* Not asserted: ns per sample converting a whole 3601-wide DEM, row
 * after row as the reader does. */
static void
cost(const char *what, const georef *g, const char *from, const char *to)
{
	tl_err e = { "" };
	vdatum_shift *v = vdatum_open(g, from, to, &e);
	float *z = calloc(g->width, sizeof *z);
	double t0, t = 0, ns;

	if (v == NULL || z == NULL) {
		printf("# cost %s: %s\n", what,
		    v == NULL ? e.msg : "no memory");
		vdatum_close(v);
		free(z);
		return;
	}
	for (int j = 0; j < g->height; j++) {
		for (int i = 0; i < g->width; i++)
			z[i] = (float)(i % 1000);
		t0 = now();
		if (vdatum_apply(v, j, 0, g->width, z, &e) < 0) {
			printf("# cost %s: %s\n", what, e.msg);
			break;
		}
		t += now() - t0;
	}
	ns = t / ((double)g->height * g->width) * 1e9;
	printf("# cost %s: %.1f ns per sample, %.3f s for the %dx%d DEM\n",
	    what, ns, t, g->width, g->height);
	vdatum_close(v);
	free(z);
}

static void
test_cost(void)
{
	georef g = srtm(-125, 49, 3601), u = bigtujunga();

	u.width = u.height = 3601;
	cost("EPSG:4326, EGM96 -> ellipsoid", &g, "EPSG:5773", "ellipsoid");
	cost("EPSG:4326, ellipsoid -> EGM96", &g, "ellipsoid", "EPSG:5773");
	cost("UTM 11N, EGM96 -> ellipsoid", &u, "EPSG:5773", "ellipsoid");
	cost("UTM 11N, ellipsoid -> EGM96", &u, "ellipsoid", "EPSG:5773");
}

int
main(void)
{
	/* Grids fetched from the network would make this test depend on
	 * it; vdatum_open honours PROJ_NETWORK like any PROJ program. */
	unsetenv("PROJ_NETWORK");
	test_egm96();
	test_utm();
	test_lattice();
	test_pieces();
	test_huge();
	test_wkt();
	test_refusals();
	test_units();
	test_identity();
	test_feet();
	test_cost();
	return tap_done();
}
