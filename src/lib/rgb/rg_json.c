/* rg_json.c - the tree's TileJSON 3.0.0, OUT/tiles.json (raster-dem(5)):
 * what MapLibre's raster-dem source reads (tiles, zooms, bounds,
 * encoding, tileSize) and, in fields of their own, the vertical datum,
 * the method and the measured error per zoom. */
#include <stdio.h>
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

int
rg_tilejson(const rg_job *j, const rg_report *rep, const double ll[4],
    tl_err *e)
{
	const rg_args *a = j->a;
	char tiles[4200], path[4200];
	int cz = rep->minzoom + (rep->maxzoom - rep->minzoom) / 2;
	json_t *t;
	int r;

	/* TileJSON 3.0.0 wants absolute URLs: MapLibre resolves a relative
	 * one against the page, not against tiles.json */
	if (a->url != NULL && strlen(a->url) > 4000)
		return tl_fail(e, "-u: a URL of over 4000 bytes");
	snprintf(tiles, sizeof tiles, "%s%s{z}/{x}/{y}.%s", a->url ? a->url :
	    "", a->url && *a->url && a->url[strlen(a->url) - 1] != '/' ? "/" :
	    "", rg_format_ext(a->fmt));
	snprintf(path, sizeof path, "%s/tiles.json", j->tree);
	t = json_pack("{s:s,s:[s],s:s,s:i,s:i,s:[f,f,f,f],s:[f,f,i],"
	    "s:s,s:i,s:s,s:s,s:s,s:s,s:o}",
	    "tilejson", "3.0.0", "tiles", tiles, "scheme", "xyz",
	    "minzoom", rep->minzoom, "maxzoom", rep->maxzoom,
	    "bounds", ll[0], ll[1], ll[2], ll[3],
	    "center", (ll[0] + ll[2]) / 2, (ll[1] + ll[3]) / 2, cz,
	    "encoding", rg_encoding_name(a->enc), "tileSize", a->dim,
	    "vertical_datum", rep->vdatum[0] ? rep->vdatum :
	    "not declared (heights as the DEM holds them)",
	    "method", a->mode == SOLVE_FILTERED ? "average" :
	    solve_mode_name(a->mode),
	    "resampling", a->cubic ? "cubic" : "bilinear",
	    "generator", "dem2rgb " TL_VERSION, "error", errors(rep));
	if (t == NULL)
		return tl_fail(e, "%s: out of memory", path);
	r = tl_json_write(t, JSON_INDENT(1) | JSON_PRESERVE_ORDER, path, e);
	json_decref(t);
	return r;
}
