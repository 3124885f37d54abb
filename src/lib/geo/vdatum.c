/* vdatum.c - setting up the conversion of DEM heights between vertical
 * datums with PROJ (vdatum.h); vdatum_lattice.c applies it to rows.
 *
 * vdatum_open chooses one operation, from the DEM's compound CRS (its
 * horizontal CRS + the declared vertical CRS, or EPSG:4979 for
 * ellipsoidal heights) to the target, among those PROJ lists for the
 * DEM's whole area, and refuses what would shift heights by zero without
 * saying so: PROJ falls back, when a geoid grid is missing, to a
 * "ballpark" vertical transformation that leaves heights unchanged (and
 * proj_create_crs_to_crs picks it silently). */
#include "geo/vdatum_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <proj_experimental.h> /* compound CRSs, 3D to 2D */

/* Boundary points per DEM edge sampled for its lon/lat extent. */
#define EDGE_POINTS 32

/* One side of the conversion. */
typedef struct {
	PJ *crs;     /* the vertical CRS, NULL for ellipsoidal heights */
	double unit; /* metres per unit of its heights */
} side;

/* PROJ reports through the context's logger, never on stderr: keep the
 * last message to explain our own failures. */
static void
keep_log(void *data, int level, const char *msg)
{
	char *buf = data;

	(void)level;
	snprintf(buf, sizeof ((vdatum_shift *)0)->log, "%s", msg);
}

static PJ_CONTEXT *
quiet_context(char *log)
{
	PJ_CONTEXT *ctx = proj_context_create();

	if (ctx != NULL)
		proj_log_func(ctx, log, keep_log);
	return ctx;
}

int
vdatum_is_ellipsoid(const char *s)
{
	return strcasecmp(s, "ellipsoid") == 0 ||
	    strcasecmp(s, "EPSG:4979") == 0;
}

/* The vertical CRS itself under a bound CRS (a vertical CRS that carries
 * its own transformation to WGS 84, as GDAL's WKT1 geoid grids do). */
static PJ *
base_crs(PJ_CONTEXT *ctx, const PJ *crs)
{
	if (proj_get_type(crs) == PJ_TYPE_BOUND_CRS)
		return proj_get_source_crs(ctx, crs);
	return proj_clone(ctx, crs);
}

/* A vertical CRS, or the vertical part of a compound one; NULL for
 * anything else. */
static PJ *
vertical_crs(PJ_CONTEXT *ctx, const char *def)
{
	PJ *crs = proj_create(ctx, def), *sub, *base;
	int ok;

	if (crs != NULL && proj_get_type(crs) == PJ_TYPE_COMPOUND_CRS) {
		sub = proj_crs_get_sub_crs(ctx, crs, 1);
		proj_destroy(crs);
		crs = sub;
	}
	if (crs == NULL)
		return NULL;
	base = base_crs(ctx, crs);
	ok = base != NULL && proj_get_type(base) == PJ_TYPE_VERTICAL_CRS;
	proj_destroy(base);
	if (ok)
		return crs;
	proj_destroy(crs);
	return NULL;
}

/* Metres per unit of the height axis (a vertical CS has one axis). */
static double
height_unit(PJ_CONTEXT *ctx, const PJ *crs)
{
	PJ *base = base_crs(ctx, crs), *cs;
	double f = -1;
	int n;

	cs = base != NULL ? proj_crs_get_coordinate_system(ctx, base) : NULL;
	n = cs != NULL ? proj_cs_get_axis_count(ctx, cs) : 0;
	if (n < 1 || !proj_cs_get_axis_info(ctx, cs, n - 1, NULL, NULL, NULL,
	    &f, NULL, NULL, NULL) || !(f > 0))
		f = -1;
	proj_destroy(cs);
	proj_destroy(base);
	return f;
}

static int
open_side(PJ_CONTEXT *ctx, const char *def, side *s, const char *log,
    tl_err *e)
{
	s->crs = NULL;
	s->unit = 1;
	if (vdatum_is_ellipsoid(def))
		return 0;
	if ((s->crs = vertical_crs(ctx, def)) == NULL)
		return tl_fail(e, "%s: not a vertical CRS PROJ knows (%s)", def,
		    vdatum_why(log));
	if ((s->unit = height_unit(ctx, s->crs)) < 0)
		return tl_fail(e, "%s: cannot find the unit of its heights",
		    def);
	return 0;
}

