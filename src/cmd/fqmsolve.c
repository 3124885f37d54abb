/* fqmsolve - the vertex map of a level: each vertex placed where its
 * quadric is least (QEM-1D: z on the grid position; QEM-3D: x, y, z), or
 * the vertex-filtered or sub-sampled heights the FQM carries. */
#include <stdlib.h>
#include <unistd.h>

#include "cli.h"
#include "qem/fqm_input.h"
#include "base/paths.h"
#include "base/pool.h"
#include "raster/rowpipe.h"
#include "qem/solve.h"

static const char usage[] =
    "[-v] [-C a,b] [-j jobs] [-m mode] [-r cut] [-z compression] "
    "[in [out]]\n"
    "  -C a,b          only the level's columns a .. b-1 (a band job's)\n"
    "  -j jobs         qem3d: threads placing a row's vertices (default: "
    "the CPUs)\n"
    "  -m mode         qem1d (default), qem3d, filtered, subsample\n"
    "  -r cut          qem3d: eigenvalues below cut x largest are free "
    "(default 1e-3)\n"
    "  -v              report how many vertices the qem3d fold fix moved\n"
    "  -z compression  of an EXR output: zip (default), zips, rle, piz, none\n"
    "  in, out         FQM in, vertex map out; EXR file or - "
    "(stream, default)\n";

typedef struct {
	enum solve_mode mode;
	double rel;
	int verbose;
	int jobs;
	int cut[2], has_cut; /* -C */
	const char *in, *out;
} options;

/* The work: the solver, one FQM row in, one vertex row out. */
typedef struct {
	fqm_input in;
	const rs_header *oh;
	solve_state s;
	solve_vertex *sv;
} job;

static int
vertex_row(void *ctx, int y, float *row, tl_err *e)
{
	job *j = ctx;

	if (j->s.mode != SOLVE_QEM3D) {
		if (fqm_input_read(&j->in, e) < 0)
			return -1;
		solve_row_direct(&j->s, &j->in.L, j->in.row, j->oh, row);
		return 0;
	}
	if (fqm_input_next(&j->in, e) < 0)
		return -1;
	solve_row(&j->s, j->in.v, j->sv);
	solve_encode(j->oh, j->sv, row);
	return 0;
}

static int
solve(const cli *c, const options *o, tl_err *e)
{
	job j = { .oh = NULL };
	tl_pool *pool = NULL;
	rs_header oh;
	long long n;
	int r = -1;

	rs_header_init(&oh, 0, 0);
	j.oh = &oh;
	if (tl_path_check_raster(o->out, o->in, "FQM", e) < 0 ||
	    fqm_input_open(&j.in, o->in, e) < 0 ||
	    solve_init(&j.s, o->mode, j.in.fi.level, j.in.h->width,
	    j.in.h->height, &j.in.m, e) < 0 ||
	    solve_header(&oh, j.in.h, o->mode, e) < 0)
		goto done;
	j.s.rel = o->rel;
	if (o->mode == SOLVE_QEM3D && o->jobs > 1 &&
	    ((pool = tl_pool_new(o->jobs, e)) == NULL ||
	    solve_pool(&j.s, pool, e) < 0))
		goto done;
	if ((j.sv = tl_alloc(j.in.h->width, sizeof *j.sv, e)) != NULL)
		r = rowpipe_run_cut(c->prog, o->out, &oh, o->has_cut ?
		    o->cut : NULL, c->comp, vertex_row, &j, e);
	n = (long long)j.in.h->width * j.in.h->height;
	if (r == 0 && o->verbose && o->mode == SOLVE_QEM3D)
		cli_warn(c, "level %d: fold fix reduced %lld of %lld vertices, "
		    "%lld back onto the grid", j.in.fi.level, j.s.reduced, n,
		    j.s.zeroed);
done:
	fqm_input_close(&j.in);
	rs_header_free(&oh);
	solve_free(&j.s);
	tl_pool_free(pool);
	free(j.sv);
	return r;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "mode", required_argument, NULL, 'm' },
		{ NULL, 0, NULL, 0 },
	};
	long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
	options o = { SOLVE_QEM1D, 1e-3, 0, 1, { 0, 0 }, 0, "-", "-" };
	cli c;
	tl_err e;
	int ch;

	o.jobs = ncpu < 1 ? 1 : ncpu > TL_POOL_MAXTHREADS ?
	    TL_POOL_MAXTHREADS : (int)ncpu;
	cli_init(&c, argv, usage, CLI_COMPRESSION);
	while ((ch = cli_next(&c, argc, argv, "C:j:m:r:v", longopts)) != -1) {
		if (ch == 'C' && cli_columns(optarg, o.cut) < 0)
			return cli_bad(&c, "-C %s: not columns a,b (0 <= a < b)",
			    optarg);
		else if (ch == 'C')
			o.has_cut = 1;
		else if (ch == 'j' && (tl_parse_int(optarg, &o.jobs) < 0 ||
		    o.jobs < 1))
			return cli_bad(&c, "-j %s: not a positive number", optarg);
		else if (ch == 'j' && o.jobs > TL_POOL_MAXTHREADS)
			o.jobs = TL_POOL_MAXTHREADS;
		else if (ch == 'm' && solve_mode_parse(optarg, &o.mode) < 0)
			return cli_bad(&c, "-m %s: unknown mode", optarg);
		else if (ch == 'r' && (tl_parse_double(optarg, &o.rel) < 0 ||
		    o.rel < 0 || o.rel >= 1))
			return cli_bad(&c, "-r %s: not a number in [0, 1)", optarg);
		else if (ch == 'v')
			o.verbose = 1;
		else if (ch != 'j' && ch != 'm' && ch != 'r' && ch != 'C')
			return cli_usage_error(&c);
	}
	if ((ch = cli_filter_args(&c, argc, argv, &o.in, &o.out)) >= 0)
		return ch;
	return cli_exit(&c, solve(&c, &o, &e), &e);
}
