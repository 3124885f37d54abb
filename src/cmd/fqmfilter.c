/* fqmfilter - one level of QEM-filtering: the quadric map of level l in,
 * that of level l+1 out (quadrics low-pass filtered in each coarse vertex's
 * frame, sub-sampled by 2). The work is stage_fqmfilter (stage.h). */
#include "cli.h"
#include "stage.h"

static const char usage[] =
    "[-k kernel] [-z compression] [in [out]]\n"
    "  -k kernel       binomial (default, [1 2 1]/4), none (plain "
    "sub-sampling),\n"
    "                  box ([1 1 1]/3), binomial5 ([1 4 6 4 1]/16)\n"
    "  -z compression  of an EXR output: zip (default), zips, rle, piz, none\n"
    "  in, out         FQM of level l and l+1; EXR file or - "
    "(stream, default)\n";

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "kernel", required_argument, NULL, 'k' },
		{ NULL, 0, NULL, 0 },
	};
	stage_filter o = { .kernel = filter_find("binomial") };
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
	return cli_exit(&c, stage_fqmfilter(&c, &o, &e), &e);
}
