/* t_dem_filled_jobs - a filled DEM file made in row bands (dem_fill_pass1,
 * dem_fill_join, dem_fill_pass2, dem_fill_commit; filled(5) PARTS) is
 * byte for byte dem_save_filled's, for bands of 1 row, 7 rows, a third
 * of the DEM and the whole, on fixtures with voids across whole rows
 * (one at a band's first row, one at its last), whole columns, the first
 * and last column, orphans (a void whose row and column are all void),
 * scattered voids, and on N48W125.hgt (half sea) and a south-up,
 * east-left crop of it; the parts leave nothing behind; pass 2 run again
 * gives the same file; commit refuses, naming it, a band's missing part;
 * parts of other bands or DEMs are refused. */
#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dem/dem.h"
#include "demgrid.h"
#include "tap.h"
#include "tmpdir.h"

static char dir[PATH_MAX / 2], data[PATH_MAX / 2 + 32], top[PATH_MAX / 2];

static const char *
tmp(const char *name)
{
	return tmpdir_join(dir, name);
}

/* Files in dir whose name starts with prefix (temporaries: ".NAME."). */
static int
entries(const char *prefix)
{
	return tmpdir_entries(dir, prefix);
}

/* The whole file, its size in *n; NULL if none. */
static unsigned char *
slurp(const char *path, long long *n)
{
	FILE *f = fopen(path, "rb");
	unsigned char *b = NULL;
	struct stat st;

	*n = -1;
	if (f != NULL && fstat(fileno(f), &st) == 0 &&
	    (b = malloc((size_t)st.st_size + 1)) != NULL &&
	    fread(b, 1, (size_t)st.st_size, f) == (size_t)st.st_size)
		*n = (long long)st.st_size;
	if (f != NULL)
		fclose(f);
	return b;
}

static int
same_file(const char *a, const char *b)
{
	long long na, nb;
	unsigned char *pa = slurp(a, &na), *pb = slurp(b, &nb);
	int r = na >= 0 && na == nb && memcmp(pa, pb, (size_t)na) == 0;

	free(pa), free(pb);
	return r;
}

/* --- fixtures (demgrid.h's grids) ---------------------------------------- */

static void
make_fixtures(void)
{
	demgrid_write(tmp("cross.asc"), 9, 7, z_wave, v_cross);
	demgrid_write(tmp("tall.asc"), 3, 130, z_wave, v_tall);
	demgrid_write(tmp("edges.asc"), 300, 40, z_wave, v_edges);
	demgrid_write(tmp("bands.asc"), 20, 21, z_wave, v_bands);
	demgrid_write(tmp("none.asc"), 11, 5, z_wave, v_none);
}

/* --- the parts ----------------------------------------------------------- */

static int
height_of(const char *path, tl_err *e)
{
	dem *d = dem_open_info(path, NULL, e);
	int h = d != NULL ? dem_georef(d)->height : -1;

	dem_close(d);
	return h;
}

static int
pass_all(int pass, const char *path, const char *out, int band, int h,
    tl_err *e)
{
	int r = 0;

	/* pass 2 bottom-up: the bands' order does not matter */
	for (int k = 0; k * band < h && r == 0; k++) {
		int y0 = pass == 1 ? k * band : (h - 1) / band * band -
		    k * band;
		int y1 = y0 + band < h ? y0 + band : h;
		r = pass == 1 ? dem_fill_pass1(path, NULL, out, y0, y1, e) :
		    dem_fill_pass2(path, NULL, out, y0, y1, e);
	}
	return r;
}

/* The four parts in bands of band rows. */
static int
by_bands(const char *path, const char *out, int band, tl_err *e)
{
	int h = height_of(path, e);

	return h > 0 && pass_all(1, path, out, band, h, e) == 0 &&
	    dem_fill_join(path, NULL, out, band, e) == 0 &&
	    pass_all(2, path, out, band, h, e) == 0 &&
	    dem_fill_commit(path, NULL, out, band, e) == 0 ? 0 : -1;
}

static int
reference(const char *path, const char *ref, tl_err *e)
{
	dem *d = dem_open(path, NULL, e);
	int r = d != NULL && dem_save_filled(d, ref, e) == 0 ? 0 : -1;

	dem_close(d);
	return r;
}

/* Bands of 1 row (small DEMs), 7, a third and the whole. */
static void
check_dem(const char *name, const char *path, int ones)
{
	const char *ref = tmp("ref.fd"), *out = tmp("out.fd");
	tl_err e = { "" };
	int h = height_of(path, &e);
	int bands[] = { 1, 7, (h + 2) / 3, h };

	if (!ok(h > 0 && reference(path, ref, &e) == 0, "%s: "
	    "dem_save_filled %s", name, e.msg))
		return;
	for (size_t k = ones ? 0 : 1; k < sizeof bands / sizeof bands[0];
	    k++) {
		int r = by_bands(path, out, bands[k], &e);
		ok(r == 0 && same_file(ref, out), "%s: in bands of %d rows: "
		    "the same bytes %s", name, bands[k], e.msg);
		ok(entries("out.fd.") == 0 && entries(".out.fd") == 0,
		    "%s, %d rows: no part left", name, bands[k]);
		unlink(out);
	}
	unlink(ref);
}

