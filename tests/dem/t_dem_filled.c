/* t_dem_filled - filled DEM files (dem_save_filled, dem_open_filled,
 * filled(5)): saved from dem_open and opened again, a DEM gives bit for
 * bit the rows and spans, masks, georeferencing and void count of
 * dem_open, on the real DEMs of ../shared/data (or $DATA), mosaics of
 * them, an EXR and fixtures with voids across whole rows and columns,
 * reading only the bytes asked for; the file is laid out as filled(5)
 * says; files of another DEM, of other options, truncated, damaged or of
 * another kind are refused naming the file; a failed save leaves nothing
 * behind. */
#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "dem/dem.h"
#include "geo/georef.h"
#include "raster/raster.h"
#include "demgrid.h"
#include "tap.h"
#include "tmpdir.h"

static char dir[PATH_MAX / 2], data[PATH_MAX / 2 + 32];

static const char *
tmp(const char *name)
{
	return tmpdir_join(dir, name);
}

static const char *
dpath(const char *name)
{
	return tmpdir_join(data, name);
}

static double
now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + t.tv_nsec * 1e-9;
}

static int
sh(const char *fmt, const char *a, const char *b)
{
	char cmd[4 * PATH_MAX];

	snprintf(cmd, sizeof cmd, fmt, a, b);
	return system(cmd);
}

static int
gdal_tools(void)
{
	return system("gdal_translate --version >/dev/null 2>&1") == 0 &&
	    system("gdalbuildvrt --version >/dev/null 2>&1") == 0;
}

/* Files in dir whose name starts with prefix (temporaries: ".NAME."). */
static int
entries(const char *prefix)
{
	return tmpdir_entries(dir, prefix);
}

static long long
fsize(const char *path)
{
	struct stat st;

	return stat(path, &st) == 0 ? (long long)st.st_size : -1;
}

/* --- fixtures (demgrid.h's grids) ---------------------------------------- */

/* An EXR (the plugin's way in): row 2 and column 0 NaN. */
static int
write_exr(const char *name, tl_err *e)
{
	rs_header h;
	rs_writer *w = NULL;
	georef g;
	float row[7];
	int r;

	geo_init_none(&g, 2.5, 0);
	g.width = 7, g.height = 5;
	rs_header_init(&h, 7, 5);
	r = rs_add_channel(&h, "Z", e) == 0 && rs_put_georef(&g, &h, e) == 0 &&
	    (w = rs_create(tmp(name), &h, RS_ZIP, e)) != NULL;
	for (int j = 0; r && j < 5; j++) {
		for (int i = 0; i < 7; i++)
			row[i] = j == 2 || i == 0 ? NAN : (float)z_wave(i, j);
		r = rs_write_row(w, row, e) == 0;
	}
	r = r && rs_finish(w, e) == 0;
	rs_header_free(&h);
	return r ? 0 : -1;
}

static void
make_fixtures(void)
{
	demgrid_write(tmp("cross.asc"), 9, 7, z_wave, v_cross);
	demgrid_write(tmp("tall.asc"), 3, 130, z_wave, v_tall);
	demgrid_write(tmp("none.asc"), 11, 5, z_wave, v_none);
	demgrid_write(tmp("edges.asc"), 300, 40, z_wave, v_edges);
}

/* --- comparisons --------------------------------------------------------- */

/* Span x0, n of row j from a and b: bit for bit, masks too, and with
 * valid NULL. */
static int
same_span(dem *a, dem *b, int j, int x0, int n, tl_err *e)
{
	float *za = malloc((size_t)n * sizeof *za + 1);
	float *zb = malloc((size_t)n * sizeof *zb + 1);
	unsigned char *va = malloc((size_t)n + 1), *vb = malloc((size_t)n + 1);
	int r = dem_read_span(a, j, x0, n, za, va, e) == 0 &&
	    dem_read_span(b, j, x0, n, zb, vb, e) == 0 &&
	    memcmp(za, zb, (size_t)n * sizeof *za) == 0 &&
	    memcmp(va, vb, (size_t)n) == 0;

	memset(zb, 0, (size_t)n * sizeof *zb);
	r = r && dem_read_span(b, j, x0, n, zb, NULL, e) == 0 &&
	    memcmp(za, zb, (size_t)n * sizeof *za) == 0;
	free(za), free(zb), free(va), free(vb);
	return r;
}

