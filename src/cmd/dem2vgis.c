/* dem2vgis - a DEM in, its VGIS block pyramid out, in one command: the
 * supervisor of the whole pipeline (jobs/pipeline.h), its stages threads
 * of this process (stage_inproc.h) unless --processes or TL_PROCESSES=1
 * asks for the filters as processes. */
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "jobs/graph.h"
#include "jobs/pipeline.h"
#include "stage_inproc.h"

static const char usage[] =
    "[-3fMq] [-j jobs] [-k kernel] [-P plandir] [-r cut] [-D datum]\n"
    "                [-e encoding] [-H datum] [-N nodata] [-n name]\n"
    "                [-s dx[,dy]] [--resample] dem ... dir\n"
    "  -3              QEM-3D levels (fqmsolve -m qem3d)\n"
    "  -f              replace dir (with -P: plandir) if it exists\n"
    "  -j jobs         tilepack's threads (default: the CPUs)\n"
    "  -k kernel       fqmfilter's kernel (default binomial)\n"
    "  -P, --plan plandir  write the build as jobs for make, GNU parallel\n"
    "                  or Slurm into plandir, instead of running it\n"
    "  -q              no summary from tilepack\n"
    "  -r cut          fqmsolve -r (QEM-3D)\n"
    "  -M              only the vertex maps of every level, into dir\n"
    "  --processes     the stages as processes joined by pipes (also\n"
    "                  TL_PROCESSES=1), not threads of this one\n"
    "  --band-width n  with -P: chain jobs of n level-0 columns (0: one "
    "job)\n"
    "  --fill-rows n   with -P: the fill in jobs of n rows (0: one job)\n"
    "  --part-samples n  with -P: tilepack -b n, a piece's jobs scan at "
    "most\n"
    "                  about n DEM samples each (0: pieces whole)\n"
    CLI_DEM_HELP
    "  dem ...         the DEM, or - (stdin); several are one mosaic\n"
    "  dir             the pyramid directory to build\n";

enum { OPT_BAND_WIDTH = 256, OPT_FILL_ROWS, OPT_PART_SAMPLES,
    OPT_PROCESSES };

/* The options of a plan (dem2vgis(1), section PLANS). */
static void
parse_plan(cli *c, int ch, pipeline_opts *o)
{
	switch (ch) {
	case OPT_BAND_WIDTH:
		o->bandplan = (int)cli_number(c, "--band-width", optarg, 0,
		    INT_MAX);
		o->bandplan = o->bandplan == 0 ? -1 : o->bandplan;
		break;
	case OPT_FILL_ROWS:
		o->fillplan = (int)cli_number(c, "--fill-rows", optarg, 0,
		    INT_MAX);
		o->fillplan = o->fillplan == 0 ? -1 : o->fillplan;
		break;
	default:
		o->partplan = cli_number(c, "--part-samples", optarg, 0,
		    LLONG_MAX);
	}
}

static int
parse(cli *c, int argc, char **argv, pipeline_opts *o, int *processes)
{
	static const struct option longopts[] = {
		{ "plan", required_argument, NULL, 'P' },
		{ "band-width", required_argument, NULL, OPT_BAND_WIDTH },
		{ "fill-rows", required_argument, NULL, OPT_FILL_ROWS },
		{ "part-samples", required_argument, NULL, OPT_PART_SAMPLES },
		{ "processes", no_argument, NULL, OPT_PROCESSES },
		{ NULL, 0, NULL, 0 },
	};
	int ch;

	while ((ch = cli_next(c, argc, argv, "3fMqj:k:P:r:", longopts)) != -1) {
		switch (ch) {
		case '3': o->mode = "qem3d"; break;
		case 'f': o->force = 1; break;
		case 'q': o->quiet = 1; break;
		case 'M': o->vmaps = 1; break;
		case 'P': o->plan = optarg; break;
		case 'j': /* tilepack's, checked here */
			(void)cli_number(c, "-j", optarg, 1, CLI_JOBS_MAX);
			o->jobs = optarg;
			break;
		case 'k': o->kernel = optarg; break;
		case 'r': o->cut = optarg; break;
		case OPT_PROCESSES: *processes = 1; break;
		default:
			if (ch < OPT_BAND_WIDTH || ch > OPT_PART_SAMPLES)
				return cli_usage_error(c);
			parse_plan(c, ch, o);
		}
	}
	if (c->status >= 0)
		return c->status;
	/* the DEM options, passed on as the stages read them */
	o->name = c->dem.hgt_name;
	for (int k = 0; k < cli_dem_argc(c); k++)
		o->demopt[o->ndemopt++] = cli_dem_argv(c)[k];
	return -1;
}

int
main(int argc, char **argv)
{
	pipeline_opts o = { .mode = "qem1d", .kernel = "binomial",
	    .partplan = -1 };
	const char *env = getenv("TL_PROCESSES");
	char self[PATH_MAX];
	stage_inproc work;
	int st, processes = env != NULL && strcmp(env, "1") == 0;
	cli c;
	tl_err e;

	cli_init(&c, argv, usage, CLI_DEM);
	if ((st = parse(&c, argc, argv, &o, &processes)) >= 0)
		return st;
	if (argc - optind < 2)
		return cli_usage_error(&c);
	o.prog = c.prog, o.bindir = cli_bindir(self, sizeof self);
	o.dem = argv[optind], o.out = argv[argc - 1];
	if ((st = cli_outdir(&c, o.out)) != 0)
		return st;
	o.dems = argv + optind, o.ndem = argc - optind - 1;
	for (int k = 0; o.ndem > 1 && k < o.ndem; k++)
		if (strcmp(o.dems[k], "-") == 0)
			return cli_bad(&c, "-: stdin can only be the one DEM");
	if (o.plan != NULL && o.vmaps)
		return cli_bad(&c, "-M and -P: one or the other");
	if (o.plan != NULL && strcmp(o.dem, "-") == 0)
		return cli_bad(&c, "-P: the DEM must be a file, not stdin");
	if (!processes && o.plan == NULL && !o.vmaps) {
		/* the options are checked again by the stages' programs run
		 * on no input (pipeline.c), before any work */
		if (stage_inproc_init(&work, &c, &o, &e) == 0)
			o.work = &work.w;
		else
			processes = 1;
	}
	if (pipeline_run(&o, &st, &e) == 0)
		return 0;
	fprintf(stderr, "%s\n", e.msg); /* the failing stage's own words */
	if (st > 128 && st < 128 + NSIG) { /* die of it, as the shell expects */
		signal(st - 128, SIG_DFL);
		raise(st - 128);
	}
	return st == CLI_USAGE ? CLI_USAGE : CLI_FAIL;
}
