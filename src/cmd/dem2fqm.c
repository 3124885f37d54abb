/* dem2fqm - a DEM in, its level-0 fundamental quadric map out: per vertex
 * the area-weighted plane quadrics of its triangles, in its own frame. */
#include <string.h>

#include "cli.h"
#include "qem/fqm0.h"
#include "base/paths.h"
#include "raster/rowpipe.h"
#include "base/stamp.h"

static const char usage[] =
    "[-I] [-D datum] [-e encoding] [-F filled] [-H datum] [-N nodata]\n"
    "               [-n name] [-s dx[,dy]] [-W filled] [-w a,b] "
    "[-z compression]\n"
    "               [--guard path] [--resample] [dem [out]]\n"
    "       dem2fqm --stamp file dem ...\n"
    "       dem2fqm -W filled --fill-pass 1|2 --rows y0,y1 [DEM options] "
    "dem\n"
    "       dem2fqm -W filled --fill-pass join|commit --band-rows n\n"
    "               [DEM options] dem\n"
    "  -I              print the DEM's size, georeferencing, metric, datum "
    "and\n"
    "                  level count from its header; no output. -II also "
    "counts\n"
    "                  the voids, reading every sample\n"
    "  -D datum        the DEM's vertical datum (EPSG:5773) when it declares "
    "none\n"
    "  -e encoding     auto (default), grey, terrainrgb, terrarium\n"
    "  -F filled       the samples from this filled DEM, made by -W from "
    "dem\n"
    "  -H datum        convert heights to datum: ellipsoid (WGS 84) or "
    "EPSG:n\n"
    "  -N nodata       void value, overriding the file's\n"
    "  -n name         the file name of a DEM on stdin (N42E001.hgt)\n"
    "  -s dx[,dy]      cell size in metres (overrides the CRS's metric)\n"
    "  -W filled       write dem's samples, voids filled, to the file "
    "filled; no FQM\n"
    "  --fill-pass p   with -W: one part of a plan's filled DEM made in "
    "row bands:\n"
    "                  1 and 2 per band (--rows y0,y1: rows y0 .. y1-1), "
    "join and\n"
    "                  commit once (--band-rows n: bands of n rows); "
    "see filled(5)\n"
    "  -w a,b          only the DEM's columns a .. b-1: a window of the FQM "
    "(a band\n"
    "                  job's; its edge columns lack the cells beyond)\n"
    "  --stamp file    record what identifies every file the DEMs read "
    "into\n"
    "                  file (a plan's, dem2vgis(1)); no output\n"
    "  -z compression  of an EXR output: zip (default), zips, rle, piz, none\n"
    "  --resample      let GDAL resample a VRT's scaled sources, not refuse "
    "them\n"
    "  --guard path    fail if path is, holds or lies inside a file the DEM "
    "is\n"
    "                  read from (what dem2vgis(1) writes)\n"
    "  dem             any raster GDAL reads, EXR, or a list of DEM files (a\n"
    "                  mosaic); - (stdin, default)\n"
    "  out             level-0 FQM: EXR file or - (stream, default)\n";

#define MAXGUARD 4

typedef struct {
	int info; /* -I given: 1 the header, 2 (-II) the voids too */
	int win[2], has_win; /* -w */
	const char *filled;  /* -F: read from it; -W: write it */
	int save;            /* -W */
	const char *in, *out;
	int pass;            /* --fill-pass: 0 none, or a fill_pass */
	int rows[2], has_rows; /* --rows */
	int band;            /* --band-rows, 0 none */
	const char *stamp;   /* --stamp */
	const char *guard[MAXGUARD]; /* --guard */
	int nguard;
} options;

/* --fill-pass: the parts of a filled DEM made in row bands */
enum { PASS_1 = 1, PASS_JOIN, PASS_2, PASS_COMMIT };
enum { OPT_PASS = 256, OPT_ROWS, OPT_BAND_ROWS, OPT_STAMP, OPT_GUARD };