/* Every row whole, from the last to the first, then windows of every
 * row: the first column, the first third, the second half, the last 17
 * columns, the last column. */
static int
same_dem(dem *a, dem *b, tl_err *e)
{
	const georef *g = dem_georef(a);
	int w = g->width, h = g->height, r;
	int win[][2] = { { 0, 1 }, { 0, w / 3 + 1 }, { w / 2, w - w / 2 },
	    { w > 17 ? w - 17 : 0, w > 17 ? 17 : w }, { w - 1, 1 } };

	r = memcmp(g, dem_georef(b), sizeof *g) == 0 &&
	    dem_voids(a) == dem_voids(b) && dem_zunit(a) == dem_zunit(b);
	if (!r)
		snprintf(e->msg, sizeof e->msg, "georef, voids (%lld, %lld) or "
		    "unit differ", dem_voids(a), dem_voids(b));
	for (int j = h - 1; j >= 0 && r; j--)
		r = same_span(a, b, j, 0, w, e);
	for (int j = 0; j < h && r; j++)
		for (size_t k = 0; k < sizeof win / sizeof win[0] && r; k++)
			r = same_span(a, b, j, win[k][0], win[k][1], e);
	return r;
}

/* dem_open(path, o) saved to file and opened again from it, compared. */
static int
roundtrip(const char *path, const dem_opts *o, const char *file,
    long long *voids, tl_err *e)
{
	dem *a = dem_open(path, o, e), *b = NULL;
	int r = a != NULL && dem_save_filled(a, file, e) == 0 &&
	    (b = dem_open_filled(path, o, file, e)) != NULL &&
	    same_dem(a, b, e);

	*voids = a != NULL ? dem_voids(a) : -1;
	dem_close(a);
	dem_close(b);
	return r;
}

static void
check_roundtrip(const char *name, const char *path, const dem_opts *o,
    const char *file, long long want)
{
	tl_err e = { "" };
	long long voids;
	double t = now();
	int r = roundtrip(path, o, file, &voids, &e);

	ok(r && (want < 0 || voids == want), "%s: saved filled and opened "
	    "again: rows, spans, masks, georef and %lld voids bit for bit "
	    "(%.2f s) %s", name, voids, now() - t, e.msg);
}

/* --- the layout of filled(5) --------------------------------------------- */

static uint64_t
le(const unsigned char *p, int n)
{
	uint64_t v = 0;

	for (int i = n - 1; i >= 0; i--)
		v = v << 8 | p[i];
	return v;
}

/* cross.asc's file read by the man page: the header's fields, the
 * bitmap, a height and the masks at the offsets it gives. */
