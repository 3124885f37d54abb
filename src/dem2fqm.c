/* dem2fqm - a DEM in, its level-0 fundamental quadric map out: per vertex
 * the area-weighted plane quadrics of its triangles, in its own frame. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dem.h"
#include "fqm.h"
#include "raster.h"
#include "util.h"

static const char *prog = "dem2fqm";

static void
usage(FILE *f)
{
	fprintf(f, "usage: %s [-I] [-D datum] [-e encoding] [-H datum] "
	    "[-N nodata] [-n name]\n"
	    "               [-s dx[,dy]] [-z compression] [dem [out]]\n"
	    "  -I              print the DEM's size, georeferencing, metric, "
	    "datum, voids\n"
	    "                  and level count; no output\n"
	    "  -D datum        the DEM's vertical datum (EPSG:5773) when it "
	    "declares none\n"
	    "  -e encoding     auto (default), grey, terrainrgb, terrarium\n"
	    "  -H datum        convert heights to datum: ellipsoid (WGS 84) "
	    "or EPSG:n\n"
	    "  -N nodata       void value, overriding the file's\n"
	    "  -n name         the file name of a DEM on stdin "
	    "(N42E001.hgt)\n"
	    "  -s dx[,dy]      cell size in metres (overrides the CRS's "
	    "metric)\n"
	    "  -z compression  of an EXR output: zip (default), zips, rle, "
	    "piz, none\n"
	    "  dem             any raster GDAL reads, or EXR; - (stdin, "
	    "default)\n"
	    "  out             level-0 FQM: EXR file or - (stream, default)\n",
	    prog);
}

typedef struct {
	dem_opts dem;
	int info;
	enum rs_compression comp;
	const char *in, *out;
} options;

/* Two DEM rows (j and j+1) and the cell bands above and below row j. */
typedef struct {
	float *z[2];
	unsigned char *valid[2];
	double *band[2];
} window;

/* Ground metres per cell over the grid, min and max along x and y,
 * sampled on about 256 x 256 positions (the metric varies smoothly). */
static int
metric_range(const georef *g, double r[4], tl_err *e)
{
	int si = g->width > 256 ? g->width / 256 : 1;
	int sj = g->height > 256 ? g->height / 256 : 1;
	geo_metric m;

	if (geo_metric_init(&m, g, e) < 0)
		return -1;
	r[0] = r[2] = INFINITY, r[1] = r[3] = 0;
	for (int j = 0; j < g->height; j += sj)
		for (int i = 0; i < g->width; i += si) {
			double sx, sy;
			geo_scale(&m, i, j, &sx, &sy);
			r[0] = fmin(r[0], sx), r[1] = fmax(r[1], sx);
			r[2] = fmin(r[2], sy), r[3] = fmax(r[3], sy);
		}
	geo_metric_free(&m);
	return 0;
}

/* -I: what a user needs to trust the result and a script to plan a
 * pyramid, as "key value" lines. */
static int
info(const options *o, tl_err *e)
{
	static const char *const models[] = { "none", "projected",
		"geographic" };
	const georef *g;
	double r[4];
	dem *d;

	if ((d = dem_open(o->in, &o->dem, e)) == NULL)
		return -1;
	g = dem_georef(d);
	if (metric_range(g, r, e) < 0) {
		dem_close(d);
		return -1;
	}
	printf("size %d %d\nvoids %lld\nmodel %s\ncrs %s\nraster %s\n"
	    "origin %.17g %.17g\nstep %.17g %.17g\n", g->width, g->height,
	    dem_voids(d), models[g->model], g->crs[0] ? g->crs : "-",
	    g->point ? "point" : "area", g->origin[0], g->origin[1],
	    g->step[0], g->step[1]);
	if (g->vdatum[0] != '\0')
		printf("vdatum %s\n", g->vdatum);
	if (g->has_nodata)
		printf("nodata %.17g\n", g->nodata);
	if (g->cell[0] > 0)
		printf("cell %.17g %.17g\n", g->cell[0], g->cell[1]);
	printf("metric %.6f %.6f %.6f %.6f\nzunit %.17g\nlevels %d\n", r[0],
	    r[1], r[2], r[3], dem_zunit(d), fqm_levels(g->width, g->height));
	dem_close(d);
	return fflush(stdout) == 0 ? 0 : tl_failsys(e, "stdout");
}

/* A grid without a CRS has no known unit: say what was assumed. */
static void
warn_metric(const options *o, const georef *g)
{
	const char *n = tl_name(o->in, 0);

	if (g->model != GEO_NONE || g->cell[0] > 0 || o->dem.cell[0] > 0)
		return;
	if (g->origin[0] == 0 && g->origin[1] == 0 && g->step[0] == 1 &&
	    g->step[1] == -1)
		tl_warn(prog, "%s: not georeferenced: cells taken as 1 m "
		    "(set with -s)", n);
	else
		tl_warn(prog, "%s: a geotransform but no CRS: its pixel size "
		    "%g x %g taken as metres (set with -s, or assign the CRS: "
		    "gdal_edit.py -a_srs)", n, g->step[0], -g->step[1]);
}

