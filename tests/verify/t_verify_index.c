/* t_verify_index - the checker's own index.json reader (verify_index.c):
 * every field vgis(5) lists read, and an index it cannot check against
 * refused with the field named (not JSON, duplicate keys, a field
 * missing or of the wrong type, block counts not those of the level's
 * size), while faults the checks report (a level of the wrong size, a
 * wrong level count) are read and left to them. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "indextext.h"
#include "verify/verify.h"
#include "tap.h"
#include "tmpdir.h"

static char tmp[PATH_MAX - 64];

/* Reads the good index with one edit; 0 or -1, e filled. */
static int
read_edited(const char *what, const char *with, vf_index *ix, tl_err *e)
{
	char text[4096];

	itext_edit(text, sizeof text, what, with);
	e->msg[0] = '\0';
	if (itext_write(tmp, text) < 0)
		return tl_fail(e, "cannot write the index");
	return vf_index_read(tmp, ix, e);
}

static void
test_good(void)
{
	vf_index ix;
	const vf_ilevel *L;
	tl_err e;

	if (read_edited(NULL, NULL, &ix, &e) < 0) {
		ok(0, "the good index reads (%s)", e.msg);
		return;
	}
	L = ix.lev;
	ok(ix.size0[0] == 200 && ix.size0[1] == 150 && ix.nlevels == 2 &&
	    ix.geo.width == 200 && ix.geo.height == 150 &&
	    ix.geo.model == GEO_NONE && ix.geo.point && ix.geo.step[1] == -1 &&
	    !ix.geo.has_nodata, "the good index: size0, levels, georef");
	ok(L[0].level == 0 && L[0].size[0] == 200 && L[0].blocks[0] == 2 &&
	    L[0].blocks[1] == 2 && !L[0].displaced &&
	    strcmp(L[0].mode, "qem1d") == 0 &&
	    strcmp(L[1].kernel, "binomial") == 0 && L[0].zmax[3] == 1 &&
	    L[1].emax[0] == 1, "... its levels and per-block arrays");
	vf_index_free(&ix);
	ok(ix.lev == NULL && ix.nlevels == 0, "vf_index_free clears");
	ok(read_edited("\"unit\": 1}", "\"unit\": 1, \"nodata\": \"nan\", "
	    "\"cell\": [2, 3], \"vdatum\": \"EGM96\"}", &ix, &e) == 0 &&
	    ix.geo.has_nodata && isnan(ix.geo.nodata) &&
	    ix.geo.cell[0] == 2 && ix.geo.cell[1] == 3 &&
	    strcmp(ix.geo.vdatum, "EGM96") == 0, "optional georef fields: "
	    "a NaN nodata (\"nan\"), cell, vdatum");
	vf_index_free(&ix);
	ok(read_edited("\"size\": [101, 76]", "\"size\": [101, 77]", &ix,
	    &e) == 0 && ix.lev[1].size[1] == 77, "a level of another size "
	    "than its level's is read: the checks report it");
	vf_index_free(&ix);
	ok(read_edited(", {\"level\": 1", "], \"x\": [{\"level\": 1", &ix,
	    &e) == 0 && ix.nlevels == 1,
	    "a level count the DEM does not have is read: the checks report "
	    "it");
	vf_index_free(&ix);
}

static void
test_refused(void)
{
	static const struct {
		const char *what, *with, *msg;
	} t[] = {
		{ "}]}", "}]", "not JSON" },
		{ "\"version\": 1,", "\"version\": 1, \"version\": 1,",
		    "not JSON" },
		{ "terrain-lod vgis", "other", "(format)" },
		{ "\"version\": 1", "\"version\": 2", "version 2" },
		{ "\"version\": 1", "\"version\": 1.5", "(version)" },
		{ "\"block\": 129", "\"block\": 65", "blocks of 65" },
		{ "[200, 150], \"georef\"", "[1, 150], \"georef\"", "(size0)" },
		{ "\"levels\": [", "\"levels\": [] , \"x\": [", "(levels)" },
		{ "\"step\": [1, -1], ", "", "(georef.step)" },
		{ "\"model\": \"none\"", "\"model\": \"mercator\"",
		    "(georef.model)" },
		{ "\"raster\": \"point\"", "\"raster\": \"pixel\"",
		    "(georef.raster)" },
		{ "\"epsg\": 0", "\"epsg\": 4294967296", "(georef.epsg)" },
		{ "\"unit\": 1}", "\"unit\": 1, \"nodata\": \"x\"}",
		    "(georef.nodata)" },
		{ "\"unit\": 1}", "\"unit\": 1, \"cell\": [0, 1]}",
		    "(georef.cell)" },
		{ "\"unit\": 1}", "\"unit\": \"1\"}", "(georef.unit)" },
		{ "\"displaced\": false", "\"displaced\": \"no\"",
		    "levels[0]: level, size" },
		{ "\"size\": [200, 150]", "\"size\": [1, 150]", "bad size" },
		{ "\"blocks\": [2, 2]", "\"blocks\": [2, 3]",
		    "a 200x150 level has 2x2" },
		{ "\"zmin\": [0, 0, 0, 0]", "\"zmin\": [0, 0, 0]",
		    "must list 4 numbers" },
		{ "\"max_error\": [1]", "\"max_error\": [null]",
		    "must list 1 numbers" },
	};
	vf_index ix;
	tl_err e;

	for (size_t q = 0; q < sizeof t / sizeof t[0]; q++)
		ok(read_edited(t[q].what, t[q].with, &ix, &e) < 0 &&
		    strstr(e.msg, t[q].msg) != NULL && ix.lev == NULL,
		    "refused: %s -> %s (%s)", t[q].what, t[q].with, e.msg);
	ok(vf_index_read("/nonexistent", &ix, &e) < 0 &&
	    strstr(e.msg, "/nonexistent/index.json: ") != NULL,
	    "no index.json: refused, the path named (%s)", e.msg);
	ok(itext_write(tmp, "[1, 2]") == 0 && vf_index_read(tmp, &ix, &e) <
	    0 && strstr(e.msg, "(an object)") != NULL, "JSON but not an "
	    "object: refused (%s)", e.msg);
}

int
main(void)
{
	if (tmpdir_make(tmp, sizeof tmp, "tlvfindex") < 0) {
		ok(0, "set up");
		return tap_done();
	}
	test_good();
	test_refused();
	tmpdir_done(tmp);
	return tap_done();
}
