/* fqmfilter - one level of QEM-filtering: the quadric map of level l in,
 * that of level l+1 out (quadrics low-pass filtered in each coarse vertex's
 * frame, sub-sampled by 2). */
#include <stdlib.h>

#include "core/cli.h"
#include "core/filter.h"
#include "core/fqm_input.h"
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

/* The work: the fine rows read so far, the filter. */
typedef struct {
	fqm_input in;
	filter_state f;
} job;

static int
coarse_row(void *ctx, int y, float *row, tl_err *e)
{
	job *j = ctx;

	while (!filter_ready(&j->f)) {
		if (fqm_input_read(&j->in, e) < 0)
			return -1;
		filter_push_row(&j->f, &j->in.L, j->in.row);
	}
	filter_pull_row(&j->f, &j->in.L, row);
	return 0;
}

static int
filter(const cli *c, const options *o, tl_err *e)
{
	job j = { 0 };
	rs_header oh;
	const rs_header *h;
	int r = -1;

	rs_header_init(&oh, 0, 0);
	if (fqm_input_open(&j.in, o->in, e) < 0)
		goto done;
	h = j.in.h;
	if (h->width <= 2 && h->height <= 2) {
		tl_fail(e, "%s: level %d is %dx%d: nothing left to reduce",
		    j.in.what, j.in.fi.level, h->width, h->height);
		goto done;
	}
	if (filter_init(&j.f, o->kernel, j.in.fi.level, h->width, h->height,
	    j.in.fi.size0[0], j.in.fi.size0[1], &j.in.m, e) < 0 ||
	    rs_header_copy(&oh, h, e) < 0)
		goto done;
	oh.width = j.f.cw, oh.height = j.f.ch;
	if (rs_set_int(&oh, FQM_ATTR_LEVEL, j.in.fi.level + 1, e) < 0 ||
	    rs_set_string(&oh, FQM_ATTR_KERNEL, o->kernel->name, e) < 0)
		goto done;
	r = rowpipe_run(c->prog, o->out, &oh, c->comp, coarse_row, &j, e);
done:
	fqm_input_close(&j.in);
	rs_header_free(&oh);
	filter_free(&j.f);
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
	if ((ch = cli_filter_args(&c, argc, argv, &o.in, &o.out)) >= 0)
		return ch;
	return cli_exit(&c, filter(&c, &o, &e), &e);
}
