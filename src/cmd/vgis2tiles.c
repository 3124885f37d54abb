/* vgis2tiles - a VGIS pyramid as an OGC 3D Tiles 1.1 tileset for
 * CesiumJS and the other 3D Tiles readers: tileset.json and one glb per
 * block. The work is t3_run (tiles3d/tiles3d.h). */
#include <stdlib.h>
#include <unistd.h>

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
	long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
	t3_args a = { .tau0 = T3_TAU0 };
	t3_report rep;
	tl_err e;
	cli c;
	int ch, r;

	cli_init(&c, argv, usage, 0);
	a.jobs = ncpu < 1 ? 1 : ncpu > T3_MAXJOBS ? T3_MAXJOBS : (int)ncpu;
	while ((ch = cli_next(&c, argc, argv, "j:qt:", NULL)) != -1) {
		switch (ch) {
		case 'j':
			if (tl_parse_int(optarg, &a.jobs) < 0 || a.jobs < 1)
				return cli_bad(&c, "-j %s: expected a number "
				    ">= 1", optarg);
			break;
		case 'q':
			a.quiet = 1;
			break;
		case 't':
			if (tl_parse_double(optarg, &a.tau0) < 0 ||
			    !(a.tau0 >= 0) || a.tau0 > 1e6)
				return cli_bad(&c, "-t %s: expected metres, "
				    "0 to 1e6", optarg);
			break;
		default:
			return cli_usage_error(&c);
		}
	}
	if (c.status >= 0)
		return c.status;
	if (argc - optind != 2)
		return cli_usage_error(&c);
	a.dir = argv[optind], a.out = argv[optind + 1], a.prog = c.prog;
	r = t3_run(&a, &rep, &e);
	if (r == 0 && !a.quiet)
		report(&c, &rep);
	return cli_exit(&c, r, &e);
}