/* Pass 2 run again, before the commit, writes the same bytes; a commit
 * with a band's mark missing is refused, naming it, and commits nothing;
 * parts for other bands are refused. */
static void
check_rerun(const char *path)
{
	const char *ref = tmp("ref.fd"), *out = tmp("out.fd");
	tl_err e = { "" };
	int h = height_of(path, &e), r;

	r = reference(path, ref, &e) == 0 &&
	    pass_all(1, path, out, 7, h, &e) == 0 &&
	    dem_fill_join(path, NULL, out, 7, &e) == 0 &&
	    pass_all(2, path, out, 7, h, &e) == 0 &&
	    dem_fill_pass2(path, NULL, out, 7, 14, &e) == 0 &&
	    dem_fill_pass2(path, NULL, out, 0, 7, &e) == 0;
	ok(r, "bands.asc: pass 2 of rows 7 .. 13 and 0 .. 6 run again %s",
	    e.msg);
	r = dem_fill_pass2(path, NULL, out, 7, 13, &e) < 0;
	ok(r && strstr(e.msg, "out.fd.e.7") != NULL, "pass 2 of rows 7 .. "
	    "12 refused (the bands are of 7 rows): %s", e.msg);
	r = dem_fill_join(path, NULL, tmp("nope.fd"), 7, &e) < 0;
	ok(r && strstr(e.msg, "nope.fd.s.") != NULL, "a join without pass 1 "
	    "refused: %s", e.msg);
	rename(tmp("out.fd.d.7"), tmp("d7"));
	r = dem_fill_commit(path, NULL, out, 7, &e) < 0;
	ok(r && strstr(e.msg, "out.fd.d.7") != NULL && access(out, F_OK) != 0,
	    "commit without rows 7 .. 13's pass 2 refused, nothing committed: "
	    "%s", e.msg);
	rename(tmp("d7"), tmp("out.fd.d.7"));
	e.msg[0] = '\0';
	r = dem_fill_commit(path, NULL, out, 7, &e) == 0;
	ok(r && same_file(ref, out) && entries("out.fd.") == 0, "then "
	    "committed: the same bytes %s", e.msg);
	unlink(out), unlink(ref);
}

/* A crop of N48W125 south-up and east-left (float32, NaN voids), from
 * tests/tools/mkgdal.py; 0 when the tools are missing. */
static int
make_flipped(void)
{
	char cmd[4 * PATH_MAX];

	snprintf(cmd, sizeof cmd, "gdal_translate -q -srcwin 1300 2900 700 "
	    "300 '%s/N48W125.hgt' '%s/crop.tif' 2>/dev/null && "
	    "/usr/bin/python3 '%s/tests/tools/mkgdal.py' flipped "
	    "'%s/crop.tif' '%s/flip.tif' 2>/dev/null", data, dir, top, dir,
	    dir);
	return system(cmd) == 0;
}

static void
setup(void)
{
	char self[PATH_MAX / 2];
	ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
	char *t;

	snprintf(data, sizeof data, "../shared/data");
	snprintf(top, sizeof top, ".");
	if (n > 0 && (self[n] = '\0', t = strstr(self, "/build/tests/dem/"))) {
		*t = '\0';
		snprintf(top, sizeof top, "%s", self);
		if ((t = strrchr(self, '/')) != NULL) {
			*t = '\0';
			snprintf(data, sizeof data, "%s/shared/data", self);
		}
	}
	if (getenv("DATA") != NULL)
		snprintf(data, sizeof data, "%s", getenv("DATA"));
}

int
main(void)
{
	char n48[PATH_MAX];

	setup();
	if (tmpdir_make(dir, sizeof dir, "tfillrows") < 0) {
		ok(0, "a scratch directory");
		return tap_done();
	}
	make_fixtures();
	check_dem("cross.asc", tmp("cross.asc"), 1);
	check_dem("tall.asc", tmp("tall.asc"), 1);
	check_dem("edges.asc", tmp("edges.asc"), 1);
	check_dem("bands.asc", tmp("bands.asc"), 1);
	check_dem("none.asc", tmp("none.asc"), 1);
	check_rerun(tmp("bands.asc"));
	snprintf(n48, sizeof n48, "%s/N48W125.hgt", data);
	check_dem("N48W125.hgt", n48, 0);
	if (make_flipped())
		check_dem("N48W125 crop, south-up, east-left", tmp("flip.tif"),
		    1);
	else
		ok(1, "# SKIP the flipped crop: gdal_translate or python3 "
		    "with GDAL missing");
	tmpdir_done(dir);
	return tap_done();
}