static void
check_layout(void)
{
	unsigned char b[4096 + 4 * 63 + 4 * 9];
	FILE *f = fopen(tmp("cross.fd"), "rb");
	size_t n = f != NULL ? fread(b, 1, sizeof b, f) : 0;
	unsigned char m[9];
	uint64_t zoff = le(b + 40, 8), moff = le(b + 48, 8);
	float z;
	int good;

	good = n == sizeof b && memcmp(b, "TLFILLED", 8) == 0 &&
	    le(b + 8, 4) == 1 && le(b + 12, 4) == 9 && le(b + 16, 4) == 7 &&
	    le(b + 20, 4) == 7 && le(b + 24, 8) == 7 + 9 - 1 + 1 &&
	    zoff == 4096 && moff == 4096 + 4 * 63 &&
	    b[64] == 0x7f && fsize(tmp("cross.fd")) == (long long)moff + 7 * 9;
	ok(good, "cross.asc's file: TLFILLED, version 1, 9 x 7, 7 rows with "
	    "voids, 16 voids, heights at 4096, masks after them, bitmap 0x%02x",
	    b[64]);
	memcpy(&z, b + zoff + 4 * (2 * 9 + 5), 4);
	ok(z == (float)z_wave(5, 2), "row 2 column 5 at Z + 4(2W + 5): %g", z);
	fseek(f, (long)moff + 3 * 9, SEEK_SET);
	n = fread(m, 1, sizeof m, f);
	good = n == 9;
	for (int i = 0; i < 9 && good; i++)
		good = m[i] == 0;
	fseek(f, (long)moff + 6 * 9, SEEK_SET);
	n = fread(m, 1, sizeof m, f);
	good = good && n == 9 && m[4] == 0 && m[8] == 0 && m[0] == 1 &&
	    m[7] == 1;
	ok(good, "masks of rows 3 (all void) and 6 (column 4 and 8 void) at "
	    "M + kW, k their rank among the rows with voids");
	if (f != NULL)
		fclose(f);
}

/* --- refusals ------------------------------------------------------------ */

/* dem_open_filled(path, o, file) fails with want in a message that
 * starts with the filled file's name (or with start). */
static void
refused(const char *what, const char *path, const dem_opts *o,
    const char *file, const char *start, const char *want)
{
	tl_err e = { "" };
	dem *d = dem_open_filled(path, o, file, &e);

	if (start == NULL)
		start = file;
	ok(d == NULL && strncmp(e.msg, start, strlen(start)) == 0 &&
	    strstr(e.msg, want) != NULL, "%s: refused: %s", what, e.msg);
	dem_close(d);
}

static void
copy_cut(const char *from, const char *to, long long keep)
{
	FILE *f = fopen(from, "rb"), *g = fopen(to, "wb");
	int c;

	for (long long k = 0; (keep < 0 || k < keep) &&
	    (c = getc(f)) != EOF; k++)
		putc(c, g);
	fclose(f);
	fclose(g);
}

static void
poke(const char *path, long off, unsigned char v)
{
	FILE *f = fopen(path, "r+b");

	fseek(f, off, SEEK_SET);
	putc(v, f);
	fclose(f);
}

static void
check_damage(void)
{
	char a[PATH_MAX], fd[PATH_MAX];
	long long n;

	snprintf(a, sizeof a, "%s", tmp("cross.asc"));
	snprintf(fd, sizeof fd, "%s", tmp("cross.fd"));
	n = fsize(fd);

	copy_cut(fd, tmp("cut1"), n - 1);
	refused("the file less its last byte", a, NULL, tmp("cut1"), NULL,
	    "truncated filled DEM file");
	copy_cut(fd, tmp("cut2"), 4096 + 100);
	refused("the file cut in its heights", a, NULL, tmp("cut2"), NULL,
	    "truncated");
	copy_cut(fd, tmp("cut3"), 64);
	refused("the file cut after its header", a, NULL, tmp("cut3"), NULL,
	    "truncated");
	copy_cut(fd, tmp("cut4"), 30);
	refused("the file cut in its header", a, NULL, tmp("cut4"), NULL,
	    "truncated");
	copy_cut(fd, tmp("long"), -1);
	poke(tmp("long"), (long)n, 0);
	refused("a byte appended", a, NULL, tmp("long"), NULL, "damaged");
	copy_cut(fd, tmp("poked"), -1);
	poke(tmp("poked"), 24, 99);
	refused("its void count changed", a, NULL, tmp("poked"), NULL,
	    "checksum");
	copy_cut(fd, tmp("bits"), -1);
	poke(tmp("bits"), 64, 0x3f);
	refused("its bitmap changed", a, NULL, tmp("bits"), NULL, "checksum");
	copy_cut(fd, tmp("v2"), -1);
	poke(tmp("v2"), 8, 2);
	refused("version 2", a, NULL, tmp("v2"), NULL, "version 2");
	refused("the DEM itself", a, NULL, a, NULL, "not a filled DEM file");
	copy_cut(fd, tmp("empty"), 0);
	refused("an empty file", a, NULL, tmp("empty"), NULL,
	    "not a filled DEM file");
	refused("a directory", a, NULL, dir, NULL, "not a regular file");
	mkfifo(tmp("fifo"), 0600);
	refused("a FIFO (not waited on)", a, NULL, tmp("fifo"), NULL,
	    "not a regular file");
	refused("a missing file", a, NULL, tmp("missing.fd"), NULL,
	    "cannot open");
}

