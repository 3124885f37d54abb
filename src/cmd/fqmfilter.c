/* fqmfilter - one level of QEM-filtering: the quadric map of level l in,
 * that of level l+1 out (quadrics low-pass filtered in each coarse vertex's
 * frame, sub-sampled by 2). */
#include <stdlib.h>

#include "core/cli.h"
#include "core/filter.h"
#include "core/rowpipe.h"

static const char usage[] =
    "[-k kernel] [-z compression] [in [out]]\n"
    "  -k kernel       binomial (default, [1 2 1]/4), none (plain "
    "sub-sampling),\n"
    "                  box ([1 1 1]/3), binomial5 ([1 4 6 4 1]/16)\n"
    "  -z compression  of an EXR output: zip (default), zips, rle, piz, none\n"
    "  in, out         FQM of level l and l+1; EXR file or - "
    "(stream, default)\n";

typedef struct {
	const filter_kernel *kernel;
	const char *in, *out;
} options;

/* The work: the fine rows read so far, the filter, one coarse row. */
typedef struct {
	rs_reader *in;
	const rs_header *ih;
	const char *what; /* the input, for messages */
	int fy;           /* the next fine row */
	fqm_layout L;
	filter_state f;
	float *frow;
	fqm_vertex *fine, *coarse;
} job;

static int
coarse_row(void *ctx, int y, float *row, tl_err *e)
{
	job *j = ctx;

	while (!filter_ready(&j->f)) {
		if (rs_read_row(j->in, j->frow, e) < 0 ||
		    fqm_check_row(j->frow, j->ih->width, j->ih->nch, j->fy++,
		    j->what, e) < 0)
			return -1;
		fqm_decode(&j->L, j->frow, j->ih->width, j->fine);
		filter_push(&j->f, j->fine);
	}
	filter_pull(&j->f, j->coarse);
	fqm_encode(&j->L, j->coarse, j->f.cw, row);
	return 0;
}

static int
filter(const cli *c, const options *o, tl_err *e)
{
	job j = { 0 };
	rs_header oh;
	fqm_info fi;
	geo_metric m = { 0 };
	int r = -1;

	rs_header_init(&oh, 0, 0);
	if ((j.in = fqm_open(o->in, &fi, &j.L, e)) == NULL)
		return -1;
	j.ih = rs_header_of(j.in);
	j.what = tl_name(o->in, 0);
	if (j.ih->width <= 2 && j.ih->height <= 2) {
		tl_fail(e, "%s: level %d is %dx%d: nothing left to reduce",
		    tl_name(o->in, 0), fi.level, j.ih->width, j.ih->height);
		goto done;
	}
	if (geo_metric_init(&m, &fi.geo, e) < 0 ||
	    filter_init(&j.f, o->kernel, fi.level, j.ih->width, j.ih->height,
	    fi.size0[0], fi.size0[1], &m, e) < 0 ||
	    rs_header_copy(&oh, j.ih, e) < 0)
		goto done;
	oh.width = j.f.cw, oh.height = j.f.ch;
	if (rs_set_int(&oh, FQM_ATTR_LEVEL, fi.level + 1, e) < 0 ||
	    rs_set_string(&oh, FQM_ATTR_KERNEL, o->kernel->name, e) < 0)
		goto done;
	j.frow = tl_alloc((size_t)j.ih->width * j.ih->nch, sizeof *j.frow, e);
	j.fine = tl_alloc(j.ih->width, sizeof *j.fine, e);
	j.coarse = tl_alloc(j.f.cw, sizeof *j.coarse, e);
	if (j.frow != NULL && j.fine != NULL && j.coarse != NULL)
		r = rowpipe_run(c->prog, o->out, &oh, c->comp, coarse_row, &j,
		    e);
done:
	rs_close(j.in);
	rs_header_free(&oh);
	filter_free(&j.f);
	geo_metric_free(&m);
	free(j.frow), free(j.fine), free(j.coarse);
	return r;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "kernel", required_argument, NULL, 'k' },
		{ NULL, 0, NULL, 0 },
	};
	options o = { filter_find("binomial"), "-", "-" };
	cli c;
	tl_err e;
	int ch;

	cli_init(&c, argv, usage, CLI_COMPRESSION);
	while ((ch = cli_next(&c, argc, argv, "k:", longopts)) != -1) {
		if (ch != 'k')
			return cli_usage_error(&c);
		if ((o.kernel = filter_find(optarg)) == NULL)
			return cli_bad(&c, "-k %s: unknown kernel", optarg);
	}
	if (c.status >= 0)
		return c.status;
	if ((ch = cli_operands(&c, argc - optind, argv + optind, &o.in,
	    &o.out)) != 0)
		return ch;
	return cli_exit(&c, filter(&c, &o, &e), &e);
}
