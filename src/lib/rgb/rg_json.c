/* rg_json.c - what the containers say besides the tiles (raster-dem(5)):
 * the tree's TileJSON 3.0.0, OUT/tiles.json (what MapLibre's raster-dem
 * source reads: tiles, zooms, bounds, encoding, tileSize; in fields of
 * their own the vertical datum, the method and the measured error per
 * zoom), and the PMTiles archive's header and metadata: the same fields
 * but the TileJSON version and the tile URLs, built by the same code. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rgb/rg_impl.h"
#include "base/json.h"

static json_t *
errors(const rg_report *rep)
{
	json_t *a = json_array();

	for (int z = rep->minzoom; a != NULL && z <= rep->maxzoom; z++)
		json_array_append_new(a, json_pack("{s:i,s:f,s:f,s:I,s:I}",
		    "zoom", z, "max", rep->max[z], "rms", rep->rms[z],
		    "samples", (json_int_t)rep->n[z],
		    "tiles", (json_int_t)rep->tiles[z]));
	return a;
}

static int
centre_zoom(const rg_report *rep)
{
	return rep->minzoom + (rep->maxzoom - rep->minzoom) / 2;
}

/* The bounds and centre said of the DEM's bounds ll: across the
 * antimeridian (east past 180), the world's longitudes (TileJSON 3.0.0:
 * bounds "MUST NOT wrap around the ante-meridian"; MapLibre's
 * TileBounds loads nothing when west > east) and the centre's longitude
 * within -180 .. 180. */
static void
said(const double ll[4], double b[4], double c[2])
{
	memcpy(b, ll, 4 * sizeof *b);
	c[0] = (ll[0] + ll[2]) / 2, c[1] = (ll[1] + ll[3]) / 2;
	if (ll[2] <= 180)
		return;
	b[0] = -180, b[2] = 180;
	c[0] = c[0] >= 180 ? c[0] - 360 : c[0];
}

/* The fields after "tiles", in tiles.json's order; NULL: no memory. */
static json_t *
fields(const rg_job *j, const rg_report *rep, const double ll0[4])
{
	const rg_args *a = j->a;
	double ll[4], c[2];

	said(ll0, ll, c);
	return json_pack("{s:s,s:i,s:i,s:[f,f,f,f],s:[f,f,i],"
	    "s:s,s:i,s:s,s:s,s:s,s:s,s:o}",
	    "scheme", "xyz",
	    "minzoom", rep->minzoom, "maxzoom", rep->maxzoom,
	    "bounds", ll[0], ll[1], ll[2], ll[3],
	    "center", c[0], c[1], centre_zoom(rep),
	    "encoding", rg_encoding_name(a->enc), "tileSize", a->dim,
	    "vertical_datum", rep->vdatum[0] ? rep->vdatum :
	    "not declared (heights as the DEM holds them)",
	    "method", a->mode == SOLVE_FILTERED ? "average" :
	    solve_mode_name(a->mode),
	    "resampling", a->cubic ? "cubic" : "bilinear",
	    "generator", "dem2rgb " TL_VERSION, "error", errors(rep));
}

int
rg_tilejson(const rg_job *j, const rg_report *rep, const double ll[4],
    tl_err *e)
{
	const rg_args *a = j->a;
	char tiles[4200], path[4200];
	json_t *t, *f;
	int r;

	/* TileJSON 3.0.0 wants absolute URLs: MapLibre resolves a relative
	 * one against the page, not against tiles.json */
	if (a->url != NULL && strlen(a->url) > 4000)
		return tl_fail(e, "-u: a URL of over 4000 bytes");
	snprintf(tiles, sizeof tiles, "%s%s{z}/{x}/{y}.%s", a->url ? a->url :
	    "", a->url && *a->url && a->url[strlen(a->url) - 1] != '/' ? "/" :
	    "", rg_format_ext(a->fmt));
	snprintf(path, sizeof path, "%s/tiles.json", j->tree);
	t = json_pack("{s:s,s:[s]}", "tilejson", "3.0.0", "tiles", tiles);
	f = fields(j, rep, ll);
	if (t == NULL || f == NULL || json_object_update(t, f) < 0) {
		json_decref(t), json_decref(f);
		return tl_fail(e, "%s: out of memory", path);
	}
	json_decref(f);
	r = tl_json_write(t, JSON_INDENT(1) | JSON_PRESERVE_ORDER, path, e);
	json_decref(t);
	return r;
}

int
rg_pmtiles_close(pm_writer *w, const rg_job *j, const rg_report *rep,
    const double ll[4], tl_err *e)
{
	pm_meta m = { j->a->fmt == RG_WEBP ? PM_WEBP : PM_PNG,
	    rep->minzoom, rep->maxzoom, { 0 }, { 0 }, centre_zoom(rep),
	    NULL };
	json_t *f = fields(j, rep, ll);
	char *s = f != NULL ? json_dumps(f, JSON_COMPACT |
	    JSON_PRESERVE_ORDER) : NULL;
	int r;

	said(ll, m.bounds, m.center);

	json_decref(f);
	if (s == NULL) {
		pm_abort(w);
		return tl_fail(e, "%s: out of memory", j->a->out);
	}
	m.json = s;
	r = pm_close(w, &m, e);
	free(s);
	return r;
}
