/* fz_block - a block file (vgis(5)) as the viewer reads it
 * (pyramid_block_read: size, channels, vgis:* attributes checked against
 * what the block must be), level 0 block (0, 0), 1D; and, when it loads,
 * the checker over a one-block pyramid holding it. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz.h"
#include "pyramid/pyramid.h"
#include "verify/verify.h"

/* A one-level, one-block index, written by the producer's own writer
 * once per process: a 129x129 DEM without georeferencing. */
static int
index_once(const char *dir)
{
	static int done;
	pyramid_index ix;
	tl_err e;

	if (done)
		return 0;
	memset(&ix, 0, sizeof ix);
	ix.size0[0] = ix.size0[1] = 129;
	geo_init_none(&ix.geo, 1, 1);
	ix.geo.width = ix.geo.height = 129;
	ix.nlevels = 1;
	ix.lev = calloc(1, sizeof *ix.lev);
	if (ix.lev == NULL || pyramid_level_init(&ix.lev[0], 0, 129, 129, &e) < 0)
		return -1;
	snprintf(ix.lev[0].mode, sizeof ix.lev[0].mode, "qem1d");
	snprintf(ix.lev[0].kernel, sizeof ix.lev[0].kernel, "none");
	done = pyramid_index_write(dir, &ix, &e) == 0;
	pyramid_index_free(&ix);
	return done ? 0 : -1;
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *path = fuzz_file("0_0.exr", data, size);
	char dir[512], blk[600], idx[600];
	pyramid_block b;
	tl_err e;

	if (path == NULL)
		return 0;
	/* DIR/0/0_0.exr beside DIR/index.json */
	snprintf(dir, sizeof dir, "%s", path);
	*strrchr(dir, '/') = '\0';
	snprintf(blk, sizeof blk, "%s/p/0", dir);
	mkdir(dir, 0700), snprintf(idx, sizeof idx, "%s/p", dir);
	mkdir(idx, 0700), mkdir(blk, 0700);
	snprintf(blk, sizeof blk, "%s/p/0/0_0.exr", dir);
	rename(path, blk);
	snprintf(idx, sizeof idx, "%s/p", dir);
	if (index_once(idx) < 0)
		return 0;
	memset(&b, 0, sizeof b);
	b.level = 0, b.bi = 0, b.bj = 0, b.displaced = 0;
	if (pyramid_block_alloc(&b, 0, &e) == 0) {
		int r = pyramid_block_read(blk, &b, &e);
		pyramid_block_free(&b);
		if (r == 0) {
			vf_opts o;
			vf_report rep;
			memset(&rep, 0, sizeof rep);
			vf_opts_init(&o);
			o.nsweep = 3;
			snprintf(dir + strlen(dir), sizeof dir - strlen(dir), "/p");
			if (vf_check(dir, NULL, NULL, &o, &rep, &e) == 0)
				vf_report_free(&rep);
		}
	}
	return 0;
}
