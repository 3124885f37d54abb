/* vgis2tiles - a VGIS pyramid as an OGC 3D Tiles 1.1 tileset for
 * CesiumJS and the other 3D Tiles readers: tileset.json and one glb per
 * block. The work is t3_run (tiles3d/tiles3d.h). */

#include "cli.h"
#include "tiles3d/tiles3d.h"

static const char usage[] =
    "[-q] [-j jobs] [-t tau0] dir outdir\n"
    "  -j jobs         threads (default: the CPUs)\n"
    "  -q              no warnings, no report on stderr\n"
    "  -t tau0         level 0's tolerance in metres (default 1), doubled "
    "per level\n"
    "  dir             the pyramid (dem2vgis(1)), heights ellipsoidal\n"
    "  outdir          the tileset directory to make (or replace)\n";

static void
report(const cli *c, const t3_report *r)
{
	fprintf(stderr, "%s: %d tiles, %lld vertices, %lld triangles "
	    "(skirts included), %.1f MiB; root error %.3f m, %d errors "
	    "raised to a child's, flat-triangle term up to %.4f m\n", c->prog,
	    r->tiles, r->verts, r->tris, r->bytes / 1048576.0, r->root_error,
	    r->raised, r->max_curve);
}

int
main(int argc, char **argv)
{
	t3_args a = { .tau0 = T3_TAU0 };
	t3_report rep;
	tl_err e;
	cli c;
	int ch, r;

	cli_init(&c, argv, usage, 0);
	a.jobs = cli_jobs();
	while ((ch = cli_next(&c, argc, argv, "j:qt:", NULL)) != -1) {
		switch (ch) {
		case 'j':
			a.jobs = (int)cli_number(&c, "-j", optarg, 1,
			    CLI_JOBS_MAX);
			break;
		case 'q':
			a.quiet = 1;
			break;
		case 't':
			a.tau0 = cli_real(&c, "-t", optarg, 0, 1e6);
			break;
		default:
			return cli_usage_error(&c);
		}
	}
	if (c.status >= 0)
		return c.status;
	/* more threads than t3_run takes: as many as it takes */
	a.jobs = a.jobs > T3_MAXJOBS ? T3_MAXJOBS : a.jobs;
	if (argc - optind != 2)
		return cli_usage_error(&c);
	if (cli_outdir(&c, argv[optind + 1]) != 0)
		return CLI_USAGE;
	a.dir = argv[optind], a.out = argv[optind + 1], a.prog = c.prog;
	r = t3_run(&a, &rep, &e);
	if (r == 0 && !a.quiet)
		report(&c, &rep);
	return cli_exit(&c, r, &e);
}
