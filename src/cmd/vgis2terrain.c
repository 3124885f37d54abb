/* vgis2terrain - a VGIS pyramid as quantized-mesh-1.0 terrain for
 * CesiumJS, cesium-native and the other terrain readers: layer.json and
 * {z}/{x}/{y}.terrain on the global geographic quadtree. The work is
 * tr_run (terrain/terrain.h); --plan writes it as a plan's jobs instead
 * (jobs/plan_terrain.h). */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "terrain_cli.h"
#include "jobs/plan_terrain.h"

static const char usage[] =
    "[-qz] [-f qm|3dtiles] [-j jobs] [--parent-url URL] [--attribution "
    "TEXT]\n                    [--plan plandir [--part-samples n]] dir "
    "outdir\n"
    "  -f format           qm: quantized-mesh (default); 3dtiles: the 3D "
    "Tiles terrain profile\n"
    "  -j jobs             threads (default: the CPUs)\n"
    "  -q                  no warnings, no report on stderr\n"
    "  -z                  gzip the tiles (serve them with "
    "Content-Encoding: gzip)\n"
    "  --parent-url URL    layer.json's parentUrl: the terrain past the "
    "DEM\n"
    "  --attribution TEXT  layer.json's attribution\n"
    "  --plan plandir      write the export as jobs for make, GNU parallel "
    "and Slurm\n"
    "                      into plandir instead of running it\n"
    "  --part-samples n    a job's share of a level: about n DEM samples "
    "(default\n"
    "                      2^26)\n"
    "  dir                 the pyramid (dem2vgis(1)), heights ellipsoidal\n"
    "  outdir              the terrain directory to make (or replace)\n";

enum { OPT_PLAN = 256, OPT_SAMPLES };

static const struct option longopts[] = {
	TR_CLI_LONGOPTS,
	{ "plan", required_argument, NULL, OPT_PLAN },
	{ "part-samples", required_argument, NULL, OPT_SAMPLES },
	{ NULL, 0, NULL, 0 }
};

/* The export of a written as a plan into dir: its ranges of samples DEM
 * samples, every job given the export's options (jobs: -j, when given). */
static int
write_plan(const cli *c, const tr_args *a, const char *dir, long long samples,
    int jobs, tl_err *e)
{
	plan_terrain_opts o = { .prog = c->prog, .pyr = a->dir, .out = a->out,
		.jobs = jobs };
	const char *words[8];
	char self[PATH_MAX];
	tr_range *r;
	int n, (*rr)[3];

	if (tr_plan_ranges(a, samples, &r, &n, e) < 0)
		return -1;
	if ((rr = tl_alloc(n, sizeof *rr, e)) == NULL) {
		free(r);
		return -1;
	}
	for (int k = 0; k < n; k++)
		rr[k][0] = r[k].z, rr[k][1] = r[k].i0, rr[k][2] = r[k].i1;
	o.bindir = cli_bindir(self, sizeof self);
	o.opt = words, o.nopt = tr_cli_words(a, words);
	o.range = (const int (*)[3])rr, o.nrange = n;
	n = plan_terrain_write(&o, dir, e);
	free(r), free(rr);
	return n;
}

int
main(int argc, char **argv)
{
	tr_args a = { 0 };
	tr_report rep;
	const char *plan = NULL;
	long long samples = 1LL << 26;
	tl_err e;
	cli c;
	int ch, r, jobs = 0;

	cli_init(&c, argv, usage, 0);
	a.jobs = cli_jobs() > TR_MAXJOBS ? TR_MAXJOBS : cli_jobs();
	while ((ch = cli_next(&c, argc, argv, TR_CLI_OPTS, longopts)) != -1) {
		if (ch == OPT_PLAN)
			plan = optarg;
		else if (ch == OPT_SAMPLES)
			samples = cli_number(&c, "--part-samples", optarg, 1,
			    LLONG_MAX);
		else if ((r = tr_cli_option(&c, ch, &a)) <= 0)
			return cli_usage_error(&c);
		else if (ch == 'j')
			jobs = a.jobs;
	}
	if (c.status >= 0)
		return c.status;
	if (argc - optind != 2 || (a.format && a.gzip))
		return cli_usage_error(&c); /* glbs are not gzipped */
	if (cli_outdir(&c, argv[optind + 1]) != 0)
		return CLI_USAGE;
	a.dir = argv[optind], a.out = argv[optind + 1], a.prog = c.prog;
	if (plan != NULL)
		return cli_exit(&c, write_plan(&c, &a, plan, samples, jobs, &e),
		    &e);
	r = tr_run(&a, &rep, &e);
	if (r == 0 && !a.quiet)
		tr_cli_report(&c, &rep);
	return cli_exit(&c, r, &e);
}
