/* vgis-job - the steps a plan runs (dem2vgis --plan; plan.h), in one
 * place, so that the filters a person scripts (dem2fqm, fqmfilter,
 * fqmsolve, tilepack) carry none of a plan's internals: the DEM's stamp,
 * the guard of the outputs, the fill in row bands, a band's window and
 * columns, the chain, the pieces and the gather; and the terrain's
 * (vgis2terrain --plan: terrain_cli.c) and the raster-dem tiles'
 * (dem2rgb --plan: rgb_cli.c). Each step is a thin call
 * of the library's work (stage.h, dem.h, stamp.h, pipeline.h, pack.h);
 * its messages say "vgis-job STEP: ...". Internal: the plans write these
 * command lines, vgis-job(1) lists them. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "stage.h"
#include "rgb_cli.h"
#include "terrain_cli.h"
#include "base/stamp.h"
#include "jobs/pipeline.h"

static const char usage[] =
    "step [option ...] operand ...\n"
    "       vgis-job stamp file dem ...\n"
    "       vgis-job check-stamp file\n"
    "       vgis-job guard dem path ...\n"
    "       vgis-job fill [--pass p] [--rows y0,y1] [--band-rows n] "
    "[DEM options]\n"
    "                dem filled\n"
    "       vgis-job level0 [-F filled] [-w a,b] [-z compression] "
    "[DEM options]\n"
    "                [dem [out]]\n"
    "       vgis-job filter [-C a,b] [-k kernel] [-z compression] "
    "[in [out]]\n"
    "       vgis-job solve [-C a,b] [-m mode] [-r cut] [-z compression] "
    "[in [out]]\n"
    "       vgis-job chain [-3] [-k kernel] [-r cut] [--band a,b "
    "--band-levels t]\n"
    "                [--fill filled] [--from fqm] [DEM options] dem dir\n"
    "       vgis-job pieces [-b samples] [DEM options] dem level0 ...\n"
    "       vgis-job piece [-b samples] [DEM options] level:b0:b1 dem work "
    "level0 ...\n"
    "       vgis-job part [-b samples] [DEM options] level:b0:b1:y0:y1 dem "
    "work\n"
    "                level0 ...\n"
    "       vgis-job gather [-f] [DEM options] work dem dir level0 ...\n"
    "       vgis-job terrain-part [-qz] [-f format] [-j jobs] [--settle] "
    "z:i0:i1 dir work\n"
    "       vgis-job terrain-gather [-qz] [-f format] [-j jobs] dir work "
    "outdir\n"
    "       vgis-job rgb-warp [dem2rgb options] dem work\n"
    "       vgis-job rgb-part [dem2rgb options] k:n dem work\n"
    "       vgis-job rgb-gather [dem2rgb options] [-o archive] dem work "
    "[outdir]\n"
    "  the steps of a plan (dem2vgis(1), PLANS; vgis-job(1)); "
    "vgis-job STEP --help\n"
    "  says a step's options\n";

typedef int (*step_fn)(cli *c, int argc, char **argv);

/* The operands after the options: exactly n (n > 0), or at least -n. */
static int
operands(const cli *c, int argc, int n)
{
	if (c->status >= 0)
		return c->status;
	if (n > 0 ? argc - optind != n : argc - optind < -n)
		return cli_usage_error(c);
	return -1;
}

static int
step_stamp(cli *c, int argc, char **argv)
{
	tl_err e;
	int st;

	while (cli_next(c, argc, argv, "", NULL) != -1)
		return cli_usage_error(c);
	if ((st = operands(c, argc, -2)) >= 0)
		return st;
	return cli_exit(c, dem_stamp(argv[optind], argv + optind + 1,
	    argc - optind - 1, &e), &e);
}

