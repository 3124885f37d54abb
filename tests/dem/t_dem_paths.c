/* t_dem_paths - the files of a DEM (dem_paths) kept apart from outputs:
 * a list's entries, a VRT's sources, VRTs within VRTs. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tap.h"
#include "tmpdir.h"

#include "base/paths.h"
#include "dem/dem.h"

static char dir[PATH_MAX];

static const char *
at(const char *name)
{
	return tmpdir_join(dir, name);
}

static void
put(const char *name, const char *text)
{
	FILE *f = fopen(at(name), "w");

	if (f != NULL) {
		fputs(text, f);
		fclose(f);
	}
}

static const char asc[] = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\n"
    "cellsize 1\n1 2 3\n4 5 6\n7 8 9\n";

static void
vrt(const char *name, const char *src)
{
	char t[1024];

	snprintf(t, sizeof t, "<VRTDataset rasterXSize=\"3\" rasterYSize=\"3\">"
	    "<VRTRasterBand dataType=\"Float32\" band=\"1\"><SimpleSource>"
	    "<SourceFilename relativeToVRT=\"1\">%s</SourceFilename>"
	    "<SourceBand>1</SourceBand></SimpleSource></VRTRasterBand>"
	    "</VRTDataset>\n", src);
	put(name, t);
}

static int
dem_check(const char *path, const char *out, tl_err *e)
{
	char d[PATH_MAX], o[PATH_MAX];
	tl_paths s = { 0 };
	int r;

	snprintf(d, sizeof d, "%s", at(path));
	snprintf(o, sizeof o, "%s", at(out));
	r = dem_paths(&s, d, e);
	if (r == 0)
		r = tl_paths_check(&s, o, e);
	tl_paths_free(&s);
	return r;
}

static void
dems(void)
{
	tl_err e;

	mkdir(at("T"), 0777), mkdir(at("U"), 0777);
	put("T/a.asc", asc), put("U/b.asc", asc);
	vrt("m.vrt", "T/a.asc");
	vrt("outer.vrt", "m.vrt");
	put("list.txt", "# tiles\nT/a.asc\n  U/b.asc\n");
	ok(dem_check("m.vrt", "T", &e) < 0 && strstr(e.msg, "a file of the "
	    "input DEM") && strstr(e.msg, "a.asc"), "a VRT's source: %s",
	    e.msg);
	ok(dem_check("outer.vrt", "T", &e) < 0 && strstr(e.msg, "a.asc"),
	    "a VRT's VRT's source: %s", e.msg);
	ok(dem_check("list.txt", "U", &e) < 0 && strstr(e.msg, "an entry of "
	    "the input DEM list") && strstr(e.msg, "b.asc"), "a list's entry: "
	    "%s", e.msg);
	ok(dem_check("list.txt", "U/b.asc", &e) < 0, "a list's entry as an "
	    "output file");
	put("vlist.txt", "m.vrt\n");
	ok(dem_check("vlist.txt", "T", &e) < 0 && strstr(e.msg, "a.asc"),
	    "a VRT in a list: its source: %s", e.msg);
	ok(dem_check("m.vrt", "U", &e) == 0 && dem_check("list.txt", "V",
	    &e) == 0 && dem_check("T/a.asc", "U", &e) == 0, "outputs beside "
	    "every file: apart");
	ok(dem_check("none.tif", "T", &e) == 0, "a DEM that does not exist: "
	    "left to its reader");
}


int
main(void)
{
	if (tmpdir_make(dir, sizeof dir, "t_dem_paths") < 0)
		return 1;
	dems();
	tmpdir_done(dir);
	return tap_done();
}
