/* t_pyramid - the directory format's producer side (pyramid.h): block
 * counts and paths, index.json written and read back field for field
 * (NaN nodata, vdatum, cell), a hostile index refused before anything is
 * allocated from it, block files written and read back bit for bit, a
 * block that is not what its name says refused. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "qem/fqm.h"
#include "indextext.h"
#include "pyramid/pyramid.h"
#include "tap.h"
#include "tmpdir.h"

static char tmp[PATH_MAX - 64];

static void
test_counts(void)
{
	char p[256];

	ok(pyramid_nblocks(2) == 1 && pyramid_nblocks(129) == 1 &&
	    pyramid_nblocks(130) == 2 && pyramid_nblocks(257) == 2 &&
	    pyramid_nblocks(258) == 3, "blocks along an axis: ceil((n-1)/128)"
	    ", at least 1");
	pyramid_block_path(p, sizeof p, "d", 3, 4, 5);
	ok(strcmp(p, "d/3/5_4.exr") == 0, "block (4,5) of level 3 is "
	    "d/3/5_4.exr (row_col): %s", p);
}

/* A two-level index of a 200x150 DEM with every optional georef field. */
static int
make_index(pyramid_index *ix)
{
	static const int size[2][2] = { { 200, 150 }, { 101, 76 } };
	tl_err e;

	memset(ix, 0, sizeof *ix);
	ix->version = VGIS_VERSION;
	ix->size0[0] = 200, ix->size0[1] = 150;
	geo_init_none(&ix->geo, 30, 30);
	ix->geo.epsg = 32611;
	snprintf(ix->geo.crs, sizeof ix->geo.crs, "EPSG:32611");
	snprintf(ix->geo.vdatum, sizeof ix->geo.vdatum, "EGM96");
	ix->geo.cell[0] = 29.5, ix->geo.cell[1] = 31.25;
	ix->geo.has_nodata = 1, ix->geo.nodata = NAN;
	ix->geo.origin[0] = 1000.125, ix->geo.origin[1] = 0.1 + 0.2;
	ix->nlevels = 2;
	if ((ix->lev = calloc(2, sizeof *ix->lev)) == NULL)
		return -1;
	for (int l = 0; l < 2; l++) {
		pyramid_level *L = &ix->lev[l];
		size_t nb;
		if (pyramid_level_init(L, l, size[l][0], size[l][1], &e) < 0)
			return -1;
		L->displaced = l;
		snprintf(L->mode, sizeof L->mode, l ? "qem3d" : "qem1d");
		snprintf(L->kernel, sizeof L->kernel, l ? "binomial" : "none");
		nb = (size_t)L->blocks[0] * L->blocks[1];
		for (size_t k = 0; k < nb; k++) {
			L->zmin[k] = -10.5 + k, L->zmax[k] = 1e3 / 3 + k;
			L->base[k] = l ? 0.1 * (k + 1) : 0;
			L->emax[k] = 12.0 / 7 + k;
		}
	}
	return 0;
}

static int
same_level(const pyramid_level *a, const pyramid_level *b)
{
	size_t nb = (size_t)a->blocks[0] * a->blocks[1];

	if (a->level != b->level || a->size[0] != b->size[0] ||
	    a->size[1] != b->size[1] || a->blocks[0] != b->blocks[0] ||
	    a->blocks[1] != b->blocks[1] || a->displaced != b->displaced ||
	    strcmp(a->mode, b->mode) != 0 || strcmp(a->kernel, b->kernel) != 0)
		return 0;
	for (size_t k = 0; k < nb; k++)
		if (a->zmin[k] != b->zmin[k] || a->zmax[k] != b->zmax[k] ||
		    a->base[k] != b->base[k] || a->emax[k] != b->emax[k])
			return 0;
	return 1;
}

