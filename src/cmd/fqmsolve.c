/* fqmsolve - the vertex map of a level: each vertex placed where its
 * quadric is least (QEM-1D: z on the grid position; QEM-3D: x, y, z), or
 * the vertex-filtered or sub-sampled heights the FQM carries. The work is
 * stage_fqmsolve (stage.h). */
#include "cli.h"
#include "stage.h"
#include "base/pool.h"

static const char usage[] =
    "[-v] [-j jobs] [-m mode] [-r cut] [-z compression] [in [out]]\n"
    "  -j jobs         qem3d: threads placing a row's vertices (default: "
    "the CPUs)\n"
    "  -m mode         qem1d (default), qem3d, filtered, subsample\n"
    "  -r cut          qem3d: eigenvalues below cut x largest are free "
    "(default 1e-3)\n"
    "  -v              report how many vertices the qem3d fold fix moved\n"
    "  -z compression  of an EXR output: zip (default), zips, rle, piz, none\n"
    "  in, out         FQM in, vertex map out; EXR file or - "
    "(stream, default)\n";

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "mode", required_argument, NULL, 'm' },
		{ NULL, 0, NULL, 0 },
	};
	stage_solve o = { .mode = SOLVE_QEM1D, .rel = 1e-3 };
	cli c;
	tl_err e;
	int ch;

	cli_init(&c, argv, usage, CLI_COMPRESSION);
	o.jobs = cli_jobs();
	while ((ch = cli_next(&c, argc, argv, "j:m:r:v", longopts)) != -1) {
		if (ch == 'j')
			o.jobs = (int)cli_number(&c, "-j", optarg, 1,
			    CLI_JOBS_MAX);
		else if (ch == 'm' && solve_mode_parse(optarg, &o.mode) < 0)
			return cli_bad(&c, "-m %s: unknown mode", optarg);
		else if (ch == 'r')
			o.rel = cli_real(&c, "-r", optarg, 0, 1);
		else if (ch == 'v')
			o.verbose = 1;
		else if (ch != 'm')
			return cli_usage_error(&c);
	}
	/* more threads than the pool takes: as many as it takes */
	o.jobs = o.jobs > TL_POOL_MAXTHREADS ? TL_POOL_MAXTHREADS : o.jobs;
	if ((ch = cli_filter_args(&c, argc, argv, &o.in, &o.out)) >= 0)
		return ch;
	return cli_exit(&c, stage_fqmsolve(&c, &o, &e), &e);
}