double
vdatum_unit_of(const char *vcrs, tl_err *e)
{
	char log[sizeof ((vdatum_shift *)0)->log] = "";
	PJ_CONTEXT *ctx;
	side s;
	int rc;

	if (vcrs == NULL || vcrs[0] == '\0')
		return tl_fail(e, "no vertical CRS given");
	if ((ctx = quiet_context(log)) == NULL)
		return tl_fail(e, "%s: cannot create a PROJ context", vcrs);
	rc = open_side(ctx, vcrs, &s, log, e);
	proj_destroy(s.crs);
	proj_context_destroy(ctx);
	return rc < 0 ? -1 : s.unit;
}

/* Same vertical datum, whatever the units (NAVD88 in feet and in metres):
 * heights in metres need nothing then. */
static int
same_datum(PJ_CONTEXT *ctx, const PJ *a, const PJ *b)
{
	PJ *ba, *bb, *da, *db;
	int same;

	if (a == NULL || b == NULL)
		return a == b;
	ba = base_crs(ctx, a), bb = base_crs(ctx, b);
	da = ba != NULL ? proj_crs_get_datum_forced(ctx, ba) : NULL;
	db = bb != NULL ? proj_crs_get_datum_forced(ctx, bb) : NULL;
	same = da != NULL && db != NULL &&
	    proj_is_equivalent_to_with_ctx(ctx, da, db, PJ_COMP_EQUIVALENT);
	proj_destroy(da), proj_destroy(db);
	proj_destroy(ba), proj_destroy(bb);
	return same;
}

/* What the index records: the CRS's code, else its name. */
static void
name_target(vdatum_shift *v, const side *t, const char *def)
{
	const char *auth, *code;

	if (t->crs == NULL) {
		snprintf(v->target, sizeof v->target, "EPSG:4979");
		return;
	}
	auth = proj_get_id_auth_name(t->crs, 0);
	code = proj_get_id_code(t->crs, 0);
	if (auth != NULL && code != NULL)
		snprintf(v->target, sizeof v->target, "%s:%s", auth, code);
	else if (proj_get_name(t->crs) != NULL)
		snprintf(v->target, sizeof v->target, "%s",
		    proj_get_name(t->crs));
	else
		snprintf(v->target, sizeof v->target, "%.100s", def);
}

static int
axes(PJ_CONTEXT *ctx, const PJ *crs)
{
	PJ *cs = proj_crs_get_coordinate_system(ctx, crs);
	int n = cs != NULL ? proj_cs_get_axis_count(ctx, cs) : -1;

	proj_destroy(cs);
	return n;
}

/* The DEM's horizontal CRS, 2D: a compound CRS gives its first part, a 3D
 * one is demoted (the heights are ours to describe). */
static PJ *
horizontal_crs(vdatum_shift *v, const georef *g, tl_err *e)
{
	char def[sizeof g->crs + 16];
	PJ *crs, *h;

	if (g->model == GEO_NONE || (g->crs[0] == '\0' && g->epsg <= 0)) {
		tl_fail(e, "%s: the DEM has no horizontal CRS, and the shift "
		    "between vertical datums depends on where a sample is",
		    v->name);
		return NULL;
	}
	if (g->crs[0] != '\0')
		snprintf(def, sizeof def, "%s", g->crs);
	else
		snprintf(def, sizeof def, "EPSG:%d", g->epsg);
	/* A bare PROJ string names an operation unless it says it is a
	 * CRS. */
	if (def[0] == '+' && strstr(def, "+type=crs") == NULL)
		strcat(def, " +type=crs");
	crs = proj_create(v->ctx, def);
	if (crs != NULL && proj_get_type(crs) == PJ_TYPE_COMPOUND_CRS) {
		h = proj_crs_get_sub_crs(v->ctx, crs, 0);
		proj_destroy(crs);
		crs = h;
	}
	if (crs != NULL && axes(v->ctx, crs) == 3) {
		h = proj_crs_demote_to_2D(v->ctx, NULL, crs);
		proj_destroy(crs);
		crs = h;
	}
	if (crs == NULL || !proj_is_crs(crs)) {
		proj_destroy(crs);
		tl_fail(e, "%s: cannot read the DEM's CRS (%s)", v->name,
		    vdatum_why(v->log));
		return NULL;
	}
	return crs;
}

