/* dem2vgis - a DEM in, its VGIS block pyramid out, in one command: the
 * supervisor of the whole pipeline (jobs/pipeline.h). */
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "base/stamp.h"
#include "jobs/graph.h"
#include "jobs/pipeline.h"

static const char usage[] =
    "[-3fMq] [-j jobs] [-k kernel] [-P plandir] [-r cut] [-D datum]\n"
    "                [-e encoding] [-H datum] [-N nodata] [-n name]\n"
    "                [-s dx[,dy]] dem ... dir\n"
    "       dem2vgis --check-stamp file\n"
    "  -3              QEM-3D levels (fqmsolve -m qem3d)\n"
    "  -f              replace dir (with -P: plandir) if it exists\n"
    "  -j jobs         tilepack's threads (default: the CPUs)\n"
    "  -k kernel       fqmfilter's kernel (default binomial)\n"
    "  -P, --plan plandir  write the build as jobs for make, GNU parallel\n"
    "                  or Slurm into plandir, instead of running it\n"
    "  -q              no summary from tilepack\n"
    "  -r cut          fqmsolve -r (QEM-3D)\n"
    "  -M              only the vertex maps of every level, into dir\n"
    "  --band-width n  with -P: chain jobs of n level-0 columns (0: one "
    "job)\n"
    "  --fill-rows n   with -P: the fill in jobs of n rows (0: one job)\n"
    "  --part-samples n  with -P: tilepack -b n, a piece's jobs scan at "
    "most\n"
    "                  about n DEM samples each (0: pieces whole)\n"
    "  --band a,b --band-levels t [--fill file]  with -M: a plan's band "
    "job, levels\n"
    "                  0 .. t-1 of columns a .. b-1, and level t's FQM\n"
    "  --from fqm      with -M: the chain from this FQM (a band list)\n"
    "  --check-stamp file  a plan's job: its DEM's files as the plan "
    "recorded\n"
    "                  them (dem2fqm --stamp), or exit 1\n"
    "  -D, -e, -H, -N, -n, -s, --resample  how to read the DEM, as for "
    "dem2fqm(1)\n"
    "  dem ...         the DEM, or - (stdin); several are one mosaic\n"
    "  dir             the pyramid directory to build\n";

/* The directory of this program: the stages installed beside it, or the
 * build tree it runs from, before PATH; TL_BIN, when set, before both. */
static const char *
bindir(char *buf, size_t n)
{
	const char *env = getenv("TL_BIN");
	ssize_t r;
	char *slash;

	if (env != NULL && env[0] != '\0')
		return env;
	if ((r = readlink("/proc/self/exe", buf, n - 1)) <= 0)
		return NULL;
	buf[r] = '\0';
	if ((slash = strrchr(buf, '/')) == NULL)
		return NULL;
	*slash = '\0';
	return buf;
}

/* The DEM options, passed on as they are: the stages read them. */
static const char dem_letters[] = "DeHNs";
static const char *const flags[] = { "-D", "-e", "-H", "-N", "-s" };

enum { OPT_BAND = 256, OPT_BAND_LEVELS, OPT_BAND_WIDTH, OPT_FILL, OPT_FROM,
    OPT_FILL_ROWS, OPT_PART_SAMPLES, OPT_CHECK_STAMP };

static const char *check_stamp; /* --check-stamp */

/* The options of a plan's band jobs (dem2vgis(1), section PLANS). */
static int
parse_band(cli *c, int ch, pipeline_opts *o)
{
	switch (ch) {
	case OPT_BAND:
		if (cli_columns(optarg, o->band) < 0)
			return cli_bad(c, "--band %s: not columns a,b", optarg);
		return 0;
	case OPT_BAND_LEVELS:
		if (tl_parse_int(optarg, &o->band_levels) < 0 ||
		    o->band_levels < 1 || o->band_levels > 20)
			return cli_bad(c, "--band-levels %s: not 1 .. 20",
			    optarg);
		return 0;
	case OPT_BAND_WIDTH:
		if (tl_parse_int(optarg, &o->bandplan) < 0 || o->bandplan < 0)
			return cli_bad(c, "--band-width %s: not a column count",
			    optarg);
		o->bandplan = o->bandplan == 0 ? -1 : o->bandplan;
		return 0;
	case OPT_FILL_ROWS:
		if (tl_parse_int(optarg, &o->fillplan) < 0 || o->fillplan < 0)
			return cli_bad(c, "--fill-rows %s: not a row count",
			    optarg);
		o->fillplan = o->fillplan == 0 ? -1 : o->fillplan;
		return 0;
	case OPT_PART_SAMPLES:
		if (tl_parse_ll(optarg, &o->partplan) < 0 || o->partplan < 0)
			return cli_bad(c, "--part-samples %s: not a sample "
			    "count", optarg);
		return 0;
	case OPT_FILL:
		o->fill = optarg;
		return 0;
	case OPT_FROM:
		o->from = optarg;
		return 0;
	case OPT_CHECK_STAMP:
		check_stamp = optarg;
		return 0;
	}
	return cli_usage_error(c);
}

