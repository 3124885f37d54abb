/* fz_pyrindex - index.json as the viewer and the exporters read it: the
 * shared strict reader (pyramid_index_parse), the text in memory, not
 * NUL-terminated. What it accepts must be what they can use: the grid
 * in metres (geo_ground_init, their next step; not of projected CRSs,
 * which PROJ may look up for seconds), and the index written
 * back by the producer's writer reads again the same. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fuzz.h"
#include "pyramid/pyramid.h"

/* A directory of this process for the written index, made once. */
static const char *
rt_dir(void)
{
	static char dir[512];
	const char *p;

	if (dir[0] == '\0') {
		if ((p = fuzz_file("rt.keep", (const uint8_t *)"", 0)) == NULL)
			return NULL;
		snprintf(dir, sizeof dir, "%s", p);
		snprintf(strrchr(dir, '/'), 4, "/rt");
		if (mkdir(dir, 0700) != 0 && errno != EEXIST) {
			dir[0] = '\0';
			return NULL;
		}
	}
	return dir;
}

/* Writes ix and reads it back: a reader that accepts what it then cannot
 * read again, or reads differently, is a bug. */
static void
round_trip(const pyramid_index *ix)
{
	const char *dir = rt_dir();
	pyramid_index back;
	tl_err e;

	if (dir == NULL || pyramid_index_write(dir, ix, &e) < 0)
		return;
	if (pyramid_index_read(dir, &back, &e) < 0) {
		fprintf(stderr, "fz_pyrindex: accepted, written, refused: %s\n",
		    e.msg);
		abort();
	}
	if (back.nlevels != ix->nlevels || back.size0[0] != ix->size0[0] ||
	    back.size0[1] != ix->size0[1] || geo_differs(&back.geo, &ix->geo))
		abort();
	pyramid_index_free(&back);
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	pyramid_index ix;
	geo_ground m;
	tl_err e;

	if (pyramid_index_parse((const char *)data, size, "index.json", &ix,
	    &e) < 0)
		return 0;
	/* not a projected CRS: PROJ looks a CRS string it does not know up
	 * by name in its database, seconds under ASan ("EPSG;32611" timed
	 * out), which tests PROJ, not the reader */
	if (ix.geo.model != GEO_PROJECTED &&
	    geo_ground_init(&m, &ix.geo, &e) == 0)
		geo_ground_free(&m);
	round_trip(&ix);
	pyramid_index_free(&ix);
	return 0;
}