/* The operation from the horizontal CRS to WGS 84 longitude, latitude. */
static int
open_toll(vdatum_shift *v, PJ *h, tl_err *e)
{
	PJ *wgs = proj_create(v->ctx, "EPSG:4326"), *op = NULL;

	if (wgs != NULL)
		op = proj_create_crs_to_crs_from_pj(v->ctx, h, wgs, NULL, NULL);
	if (op != NULL)
		v->toll = proj_normalize_for_visualization(v->ctx, op);
	proj_destroy(op);
	proj_destroy(wgs);
	if (v->toll == NULL)
		return tl_fail(e, "%s: cannot convert the DEM's CRS to "
		    "longitude, latitude (%s)", v->name, vdatum_why(v->log));
	return 0;
}

/* The DEM's extent in WGS 84 degrees (west, south, east, north; west >
 * east across the antimeridian) from points along its border, where a
 * map projection's extremes lie. */
static int
dem_area(vdatum_shift *v, double box[4], tl_err *e)
{
	double x[4 * EDGE_POINTS], y[4 * EDGE_POINTS], w, h, t, lon;
	double lo = HUGE_VAL, hi = -HUGE_VAL, wlo = HUGE_VAL, whi = -HUGE_VAL;
	int n = 4 * EDGE_POINTS;

	w = v->g.width > 1 ? v->g.width - 1 : 0;
	h = v->g.height > 1 ? v->g.height - 1 : 0;
	for (int k = 0; k < EDGE_POINTS; k++) {
		t = (double)k / EDGE_POINTS;
		geo_vertex_crs(&v->g, 0, t * w, 0, &x[4 * k], &y[4 * k]);
		geo_vertex_crs(&v->g, 0, w, t * h, &x[4 * k + 1],
		    &y[4 * k + 1]);
		geo_vertex_crs(&v->g, 0, w - t * w, h, &x[4 * k + 2],
		    &y[4 * k + 2]);
		geo_vertex_crs(&v->g, 0, 0, h - t * h, &x[4 * k + 3],
		    &y[4 * k + 3]);
	}
	for (int k = 0; v->g.model == GEO_GEOGRAPHIC && k < n; k++) {
		if (fabs(y[k]) > 90 && fabs(y[k]) < 90 + GEO_POLE_EPS)
			y[k] = copysign(90, y[k]); /* rounding at a pole */
		if (fabs(y[k]) > 90)
			return tl_fail(e, "%s: a row of the DEM lies at latitude "
			    "%.9g, past the pole (its georeferencing is wrong: a "
			    "pixel-is-area cell's centre, not its edge, must lie "
			    "within -90..90)", v->name, y[k]);
	}
	proj_trans_generic(v->toll, PJ_FWD, x, sizeof *x, n, y, sizeof *y,
	    n, NULL, 0, 0, NULL, 0, 0);
	box[1] = 90, box[3] = -90;
	for (int k = 0; k < n; k++) {
		if (!isfinite(x[k]) || !isfinite(y[k]) || fabs(y[k]) > 90)
			return tl_fail(e, "%s: the DEM's border does not "
			    "convert to longitude, latitude (%s)", v->name,
			    vdatum_why(v->log));
		lon = remainder(x[k], 360);
		lo = fmin(lo, lon), hi = fmax(hi, lon);
		lon = lon < 0 ? lon + 360 : lon;
		wlo = fmin(wlo, lon), whi = fmax(whi, lon);
		box[1] = fmin(box[1], y[k]), box[3] = fmax(box[3], y[k]);
	}
	/* Narrower in 0..360: the DEM crosses the antimeridian. */
	if (whi - wlo < hi - lo)
		lo = remainder(wlo, 360), hi = remainder(whi, 360);
	box[0] = lo, box[2] = hi;
	return 0;
}
/* Grids the operation names that PROJ cannot open. */
static int
missing_grids(PJ_CONTEXT *ctx, const PJ *op)
{
	const char *name, *full, *pkg, *url;
	int n = proj_coordoperation_get_grid_used_count(ctx, op), miss = 0;
	int direct, open, avail;

	for (int k = 0; k < n; k++)
		if (proj_coordoperation_get_grid_used(ctx, op, k, &name, &full,
		    &pkg, &url, &direct, &open, &avail) && !avail)
			miss++;
	return miss;
}

