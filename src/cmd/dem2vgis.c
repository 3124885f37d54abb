/* dem2vgis - a DEM in, its VGIS block pyramid out, in one command: the
 * supervisor of the whole pipeline (jobs/pipeline.h). */
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/cli.h"
#include "jobs/graph.h"
#include "jobs/pipeline.h"

static const char usage[] =
    "[-3fMq] [-j jobs] [-k kernel] [-P plandir] [-r cut] [-D datum]\n"
    "                [-e encoding] [-H datum] [-N nodata] [-n name]\n"
    "                [-s dx[,dy]] dem ... dir\n"
    "  -3              QEM-3D levels (fqmsolve -m qem3d)\n"
    "  -f              replace dir (with -P: plandir) if it exists\n"
    "  -j jobs         tilepack's threads (default: the CPUs)\n"
    "  -k kernel       fqmfilter's kernel (default binomial)\n"
    "  -P, --plan plandir  write the build as jobs for make, GNU parallel\n"
    "                  or Slurm into plandir, instead of running it\n"
    "  -q              no summary from tilepack\n"
    "  -r cut          fqmsolve -r (QEM-3D)\n"
    "  -M              only the vertex maps of every level, into dir\n"
    "  -D, -e, -H, -N, -n, -s  how to read the DEM, as for dem2fqm(1)\n"
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

static int
parse(cli *c, int argc, char **argv, pipeline_opts *o)
{
	static const struct option longopts[] = {
		{ "plan", required_argument, NULL, 'P' },
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
		default:
			return cli_usage_error(c);
		}
	}
	return c->status >= 0 ? c->status : -1;
}

int
main(int argc, char **argv)
{
	pipeline_opts o = { .mode = "qem1d", .kernel = "binomial" };
	char self[PATH_MAX];
	cli c;
	tl_err e;
	int st;

	cli_init(&c, argv, usage, 0);
	if ((st = parse(&c, argc, argv, &o)) >= 0)
		return st;
	if (argc - optind < 2)
		return cli_usage_error(&c);
	o.prog = c.prog, o.bindir = bindir(self, sizeof self);
	o.dem = argv[optind], o.out = argv[argc - 1];
	o.dems = argv + optind, o.ndem = argc - optind - 1;
	for (int k = 0; o.ndem > 1 && k < o.ndem; k++)
		if (strcmp(o.dems[k], "-") == 0)
			return cli_bad(&c, "-: stdin can only be the one DEM");
	if (o.plan != NULL && o.vmaps)
		return cli_bad(&c, "-M and -P: one or the other");
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
