/* stage_solve.c - fqmsolve's work (stage.h): a level's vertex map, one
 * FQM row in, one vertex row out, QEM-3D's rows on a pool of threads. */
#include <stdlib.h>

#include "stage.h"
#include "qem/fqm_input.h"
#include "base/paths.h"
#include "base/pool.h"
#include "raster/rowpipe.h"

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

int
stage_fqmsolve(const cli *c, const stage_solve *o, tl_err *e)
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