static int
convert(const options *o, tl_err *e)
{
	dem *d;
	rs_writer *out = NULL;
	rs_header h;
	fqm_info fi = { 0 };
	fqm_layout L;
	geo_metric m = { 0 };
	window win = { 0 };
	fqm_vertex *fv = NULL;
	float *row = NULL;
	tl_progress pr;
	int W, H, r = -1;

	rs_header_init(&h, 0, 0);
	if ((d = dem_open(o->in, &o->dem, e)) == NULL)
		return -1;
	fi.geo = *dem_georef(d);
	W = fi.size0[0] = fi.geo.width;
	H = fi.size0[1] = fi.geo.height;
	if (W < 3 || H < 3) {
		tl_fail(e, "%s: %dx%d samples: a DEM needs at least 3x3",
		    tl_name(o->in, 0), W, H);
		goto done;
	}
	warn_metric(o, &fi.geo);
	if (geo_metric_init(&m, &fi.geo, e) < 0 ||
	    fqm_header(&h, &fi, "none", e) < 0 ||
	    fqm_layout_of(&h, &L, "dem2fqm", e) < 0)
		goto done;
	for (int k = 0; k < 2; k++) {
		win.z[k] = tl_alloc(W, sizeof *win.z[k], e);
		win.valid[k] = tl_alloc(W, 1, e);
		win.band[k] = tl_alloc((size_t)(W - 1) * FQM_BAND0_DOUBLES,
		    sizeof(double), e);
		if (win.z[k] == NULL || win.valid[k] == NULL ||
		    win.band[k] == NULL)
			goto done;
	}
	fv = tl_alloc(W, sizeof *fv, e);
	row = tl_alloc((size_t)W * h.nch, sizeof *row, e);
	if (fv == NULL || row == NULL)
		goto done;
	if ((out = rs_create(o->out, &h, o->comp, e)) == NULL)
		goto done;
	tl_progress_start(&pr, prog, H);
	if (dem_read_row(d, 0, win.z[0], win.valid[0], e) < 0)
		goto done;
	for (int j = 0; j < H; j++) {
		int cur = j & 1, nxt = !cur;
		/* band j (rows j, j+1) goes where band j-2 was */
		if (j + 1 < H) {
			if (dem_read_row(d, j + 1, win.z[nxt], win.valid[nxt],
			    e) < 0)
				goto done;
			fqm_band0(win.z[cur], win.valid[cur], win.z[nxt],
			    win.valid[nxt], W, j, &m, win.band[cur]);
		}
		fqm_row0(j > 0 ? win.band[nxt] : NULL,
		    j + 1 < H ? win.band[cur] : NULL, win.z[cur],
		    win.valid[cur], W, fv);
		fqm_encode(&L, fv, W, row);
		if (rs_write_row(out, row, e) < 0)
			goto done;
		tl_progress_step(&pr, j + 1);
	}
	tl_progress_end(&pr);
	r = rs_finish(out, e);
	out = NULL;
done:
	rs_abort(out);
	dem_close(d);
	rs_header_free(&h);
	geo_metric_free(&m);
	for (int k = 0; k < 2; k++)
		free(win.z[k]), free(win.valid[k]), free(win.band[k]);
	free(fv), free(row);
	return r;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	options o = { .comp = RS_ZIP, .in = "-", .out = "-" };
	tl_err e;
	int c;

	while ((c = getopt_long(argc, argv, DEM_OPTS "hIVz:", longopts, NULL)) !=
	    -1) {
		switch (c) {
		case 'I':
			o.info = 1;
			break;
		case 'h':
			usage(stdout);
			return 0;
		case 'V':
			printf("%s %s\n", prog, TL_VERSION);
			return 0;
		case 'z':
			if (rs_compression_parse(optarg, &o.comp) < 0) {
				tl_warn(prog, "-z %s: unknown compression", optarg);
				return 2;
			}
			break;
		default:
			switch (dem_option(&o.dem, c, optarg, &e)) {
			case 1:
				continue;
			case -1:
				tl_warn(prog, "%s", e.msg);
				return 2;
			}
			usage(stderr);
			return 2;
		}
	}
	argc -= optind, argv += optind;
	if (o.info) { /* one DEM in, "key value" lines out */
		if (argc > 1) {
			usage(stderr);
			return 2;
		}
		o.in = argc > 0 ? argv[0] : "-";
		if (info(&o, &e) < 0) {
			tl_warn(prog, "%s", e.msg);
			return 1;
		}
		return 0;
	}
	if ((c = tl_operands(prog, argc, argv, &o.in, &o.out)) != 0) {
		if (c == 2)
			usage(stderr);
		return c;
	}
	if (convert(&o, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		return 1;
	}
	return 0;
}