static int
step_check_stamp(cli *c, int argc, char **argv)
{
	tl_err e;
	int st;

	while (cli_next(c, argc, argv, "", NULL) != -1)
		return cli_usage_error(c);
	if ((st = operands(c, argc, 1)) >= 0)
		return st;
	if (stamp_check(argv[optind], &e) == 0)
		return CLI_OK;
	cli_warn(c, "%s: a plan's jobs must all read the DEM (or, for "
	    "vgis2terrain --plan, the pyramid) it was made from; write the "
	    "plan again (dem2vgis -f --plan, vgis2terrain --plan, dem2rgb "
	    "--plan)", e.msg);
	return CLI_FAIL;
}

static int
step_guard(cli *c, int argc, char **argv)
{
	tl_err e;
	int st;

	while (cli_next(c, argc, argv, "", NULL) != -1)
		return cli_usage_error(c);
	if ((st = operands(c, argc, -2)) >= 0)
		return st;
	return cli_exit(c, stage_guard(argv[optind], NULL,
	    (const char *const *)argv + optind + 1, argc - optind - 1, &e),
	    &e);
}

/* vgis-job fill: the DEM's voids filled into a filled DEM (filled(5)),
 * whole or as one of the parts of a fill in row bands. */
enum { PASS_NONE, PASS_1, PASS_JOIN, PASS_2, PASS_COMMIT };
enum { OPT_PASS = 256, OPT_ROWS, OPT_BAND_ROWS, OPT_BAND, OPT_BAND_LEVELS,
    OPT_FILL, OPT_FROM };

typedef struct {
	const char *in, *filled;
	int pass;
	int rows[2], has_rows; /* --rows */
	int band;              /* --band-rows, 0 none */
} fill_opts;

static int
fill_work(const cli *c, const fill_opts *o, tl_err *e)
{
	static const char *const kinds[] = { "raw", "tmp", "s", "d" };
	char part[4][4200];
	const char *outs[5] = { o->filled };
	int n = 1;
	dem *d;

	for (int k = 0; o->pass != PASS_NONE && k < 4; k++) {
		snprintf(part[k], sizeof part[k], k < 2 ? "%s.%s" : "%s.%s.%d",
		    o->filled, kinds[k], o->rows[0]);
		if (k < 2 || o->pass == (k == 2 ? PASS_1 : PASS_2))
			outs[n++] = part[k];
	}
	if (stage_guard(o->in, NULL, outs, n, e) < 0)
		return -1;
	switch (o->pass) {
	case PASS_1:
		return dem_fill_pass1(o->in, &c->dem, o->filled, o->rows[0],
		    o->rows[1], e);
	case PASS_JOIN:
		return dem_fill_join(o->in, &c->dem, o->filled, o->band, e);
	case PASS_2:
		return dem_fill_pass2(o->in, &c->dem, o->filled, o->rows[0],
		    o->rows[1], e);
	case PASS_COMMIT:
		return dem_fill_commit(o->in, &c->dem, o->filled, o->band, e);
	}
	if ((d = dem_open(o->in, &c->dem, e)) == NULL)
		return -1;
	n = dem_save_filled(d, o->filled, e);
	dem_close(d);
	return n;
}

/* --pass 1 and 2 go with --rows, join and commit with --band-rows, on a
 * named DEM (the parts read it each). */
static int
fill_check(const cli *c, const fill_opts *o)
{
	int banded = o->pass == PASS_1 || o->pass == PASS_2;

	if (o->pass == PASS_NONE)
		return o->has_rows || o->band ? cli_bad(c, "--rows, --band-rows: "
		    "only with --pass") : 0;
	if (banded && (!o->has_rows || o->band))
		return cli_bad(c, "--pass 1, 2: with --rows y0,y1, not "
		    "--band-rows");
	if (!banded && (o->has_rows || !o->band))
		return cli_bad(c, "--pass join, commit: with --band-rows n, "
		    "not --rows");
	if (strcmp(o->in, "-") == 0)
		return cli_bad(c, "--pass: the DEM must be a named file (every "
		    "part reads it)");
	return 0;
}

