/* terrain_cli.c - the terrain export's options, report and plan steps,
 * shared by vgis2terrain and vgis-job (terrain_cli.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "terrain_cli.h"

int
tr_cli_option(cli *c, int ch, tr_args *a)
{
	switch (ch) {
	case 'j':
		a->jobs = (int)cli_number(c, "-j", optarg, 1, TR_MAXJOBS);
		return 1;
	case 'f':
		if (strcmp(optarg, "qm") && strcmp(optarg, "3dtiles"))
			return -1;
		a->format = strcmp(optarg, "3dtiles") == 0;
		return 1;
	case 'q':
		a->quiet = 1;
		return 1;
	case 'z':
		a->gzip = 1;
		return 1;
	case TR_CLI_PARENT:
		a->parent = optarg;
		return 1;
	case TR_CLI_ATTRIB:
		a->attrib = optarg;
		return 1;
	}
	return 0;
}

int
tr_cli_words(const tr_args *a, const char **w)
{
	int n = 0;

	if (a->format)
		w[n++] = "-f", w[n++] = "3dtiles";
	if (a->gzip)
		w[n++] = "-z";
	if (a->quiet)
		w[n++] = "-q";
	if (a->parent)
		w[n++] = "--parent-url", w[n++] = a->parent;
	if (a->attrib)
		w[n++] = "--attribution", w[n++] = a->attrib;
	return n;
}

void
tr_cli_report(const cli *c, const tr_report *r)
{
	char at[64], d[32];

	for (int z = 0; z <= r->maxzoom; z++) {
		at[0] = 0;
		if (r->measured[z] >= 0)
			snprintf(at, sizeof at, " at %.1f%% of samples",
			    100 * r->measured[z]);
		/* no sample measured: no distance to give, not 0 m */
		if (r->measured[z] == 0)
			snprintf(d, sizeof d, "-");
		else
			snprintf(d, sizeof d, "%.3f m", r->direct[z]);
		fprintf(stderr, "%s: level %d: %lld tiles, %lld triangles, "
		    "%.1f KiB; pyramid level %d, tolerance %.3f m (try %d); "
		    "measured %s%s; bound %.3f m = %.3f E_L\n", c->prog, z,
		    r->tiles[z], r->tris[z], r->bytes[z] / 1024.0, r->plevel[z],
		    r->tau[z], r->tries[z], d, at, r->err[z],
		    r->err[z] / (TR_E0 / (1 << z)));
	}
}

const char tr_step_part_usage[] =
    "[-qz] [-f format] [-j jobs] [--parent-url URL]\n"
    "                     [--attribution TEXT] [--settle] z:i0:i1 dir "
    "work\n"
    "  tiles i0 .. i1-1 of level z of the terrain of the pyramid dir into "
    "the\n  work directory, at the first try at which they hold (round 1)"
    "; --settle:\n  from the largest try of the level's round-1 records "
    "(round 2); one thread\n  unless -j; the other options as for "
    "vgis2terrain(1)\n";
const char tr_step_gather_usage[] =
    "[-qz] [-f format] [-j jobs] [--parent-url URL]\n"
    "                       [--attribution TEXT] dir work outdir\n"
    "  the ranges in work become the terrain outdir (layer.json, or the "
    "3D Tiles\n  subtrees and tileset.json, written); ranges at an earlier "
    "try than their\n  level's made again; the options as for "
    "vgis2terrain(1)\n";

enum { OPT_SETTLE = 256 };

/* The options of both steps into a (settle: --settle given); the
 * status to exit with now, or -1. */
static int
step_options(cli *c, int argc, char **argv, tr_args *a, int *settle)
{
	static const struct option lo[] = {
		TR_CLI_LONGOPTS,
		{ "settle", no_argument, NULL, OPT_SETTLE },
		{ NULL, 0, NULL, 0 }
	};
	int ch, r;

	a->jobs = 0, a->prog = c->prog;
	while ((ch = cli_next(c, argc, argv, TR_CLI_OPTS, lo)) != -1) {
		if (ch == OPT_SETTLE && settle != NULL)
			*settle = 1;
		else if ((r = tr_cli_option(c, ch, a)) <= 0)
			return cli_usage_error(c);
	}
	if (c->status >= 0)
		return c->status;
	if (a->format && a->gzip)
		return cli_usage_error(c);
	return argc - optind != 3 ? cli_usage_error(c) : -1;
}

int
tr_step_part(cli *c, int argc, char **argv)
{
	tr_args a = { 0 };
	tr_range r;
	int settle = 0, st, n;
	tl_err e;

	if ((st = step_options(c, argc, argv, &a, &settle)) >= 0)
		return st;
	if (sscanf(argv[optind], "%d:%d:%d%n", &r.z, &r.i0, &r.i1, &n) != 3 ||
	    argv[optind][n] != '\0')
		return cli_bad(c, "%s: not a range of tiles, z:i0:i1",
		    argv[optind]);
	a.dir = argv[optind + 1], a.out = argv[optind + 2];
	a.jobs = a.jobs ? a.jobs : 1; /* the plan runs many at once */
	return cli_exit(c, tr_plan_part(&a, a.out, &r, settle ? 2 : 1, &e),
	    &e);
}

int
tr_step_gather(cli *c, int argc, char **argv)
{
	tr_args a = { 0 };
	tr_report rep;
	tl_err e;
	int st, r;

	if ((st = step_options(c, argc, argv, &a, NULL)) >= 0)
		return st;
	if (a.jobs == 0)
		a.jobs = cli_jobs() > TR_MAXJOBS ? TR_MAXJOBS : cli_jobs();
	a.dir = argv[optind], a.out = argv[optind + 2];
	r = tr_plan_gather(&a, argv[optind + 1], &rep, &e);
	if (r == 0 && !a.quiet)
		tr_cli_report(c, &rep);
	return cli_exit(c, r, &e);
}
