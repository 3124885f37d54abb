/* fz_pyrblock - a block file as the viewer and the exporters read it:
 * pyramid_block_load (size, channels, vgis:* attributes, Z E X Y values,
 * the index's entry for it) and pyramid_levels_probe (its fqm:* and geo:*
 * attributes against the index), on one-block pyramids of a 129x129 DEM.
 * The first byte picks the pyramid: bit 0 its level 0 displaced (E X Y Z)
 * or not (E Z); the rest is the block file, level 0 block (0,0). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz.h"
#include "pyramid/pyramid.h"

/* The pyramid's directory (index.json and 0/), its index written once
 * per process by the producer's writer. */
static const char *
pyramid_once(int displaced, pyramid_index *ix)
{
	static char dir[2][400];
	static pyramid_index keep[2];
	char sub[1100];
	const char *p;
	tl_err e;

	if (dir[displaced][0] != '\0') {
		*ix = keep[displaced];
		return dir[displaced];
	}
	if ((p = fuzz_file(displaced ? "d.keep" : "f.keep",
	    (const uint8_t *)"", 0)) == NULL)
		return NULL;
	snprintf(dir[displaced], sizeof dir[0], "%s", p);
	snprintf(strrchr(dir[displaced], '/'), 8, "/%s",
	    displaced ? "pd" : "pf");
	snprintf(sub, sizeof sub, "%s/0", dir[displaced]);
	mkdir(dir[displaced], 0700), mkdir(sub, 0700);
	memset(ix, 0, sizeof *ix);
	ix->size0[0] = ix->size0[1] = 129;
	geo_init_none(&ix->geo, 1, 1);
	ix->geo.width = ix->geo.height = 129;
	ix->nlevels = 1;
	if ((ix->lev = calloc(1, sizeof *ix->lev)) == NULL ||
	    pyramid_level_init(&ix->lev[0], 0, 129, 129, &e) < 0)
		abort();
	ix->lev[0].displaced = displaced;
	snprintf(ix->lev[0].mode, sizeof ix->lev[0].mode, "%s",
	    displaced ? "qem3d" : "qem1d");
	snprintf(ix->lev[0].kernel, sizeof ix->lev[0].kernel, "none");
	if (pyramid_index_write(dir[displaced], ix, &e) < 0)
		abort();
	keep[displaced] = *ix;
	return dir[displaced];
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char path[1100];
	const char *dir;
	pyramid_index ix;
	pyramid_block b;
	tl_err e;
	int d;

	if (size < 1)
		return 0;
	d = data[0] & 1;
	if ((dir = pyramid_once(d, &ix)) == NULL)
		return 0;
	snprintf(path, sizeof path, "%s/0/0_0.exr", dir);
	{
		const char *f = fuzz_file("blk", data + 1, size - 1);
		if (f == NULL || rename(f, path) != 0)
			return 0;
	}
	/* the index's entry is the block's own, so that a sound block
	 * passes and the fuzzer reaches past the comparison */
	if (pyramid_block_alloc(&b, d, &e) < 0)
		return 0;
	b.level = 0, b.bi = b.bj = 0;
	if (pyramid_block_read(path, &b, &e) == 0) {
		ix.lev[0].zmin[0] = b.zmin, ix.lev[0].zmax[0] = b.zmax;
		ix.lev[0].base[0] = b.base, ix.lev[0].emax[0] = b.emax;
	}
	b.level = 0, b.bi = b.bj = 0, b.displaced = d;
	pyramid_block_load(dir, &ix, &b, &e);
	pyramid_levels_probe(dir, &ix, &e);
	pyramid_block_free(&b);
	return 0;
}