static void
check_mismatch(void)
{
	dem_opts nd = { .has_nodata = 1, .nodata = 349 };
	dem_opts ell = { .heights = "ellipsoid" };
	dem_opts cell = { .cell = { 30, 0 } };
	dem_opts grey = { .encoding = DEM_ENC_GREY };
	char hgt[PATH_MAX];
	tl_err e = { "" };
	dem *d;

	snprintf(hgt, sizeof hgt, "%s", dpath("N42E001.hgt"));

	refused("N42E001.hgt's file for N44W072.hgt (same size)",
	    dpath("N44W072.hgt"), NULL, tmp("n42.fd"), NULL,
	    "made from another DEM or other options");
	refused("N42E001.hgt's file for N42E001.tif (the same heights, "
	    "no vertical datum declared)", dpath("N42E001.tif"), NULL,
	    tmp("n42.fd"), NULL, "made from another DEM or other options");
	refused("its file for N42E001.hgt -N 349", hgt, &nd, tmp("n42.fd"),
	    NULL, "made from another DEM or other options");
	refused("its file for N42E001.hgt -H ellipsoid", hgt, &ell,
	    tmp("n42.fd"), NULL, "made from another DEM or other options");
	refused("its -H ellipsoid file for N42E001.hgt", hgt, NULL,
	    tmp("n42h.fd"), NULL, "made from another DEM or other options");
	refused("its file for N42E001.hgt -s 30 (the georeferencing "
	    "differs)", hgt, &cell, tmp("n42.fd"), NULL,
	    "made from another DEM or other options");
	refused("cross.asc's file for tall.asc", tmp("tall.asc"), NULL,
	    tmp("cross.fd"), NULL, "9 x 7");
	d = dem_open_filled(hgt, &grey, tmp("n42.fd"), &e);
	ok(d != NULL && dem_voids(d) == 7652, "-e grey on a grey DEM "
	    "changes no value: its file opens %s", e.msg);
	dem_close(d);
	refused("a DEM on stdin", "-", NULL, tmp("n42.fd"), "-: ", "stdin");
	refused("a filled file on stdin", hgt, NULL, "-", "-: ",
	    "named file");
	refused("a missing DEM", tmp("nodem.hgt"), NULL, tmp("n42.fd"),
	    tmp("nodem.hgt"), "cannot open");
}

/* --- saving -------------------------------------------------------------- */

static void
save_fails(const char *what, dem *d, const char *path, const char *want)
{
	tl_err e = { "" };

	ok(d != NULL && dem_save_filled(d, path, &e) < 0 &&
	    strstr(e.msg, want) != NULL && fsize(path) < 0, "%s: refused, "
	    "nothing written: %s", what, e.msg);
}

/* Fails writing past RLIMIT_FSIZE (EFBIG, SIGXFSZ ignored): no file,
 * no temporary. */
static void
check_full_disk(dem *d)
{
	struct rlimit old, lim;
	void (*was)(int) = signal(SIGXFSZ, SIG_IGN);
	tl_err e = { "" };
	int r;

	getrlimit(RLIMIT_FSIZE, &old);
	lim = old;
	lim.rlim_cur = 100000;
	setrlimit(RLIMIT_FSIZE, &lim);
	r = d != NULL ? dem_save_filled(d, tmp("full.fd"), &e) : 0;
	setrlimit(RLIMIT_FSIZE, &old);
	signal(SIGXFSZ, was);
	ok(r < 0 && strncmp(e.msg, tmp("full.fd"), strlen(tmp("full.fd"))) ==
	    0 && fsize(tmp("full.fd")) < 0 && entries(".full.fd") == 0,
	    "a write failing half way (file size limit): refused, no file, "
	    "no temporary: %s", e.msg);
}

