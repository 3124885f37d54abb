/* tilecheck - the brute-force checker of a VGIS pyramid (verify.h): its
 * options into a vf_args, then vf_run. No GL. Exit 0 pass, 1 violations,
 * 2 usage, 3 cannot check (as cmp(1) has it). */
#include <getopt.h>
#include <stdio.h>

#include "core/dem.h"
#include "core/util.h"
#include "pyramid/verify.h"

static const char *prog = "tilecheck";

static void
usage(FILE *f)
{
	fprintf(f, "usage: %s [--dem dem] [--tau t,...] [-D datum] "
	    "[-e encoding] [-H datum]\n"
	    "                 [-N nodata] [-n name] [-s dx[,dy]] dir\n"
	    "  dir             the pyramid: index, blocks, borders, "
	    "saturation, triangulations\n"
	    "                  at a sweep of tolerances\n"
	    "  --dem dem       the DEM it was made from: check its errors "
	    "too\n"
	    "  --tau t,...     tolerances in metres instead of each level's "
	    "sweep\n"
	    "  -D, -e, -H, -N, -n, -s  how to read the DEM, as for "
	    "dem2fqm(1)\n"
	    "exit status: 0 pass, 1 violations, 2 usage, 3 cannot check\n",
	    prog);
}

enum { OPT_DEM = 256, OPT_TAU };

/* -1: go on; else the exit status. */
static int
option(vf_args *a, int c, const char *arg)
{
	tl_err e;

	switch (c) {
	case OPT_DEM:
		a->dem_path = arg;
		return -1;
	case OPT_TAU:
		if (vf_parse_taus(a, arg) == 0)
			return -1;
		tl_warn(prog, "--tau %s: expected up to %d numbers >= 0, "
		    "comma-separated", arg, VF_MAXTAU);
		return 2;
	case 'h':
		usage(stdout);
		return 0;
	case 'V':
		printf("%s %s\n", prog, TL_VERSION);
		return 0;
	}
	switch (dem_option(&a->dem, c, arg, &e)) {
	case 1:
		return -1;
	case -1:
		tl_warn(prog, "%s", e.msg);
		return 2;
	}
	usage(stderr);
	return 2;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "dem", required_argument, NULL, OPT_DEM },
		{ "tau", required_argument, NULL, OPT_TAU },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	vf_args a = { 0 };
	int c, r;

	while ((c = getopt_long(argc, argv, DEM_OPTS "hV", longopts, NULL)) !=
	    -1)
		if ((r = option(&a, c, optarg)) >= 0)
			return r;
	if (optind != argc - 1) {
		usage(stderr);
		return 2;
	}
	a.dir = argv[optind];
	r = vf_run(&a, prog);
	return r < 0 ? 3 : r;
}