static void
test_index_roundtrip(void)
{
	pyramid_index a, b;
	const georef *g = &b.geo;
	tl_err e;
	int same = 1;

	if (make_index(&a) < 0 || pyramid_index_write(tmp, &a, &e) < 0) {
		ok(0, "index written");
		return;
	}
	ok(pyramid_index_read(tmp, &b, &e) == 0, "index written and read "
	    "back");
	ok(b.version == VGIS_VERSION && b.size0[0] == 200 &&
	    b.size0[1] == 150 && b.nlevels == 2 && g->width == 200 &&
	    g->height == 150, "version, size0, level count");
	ok(g->model == a.geo.model && g->epsg == 32611 &&
	    strcmp(g->crs, "EPSG:32611") == 0 && g->point == a.geo.point &&
	    g->origin[0] == 1000.125 && g->origin[1] == 0.1 + 0.2 &&
	    g->step[0] == a.geo.step[0] && g->step[1] == a.geo.step[1] &&
	    g->unit == a.geo.unit, "georef: model, crs, raster, origin and "
	    "step to the last bit (17 digits)");
	ok(strcmp(g->vdatum, "EGM96") == 0 && g->cell[0] == 29.5 &&
	    g->cell[1] == 31.25 && g->has_nodata && isnan(g->nodata),
	    "georef: vdatum, cell and a NaN nodata (\"nan\")");
	ok(geo_differs(&a.geo, g) == NULL, "geo_differs finds nothing");
	for (int l = 0; l < 2; l++)
		same &= same_level(&a.lev[l], &b.lev[l]);
	ok(same, "levels: sizes, blocks, displaced, mode, kernel, per-block "
	    "zmin zmax base_error max_error");
	pyramid_index_free(&a);
	pyramid_index_free(&b);
	ok(b.lev == NULL && b.nlevels == 0, "pyramid_index_free clears");
}

static void
test_hostile(void)
{
	static const struct {
		const char *what, *with, *msg, *why;
	} t[] = {
		{ "\"levels\": [", "\"levels\": [] , \"x\": [", "levels: 0,",
		    "no levels (tileplay --shot segfaulted on it)" },
		{ "[200, 150], \"georef\"", "[200000000, 150], \"georef\"",
		    "3 .. 2^26", "size0 past 2^26" },
		{ "[200, 150], \"georef\"", "[2, 150], \"georef\"",
		    "3 .. 2^26", "size0 below 3" },
		{ "\"size\": [101, 76]", "\"size\": [101, 77]", "level 1 of a",
		    "a level's size not that of its level" },
		{ "\"blocks\": [2, 2]", "\"blocks\": [2, 3]", "blocks: 2x3, a",
		    "block counts not those of the size" },
		{ "\"level\": 1,", "\"level\": 2,", "levels[1]: level 2",
		    "levels out of order" },
		{ "\"version\": 1", "\"version\": 2", "version 2",
		    "another version" },
		{ "\"max_error\": [1]", "\"max_error\": [1, 2]", "must list",
		    "a per-block array of the wrong length" },
		{ "\"zmin\": [0]", "\"zmin\": [\"0\"]", "zmin[0]: not a finite number",
		    "a per-block value that is not a number" },
		{ "\"kernel\": \"none\", ", "", "kernel missing",
		    "a level without its kernel" },
		{ "\"step\": [1, -1], ", "", "not a pyramid index",
		    "georef without step" },
		{ "\"model\": \"none\"", "\"model\": \"mercator\"",
		    "not a pyramid index", "an unknown georef model" },
		{ "}]}", "}]", "line", "text that is not JSON" },
	};
	char text[4096];
	pyramid_index ix;
	tl_err e;

	itext_edit(text, sizeof text, NULL, NULL);
	ok(itext_write(tmp, text) == 0 && pyramid_index_read(tmp, &ix, &e) ==
	    0 && ix.nlevels == 2, "the unedited index reads");
	pyramid_index_free(&ix);
	for (size_t q = 0; q < sizeof t / sizeof t[0]; q++) {
		int r;
		itext_edit(text, sizeof text, t[q].what, t[q].with);
		e.msg[0] = '\0';
		r = itext_write(tmp, text) == 0 ?
		    pyramid_index_read(tmp, &ix, &e) : 0;
		ok(r < 0 && strstr(e.msg, t[q].msg) != NULL && ix.lev == NULL,
		    "refused: %s (%s)", t[q].why, e.msg);
	}
	ok(pyramid_index_read("/nonexistent", &ix, &e) < 0 &&
	    strstr(e.msg, "/nonexistent/index.json") != NULL,
	    "no index.json: refused, the path named (%s)", e.msg);
}