static int
parse(cli *c, int argc, char **argv, pipeline_opts *o)
{
	static const struct option longopts[] = {
		{ "plan", required_argument, NULL, 'P' },
		{ "band", required_argument, NULL, OPT_BAND },
		{ "band-levels", required_argument, NULL, OPT_BAND_LEVELS },
		{ "band-width", required_argument, NULL, OPT_BAND_WIDTH },
		{ "fill", required_argument, NULL, OPT_FILL },
		{ "fill-rows", required_argument, NULL, OPT_FILL_ROWS },
		{ "from", required_argument, NULL, OPT_FROM },
		{ "part-samples", required_argument, NULL, OPT_PART_SAMPLES },
		{ "check-stamp", required_argument, NULL, OPT_CHECK_STAMP },
		{ "resample", no_argument, NULL, DEM_RESAMPLE },
		{ NULL, 0, NULL, 0 },
	};
	int ch, j;

	while ((ch = cli_next(c, argc, argv, "3fMqj:k:P:r:" DEM_OPTS,
	    longopts)) != -1) {
		switch (ch) {
		case '3': o->mode = "qem3d"; break;
		case 'f': o->force = 1; break;
		case 'q': o->quiet = 1; break;
		case 'M': o->vmaps = 1; break;
		case 'P': o->plan = optarg; break;
		case 'j':
			if (tl_parse_int(optarg, &j) < 0 || j < 1)
				return cli_bad(c, "-j %s: not a job count",
				    optarg);
			o->jobs = optarg;
			break;
		case 'k': o->kernel = optarg; break;
		case 'r': o->cut = optarg; break;
		case 'n': o->name = optarg; break;
		case 'D': case 'e': case 'H': case 'N': case 's':
			if (o->ndemopt + 2 > PIPELINE_MAXOPTS)
				return cli_bad(c, "too many DEM options");
			o->demopt[o->ndemopt++] =
			    flags[strchr(dem_letters, ch) - dem_letters];
			o->demopt[o->ndemopt++] = optarg;
			break;
		case DEM_RESAMPLE: /* the stages' own option */
			if (o->ndemopt + 1 > PIPELINE_MAXOPTS)
				return cli_bad(c, "too many DEM options");
			o->demopt[o->ndemopt++] = "--resample";
			break;
		default:
			if (ch < OPT_BAND || ch > OPT_CHECK_STAMP)
				return cli_usage_error(c);
			if (parse_band(c, ch, o) != 0)
				return CLI_USAGE;
		}
	}
	return c->status >= 0 ? c->status : -1;
}

int
main(int argc, char **argv)
{
	pipeline_opts o = { .mode = "qem1d", .kernel = "binomial",
	    .partplan = -1 };
	char self[PATH_MAX];
	cli c;
	tl_err e;
	int st;

	cli_init(&c, argv, usage, 0);
	if ((st = parse(&c, argc, argv, &o)) >= 0)
		return st;
	if (check_stamp != NULL && argc == optind) {
		if (stamp_check(check_stamp, &e) == 0)
			return 0;
		fprintf(stderr, "%s: %s: a plan's jobs must all read the DEM "
		    "it was made from; write the plan again (dem2vgis -f "
		    "--plan)\n", c.prog, e.msg);
		return CLI_FAIL;
	}
	if (argc - optind < 2 || check_stamp != NULL)
		return cli_usage_error(&c);
	o.prog = c.prog, o.bindir = bindir(self, sizeof self);
	o.dem = argv[optind], o.out = argv[argc - 1];
	o.dems = argv + optind, o.ndem = argc - optind - 1;
	for (int k = 0; o.ndem > 1 && k < o.ndem; k++)
		if (strcmp(o.dems[k], "-") == 0)
			return cli_bad(&c, "-: stdin can only be the one DEM");
	if (o.plan != NULL && o.vmaps)
		return cli_bad(&c, "-M and -P: one or the other");
	if ((o.band[1] > 0) != (o.band_levels > 0) || ((o.band[1] > 0 ||
	    o.fill != NULL || o.from != NULL) && !o.vmaps) ||
	    (o.from != NULL && (o.band[1] > 0 || o.fill != NULL)))
		return cli_bad(&c, "--band and --band-levels go together, with "
		    "-M; --from with -M, alone");
	if (o.plan != NULL && strcmp(o.dem, "-") == 0)
		return cli_bad(&c, "-P: the DEM must be a file, not stdin");
	if (pipeline_run(&o, &st, &e) == 0)
		return 0;
	fprintf(stderr, "%s\n", e.msg); /* the failing stage's own words */
	if (st > 128 && st < 128 + NSIG) { /* die of it, as the shell expects */
		signal(st - 128, SIG_DFL);
		raise(st - 128);
	}
	return st == CLI_USAGE ? CLI_USAGE : CLI_FAIL;
}
