/* tilepack - the VGIS block pyramid: the vertex maps of levels 0..L and
 * the original DEM in, a directory of 129x129 blocks per level out, each
 * vertex with its height and its saturated error (vgis(5)). The work is
 * pack_run (pyramid/pack.h). */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "base/paths.h"
#include "pack/pack.h"

static const char usage[] =
    "[-flq] [-b samples] [-D datum] [-e encoding] [-g work | -p piece]\n"
    "                [-H datum] [-j jobs] [-N nodata] [-n name] [-s dx[,dy]]\n"
    "                dem dir level0 [level1 ...]\n"
    "  -b samples      with -l and -p: a piece whose DEM window holds more\n"
    "                  samples is made in parts of rows (default 2^30; 0:\n"
    "                  never)\n"
    "  -f              replace dir even if it is not a pyramid\n"
    "  -g work         gather: the pieces made in work become dir\n"
    "  -j jobs         threads (default: the CPUs)\n"
    "  -l              list the pieces, level:b0:b1 a line, each after its\n"
    "                  parts, level:b0:b1:y0:y1 (dir unused)\n"
    "  -p piece        make one piece, level:b0:b1 (its block columns\n"
    "                  b0..b1-1), or one part, level:b0:b1:y0:y1 (its DEM\n"
    "                  rows y0..y1-1), in dir taken as a work directory\n"
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

/* What to make: the whole pyramid, one piece, or the pyramid from the
 * pieces in a work directory. */
typedef struct {
	int piece, level, b0, b1, y0, y1, list;
	const char *gather;
	int quiet;
} mode;

/* dir kept off every input before any work (paths.h): the DEM's files,
 * the vertex maps (a band list's bands too), the gather's work. */
static int
guard(const pack_args *a, const mode *md, tl_err *e)
{
	tl_paths s = { 0 };
	int r = dem_paths(&s, a->dem_path, e);

	for (int l = 0; r == 0 && l < a->nlevels; l++)
		r = tl_paths_add_raster(&s, a->levels[l], "vertex map", e);
	if (r == 0 && md->gather != NULL)
		r = tl_paths_add(&s, md->gather, TL_PATH_TREE, e,
		    "the input work directory %s", md->gather);
	if (r == 0)
		r = tl_paths_check(&s, a->dir, e);
	tl_paths_free(&s);
	return r;
}

static int
pack(const cli *c, const pack_args *a, const mode *md, tl_err *e)
{
	pack_level *lev;
	int r = -1;

	if (!md->list && guard(a, md, e) < 0)
		return -1;
	if (md->piece)
		return pack_piece(a, md->level, md->b0, md->b1, md->y0, md->y1,
		    e);
	if (md->list)
		return pack_list(a, stdout, e);
	if ((lev = tl_alloc(a->nlevels, sizeof *lev, e)) == NULL)
		return -1;
	r = md->gather != NULL ? pack_gather(a, md->gather, lev, e) :
	    pack_run(a, lev, e);
	if (r == 0 && !md->quiet)
		pack_report(stderr, c->prog, lev, a->nlevels);
	free(lev);
	return r;
}

static int
parse_piece(const char *s, mode *md)
{
	char end;
	int n = sscanf(s, "%d:%d:%d:%d:%d%c", &md->level, &md->b0, &md->b1,
	    &md->y0, &md->y1, &end);

	if (n == 3)
		md->y0 = md->y1 = 0;
	else if (n != 5 || md->y0 < 0 || md->y1 <= md->y0)
		return -1;
	if (md->level < 0 || md->b0 < 0 || md->b1 <= md->b0)
		return -1;
	md->piece = 1;
	return 0;
}

int
main(int argc, char **argv)
{
	long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
	pack_args a = { 0 };
	mode md = { 0 };
	int ch;
	cli c;
	tl_err e;

	cli_init(&c, argv, usage, CLI_DEM);
	a.jobs = ncpu < 1 ? 1 : ncpu > PACK_MAXJOBS ? PACK_MAXJOBS : (int)ncpu;
	a.part_samples = 1LL << 30;
	while ((ch = cli_next(&c, argc, argv, "b:fg:j:lp:q", NULL)) != -1) {
		switch (ch) {
		case 'b':
			if (tl_parse_ll(optarg, &a.part_samples) < 0 ||
			    a.part_samples < 0)
				return cli_bad(&c, "-b %s: expected a number "
				    ">= 0", optarg);
			break;
		case 'f':
			a.force = 1;
			break;
		case 'g':
			md.gather = optarg;
			break;
		case 'p':
			if (parse_piece(optarg, &md) < 0)
				return cli_bad(&c, "-p %s: expected level:b0:b1 "
				    "or level:b0:b1:y0:y1, 0 <= b0 < b1, 0 <= "
				    "y0 < y1", optarg);
			break;
		case 'j':
			if (tl_parse_int(optarg, &a.jobs) < 0 || a.jobs < 1)
				return cli_bad(&c, "-j %s: expected a number "
				    ">= 1", optarg);
			if (a.jobs > PACK_MAXJOBS)
				a.jobs = PACK_MAXJOBS;
			break;
		case 'l':
			md.list = 1;
			break;
		case 'q':
			md.quiet = 1;
			break;
		default:
			return cli_usage_error(&c);
		}
	}
	if (c.status >= 0)
		return c.status;
	if (md.piece + md.list + (md.gather != NULL) > 1)
		return cli_bad(&c, "-g, -l and -p: one at most");
	if ((ch = operands(&c, &a, argc - optind, argv + optind)) != 0)
		return ch;
	a.dem = c.dem;
	a.prog = c.prog;
	return cli_exit(&c, pack(&c, &a, &md, &e), &e);
}