static void
fill_block(pyramid_block *b, int level, int bi, int bj)
{
	b->level = level, b->bi = bi, b->bj = bj;
	b->zmin = INFINITY, b->zmax = -INFINITY, b->emax = 0;
	for (int k = 0; k < PYRAMID_N; k++) {
		b->z[k] = (float)(100 + sin(k * 0.01) * 50 + k * 1e-3);
		b->e[k] = (float)(k % 97) / 7.0f;
		if (b->displaced) {
			b->x[k] = (float)(k % 13) - 6;
			b->y[k] = -(float)(k % 5);
		}
		b->zmin = fmin(b->zmin, b->z[k]);
		b->zmax = fmax(b->zmax, b->z[k]);
	}
	b->e[0] = b->e[BT_CELLS] = b->e[PYRAMID_N - 1] = FLT_MAX;
	b->e[BT_CELLS * BT_SIZE] = FLT_MAX;
	b->base = level ? 0.75 : 0;
}

static int
same_block(const pyramid_block *a, const pyramid_block *b)
{
	size_t n = PYRAMID_N * sizeof(float);

	return memcmp(a->z, b->z, n) == 0 && memcmp(a->e, b->e, n) == 0 &&
	    (!a->displaced || (memcmp(a->x, b->x, n) == 0 &&
	    memcmp(a->y, b->y, n) == 0)) && a->zmin == b->zmin &&
	    a->zmax == b->zmax && a->base == b->base;
}

static void
test_block(int displaced)
{
	const char *kind = displaced ? "displaced" : "1D";
	char p[PATH_MAX];
	pyramid_block a, b;
	rs_header h;
	tl_err e;

	rs_header_init(&h, 0, 0);
	snprintf(p, sizeof p, "%s/%d", tmp, 1 + displaced);
	mkdir(p, 0777);
	pyramid_block_path(p, sizeof p, tmp, 1 + displaced, 2, 3);
	if (pyramid_block_alloc(&a, displaced, &e) < 0 ||
	    pyramid_block_alloc(&b, displaced, &e) < 0 ||
	    rs_set_string(&h, FQM_ATTR_MODE, "qem3d", &e) < 0) {
		ok(0, "%s: set up", kind);
		return;
	}
	fill_block(&a, 1 + displaced, 2, 3);
	ok(pyramid_block_write(p, &a, &h, &e) == 0, "%s block written", kind);
	b.level = 1 + displaced, b.bi = 2, b.bj = 3;
	ok(pyramid_block_read(p, &b, &e) == 0 && same_block(&a, &b),
	    "%s block read back bit for bit, zrange and base error", kind);
	b.bi = 3;
	ok(pyramid_block_read(p, &b, &e) < 0 && strstr(e.msg, "expected "
	    "level") != NULL, "%s block read as another block: refused (%s)",
	    kind, e.msg);
	pyramid_block_free(&b);
	pyramid_block_alloc(&b, !displaced, &e);
	b.level = 1 + displaced, b.bi = 2, b.bj = 3;
	ok(pyramid_block_read(p, &b, &e) < 0 && strstr(e.msg, "channels") !=
	    NULL, "%s block read as %s: refused (%s)", kind,
	    displaced ? "1D" : "displaced", e.msg);
	pyramid_block_free(&a);
	pyramid_block_free(&b);
	rs_header_free(&h);
}

int
main(void)
{
	if (tmpdir_make(tmp, sizeof tmp, "tlpyramid") < 0) {
		ok(0, "set up");
		return tap_done();
	}
	test_counts();
	test_index_roundtrip();
	test_hostile();
	test_block(0);
	test_block(1);
	tmpdir_done(tmp);
	return tap_done();
}
