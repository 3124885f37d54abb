/* fqmfilter - one level of QEM-filtering: the quadric map of level l in,
 * that of level l+1 out (quadrics low-pass filtered in each coarse vertex's
 * frame, sub-sampled by 2). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "filter.h"
#include "raster.h"
#include "util.h"

static const char *prog = "fqmfilter";

static void
usage(FILE *f)
{
	fprintf(f, "usage: %s [-k kernel] [-z compression] [in [out]]\n"
	    "  -k kernel       binomial (default, [1 2 1]/4), none (plain "
	    "sub-sampling),\n"
	    "                  box ([1 1 1]/3), binomial5 ([1 4 6 4 1]/16)\n"
	    "  -z compression  of an EXR output: zip (default), zips, rle, "
	    "piz, none\n"
	    "  in, out         FQM of level l and l+1; EXR file or - "
	    "(stream, default)\n", prog);
}

typedef struct {
	const fk_kernel *kernel;
	enum rs_compression comp;
	const char *in, *out;
} options;

static int
filter(const options *o, tl_err *e)
{
	rs_reader *in = NULL;
	rs_writer *out = NULL;
	rs_header oh;
	fqm_info fi;
	fqm_layout L;
	geo_metric m = { 0 };
	fk_filter f = { 0 };
	float *frow = NULL, *crow = NULL;
	fqm_vertex *fine = NULL, *coarse = NULL;
	tl_progress pr;
	const char *iname = tl_name(o->in, 0);
	int r = -1;

	rs_header_init(&oh, 0, 0);
	if ((in = rs_open(o->in, e)) == NULL)
		return -1;
	const rs_header *ih = rs_header_of(in);
	if (fqm_info_of(ih, "fqm", &fi, iname, e) < 0 ||
	    fqm_layout_of(ih, &L, iname, e) < 0)
		goto done;
	if (ih->width <= 2 && ih->height <= 2) {
		tl_fail(e, "%s: level %d is %dx%d: nothing left to reduce",
		    iname, fi.level, ih->width, ih->height);
		goto done;
	}
	if (geo_metric_init(&m, &fi.geo, e) < 0 ||
	    fk_init(&f, o->kernel, fi.level, ih->width, ih->height,
	    fi.size0[0], fi.size0[1], &m, e) < 0)
		goto done;
	if (rs_header_copy(&oh, ih, e) < 0)
		goto done;
	oh.width = f.cw, oh.height = f.ch;
	if (rs_set_int(&oh, "fqm:level", fi.level + 1, e) < 0 ||
	    rs_set_string(&oh, "fqm:kernel", o->kernel->name, e) < 0)
		goto done;
	frow = tl_alloc((size_t)ih->width * ih->nch, sizeof *frow, e);
	crow = tl_alloc((size_t)f.cw * ih->nch, sizeof *crow, e);
	fine = tl_alloc(ih->width, sizeof *fine, e);
	coarse = tl_alloc(f.cw, sizeof *coarse, e);
	if (frow == NULL || crow == NULL || fine == NULL || coarse == NULL)
		goto done;
	if ((out = rs_create(o->out, &oh, o->comp, e)) == NULL)
		goto done;
	tl_progress_start(&pr, prog, f.ch);
	for (int y = 0; y < f.ch; y++) {
		while (!fk_ready(&f)) {
			if (rs_read_row(in, frow, e) < 0)
				goto done;
			fqm_decode(&L, frow, ih->width, fine);
			fk_push(&f, fine);
		}
		fk_pull(&f, coarse);
		fqm_encode(&L, coarse, f.cw, crow);
		if (rs_write_row(out, crow, e) < 0)
			goto done;
		tl_progress_step(&pr, y + 1);
	}
	tl_progress_end(&pr);
	r = rs_finish(out, e);
	out = NULL;
done:
	rs_abort(out);
	rs_close(in);
	rs_header_free(&oh);
	fk_free(&f);
	geo_metric_free(&m);
	free(frow), free(crow), free(fine), free(coarse);
	return r;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "help", no_argument, NULL, 'h' },
		{ "kernel", required_argument, NULL, 'k' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	options o = { fk_find("binomial"), RS_ZIP, "-", "-" };
	tl_err e;
	int c;

	while ((c = getopt_long(argc, argv, "hk:Vz:", longopts, NULL)) != -1) {
		switch (c) {
		case 'h':
			usage(stdout);
			return 0;
		case 'k':
			if ((o.kernel = fk_find(optarg)) == NULL) {
				tl_warn(prog, "-k %s: unknown kernel", optarg);
				return 2;
			}
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
	if (filter(&o, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		return 1;
	}
	return 0;
}
