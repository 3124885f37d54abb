/* t_georef - georeferencing (georef.h): model names, the geo:* header
 * attributes written and read back (and bad ones refused), the one
 * equality of georeferencings (geo_differs, field by field), vertex
 * positions in CRS coordinates, the hand-made GEO_NONE grid. */
#include "geo/georef.h"
#include "raster/attr_names.h"
#include "raster/raster.h"
#include "tap.h"

#include <math.h>
#include <string.h>

static void
test_models(void)
{
	static const char *const names[] = { "none", "projected",
		"geographic" };
	enum geo_model m;
	int bad = 0;

	for (int k = 0; k < 3; k++)
		bad += geo_model_parse(names[k], &m) != 0 || (int)m != k ||
		    strcmp(geo_model_name(m), names[k]) != 0;
	ok(bad == 0 && GEO_NONE == 0 && GEO_GEOGRAPHIC == 2, "geo_model_name "
	    "and geo_model_parse round-trip none, projected, geographic");
	m = GEO_PROJECTED;
	ok(geo_model_parse("Geographic", &m) < 0 &&
	    geo_model_parse("", &m) < 0 && m == GEO_PROJECTED, "an unknown model name is refused, the model "
	    "left as it was");
}

/* Every field set, none to its default. */
static void
sample(georef *g)
{
	memset(g, 0, sizeof *g);
	g->model = GEO_PROJECTED;
	g->epsg = 0;
	strcpy(g->crs, "PROJCRS[\"Lambert\",BASEGEOGCRS[\"NAD83\"]]");
	g->point = 1;
	g->origin[0] = -117.5, g->origin[1] = 34.25;
	g->step[0] = 0.5, g->step[1] = -0.25;
	g->unit = 0.3048006096012192;
	strcpy(g->vdatum, "EPSG:6360");
	g->cell[0] = 9.5, g->cell[1] = 7.25;
	g->has_nodata = 1;
	g->nodata = NAN;
	g->width = 1201, g->height = 643;
}

static void
test_header(void)
{
	georef g, back;
	rs_header h;
	tl_err e = { "" };
	const char *diff;
	int r;

	sample(&g);
	rs_header_init(&h, 4, 4);
	r = rs_put_georef(&g, &h, &e) == 0 &&
	    rs_set_v2i(&h, FQM_ATTR_SIZE0, g.width, g.height, &e) == 0 &&
	    rs_get_georef(&back, &h, &e) == 0;
	diff = geo_differs(&g, &back);
	ok(r && diff == NULL && back.width == 1201 && isnan(back.nodata),
	    "rs_put_georef then rs_get_georef: the same georeferencing, "
	    "a NaN nodata included (%s)", diff ? diff : r ? "same" : e.msg);
	ok(strcmp(rs_get_string(&h, GEO_ATTR_MODEL), "projected") == 0 &&
	    strcmp(rs_get_string(&h, GEO_ATTR_RASTER), "point") == 0,
	    "geo:model and geo:raster as names");
	g.cell[0] = g.cell[1] = 0, g.has_nodata = 0, g.vdatum[0] = '\0';
	rs_put_georef(&g, &h, &e);
	ok(rs_get_string(&h, GEO_ATTR_VDATUM) == NULL &&
	    rs_get_v2d(&h, GEO_ATTR_CELL, back.cell) < 0 &&
	    rs_get_double(&h, GEO_ATTR_NODATA, &back.nodata) < 0,
	    "geo:cell, geo:vdatum and geo:nodata removed when not declared");
	g.model = (enum geo_model)7;
	ok(rs_put_georef(&g, &h, &e) < 0 && strstr(e.msg, "bad model 7"),
	    "rs_put_georef: a model out of range refused (%s)", e.msg);
	rs_header_free(&h);
	rs_header_init(&h, 4, 4);
	ok(rs_get_georef(&back, &h, &e) == 0 && back.model == GEO_NONE &&
	    back.unit == 1 && back.point == 1, "no geo:* at all: GEO_NONE, "
	    "unit 1, point");
	rs_header_free(&h);
}

