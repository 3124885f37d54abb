/* t_fqm - the FQM and vertex map as rasters (fqm.h): level sizes and the
 * level count, the header written and read back (fqm:* and geo:*), the
 * checks on what a header claims, channel layout and row coding, and
 * fqm_open on files of the right and the wrong kind. */
#include "qem/fqm.h"
#include "tap.h"
#include "tmpdir.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[PATH_MAX / 2];

static const char *
tmp(const char *name)
{
	return tmpdir_join(dir, name);
}

static void
test_sizes(void)
{
	ok(geo_level_size(3601, 0) == 3601 && geo_level_size(3601, 1) == 1801 &&
	    geo_level_size(3601, 5) == 114 && geo_level_size(1197, 3) == 151 &&
	    geo_level_size(643, 4) == 42, "geo_level_size: ceil((n0-1)/2^l)+1");
	ok(geo_level_size(1, 7) == 1 && geo_level_size(2, 9) == 2 &&
	    geo_level_size(3, 1) == 2 && geo_level_size(4, 1) == 3,
	    "geo_level_size: tiny extents (1, 2, 3, 4 samples)");
	ok(geo_levels(129, 129) == 1 && geo_levels(130, 129) == 2 &&
	    geo_levels(129, 130) == 2 && geo_levels(257, 257) == 2 &&
	    geo_levels(258, 3) == 3, "geo_levels: level 0 up to the first "
	    "that fits one %d-vertex block", FQM_BLOCK);
	ok(geo_levels(3601, 3601) == 6 && geo_levels(1201, 1201) == 5 &&
	    geo_levels(1197, 643) == 5 && geo_levels(512, 512) == 3,
	    "geo_levels: the DEMs of ../shared/data (6, 5, 5, 3 levels, as "
	    "dem2fqm -I says)");
	ok(geo_levels(1, 1) == 1 && geo_levels(1 << 26, 2) == 20,
	    "geo_levels: a single sample, the largest raster");
}

static void
sample_info(fqm_info *fi)
{
	memset(fi, 0, sizeof *fi);
	fi->level = 2;
	fi->size0[0] = 37, fi->size0[1] = 23;
	fi->geo.model = GEO_PROJECTED;
	fi->geo.epsg = 32611;
	strcpy(fi->geo.crs, "EPSG:32611");
	fi->geo.point = 0;
	fi->geo.origin[0] = 384000.5, fi->geo.origin[1] = 3795000.25;
	fi->geo.step[0] = 10, fi->geo.step[1] = -10;
	fi->geo.unit = 1;
	strcpy(fi->geo.vdatum, "EPSG:5703");
	fi->geo.has_nodata = 1;
	fi->geo.nodata = NAN;
	fi->geo.width = 37, fi->geo.height = 23;
}