static int
fail_grids(vdatum_shift *v, const PJ *op, tl_err *e)
{
	const char *name, *full, *pkg, *url, *where = "", *db, *at = "";
	char list[512] = "", dir[512] = "/usr/share/proj", cdn[512];
	int n = proj_coordoperation_get_grid_used_count(v->ctx, op), miss = 0;
	int direct, open, avail;
	size_t l;

	for (int k = 0; k < n; k++) {
		if (!proj_coordoperation_get_grid_used(v->ctx, op, k, &name,
		    &full, &pkg, &url, &direct, &open, &avail) || avail)
			continue;
		l = strlen(list);
		snprintf(list + l, sizeof list - l, "%s%s", miss++ ? ", " : "",
		    name);
		if (url != NULL && url[0] != '\0' && at[0] == '\0')
			at = url;
	}
	/* Several: the directory of the first one's address. */
	if (at[0] != '\0' && miss > 1 && strrchr(at, '/') != NULL) {
		snprintf(cdn, sizeof cdn, "%.*s",
		    (int)(strrchr(at, '/') - at + 1), at);
		at = cdn;
	}
	if (at[0] != '\0')
		where = miss > 1 ? "; they are at " : "; it is at ";
	/* Grids go beside proj.db, the data directory this PROJ reads. */
	db = proj_context_get_database_path(v->ctx);
	if (db != NULL && strrchr(db, '/') != NULL) {
		snprintf(dir, sizeof dir, "%s", db);
		*strrchr(dir, '/') = '\0';
	}
	return tl_fail(e, "%s: needs the grid%s %s, which PROJ cannot find "
	    "(install %s into %s or set PROJ_DATA%s%s)", v->name,
	    miss > 1 ? "s" : "", list, miss > 1 ? "them" : "it", dir, where,
	    at);
}

/* The first operation, in PROJ's order of preference, that covers the
 * whole DEM, uses only grids PROJ finds and no ballpark step (a
 * ballpark vertical step leaves heights unchanged). */
static PJ *
choose(vdatum_shift *v, PJ *src, PJ *dst, const double box[4], tl_err *e)
{
	PJ_OPERATION_FACTORY_CONTEXT *f;
	PJ_OBJ_LIST *l = NULL;
	PJ *op, *best = NULL, *miss = NULL;
	int n = 0, ballpark = 0;

	if ((f = proj_create_operation_factory_context(v->ctx, NULL))
	    != NULL) {
		proj_operation_factory_context_set_grid_availability_use(
		    v->ctx, f, PROJ_GRID_AVAILABILITY_USED_FOR_SORTING);
		proj_operation_factory_context_set_spatial_criterion(v->ctx,
		    f, PROJ_SPATIAL_CRITERION_STRICT_CONTAINMENT);
		proj_operation_factory_context_set_area_of_interest(v->ctx, f,
		    box[0], box[1], box[2], box[3]);
		l = proj_create_operations(v->ctx, src, dst, f);
	}
	n = l != NULL ? proj_list_get_count(l) : 0;
	for (int k = 0; k < n && best == NULL; k++) {
		if ((op = proj_list_get(v->ctx, l, k)) == NULL)
			continue;
		if (proj_coordoperation_has_ballpark_transformation(v->ctx,
		    op))
			ballpark = 1;
		else if (missing_grids(v->ctx, op) > 0 && miss == NULL)
			miss = op, op = NULL;
		else if (missing_grids(v->ctx, op) == 0 &&
		    proj_coordoperation_is_instantiable(v->ctx, op))
			best = op, op = NULL;
		proj_destroy(op);
	}
	proj_list_destroy(l);
	proj_operation_factory_context_destroy(f);
	if (best == NULL && miss != NULL)
		fail_grids(v, miss, e);
	else if (best == NULL && ballpark)
		tl_fail(e, "%s: PROJ knows only a ballpark operation over the "
		    "DEM's area (lon %.6g..%.6g, lat %.6g..%.6g), which would "
		    "leave heights unchanged", v->name, box[0], box[2],
		    box[1], box[3]);
	else if (best == NULL)
		tl_fail(e, "%s: PROJ knows no operation over the DEM's area "
		    "(lon %.6g..%.6g, lat %.6g..%.6g) (%s)", v->name, box[0],
		    box[2], box[1], box[3], vdatum_why(v->log));
	proj_destroy(miss);
	return best;
}

/* The DEM's heights' CRS and the target's, both with the horizontal CRS
 * h where they are vertical; EPSG:4979 for ellipsoidal heights. */