static void
check_save(void)
{
	char hgt[PATH_MAX];
	tl_err e = { "" };
	dem *d, *f;
	int r;

	snprintf(hgt, sizeof hgt, "%s", dpath("N42E001.hgt"));
	d = dem_open(hgt, NULL, &e);

	save_fails("a missing directory", d, tmp("nodir/x.fd"), "nodir/x.fd");
	save_fails("a directory under a file", d, tmp("cross.asc/x.fd"),
	    "cross.asc/x.fd");
	save_fails("standard output", d, "-", "named file");
	check_full_disk(d);
	dem_close(d);
	d = dem_open_cols(hgt, NULL, 10, 20, &e);
	save_fails("a window of columns", d, tmp("cols.fd"), "unfilled");
	dem_close(d);
	d = dem_open_info(hgt, NULL, &e);
	save_fails("a DEM opened for its header", d, tmp("info.fd"),
	    "header only");
	dem_close(d);
	f = dem_open_filled(hgt, NULL, tmp("n42.fd"), &e);
	r = f != NULL && dem_save_filled(f, tmp("again.fd"), &e) == 0 &&
	    sh("cmp -s '%s' '%s'", tmp("n42.fd"), tmp("again.fd")) == 0;
	ok(r, "a DEM opened filled saves the same bytes again %s", e.msg);
	dem_close(f);
	ok(entries(".") == 2, "no temporary left in the directory");
}

/* A DEM read on stdin (dem2fqm - -n NAME) saved: its file opens with the
 * DEM's path. */
static void
check_stdin(void)
{
	dem_opts o = { .hgt_name = "N42E001.hgt" };
	int saved = dup(0), fd = open(dpath("N42E001.hgt"), O_RDONLY);
	tl_err e = { "" };
	dem *d, *a, *b;
	int r;

	dup2(fd, 0);
	close(fd);
	d = dem_open("-", &o, &e);
	dup2(saved, 0);
	close(saved);
	r = d != NULL && dem_save_filled(d, tmp("stdin.fd"), &e) == 0;
	dem_close(d);
	a = dem_open(dpath("N42E001.hgt"), NULL, &e);
	b = r ? dem_open_filled(dpath("N42E001.hgt"), NULL, tmp("stdin.fd"),
	    &e) : NULL;
	ok(b != NULL && same_dem(a, b, &e), "N42E001.hgt read on stdin, "
	    "saved filled: opens with its path, the same rows %s", e.msg);
	dem_close(a), dem_close(b);
}

/* --- GDAL's own tiles: mosaics, and no sample read through GDAL ---------- */

/* N42E001.tif (voids) cut into 2 x 2 tiles sharing their edges, as a
 * list and as gdalbuildvrt's VRT. */
static void
check_mosaic(void)
{
	static const char *tiles[][3] = { { "a", "0", "0" },
	    { "b", "600", "0" }, { "c", "0", "600" }, { "d", "600", "600" } };
	char cmd[4 * PATH_MAX];
	FILE *f;
	int r = 0;

	for (int k = 0; k < 4 && r == 0; k++) {
		snprintf(cmd, sizeof cmd, "cd '%s' && gdal_translate -q "
		    "-srcwin %s %s 601 601 '%s' %s.tif", dir, tiles[k][1],
		    tiles[k][2], dpath("N42E001.tif"), tiles[k][0]);
		r = system(cmd);
	}
	if (r == 0)
		r = sh("cd '%s' && gdalbuildvrt -q m.vrt a.tif b.tif c.tif "
		    "d.tif%s", dir, "");
	if (!ok(r == 0, "N42E001.tif in 2 x 2 tiles (gdal_translate), a VRT "
	    "(gdalbuildvrt)"))
		return;
	f = fopen(tmp("tiles.txt"), "w");
	fprintf(f, "# N42E001\na.tif\nb.tif\nc.tif\nd.tif\n");
	fclose(f);
	check_roundtrip("a list of 4 tiles", tmp("tiles.txt"), NULL,
	    tmp("list.fd"), 7652);
	check_roundtrip("their VRT", tmp("m.vrt"), NULL, tmp("vrt.fd"), 7652);
}