static int
step_fill(cli *c, int argc, char **argv)
{
	static const struct option lo[] = {
		{ "pass", required_argument, NULL, OPT_PASS },
		{ "rows", required_argument, NULL, OPT_ROWS },
		{ "band-rows", required_argument, NULL, OPT_BAND_ROWS },
		{ NULL, 0, NULL, 0 },
	};
	static const char *const passes[] = { "1", "join", "2", "commit" };
	fill_opts o = { 0 };
	tl_err e;
	int ch;

	while ((ch = cli_next(c, argc, argv, "", lo)) != -1) {
		if (ch == OPT_ROWS && cli_columns(optarg, o.rows) < 0)
			return cli_bad(c, "--rows %s: not rows y0,y1 (0 <= y0 "
			    "< y1)", optarg);
		else if (ch == OPT_ROWS)
			o.has_rows = 1;
		else if (ch == OPT_BAND_ROWS)
			o.band = (int)cli_number(c, "--band-rows", optarg, 1,
			    INT_MAX);
		else if (ch != OPT_PASS)
			return cli_usage_error(c);
		for (int k = 0; ch == OPT_PASS && k < 4; k++)
			if (strcmp(optarg, passes[k]) == 0)
				o.pass = k + 1;
		if (ch == OPT_PASS && o.pass == PASS_NONE)
			return cli_bad(c, "--pass %s: not 1, join, 2 or commit",
			    optarg);
	}
	if ((ch = operands(c, argc, 2)) >= 0)
		return ch;
	o.in = argv[optind], o.filled = argv[optind + 1];
	if ((ch = fill_check(c, &o)) != 0)
		return ch;
	return cli_exit(c, fill_work(c, &o, &e), &e);
}

/* vgis-job level0: dem2fqm of a window (-w) of the DEM's samples, or of
 * its filled DEM's (-F), for a band job. */
static int
step_level0(cli *c, int argc, char **argv)
{
	stage_level0 o = { .in = "-", .out = "-" };
	tl_err e;
	int ch;

	while ((ch = cli_next(c, argc, argv, "F:w:", NULL)) != -1)
		if (ch == 'F')
			o.filled = optarg;
		else if (ch == 'w' && cli_columns(optarg, o.win) < 0)
			return cli_bad(c, "-w %s: not columns a,b (0 <= a < b)",
			    optarg);
		else if (ch == 'w')
			o.has_win = 1;
		else
			return cli_usage_error(c);
	if ((ch = cli_filter_args(c, argc, argv, &o.in, &o.out)) >= 0)
		return ch;
	return cli_exit(c, stage_dem2fqm(c, &o, &e), &e);
}

/* -C a,b of filter and solve. */
static int
cut_option(const cli *c, const char *arg, int cut[2], int *has)
{
	if (cli_columns(arg, cut) < 0)
		return cli_bad(c, "-C %s: not columns a,b (0 <= a < b)", arg);
	*has = 1;
	return 0;
}

static int
step_filter(cli *c, int argc, char **argv)
{
	stage_filter o = { .kernel = filter_find("binomial") };
	tl_err e;
	int ch;

	while ((ch = cli_next(c, argc, argv, "C:k:", NULL)) != -1)
		if (ch == 'C' && cut_option(c, optarg, o.cut, &o.has_cut) != 0)
			return CLI_USAGE;
		else if (ch == 'k' && (o.kernel = filter_find(optarg)) == NULL)
			return cli_bad(c, "-k %s: unknown kernel", optarg);
		else if (ch != 'C' && ch != 'k')
			return cli_usage_error(c);
	if ((ch = cli_filter_args(c, argc, argv, &o.in, &o.out)) >= 0)
		return ch;
	return cli_exit(c, stage_fqmfilter(c, &o, &e), &e);
}