static PJ *
side_crs(vdatum_shift *v, PJ *h, const side *s)
{
	if (s->crs == NULL)
		return proj_create(v->ctx, "EPSG:4979");
	return proj_create_compound_crs(v->ctx, NULL, h, s->crs);
}

static int
open_operation(vdatum_shift *v, const georef *g, const side *from,
    const side *to, tl_err *e)
{
	PJ *h, *src = NULL, *dst = NULL, *op = NULL;
	double box[4];
	int rc = -1;

	if ((h = horizontal_crs(v, g, e)) == NULL)
		return -1;
	if (open_toll(v, h, e) < 0 || dem_area(v, box, e) < 0)
		goto done;
	src = side_crs(v, h, from);
	dst = side_crs(v, h, to);
	if (src == NULL || dst == NULL) {
		tl_fail(e, "%s: cannot build the compound CRSs (%s)", v->name,
		    vdatum_why(v->log));
		goto done;
	}
	if ((op = choose(v, src, dst, box, e)) == NULL)
		goto done;
	snprintf(v->opname, sizeof v->opname, "%s",
	    proj_get_name(op) != NULL ? proj_get_name(op) : "unnamed");
	if ((v->op = proj_normalize_for_visualization(v->ctx, op)) == NULL) {
		tl_fail(e, "%s: cannot use the operation \"%s\" (%s)",
		    v->name, v->opname, vdatum_why(v->log));
		goto done;
	}
	if (vdatum_lattice_open(v, e) < 0)
		goto done;
	/* Ellipsoidal source heights: EPSG:4979 takes lon/lat, toll gives
	 * them; otherwise the operation takes the DEM's CRS as it is. */
	if (from->crs != NULL) {
		proj_destroy(v->toll);
		v->toll = NULL;
	}
	rc = 0;
done:
	proj_destroy(op);
	proj_destroy(src);
	proj_destroy(dst);
	proj_destroy(h);
	return rc;
}

vdatum_shift *
vdatum_open(const georef *g, const char *from, const char *to, tl_err *e)
{
	vdatum_shift *v;
	side s = { NULL, 1 }, t = { NULL, 1 };
	int rc = -1;

	if (from == NULL || from[0] == '\0') {
		tl_fail(e, "the DEM declares no vertical datum: name it with "
		    "-D (e.g. -D EPSG:5773 for SRTM's EGM96)");
		return NULL;
	}
	if (to == NULL || to[0] == '\0') {
		tl_fail(e, "no target vertical datum given");
		return NULL;
	}
	if ((v = tl_alloc(1, sizeof *v, e)) == NULL)
		return NULL;
	v->g = *g;
	snprintf(v->name, sizeof v->name, "%.80s to %.80s",
	    vdatum_is_ellipsoid(from) ? "EPSG:4979" : from,
	    vdatum_is_ellipsoid(to) ? "EPSG:4979" : to);
	if ((v->ctx = quiet_context(v->log)) == NULL) {
		tl_fail(e, "%s: cannot create a PROJ context", v->name);
		goto done;
	}
	if (open_side(v->ctx, from, &s, v->log, e) < 0 ||
	    open_side(v->ctx, to, &t, v->log, e) < 0)
		goto done;
	if (t.unit != 1) {
		tl_fail(e, "%s: the pyramid stores heights in metres, and %s "
		    "is in units of %.10g m: name the vertical CRS of the same "
		    "datum in metres", v->name, to, t.unit);
		goto done;
	}
	v->fs = s.unit, v->ft = t.unit;
	name_target(v, &t, to);
	snprintf(v->opname, sizeof v->opname, "identity");
	if (same_datum(v->ctx, s.crs, t.crs))
		rc = 0;
	else
		rc = open_operation(v, g, &s, &t, e);
done:
	proj_destroy(s.crs);
	proj_destroy(t.crs);
	if (rc < 0) {
		vdatum_close(v);
		return NULL;
	}
	return v;
}

const char *
vdatum_target_name(const vdatum_shift *v)
{
	return v->target;
}

const char *
vdatum_operation_name(const vdatum_shift *v)
{
	return v->opname;
}

void
vdatum_close(vdatum_shift *v)
{
	if (v == NULL)
		return;
	proj_destroy(v->op);
	proj_destroy(v->toll);
	if (v->ctx != NULL)
		proj_context_destroy(v->ctx);
	free(v->x), free(v->y), free(v->z);
	free(v->rows[0].d), free(v->rows[1].d);
	free(v);
}