static int
convert(const cli *c, const options *o, dem *d, tl_err *e)
{
	fqm_info fi = { .geo = *dem_georef(d) };
	int win[2] = { o->win[0], o->win[1] };
	rs_header h;
	geo_ground m = { 0 };
	fqm0_source j = { 0 };
	char note[512];
	int r = -1;

	fi.size0[0] = fi.geo.width, fi.size0[1] = fi.geo.height;
	if (fi.geo.width < 3 || fi.geo.height < 3)
		return tl_fail(e, "%s: %dx%d samples: a DEM needs at least 3x3",
		    tl_name(o->in, 0), fi.geo.width, fi.geo.height);
	if (!o->has_win)
		win[0] = 0, win[1] = fi.geo.width;
	else if (win[1] > fi.geo.width || win[1] - win[0] < 3)
		return tl_fail(e, "-w %d,%d: not 3 or more of the DEM's %d "
		    "columns", win[0], win[1], fi.geo.width);
	fi.x0 = win[0];
	if (dem_ground_note(d, &c->dem, tl_name(o->in, 0), note, sizeof note))
		cli_warn(c, "%s", note);
	rs_header_init(&h, 0, 0);
	if (geo_ground_init(&m, &fi.geo, e) == 0 &&
	    fqm_header(&h, &fi, "none", e) == 0 &&
	    fqm_layout_of(&h, &j.L, c->prog, e) == 0) {
		/* the window's columns, its metric answering in them */
		h.width = win[1] - win[0];
		m.x0 = win[0];
		if (fqm0_init_cols(&j.s, d, &m, win[0], h.width, e) == 0)
			r = rowpipe_run(c->prog, o->out, &h, c->comp,
			    fqm0_encoded_row, &j, e);
	}
	fqm0_free(&j.s);
	rs_header_free(&h);
	geo_ground_free(&m);
	return r;
}

static int
fill_part(const cli *c, const options *o, tl_err *e)
{
	switch (o->pass) {
	case PASS_1:
		return dem_fill_pass1(o->in, &c->dem, o->filled, o->rows[0],
		    o->rows[1], e);
	case PASS_JOIN:
		return dem_fill_join(o->in, &c->dem, o->filled, o->band, e);
	case PASS_2:
		return dem_fill_pass2(o->in, &c->dem, o->filled, o->rows[0],
		    o->rows[1], e);
	default:
		return dem_fill_commit(o->in, &c->dem, o->filled, o->band, e);
	}
}

/* The outputs kept off the files the DEM is read from and -F's filled
 * DEM (paths.h), before any work: out, -W's filled DEM and the files of
 * a fill part (filled(5)), --guard's paths. */
static int
guard(const options *o, tl_err *e)
{
	static const char *const kinds[] = { "raw", "tmp", "s", "d" };
	char part[4][4200];
	const char *outs[MAXGUARD + 6];
	tl_paths s = { 0 };
	int n = 0, r;

	if (!o->info && !o->save && strcmp(o->out, "-") != 0)
		outs[n++] = o->out;
	for (int k = 0; k < o->nguard; k++)
		outs[n++] = o->guard[k];
	if (o->save)
		outs[n++] = o->filled;
	for (int k = 0; o->pass != 0 && k < 4; k++) {
		snprintf(part[k], sizeof part[k], k < 2 ? "%s.%s" : "%s.%s.%d",
		    o->filled, kinds[k], o->rows[0]);
		if (k < 2 || o->pass == (k == 2 ? PASS_1 : PASS_2))
			outs[n++] = part[k];
	}
	if (n == 0)
		return 0;
	r = dem_paths(&s, o->in, e);
	if (r == 0 && o->filled != NULL && !o->save)
		r = tl_paths_add(&s, o->filled, 0, e, "the input filled DEM %s",
		    o->filled);
	for (int k = 0; r == 0 && k < n; k++)
		r = tl_paths_check(&s, outs[k], e);
	tl_paths_free(&s);
	return r;
}

static int
work(const cli *c, const options *o, tl_err *e)
{
	dem *d;
	int r;

	if (guard(o, e) < 0)
		return -1;

	/* -I reads the header only; -II and the conversion every sample;
	 * -F the header, the samples from the filled DEM */
	if (o->pass != 0)
		return fill_part(c, o, e);
	if (o->info == 1)
		d = dem_open_info(o->in, &c->dem, e);
	else if (o->filled != NULL && !o->save)
		d = dem_open_filled(o->in, &c->dem, o->filled, e);
	else
		d = dem_open(o->in, &c->dem, e);
	if (d == NULL)
		return -1;
	if (o->info)
		r = dem_info_print(d, stdout, e);
	else if (o->save)
		r = dem_save_filled(d, o->filled, e);
	else
		r = convert(c, o, d, e);
	dem_close(d);
	return r;
}