/* A DEFLATE GeoTIFF saved filled, then cut to 60 %: GDAL can read its
 * header but not its samples, and the filled file still gives them all. */
static void
check_no_samples(void)
{
	tl_err e = { "" };
	dem *a, *b, *c;
	int r;

	r = sh("gdal_translate -q -co COMPRESS=DEFLATE '%s' '%s'",
	    dpath("N42E001.hgt"), tmp("z.tif"));
	a = r == 0 ? dem_open(tmp("z.tif"), NULL, &e) : NULL;
	r = a != NULL && dem_save_filled(a, tmp("z.fd"), &e) == 0;
	if (r)
		copy_cut(tmp("z.tif"), tmp("cut.tif"), fsize(tmp("z.tif")) * 6 /
		    10);
	c = r ? dem_open(tmp("cut.tif"), NULL, &e) : NULL;
	ok(r && c == NULL && strstr(e.msg, "cut.tif") != NULL, "the cut "
	    "GeoTIFF cannot be read whole: %s", e.msg);
	e.msg[0] = '\0';
	b = r ? dem_open_filled(tmp("cut.tif"), NULL, tmp("z.fd"), &e) : NULL;
	ok(b != NULL && same_dem(a, b, &e), "but opened filled it gives "
	    "every sample: no sample is read through GDAL %s", e.msg);
	dem_close(a), dem_close(b), dem_close(c);
}

/* --- reading only what is asked for ------------------------------------ */

/* Bytes this process has read (rchar of /proc/self/io) before this
 * call; *n gets those this call reads, which the next call counts. */
static long long
rchar(long long *n)
{
	char buf[1024], *p;
	int fd = open("/proc/self/io", O_RDONLY);
	ssize_t k = fd >= 0 ? read(fd, buf, sizeof buf - 1) : -1;

	if (fd >= 0)
		close(fd);
	if (k <= 0)
		return -1;
	buf[k] = '\0';
	*n = k;
	p = strstr(buf, "rchar: ");
	return p != NULL ? atoll(p + 7) : -1;
}

/* A row of d with voids (want 1) or without (0), or -1. */
static int
find_row(dem *d, int want, tl_err *e)
{
	int w = dem_georef(d)->width;
	float *z = malloc((size_t)w * sizeof *z);
	unsigned char *v = malloc((size_t)w);
	int found = -1;

	for (int j = 0; j < dem_georef(d)->height && found < 0; j++) {
		int voids = 0;
		if (dem_read_row(d, j, z, v, e) < 0)
			break;
		for (int i = 0; i < w; i++)
			voids += !v[i];
		if ((voids > 0) == want)
			found = j;
	}
	free(z), free(v);
	return found;
}

/* A span of a row with voids costs its heights and its mask, one
 * without voids its heights only. */