static void
test_header(void)
{
	fqm_info fi, back;
	fqm_layout L;
	rs_header h;
	tl_err e = { "" };
	const char *diff;
	int v;

	sample_info(&fi);
	ok(fqm_header(&h, &fi, "binomial", &e) == 0 && h.width == 10 &&
	    h.height == 7 && h.nch == 13, "fqm_header: level 2 of 37x23 is "
	    "10x7, 13 channels");
	ok(strcmp(rs_get_string(&h, FQM_ATTR_KIND), "fqm") == 0 &&
	    strcmp(rs_get_string(&h, FQM_ATTR_KERNEL), "binomial") == 0 &&
	    rs_get_int(&h, FQM_ATTR_VERSION, &v) == 0 && v == FQM_VERSION,
	    "fqm_header: kind fqm, the kernel, the version");
	v = fqm_info_of(&h, "fqm", &back, "x.exr", &e);
	diff = geo_differs(&fi.geo, &back.geo);
	ok(v == 0 && back.level == 2 && back.size0[0] == 37 &&
	    back.size0[1] == 23 && diff == NULL, "fqm_info_of: level, size0 "
	    "and the georeferencing round-trip (%s)", diff ? diff : "same");
	ok(fqm_info_of(&h, NULL, &back, "x.exr", &e) == 0, "fqm_info_of: "
	    "any kind when none is wanted");
	ok(fqm_info_of(&h, "vertices", &back, "x.exr", &e) < 0 &&
	    strcmp(e.msg, "x.exr: is a fqm map, expected vertices") == 0,
	    "fqm_info_of: the wrong kind (%s)", e.msg);
	ok(fqm_layout_of(&h, &L, "x.exr", &e) == 0 &&
	    strcmp(h.ch[L.q[9]], "Q.c") == 0 && strcmp(h.ch[L.z], "Z") == 0 &&
	    strcmp(h.ch[L.v], "V") == 0, "fqm_layout_of: channel indices "
	    "in the sorted header");
	h.width = 11;
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) < 0 &&
	    strstr(e.msg, "size 11x7 is not that of level 2 of a 37x23 DEM"),
	    "fqm_info_of: a size that is not the level's (%s)", e.msg);
	/* a window: level 2 of 37 columns has 10; columns 3 .. 8 */
	h.width = 6;
	rs_set_int(&h, RS_ATTR_X0, 3, &e);
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) == 0 && back.x0 == 3 &&
	    fqm_whole(&h, &back, "x.exr", &e) < 0 &&
	    strstr(e.msg, "columns 3..8 of level 2, not the whole level"),
	    "fqm_info_of: a window; fqm_whole refuses it (%s)", e.msg);
	h.width = 8;
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) < 0 &&
	    strstr(e.msg, "size 8x7 from column 3 is not inside level 2"),
	    "fqm_info_of: a window past the level's end (%s)", e.msg);
	rs_set_int(&h, RS_ATTR_X0, -1, &e);
	h.width = 6;
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) < 0,
	    "fqm_info_of: a window before column 0");
	rs_unset(&h, RS_ATTR_X0);
	h.width = 10;
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) == 0 && back.x0 == 0 &&
	    fqm_whole(&h, &back, "x.exr", &e) == 0,
	    "fqm_info_of: the whole level");
	rs_set_int(&h, FQM_ATTR_VERSION, 2, &e);
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) < 0 &&
	    strstr(e.msg, "fqm version 2, this program reads 1"),
	    "fqm_info_of: another version (%s)", e.msg);
	rs_unset(&h, FQM_ATTR_VERSION);
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) < 0 &&
	    strstr(e.msg, "not a quadric or vertex map"),
	    "fqm_info_of: no fqm:version (%s)", e.msg);
	rs_set_int(&h, FQM_ATTR_VERSION, 1, &e);
	rs_set_int(&h, FQM_ATTR_LEVEL, 31, &e);
	ok(fqm_info_of(&h, "fqm", &back, "x.exr", &e) < 0 &&
	    strstr(e.msg, "bad fqm:level 31"), "fqm_info_of: an absurd "
	    "level (%s)", e.msg);
	rs_clear_channels(&h);
	rs_add_channel(&h, "Z", &e);
	ok(fqm_layout_of(&h, &L, "x.exr", &e) < 0 &&
	    strcmp(e.msg, "x.exr: no channel Q.a11") == 0,
	    "fqm_layout_of: a missing channel (%s)", e.msg);
	rs_header_free(&h);
}

/* Rows code and decode exactly (values representable in float). */
static void
test_rows(void)
{
	enum { W = 5 };
	fqm_info fi;
	fqm_layout L;
	fqm_vertex in[W], out[W];
	rs_header h;
	float row[13 * W];
	int bad = 0;

	sample_info(&fi);
	fqm_header(&h, &fi, "none", NULL);
	fqm_layout_of(&h, &L, "x", NULL);
	for (int i = 0; i < W; i++) {
		for (int k = 0; k < 6; k++)
			in[i].q.a[k] = i * 16 + k + 0.5;
		for (int k = 0; k < 3; k++)
			in[i].q.b[k] = -(i * 8 + k) - 0.25;
		in[i].q.c = 1000 + i;
		in[i].z = 100.125 * i, in[i].s = -i, in[i].v = i & 1;
	}
	fqm_encode(&L, in, W, row);
	fqm_decode(&L, row, W, out);
	bad = memcmp(in, out, sizeof in) != 0;
	/* channel-planar: vertex i of channel c at row[c * W + i] */
	bad += row[rs_channel(&h, "Q.a13") * W + 3] != 3 * 16 + 2 + 0.5f;
	bad += row[rs_channel(&h, "S") * W + 4] != -4;
	ok(bad == 0, "fqm_encode / fqm_decode: a row round-trips, each "
	    "coefficient in its channel");
	rs_header_free(&h);
}

/* A raster with h's header and zero rows, at path. */
static int
write_zero(const char *path, const rs_header *h)
{
	float *row = calloc((size_t)h->width * h->nch, sizeof *row);
	rs_writer *w = rs_create(path, h, RS_ZIP, NULL);
	int r = w != NULL ? 0 : -1;

	for (int y = 0; r == 0 && y < h->height; y++)
		r = rs_write_row(w, row, NULL);
	r = r == 0 ? rs_finish(w, NULL) : (rs_abort(w), -1);
	free(row);
	return r;
}

