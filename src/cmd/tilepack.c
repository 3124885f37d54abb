/* tilepack - the VGIS block pyramid: the vertex maps of levels 0..L and
 * the original DEM in, a directory of 129x129 blocks per level out, each
 * vertex with its height and its saturated error (vgis(5)). The work is
 * pack_run (pyramid/pack.h). */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/cli.h"
#include "pyramid/pack.h"

static const char usage[] =
    "[-fq] [-D datum] [-e encoding] [-H datum] [-j jobs] [-N nodata]\n"
    "                [-n name] [-s dx[,dy]] dem dir level0 [level1 ...]\n"
    "  -f              replace dir even if it is not a pyramid\n"
    "  -j jobs         threads per level (default: the CPUs)\n"
    "  -q              no report on stderr\n"
    "  -D, -e, -H, -N, -n, -s  how to read the DEM, as for dem2fqm(1)\n"
    "  dem             the original DEM (errors are measured against it);\n"
    "                  a VRT or a list of DEM files for a mosaic\n"
    "  dir             the pyramid directory to make\n"
    "  level0 ...      vertex maps (fqmsolve(1)) of levels 0, 1, ... in "
    "order;\n"
    "                  EXR or fqm stream files, FIFOs, - for one of them\n";

/* The operands: dem dir level0 [level1 ...], stdin for one input at most. */
static int
operands(const cli *c, pack_args *a, int argc, char **argv)
{
	int stdin_uses = 0;

	if (argc < 3)
		return cli_usage_error(c);
	a->dem_path = argv[0], a->dir = argv[1];
	a->levels = argv + 2, a->nlevels = argc - 2;
	for (int k = 0; k < argc; k++)
		stdin_uses += k != 1 && strcmp(argv[k], "-") == 0;
	if (stdin_uses > 1)
		return cli_bad(c, "stdin can feed only one input");
	return 0;
}

static int
pack(const cli *c, const pack_args *a, int quiet, tl_err *e)
{
	pack_level *lev = tl_alloc(a->nlevels, sizeof *lev, e);
	int r = -1;

	if (lev != NULL && (r = pack_run(a, lev, e)) == 0 && !quiet)
		pack_report(stderr, c->prog, lev, a->nlevels);
	free(lev);
	return r;
}

int
main(int argc, char **argv)
{
	long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
	pack_args a = { 0 };
	int ch, quiet = 0;
	cli c;
	tl_err e;

	cli_init(&c, argv, usage, CLI_DEM);
	a.jobs = ncpu < 1 ? 1 : ncpu > PACK_MAXJOBS ? PACK_MAXJOBS : (int)ncpu;
	while ((ch = cli_next(&c, argc, argv, "fj:q", NULL)) != -1) {
		switch (ch) {
		case 'f':
			a.force = 1;
			break;
		case 'j':
			if (tl_parse_int(optarg, &a.jobs) < 0 || a.jobs < 1)
				return cli_bad(&c, "-j %s: expected a number "
				    ">= 1", optarg);
			if (a.jobs > PACK_MAXJOBS)
				a.jobs = PACK_MAXJOBS;
			break;
		case 'q':
			quiet = 1;
			break;
		default:
			return cli_usage_error(&c);
		}
	}
	if (c.status >= 0)
		return c.status;
	if ((ch = operands(&c, &a, argc - optind, argv + optind)) != 0)
		return ch;
	a.dem = c.dem;
	a.prog = c.prog;
	return cli_exit(&c, pack(&c, &a, quiet, &e), &e);
}
