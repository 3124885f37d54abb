/* rgb_cli.c - dem2rgb's options and report, and the plan's steps,
 * shared by dem2rgb and vgis-job (rgb_cli.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "rgb_cli.h"

static int
method(const char *s, enum solve_mode *m)
{
	if (strcmp(s, "qem1d") == 0)
		*m = SOLVE_QEM1D;
	else if (strcmp(s, "average") == 0)
		*m = SOLVE_FILTERED;
	else if (strcmp(s, "subsample") == 0)
		*m = SOLVE_SUBSAMPLE;
	else
		return -1;
	return 0;
}

void
rg_cli_report(const cli *c, const rg_report *r)
{
	for (int z = r->minzoom; z <= r->maxzoom; z++)
		fprintf(stderr, "%s: zoom %d: %lld tiles, %.1f KiB; error "
		    "max %.3f m, rms %.3f m over %lld samples\n", c->prog, z,
		    r->tiles[z], r->bytes[z] / 1024.0, r->max[z], r->rms[z],
		    r->n[z]);
}

int
rg_cli_option(cli *c, rg_args *a, int ch, const char *arg, tl_err *e)
{
	switch (ch) {
	case 'e':
		if (strcmp(arg, "terrarium") && strcmp(arg, "mapbox"))
			return cli_bad(c, "-e %s: not terrarium or mapbox", arg);
		a->enc = strcmp(arg, "mapbox") == 0 ? RG_MAPBOX : RG_TERRARIUM;
		break;
	case 'f':
		if (strcmp(arg, "png") && strcmp(arg, "webp"))
			return cli_bad(c, "-f %s: not png or webp", arg);
		a->fmt = strcmp(arg, "webp") == 0 ? RG_WEBP : RG_PNG;
		break;
	case 'm':
		if (method(arg, &a->mode) < 0)
			return cli_bad(c, "-m %s: not qem1d, average or "
			    "subsample", arg);
		break;
	case 't':
		if (strcmp(arg, "512") && strcmp(arg, "256"))
			return cli_bad(c, "-t %s: not 512 or 256", arg);
		a->dim = atoi(arg);
		break;
	case 'Z':
		a->minzoom = (int)cli_number(c, "-Z", arg, 0, RG_MAXZOOM);
		break;
	case 'z':
		a->maxzoom = (int)cli_number(c, "-z", arg, 0, RG_MAXZOOM);
		break;
	case 'j':
		a->jobs = (int)cli_number(c, "-j", arg, 1, RG_MAXJOBS);
		break;
	case 'c':
		a->cubic = 1;
		break;
	case 'u':
		a->url = arg;
		break;
	case 'o':
		a->out = arg, a->pmtiles = 1;
		break;
	case 'H': case 'D': case 'N':
		if (dem_option(&a->dopt, ch, arg, e) < 0)
			return cli_bad(c, "%s", e->msg);
		break;
	default:
		return cli_usage_error(c);
	}
	return c->status >= 0 ? c->status : 0;
}

const char rg_step_warp_usage[] =
    "[dem2rgb options] dem work\n"
    "  the plan's first job: dem on the deepest zoom's grid, its voids "
    "filled,\n  into work.grid/ (nothing for -m average); the options as "
    "for dem2rgb(1)\n";
const char rg_step_part_usage[] =
    "[dem2rgb options] k:n dem work\n"
    "  part k of n of dem2rgb's tiles of dem (its range of every zoom's "
    "tiles)\n  into the work tree, its counts into work.parts/k; one "
    "thread unless -j;\n  the options as for dem2rgb(1)\n";
const char rg_step_gather_usage[] =
    "[dem2rgb options] dem work outdir\n"
    "       vgis-job rgb-gather [dem2rgb options] -o archive dem work\n"
    "  the parts in work become dem2rgb's tree outdir (tiles.json "
    "written), or\n  the archive; the report on stderr unless -q; the "
    "options as for dem2rgb(1)\n";

/* As dem2rgb: blocks of 128 KiB and more mapped for each use, not kept
 * resident by the threads' arenas (dem2rgb(1) MEMORY). */
static void
mmap_blocks(void)
{
#ifdef __GLIBC__
	mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
}

/* The options of the steps into a (-q: *quiet); the status to exit
 * with now, or -1 when the step's operands follow (the gather's with -o:
 * one fewer; gather < 0: the warp's, two). */
static int
step_options(cli *c, int argc, char **argv, rg_args *a, int *quiet,
    int gather)
{
	tl_err e;
	int ch, r;

	mmap_blocks();
	a->dim = 512, a->maxzoom = -1, a->jobs = 0, a->prog = c->prog;
	while ((ch = cli_next(c, argc, argv, RG_CLI_OPTS "qo:", NULL)) != -1)
		if (ch == 'q')
			*quiet = 1;
		else if ((r = rg_cli_option(c, a, ch, optarg, &e)) != 0)
			return r;
	if (c->status >= 0)
		return c->status;
	if (a->maxzoom >= 0 && a->minzoom > a->maxzoom)
		return cli_bad(c, "-Z %d: above -z %d", a->minzoom, a->maxzoom);
	return argc - optind != (gather && a->pmtiles ? 2 : 3) - (gather < 0) ?
	    cli_usage_error(c) : -1;
}

int
rg_step_warp(cli *c, int argc, char **argv)
{
	rg_args a = { 0 };
	int quiet = 0, st;
	tl_err e;

	if ((st = step_options(c, argc, argv, &a, &quiet, -1)) >= 0)
		return st;
	a.dem = argv[optind];
	a.jobs = a.jobs ? a.jobs : cli_jobs(); /* it runs alone */
	return cli_exit(c, rg_warp(&a, argv[optind + 1], &e), &e);
}

int
rg_step_part(cli *c, int argc, char **argv)
{
	rg_args a = { 0 };
	int quiet = 0, st, k, n, end;
	tl_err e;

	if ((st = step_options(c, argc, argv, &a, &quiet, 0)) >= 0)
		return st;
	if (sscanf(argv[optind], "%d:%d%n", &k, &n, &end) != 2 ||
	    argv[optind][end] != '\0')
		return cli_bad(c, "%s: not a part, k:n", argv[optind]);
	a.dem = argv[optind + 1];
	a.jobs = a.jobs ? a.jobs : 1; /* the plan runs many at once */
	return cli_exit(c, rg_part(&a, argv[optind + 2], k, n, &e), &e);
}

int
rg_step_gather(cli *c, int argc, char **argv)
{
	rg_args a = { 0 };
	rg_report rep;
	int quiet = 0, st, r;
	tl_err e;

	if ((st = step_options(c, argc, argv, &a, &quiet, 1)) >= 0)
		return st;
	a.dem = argv[optind];
	a.jobs = a.jobs ? a.jobs : cli_jobs(); /* it runs alone */
	if (!a.pmtiles)
		a.out = argv[optind + 2];
	r = rg_gather(&a, argv[optind + 1], &rep, &e);
	if (r == 0 && !quiet)
		rg_cli_report(c, &rep);
	return cli_exit(c, r, &e);
}