/* rs_get_georef refuses what cannot be a grid. */
static void
test_bad(void)
{
	static const struct {
		const char *attr, *want;
		int kind; /* 0 string, 1 v2d, 2 double */
		const char *s;
		double v[2];
	} cases[] = {
		{ GEO_ATTR_MODEL, "geo:model: unknown value", 0, "flat",
		    { 0 } },
		{ GEO_ATTR_RASTER, "geo:raster: unknown value", 0, "pixel",
		    { 0 } },
		{ GEO_ATTR_STEP, "geo:step: invalid pixel size", 1, NULL,
		    { 0, -1 } },
		{ GEO_ATTR_STEP, "geo:step: invalid pixel size", 1, NULL,
		    { INFINITY, -1 } },
		{ GEO_ATTR_CELL, "geo:cell: invalid cell size", 1, NULL,
		    { 30, -2 } },
		{ GEO_ATTR_UNIT, "geo:unit: invalid value", 2, NULL, { 0 } },
	};
	georef g, back;
	rs_header h;
	tl_err e;
	int bad = 0;
	char big[5000];

	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		sample(&g);
		rs_header_init(&h, 4, 4);
		rs_put_georef(&g, &h, NULL);
		if (cases[k].kind == 0)
			rs_set_string(&h, cases[k].attr, cases[k].s, NULL);
		else if (cases[k].kind == 1)
			rs_set_v2d(&h, cases[k].attr, cases[k].v[0],
			    cases[k].v[1], NULL);
		else
			rs_set_double(&h, cases[k].attr, cases[k].v[0], NULL);
		e.msg[0] = '\0';
		if (rs_get_georef(&back, &h, &e) == 0 ||
		    strstr(e.msg, cases[k].want) != e.msg) {
			printf("# case %zu: %s\n", k, e.msg);
			bad++;
		}
		rs_header_free(&h);
	}
	ok(bad == 0, "rs_get_georef refuses unknown names, zero or "
	    "infinite steps, a negative cell, a zero unit");
	memset(big, 'A', sizeof big - 1);
	big[sizeof big - 1] = '\0';
	rs_header_init(&h, 4, 4);
	rs_set_string(&h, GEO_ATTR_CRS, big, NULL);
	ok(rs_get_georef(&back, &h, &e) < 0 &&
	    strstr(e.msg, "geo:crs: too long (4999 bytes)"),
	    "a CRS longer than georef holds is refused (%s)", e.msg);
	rs_header_free(&h);
}

/* geo_differs names the first field that differs. */
static void
test_differs(void)
{
	georef a, b;
	int bad = 0;

#define FIELD(change, name) do { \
		sample(&a), sample(&b); \
		change; \
		const char *d = geo_differs(&a, &b); \
		if (d == NULL || strcmp(d, name) != 0) { \
			printf("# %s: %s\n", name, d ? d : "same"); \
			bad++; \
		} \
	} while (0)
	FIELD(b.model = GEO_GEOGRAPHIC, "model");
	FIELD(b.epsg = 2229, "crs");
	FIELD(b.crs[0] = 'Q', "crs");
	FIELD(b.point = 0, "raster");
	FIELD(b.origin[1] += 1e-9, "origin");
	FIELD(b.step[0] = 0.25, "step");
	FIELD(b.unit = 1, "unit");
	FIELD(b.cell[1] = 7, "cell");
	FIELD(strcpy(b.vdatum, "EPSG:5703"), "vdatum");
	FIELD(b.has_nodata = 0, "nodata");
	FIELD(b.nodata = -9999, "nodata");
#undef FIELD
	ok(bad == 0, "geo_differs: each field named when it alone differs");
	sample(&a), sample(&b);
	b.width = 3, b.height = 3;
	ok(geo_differs(&a, &b) == NULL && geo_differs(&a, &a) == NULL,
	    "geo_differs: NaN nodata equals NaN; the grid's size is not "
	    "georeferencing");
	a.nodata = b.nodata = -32768;
	b.has_nodata = a.has_nodata = 0, b.nodata = 0;
	ok(geo_differs(&a, &b) == NULL, "geo_differs: the value of an "
	    "undeclared nodata does not count");
}

static void
test_positions(void)
{
	georef g;
	double x, y;

	geo_init_none(&g, 30, 20);
	ok(g.model == GEO_NONE && g.point == 1 && g.unit == 1 &&
	    g.step[0] == 30 && g.step[1] == -20 && g.crs[0] == '\0',
	    "geo_init_none: point grid, steps 30, -20 m, unit 1");
	geo_init_none(&g, 0, 0);
	ok(g.step[0] == 1 && g.step[1] == -1, "geo_init_none: 1 m when no "
	    "cell size is given");
	geo_init_none(&g, 5, 0);
	ok(g.step[1] == -5, "geo_init_none: dy defaults to dx");
	sample(&g);
	geo_vertex_crs(&g, 0, 2, 3, &x, &y);
	ok(x == -117.5 + 2 * 0.5 && y == 34.25 - 3 * 0.25,
	    "geo_vertex_crs, point raster: origin + i step");
	geo_vertex_crs(&g, 2, 1, 1, &x, &y);
	ok(x == -117.5 + 4 * 0.5 && y == 34.25 - 4 * 0.25,
	    "geo_vertex_crs, level 2: vertex (1,1) at sample (4,4)");
	g.point = 0;
	geo_vertex_crs(&g, 1, 1, 0, &x, &y);
	ok(x == -117.5 + 2.5 * 0.5 && y == 34.25 - 0.5 * 0.25,
	    "geo_vertex_crs, area raster: the pixel's centre");
}

int
main(void)
{
	test_models();
	test_header();
	test_bad();
	test_differs();
	test_positions();
	return tap_done();
}