/* A band job's solver: one thread (its job runs beside the others). */
static int
step_solve(cli *c, int argc, char **argv)
{
	stage_solve o = { .mode = SOLVE_QEM1D, .rel = 1e-3, .jobs = 1 };
	tl_err e;
	int ch;

	while ((ch = cli_next(c, argc, argv, "C:m:r:", NULL)) != -1)
		if (ch == 'C' && cut_option(c, optarg, o.cut, &o.has_cut) != 0)
			return CLI_USAGE;
		else if (ch == 'm' && solve_mode_parse(optarg, &o.mode) < 0)
			return cli_bad(c, "-m %s: unknown mode", optarg);
		else if (ch == 'r')
			o.rel = cli_real(c, "-r", optarg, 0, 1);
		else if (ch != 'C' && ch != 'm')
			return cli_usage_error(c);
	if ((ch = cli_filter_args(c, argc, argv, &o.in, &o.out)) >= 0)
		return ch;
	return cli_exit(c, stage_fqmsolve(c, &o, &e), &e);
}

/* vgis-job chain's options beside the DEM's: the band (--band,
 * --band-levels, --fill) or the chain from the bands' FQM (--from). */
static int
chain_option(cli *c, int ch, pipeline_opts *o)
{
	switch (ch) {
	case '3': o->mode = "qem3d"; return 0;
	case 'k': o->kernel = optarg; return 0;
	case 'r': o->cut = optarg; return 0;
	case OPT_FILL: o->fill = optarg; return 0;
	case OPT_FROM: o->from = optarg; return 0;
	case OPT_BAND_LEVELS:
		o->band_levels = (int)cli_number(c, "--band-levels", optarg, 1,
		    20);
		return 0;
	case OPT_BAND:
		if (cli_columns(optarg, o->band) < 0)
			return cli_bad(c, "--band %s: not columns a,b", optarg);
		return 0;
	}
	return cli_usage_error(c);
}

/* vgis-job chain: the quadric chain's vertex maps into dir (dem2vgis
 * -M), of a band's columns, or from the bands' FQM. */
static int
step_chain(cli *c, int argc, char **argv)
{
	static const struct option lo[] = {
		{ "band", required_argument, NULL, OPT_BAND },
		{ "band-levels", required_argument, NULL, OPT_BAND_LEVELS },
		{ "fill", required_argument, NULL, OPT_FILL },
		{ "from", required_argument, NULL, OPT_FROM },
		{ NULL, 0, NULL, 0 },
	};
	pipeline_opts o = { .mode = "qem1d", .kernel = "binomial",
	    .vmaps = 1, .partplan = -1 };
	char self[PATH_MAX];
	tl_err e;
	int ch, st;

	while ((ch = cli_next(c, argc, argv, "3k:r:", lo)) != -1)
		if (chain_option(c, ch, &o) != 0)
			return CLI_USAGE;
	if ((st = operands(c, argc, 2)) >= 0)
		return st;
	if ((o.band[1] > 0) != (o.band_levels > 0) ||
	    (o.from != NULL && (o.band[1] > 0 || o.fill != NULL)))
		return cli_bad(c, "--band and --band-levels go together; --from "
		    "alone");
	o.prog = c->prog, o.bindir = cli_bindir(self, sizeof self);
	o.dem = argv[optind], o.out = argv[optind + 1];
	o.name = c->dem.hgt_name;
	for (int k = 0; k < cli_dem_argc(c); k++)
		o.demopt[o.ndemopt++] = cli_dem_argv(c)[k];
	if (pipeline_run(&o, &st, &e) == 0)
		return CLI_OK;
	fprintf(stderr, "%s\n", e.msg); /* the failing stage's own words */
	return st == CLI_USAGE ? CLI_USAGE : CLI_FAIL;
}

/* The pieces in the work directory work become the pyramid a->dir. */
static int
gather(const pack_args *a, const char *work, tl_err *e)
{
	pack_level *lev = tl_alloc(a->nlevels, sizeof *lev, e);
	int r = lev != NULL ? pack_gather(a, work, lev, e) : -1;

	free(lev);
	return r;
}