static void
test_open(void)
{
	fqm_info fi, back;
	fqm_layout L;
	rs_header h;
	rs_reader *r;
	tl_err e = { "" };

	sample_info(&fi);
	fqm_header(&h, &fi, "binomial", NULL);
	write_zero(tmp("l2.exr"), &h);
	r = fqm_open(tmp("l2.exr"), &back, &L, &e);
	ok(r != NULL && back.level == 2 && rs_header_of(r)->width == 10 &&
	    strcmp(rs_header_of(r)->ch[L.s], "S") == 0, "fqm_open: an FQM "
	    "file, its info and layout");
	rs_close(r);
	rs_set_string(&h, FQM_ATTR_KIND, "vertices", NULL);
	write_zero(tmp("v2.exr"), &h);
	ok(fqm_open(tmp("v2.exr"), &back, &L, &e) == NULL &&
	    strstr(e.msg, "v2.exr: is a vertices map, expected fqm"),
	    "fqm_open: a vertex map is refused (%s)", e.msg);
	rs_unset(&h, FQM_ATTR_KIND);
	rs_set_string(&h, FQM_ATTR_KIND, "fqm", NULL);
	rs_clear_channels(&h);
	rs_add_channel(&h, "Z", NULL);
	write_zero(tmp("z.exr"), &h);
	ok(fqm_open(tmp("z.exr"), &back, &L, &e) == NULL &&
	    strstr(e.msg, "no channel Q.a11"), "fqm_open: an FQM without "
	    "its quadric channels is refused (%s)", e.msg);
	ok(fqm_open(tmp("none.exr"), &back, &L, &e) == NULL &&
	    strstr(e.msg, "cannot open"), "fqm_open: a missing file (%s)",
	    e.msg);
	rs_header_free(&h);
	unlink(tmp("l2.exr")), unlink(tmp("v2.exr")), unlink(tmp("z.exr"));
}

/* Non-finite values in a row read back are errors naming the row, the
 * channel and the column; an EXR without checksums (NONE) carries a NaN
 * as written. */
static void
test_check_row(void)
{
	enum { W = 6, NCH = 13 };
	float row[NCH * W];
	fqm_info fi;
	fqm_layout L;
	rs_header h;
	rs_writer *w;
	rs_reader *r;
	tl_err e = { "" };
	int rv = 0, y, bad = -1;

	for (int k = 0; k < NCH * W; k++)
		row[k] = (float)k - 20.5f;
	row[5] = -0.0f, row[7] = 1e-40f, row[9] = 3.4e38f;
	ok(fqm_check_row(row, 0, W, NCH, 0, "x", &e) == 0, "fqm_check_row: "
	    "finite values (denormal, huge, -0) pass");
	row[3 * W + 4] = NAN;
	ok(fqm_check_row(row, 0, W, NCH, 7, "l1.exr", &e) < 0 &&
	    strcmp(e.msg, "l1.exr: row 7, channel 3: NaN at column 4 "
	    "(damaged?)") == 0, "fqm_check_row: a NaN named by row, channel, "
	    "column (%s)", e.msg);
	row[3 * W + 4] = 0;
	row[12 * W + 5] = -INFINITY;
	ok(fqm_check_row(row, 0, W, NCH, 2, "-", &e) < 0 &&
	    strstr(e.msg, "row 2, channel 12: infinite value at column 5"),
	    "fqm_check_row: an infinity too (%s)", e.msg);
	ok(fqm_check_row(row, 300, W, NCH, 2, "-", &e) < 0 &&
	    strstr(e.msg, "infinite value at column 305"),
	    "fqm_check_row: a span's columns are the raster's (%s)", e.msg);

	sample_info(&fi); /* level 2 of 37 x 23: 10 x 7 */
	fqm_header(&h, &fi, "none", NULL);
	fqm_layout_of(&h, &L, "x", NULL);
	{
		size_t n = (size_t)h.width * h.nch;
		float *buf = calloc(n, sizeof *buf);
		w = rs_create(tmp("nan.exr"), &h, RS_NONE, &e);
		for (y = 0; w != NULL && y < h.height && rv == 0; y++) {
			if (y == 3)
				buf[(size_t)L.z * h.width + 1] = NAN;
			rv = rs_write_row(w, buf, &e);
			buf[(size_t)L.z * h.width + 1] = 0;
		}
		rv = w != NULL && rv == 0 ? rs_finish(w, &e) : -1;
		r = rv == 0 ? fqm_open(tmp("nan.exr"), &fi, &L, &e) : NULL;
		for (y = 0; r != NULL && y < h.height; y++)
			if (rs_read_row(r, buf, &e) < 0 ||
			    fqm_check_row(buf, 0, h.width, h.nch, y, "nan.exr",
			    &e) < 0) {
				bad = y;
				break;
			}
		ok(bad == 3 && strstr(e.msg, "nan.exr: row 3, channel ") &&
		    strstr(e.msg, "NaN at column 1"), "an FQM EXR (NONE) with "
		    "a NaN in row 3: found there (%s)", e.msg);
		rs_close(r);
		free(buf);
	}
	rs_header_free(&h);
	unlink(tmp("nan.exr"));
}

int
main(void)
{
	if (tmpdir_make(dir, sizeof dir, "t_fqm") < 0) {
		perror(dir);
		return 1;
	}
	test_sizes();
	test_header();
	test_rows();
	test_open();
	test_check_row();
	tmpdir_done(dir);
	return tap_done();
}
