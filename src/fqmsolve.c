/* fqmsolve - the vertex map of a level: each vertex placed where its
 * quadric is least (QEM-1D: z on the grid position; QEM-3D: x, y, z), or
 * the vertex-filtered or sub-sampled heights the FQM carries. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "raster.h"
#include "solve.h"
#include "util.h"

static const char *prog = "fqmsolve";

static void
usage(FILE *f)
{
	fprintf(f, "usage: %s [-v] [-m mode] [-r cut] [-z compression] "
	    "[in [out]]\n"
	    "  -m mode         qem1d (default), qem3d, filtered, subsample\n"
	    "  -r cut          qem3d: eigenvalues below cut x largest are "
	    "free (default 1e-3)\n"
	    "  -v              report how many vertices the qem3d fold fix "
	    "moved\n"
	    "  -z compression  of an EXR output: zip (default), zips, rle, "
	    "piz, none\n"
	    "  in, out         FQM in, vertex map out; EXR file or - "
	    "(stream, default)\n", prog);
}

typedef struct {
	enum sv_mode mode;
	double rel;
	int verbose;
	enum rs_compression comp;
	const char *in, *out;
} options;

/* The vertex map header: the FQM's attributes, the vertex channels. */
static int
out_header(rs_header *oh, const rs_header *ih, enum sv_mode mode, tl_err *e)
{
	if (rs_header_copy(oh, ih, e) < 0)
		return -1;
	rs_clear_channels(oh);
	if (rs_add_channel(oh, "Z", e) < 0 || rs_add_channel(oh, "V", e) < 0)
		return -1;
	if (mode == SV_QEM3D && (rs_add_channel(oh, "X", e) < 0 ||
	    rs_add_channel(oh, "Y", e) < 0))
		return -1;
	if (rs_set_string(oh, "fqm:kind", "vertices", e) < 0)
		return -1;
	return rs_set_string(oh, "fqm:mode", sv_mode_name(mode), e);
}

static void
encode(const rs_header *oh, const sv_vertex *v, float *row)
{
	int w = oh->width, cz = rs_channel(oh, "Z"), cv = rs_channel(oh, "V");
	int cx = rs_channel(oh, "X"), cy = rs_channel(oh, "Y");

	for (int i = 0; i < w; i++) {
		row[(size_t)cz * w + i] = (float)v[i].z;
		row[(size_t)cv * w + i] = (float)v[i].v;
		if (cx >= 0) {
			row[(size_t)cx * w + i] = (float)v[i].x;
			row[(size_t)cy * w + i] = (float)v[i].y;
		}
	}
}

static int
solve(const options *o, tl_err *e)
{
	rs_reader *in = NULL;
	rs_writer *out = NULL;
	rs_header oh;
	fqm_info fi;
	fqm_layout L;
	geo_metric m = { 0 };
	sv_solver s = { 0 };
	float *irow = NULL, *orow = NULL;
	fqm_vertex *fv = NULL;
	sv_vertex *sv = NULL;
	tl_progress pr;
	const char *iname = tl_name(o->in, 0);
	int w, r = -1;

	rs_header_init(&oh, 0, 0);
	if ((in = rs_open(o->in, e)) == NULL)
		return -1;
	const rs_header *ih = rs_header_of(in);
	w = ih->width;
	if (fqm_info_of(ih, "fqm", &fi, iname, e) < 0 ||
	    fqm_layout_of(ih, &L, iname, e) < 0 ||
	    geo_metric_init(&m, &fi.geo, e) < 0 ||
	    sv_init(&s, o->mode, fi.level, w, ih->height, &m, e) < 0 ||
	    out_header(&oh, ih, o->mode, e) < 0)
		goto done;
	s.rel = o->rel;
	irow = tl_alloc((size_t)w * ih->nch, sizeof *irow, e);
	orow = tl_alloc((size_t)w * oh.nch, sizeof *orow, e);
	fv = tl_alloc(w, sizeof *fv, e);
	sv = tl_alloc(w, sizeof *sv, e);
	if (irow == NULL || orow == NULL || fv == NULL || sv == NULL)
		goto done;
	if ((out = rs_create(o->out, &oh, o->comp, e)) == NULL)
		goto done;
	tl_progress_start(&pr, prog, ih->height);
	for (int y = 0; y < ih->height; y++) {
		if (rs_read_row(in, irow, e) < 0)
			goto done;
		fqm_decode(&L, irow, w, fv);
		sv_row(&s, fv, sv);
		encode(&oh, sv, orow);
		if (rs_write_row(out, orow, e) < 0)
			goto done;
		tl_progress_step(&pr, y + 1);
	}
	tl_progress_end(&pr);
	r = rs_finish(out, e);
	out = NULL;
	if (r == 0 && o->verbose && o->mode == SV_QEM3D)
		tl_warn(prog, "level %d: fold fix reduced %lld of %lld vertices, "
		    "%lld back onto the grid", fi.level, s.reduced,
		    (long long)w * ih->height, s.zeroed);
done:
	rs_abort(out);
	rs_close(in);
	rs_header_free(&oh);
	sv_free(&s);
	geo_metric_free(&m);
	free(irow), free(orow), free(fv), free(sv);
	return r;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "help", no_argument, NULL, 'h' },
		{ "mode", required_argument, NULL, 'm' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	options o = { SV_QEM1D, 1e-3, 0, RS_ZIP, "-", "-" };
	tl_err e;
	int c;

	while ((c = getopt_long(argc, argv, "hm:r:vVz:", longopts, NULL)) != -1) {
		switch (c) {
		case 'h':
			usage(stdout);
			return 0;
		case 'm':
			if (sv_mode_parse(optarg, &o.mode) < 0) {
				tl_warn(prog, "-m %s: unknown mode", optarg);
				return 2;
			}
			break;
		case 'r':
			if (tl_parse_double(optarg, &o.rel) < 0 || o.rel < 0 ||
			    o.rel >= 1) {
				tl_warn(prog, "-r %s: not a number in [0, 1)",
				    optarg);
				return 2;
			}
			break;
		case 'v':
			o.verbose = 1;
			break;
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
			usage(stderr);
			return 2;
		}
	}
	argc -= optind, argv += optind;
	if ((c = tl_operands(prog, argc, argv, &o.in, &o.out)) != 0) {
		if (c == 2)
			usage(stderr);
		return c;
	}
	if (solve(&o, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		return 1;
	}
	return 0;
}