/* vgis-job pieces, piece, part, gather: tilepack's pieces as jobs
 * (pack.h). what: 'l' (pieces: dem level0 ...), 'p' and 'q' (piece,
 * part: spec dem work level0 ...), 'g' (gather: work dem dir level0 ...).
 * A piece's job is one thread: the plan runs many at once. */
static int
pack_step(cli *c, int argc, char **argv, int what)
{
	pack_args a = { .part_samples = 1LL << 30, .jobs = 1 };
	int ch, p[5], first = what == 'l' ? 0 : 1;
	tl_err e;

	while ((ch = cli_next(c, argc, argv, what == 'g' ? "f" : "b:",
	    NULL)) != -1)
		if (ch == 'b')
			a.part_samples = cli_number(c, "-b", optarg, 0,
			    LLONG_MAX);
		else if (ch == 'f')
			a.force = 1;
		else
			return cli_usage_error(c);
	if ((ch = operands(c, argc, what == 'l' ? -2 : -4)) >= 0)
		return ch;
	argv += optind, argc -= optind;
	if ((what == 'p' || what == 'q') && (stage_piece_parse(argv[0],
	    p) < 0 || (p[4] > 0) != (what == 'q')))
		return cli_bad(c, "%s: not a %s", argv[0], what == 'q' ?
		    "part, level:b0:b1:y0:y1" : "piece, level:b0:b1");
	a.dem_path = argv[first], a.dem = c->dem, a.prog = c->prog;
	a.dir = what == 'l' ? "-" : argv[first + 1];
	a.levels = argv + first + 1 + (what != 'l');
	a.nlevels = argc - first - 1 - (what != 'l');
	if (what == 'g')
		a.jobs = cli_jobs() > PACK_MAXJOBS ? PACK_MAXJOBS : cli_jobs();
	if (what != 'l' && stage_pack_guard(&a, what == 'g' ? argv[0] :
	    NULL, &e) < 0)
		return cli_exit(c, -1, &e);
	return cli_exit(c, what == 'l' ? pack_list(&a, stdout, &e) :
	    what == 'g' ? gather(&a, argv[0], &e) :
	    pack_piece(&a, p[0], p[1], p[2], p[3], p[4], &e), &e);
}

static int
step_pieces(cli *c, int argc, char **argv)
{
	return pack_step(c, argc, argv, 'l');
}

static int
step_piece(cli *c, int argc, char **argv)
{
	return pack_step(c, argc, argv, 'p');
}

static int
step_part(cli *c, int argc, char **argv)
{
	return pack_step(c, argc, argv, 'q');
}

static int
step_gather(cli *c, int argc, char **argv)
{
	return pack_step(c, argc, argv, 'g');
}

