/* tilepack - the VGIS block pyramid: the vertex maps of levels 0..L and
 * the original DEM in, a directory of 129x129 blocks per level out, each
 * vertex with its height and its saturated error (vgis(5)). The work is
 * pack_run (pyramid/pack.h). */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "base/paths.h"
#include "pack/pack.h"
#include "stage.h"

static const char usage[] =
    "[-flq] [-b samples] [-D datum] [-e encoding] [-g work | -p piece]\n"
    "                [-H datum] [-j jobs] [-N nodata] [-n name] [-s dx[,dy]]\n"
    "                [-z compression]\n"
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
    "  -z compression  the blocks': zip (default), zips, rle, piz, none\n"
    CLI_DEM_HELP
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
	int piece, list;
	int p[5];     /* -p: level, b0, b1, y0, y1 */
	const char *gather;
	int quiet;
} mode;

static int
pack(const cli *c, const pack_args *a, const mode *md, tl_err *e)
{
	pack_level *lev;
	int r = -1;

	if (!md->list && stage_pack_guard(a, md->gather, e) < 0)
		return -1;
	if (md->piece)
		return pack_piece(a, md->p[0], md->p[1], md->p[2], md->p[3],
		    md->p[4], e);
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

int
main(int argc, char **argv)
{
	pack_args a = { 0 };
	mode md = { 0 };
	int ch;
	cli c;
	tl_err e;

	cli_init(&c, argv, usage, CLI_DEM | CLI_COMPRESSION);
	a.jobs = cli_jobs();
	a.part_samples = 1LL << 30;
	while ((ch = cli_next(&c, argc, argv, "b:fg:j:lp:q", NULL)) != -1) {
		switch (ch) {
		case 'b':
			a.part_samples = cli_number(&c, "-b", optarg, 0,
			    LLONG_MAX);
			break;
		case 'f':
			a.force = 1;
			break;
		case 'g':
			md.gather = optarg;
			break;
		case 'p':
			if (stage_piece_parse(optarg, md.p) < 0)
				return cli_bad(&c, "-p %s: expected level:b0:b1 "
				    "or level:b0:b1:y0:y1, 0 <= b0 < b1, 0 <= "
				    "y0 < y1", optarg);
			md.piece = 1;
			break;
		case 'j':
			a.jobs = (int)cli_number(&c, "-j", optarg, 1,
			    CLI_JOBS_MAX);
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
	/* more threads than pieces at once: as many as pack takes */
	a.jobs = a.jobs > PACK_MAXJOBS ? PACK_MAXJOBS : a.jobs;
	if (md.piece + md.list + (md.gather != NULL) > 1)
		return cli_bad(&c, "-g, -l and -p: one at most");
	if ((ch = operands(&c, &a, argc - optind, argv + optind)) != 0)
		return ch;
	a.dem = c.dem;
	a.prog = c.prog;
	a.comp = c.comp;
	return cli_exit(&c, pack(&c, &a, &md, &e), &e);
}