static void
check_bytes(void)
{
	tl_err e = { "" };
	dem *d = dem_open_filled(dpath("N48W125.hgt"), NULL, tmp("n48.fd"),
	    &e);
	int jv = d ? find_row(d, 1, &e) : -1, jf = d ? find_row(d, 0, &e) : -1;
	long long n0, n1, n2, r0, r1, r2;
	float z[100];
	unsigned char v[100];
	int good;

	if (jv < 0 || jf < 0 || rchar(&n0) < 0) {
		ok(0, "N48W125's file: rows with and without voids, "
		    "/proc/self/io %s", e.msg);
		dem_close(d);
		return;
	}
	r0 = rchar(&n0);
	good = dem_read_span(d, jv, 1000, 100, z, v, &e) == 0;
	r1 = rchar(&n1);
	good = good && dem_read_span(d, jf, 3501, 100, z, v, &e) == 0;
	r2 = rchar(&n2);
	ok(good && r1 - r0 - n0 == 500 && r2 - r1 - n1 == 400, "N48W125's "
	    "file: 100 samples of row %d (voids) read %lld bytes, of row %d "
	    "(none) %lld %s", jv, r1 - r0 - n0, jf, r2 - r1 - n1, e.msg);
	dem_close(d);
}

/* --- setup --------------------------------------------------------------- */

/* This program is TOP/BUILD/tests/dem/t_dem_filled: the plugin is
 * BUILD's, the data beside TOP (or $DATA). */
static void
setup(void)
{
	char self[PATH_MAX / 2], so[PATH_MAX];
	ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
	char *t;

	snprintf(data, sizeof data, "../shared/data");
	if (n > 0 && (self[n] = '\0', t = strstr(self, "/tests/dem/"))) {
		*t = '\0';
		snprintf(so, sizeof so, "%s/tl_oiio.so", self);
		setenv("TL_OIIO_PLUGIN", so, 0);
		if ((t = strrchr(self, '/')) != NULL) {
			*t = '\0';
			snprintf(data, sizeof data, "%s/../shared/data", self);
		}
	}
	if (getenv("DATA") != NULL)
		snprintf(data, sizeof data, "%s", getenv("DATA"));
}

int
main(void)
{
	dem_opts ell = { .heights = "ellipsoid" };
	tl_err e = { "" };

	setup();
	if (tmpdir_make(dir, sizeof dir, "tfilled") < 0) {
		ok(0, "a scratch directory");
		return tap_done();
	}
	make_fixtures();
	check_roundtrip("cross.asc (a void row and column across it)",
	    tmp("cross.asc"), NULL, tmp("cross.fd"), 16);
	check_layout();
	check_roundtrip("tall.asc (130 rows, voids in every 64-row word)",
	    tmp("tall.asc"), NULL, tmp("tall.fd"), -1);
	check_roundtrip("none.asc (no voids)", tmp("none.asc"), NULL,
	    tmp("none.fd"), 0);
	ok(fsize(tmp("none.fd")) == 4096 + 4 * 11 * 5, "no voids: no masks, "
	    "%lld bytes", fsize(tmp("none.fd")));
	check_roundtrip("edges.asc (first and last column void)",
	    tmp("edges.asc"), NULL, tmp("edges.fd"), 80);
	if (write_exr("z.exr", &e) == 0)
		check_roundtrip("z.exr (through OpenImageIO)", tmp("z.exr"),
		    NULL, tmp("exr.fd"), 11);
	else
		ok(0, "an EXR fixture: %s", e.msg);
	check_roundtrip("N42E001.hgt", dpath("N42E001.hgt"), NULL,
	    tmp("n42.fd"), 7652);
	check_roundtrip("N42E001.hgt -H ellipsoid", dpath("N42E001.hgt"), &ell,
	    tmp("n42h.fd"), 7652);
	check_roundtrip("N44W072.hgt", dpath("N44W072.hgt"), NULL,
	    tmp("n44.fd"), 0);
	check_roundtrip("N48W125.hgt (half sea)", dpath("N48W125.hgt"), NULL,
	    tmp("n48.fd"), 6483876);
	check_roundtrip("bigtujunga.tif", dpath("bigtujunga.tif"), NULL,
	    tmp("big.fd"), 0);
	check_bytes();
	check_damage();
	check_mismatch();
	check_stdin();
	if (gdal_tools()) {
		check_mosaic();
		check_no_samples();
	} else {
		ok(1, "# SKIP mosaics: gdal_translate, gdalbuildvrt missing");
	}
	check_save();
	tmpdir_done(dir);
	return tap_done();
}