static const struct {
	const char *name;
	step_fn fn;
	int sets;
	const char *usage;
} steps[] = {
	{ "stamp", step_stamp, 0, "file dem ...\n"
	    "  record what identifies every file the DEMs are read from into "
	    "file\n  (dem.stamp); - for a list of DEMs on stdin\n" },
	{ "check-stamp", step_check_stamp, 0, "file\n"
	    "  the DEM's files as stamp recorded them into file, or exit 1\n" },
	{ "guard", step_guard, 0, "dem path ...\n"
	    "  exit 1 if a path is, holds or lies inside a file the DEM is "
	    "read from\n" },
	{ "fill", step_fill, CLI_DEM, "[--pass p] [--rows y0,y1] "
	    "[--band-rows n] [DEM options]\n                     dem filled\n"
	    "  --pass p        one part of a fill in row bands (filled(5)): 1 "
	    "and 2 per\n"
	    "                  band (--rows y0,y1: rows y0 .. y1-1), join and "
	    "commit once\n"
	    "                  (--band-rows n: bands of n rows); without it "
	    "the whole fill\n"
	    CLI_DEM_HELP
	    "  dem, filled     the DEM; the filled DEM to write\n" },
	{ "level0", step_level0, CLI_DEM | CLI_COMPRESSION, "[-F filled] "
	    "[-w a,b] [-z compression] [DEM options]\n"
	    "                       [dem [out]]\n"
	    "  -F filled       the samples from this filled DEM (vgis-job fill "
	    "of dem)\n"
	    "  -w a,b          only the DEM's columns a .. b-1 (its edge "
	    "columns lack the\n"
	    "                  cells beyond)\n"
	    CLI_DEM_HELP
	    "  -z compression  as for dem2fqm(1)\n" },
	{ "filter", step_filter, CLI_COMPRESSION, "[-C a,b] [-k kernel] "
	    "[-z compression] [in [out]]\n"
	    "  -C a,b          only the output level's columns a .. b-1\n"
	    "  -k, -z          as for fqmfilter(1)\n" },
	{ "solve", step_solve, CLI_COMPRESSION, "[-C a,b] [-m mode] [-r cut] "
	    "[-z compression]\n                      [in [out]]\n"
	    "  -C a,b          only the level's columns a .. b-1\n"
	    "  -m, -r, -z      as for fqmsolve(1); one thread\n" },
	{ "chain", step_chain, CLI_DEM, "[-3] [-k kernel] [-r cut] "
	    "[--band a,b --band-levels t]\n"
	    "                      [--fill filled] [--from fqm] "
	    "[DEM options] dem dir\n"
	    "  the vertex maps of every level into dir (dem2vgis -M); -3, -k, "
	    "-r as for\n  dem2vgis(1)\n"
	    "  --band a,b --band-levels t  levels 0 .. t-1 of columns a .. b-1,"
	    " and level\n                  t's FQM as f.fqm\n"
	    "  --fill filled   the band read from this filled DEM\n"
	    "  --from fqm      the chain from this FQM (the bands' list)\n"
	    CLI_DEM_HELP },
	{ "pieces", step_pieces, CLI_DEM, "[-b samples] [DEM options] dem "
	    "level0 ...\n"
	    "  the pieces, and their parts, as tilepack -l lists them\n" },
	{ "piece", step_piece, CLI_DEM, "[-b samples] [DEM options] "
	    "level:b0:b1 dem work\n                      level0 ...\n"
	    "  one piece into the work directory, as tilepack -j 1 -p\n" },
	{ "part", step_part, CLI_DEM, "[-b samples] [DEM options] "
	    "level:b0:b1:y0:y1 dem work\n                     level0 ...\n"
	    "  one part of a piece into the work directory, as tilepack -j 1 "
	    "-p\n" },
	{ "gather", step_gather, CLI_DEM, "[-f] [DEM options] work dem dir "
	    "level0 ...\n"
	    "  the pieces in work become the pyramid dir, as tilepack -q -g\n" },
	{ "terrain-part", tr_step_part, 0, tr_step_part_usage },
	{ "terrain-gather", tr_step_gather, 0, tr_step_gather_usage },
	{ "rgb-warp", rg_step_warp, 0, rg_step_warp_usage },
	{ "rgb-part", rg_step_part, 0, rg_step_part_usage },
	{ "rgb-gather", rg_step_gather, 0, rg_step_gather_usage },
};

int
main(int argc, char **argv)
{
	static char name[64];
	size_t k, n = sizeof steps / sizeof steps[0];
	cli c;

	cli_init(&c, argv, usage, 0);
	for (k = 0; argc > 1 && k < n; k++)
		if (strcmp(argv[1], steps[k].name) == 0)
			break;
	if (argc < 2 || k == n) { /* --help, --version, or no step */
		while (cli_next(&c, argc, argv, "", NULL) != -1)
			;
		return c.status >= 0 ? c.status : argc < 2 ?
		    cli_usage_error(&c) : cli_bad(&c, "%s: no such step",
		    argv[optind]);
	}
	snprintf(name, sizeof name, "%s %s", c.prog, steps[k].name);
	argv[1] = name;
	cli_init(&c, argv + 1, steps[k].usage, steps[k].sets);
	return steps[k].fn(&c, argc - 1, argv + 1);
}