/* A long option's value: 0, or the status to exit with. */
static int
long_option(const cli *c, int ch, options *o)
{
	static const char *const passes[] = { "1", "join", "2", "commit" };

	if (ch == OPT_PASS) {
		for (int k = 0; k < 4; k++)
			if (strcmp(optarg, passes[k]) == 0)
				o->pass = k + 1;
		if (o->pass == 0)
			return cli_bad(c, "--fill-pass %s: not 1, join, 2 or "
			    "commit", optarg);
	} else if (ch == OPT_GUARD) {
		if (o->nguard == MAXGUARD)
			return cli_bad(c, "--guard: %d at most", MAXGUARD);
		o->guard[o->nguard++] = optarg;
	} else if (ch == OPT_ROWS) {
		if (cli_columns(optarg, o->rows) < 0)
			return cli_bad(c, "--rows %s: not rows y0,y1 (0 <= y0 < "
			    "y1)", optarg);
		o->has_rows = 1;
	} else if (tl_parse_int(optarg, &o->band) < 0 || o->band < 1) {
		return cli_bad(c, "--band-rows %s: not a number of rows",
		    optarg);
	}
	return 0;
}

/* --fill-pass goes with -W, and 1 and 2 with --rows, join and commit
 * with --band-rows, on a named DEM (the parts read it each). */
static int
check_pass(const cli *c, const options *o)
{
	int banded = o->pass == PASS_1 || o->pass == PASS_2;

	if (o->pass == 0)
		return o->has_rows || o->band ? cli_bad(c, "--rows, --band-rows: "
		    "only with --fill-pass") : 0;
	if (!o->save)
		return cli_bad(c, "--fill-pass: only with -W filled");
	if (banded && (!o->has_rows || o->band))
		return cli_bad(c, "--fill-pass 1, 2: with --rows y0,y1, "
		    "not --band-rows");
	if (!banded && (o->has_rows || !o->band))
		return cli_bad(c, "--fill-pass join, commit: with --band-rows "
		    "n, not --rows");
	if (strcmp(o->in, "-") == 0)
		return cli_bad(c, "--fill-pass: the DEM must be a named file "
		    "(every part reads it)");
	return 0;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "fill-pass", required_argument, NULL, OPT_PASS },
		{ "rows", required_argument, NULL, OPT_ROWS },
		{ "band-rows", required_argument, NULL, OPT_BAND_ROWS },
		{ "stamp", required_argument, NULL, OPT_STAMP },
		{ "guard", required_argument, NULL, OPT_GUARD },
		{ NULL, 0, NULL, 0 },
	};
	options o = { .in = "-", .out = "-" };
	cli c;
	tl_err e;
	int ch;

	cli_init(&c, argv, usage, CLI_COMPRESSION | CLI_DEM);
	while ((ch = cli_next(&c, argc, argv, "F:IW:w:", longopts)) != -1) {
		if (ch == OPT_STAMP)
			o.stamp = optarg;
		else if (ch >= OPT_PASS) {
			if ((ch = long_option(&c, ch, &o)) != 0)
				return ch;
		} else if (ch == 'F' || ch == 'W') {
			if (o.filled != NULL)
				return cli_bad(&c, "-F, -W: one of them, once");
			o.filled = optarg, o.save = ch == 'W';
		} else if (ch == 'w' && cli_columns(optarg, o.win) < 0)
			return cli_bad(&c, "-w %s: not columns a,b (0 <= a < b)",
			    optarg);
		else if (ch == 'w')
			o.has_win = 1;
		else if (ch != 'I')
			return cli_usage_error(&c);
		else
			o.info = o.info < 2 ? o.info + 1 : 2;
	}
	if (c.status >= 0)
		return c.status;
	argc -= optind, argv += optind;
	if (o.stamp != NULL) /* a plan's record of its DEM (stamp.h) */
		return argc < 1 || o.info || o.filled != NULL || o.pass ?
		    cli_usage_error(&c) :
		    cli_exit(&c, dem_stamp(o.stamp, argv, argc, &e), &e);
	if (o.info || o.save) { /* one DEM in, no raster out */
		if (argc > 1 || (o.save && (o.info || o.has_win)))
			return cli_usage_error(&c);
		o.in = argc > 0 ? argv[0] : "-";
	} else if ((ch = cli_operands(&c, argc, argv, &o.in, &o.out)) != 0)
		return ch;
	if ((ch = check_pass(&c, &o)) != 0)
		return ch;
	return cli_exit(&c, work(&c, &o, &e), &e);
}
