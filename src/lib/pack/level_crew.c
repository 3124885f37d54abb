/* level_crew.c - a run's pass and its thread crew: the DEM rows read in
 * batches, each batch scanned by every share on the pool's threads, each
 * block row saturated and handed out (again by the shares) once no later
 * row can change it, or a part's local errors given out. */
#include "pack/level_impl.h"
#include "base/pool.h"
#include "base/progress.h"

#include <assert.h>
#include <math.h>

/* A block row is final once no DEM row left can reach the local errors
 * its saturation band reads: 64 rows past that band, plus the margin. */
static int
ready(const state *s, int bj, double y)
{
	return y >= bj * BT_CELLS + BT_CELLS + REACH + BT_MAXH + 2;
}

/* A task for every share, on the pool's threads (base/pool.h): the
 * pool has a thread per share, so each range is one share (or, with
 * fewer threads, a few in a row). */
enum task { SCAN, EMIT };
_Static_assert(LEVEL_MAXTHREADS <= TL_POOL_MAXTHREADS, "a pool per piece");

typedef struct {
	tl_pool *pool;
	state *s;
	enum task task;
	int J0, J1, bj;    /* SCAN: DEM rows J0 .. J1-1; EMIT: block row bj */
} crew;

static void
do_shares(void *arg, int k, int i0, int i1)
{
	const crew *c = arg;

	(void)k;
	for (int i = i0; i < i1; i++)
		if (c->task == SCAN)
			lv_error_rows(&c->s->shares[i], c->J0, c->J1);
		else
			lv_emit_share(&c->s->shares[i], c->bj);
}

/* The crew's task (set by the caller) on every share. */
static void
run_shares(state *s, crew *c)
{
	tl_pool_for(c->pool, s->nshare, do_shares, c);
}

/* Block row bj: saturated, then its blocks handed out by the shares;
 * the failure told is the leftmost share's. */
static int
emit_row(state *s, crew *c, int bj, tl_err *e)
{
	lv_saturate(s, bj);
	c->task = EMIT, c->bj = bj;
	run_shares(s, c);
	for (int k = 0; k < s->nshare; k++) {
		const share *t = &s->shares[k];
		if (t->failed) {
			*e = t->err;
			return -1;
		}
		s->st->max_e = dmax(s->st->max_e, t->max_e);
		s->st->max_base = dmax(s->st->max_base, t->max_base);
	}
	return 0;
}

/* The window's columns of DEM rows J0 .. J1-1 as doubles, NaN where not
 * valid; the valid samples of the piece's own columns counted (the
 * pieces' own columns partition the DEM's). */
static int
read_batch(state *s, int J0, int J1, tl_err *e)
{
	long n = s->dend - s->d0, S = (long)s->step;
	long own0 = s->b0 * BT_CELLS * S - s->d0;
	long own1 = s->b1 == s->bx ? n : s->b1 * BT_CELLS * S - s->d0;

	for (int J = J0; J < J1; J++) {
		double *dd = s->dd + (size_t)(J - J0) * (n + 1);
		long long k = 0;
		if (dem_read_span(s->d, J, (int)s->d0, (int)n, s->dz, s->dv,
		    e) < 0)
			return -1;
		for (long i = 0; i < n; i++)
			dd[i] = s->dv[i] ? (double)s->dz[i] : NAN;
		for (long i = own0; i < own1; i++)
			k += s->dv[i];
		s->st->samples += k;
	}
	return 0;
}

/* The block rows not yet handed out: every level row loaded (a merged
 * piece's local errors read as they are), each block row once its
 * saturation band is. */
static int
run_blocks(state *s, crew *c, tl_err *e)
{
	while (s->next_bj < s->by) {
		if (lv_ensure(s, s->next_bj * BT_CELLS + BT_CELLS + REACH,
		    e) < 0 || emit_row(s, c, s->next_bj++, e) < 0)
			return -1;
	}
	return 0;
}

/* A part's local errors of the rows no later DEM row can reach (below
 * level row `below`), given out. A DEM row at level row y reaches the
 * centres from y - 64 - margin (less than 65) on. */
static int
give_out(state *s, int below, tl_err *e)
{
	const level_part *q = s->part;

	for (; s->next_out < q->g1 && s->next_out < below; s->next_out++)
		if (s->out(s->out_ctx, s->next_out, s->acc + eslot(s,
		    s->next_out) + (q->lo - s->c0), e) < 0)
			return -1;
	return 0;
}

/* Every DEM row scanned (a part's), in batches, each block row handed
 * out once no later row can change it (a part's local errors likewise). */
static int
run_rows(state *s, crew *c, tl_progress *pr, tl_err *e)
{
	for (int J0 = s->y0; J0 < s->y1; J0 += BATCH) {
		int J1 = J0 + BATCH < s->y1 ? J0 + BATCH : s->y1;
		double y = (J1 - 1) / s->step;
		s->yfirst = (int)(J0 / s->step);
		/* diamond vertices reach 2 x 64 rows (+ margin) below */
		if (lv_ensure(s, (int)y + 2 * BT_MAXH + 2, e) < 0 ||
		    read_batch(s, J0, J1, e) < 0)
			return -1;
		c->task = SCAN, c->J0 = J0, c->J1 = J1;
		run_shares(s, c);
		if (s->part != NULL &&
		    give_out(s, (int)floor(J1 / s->step) - BT_MAXH - 1, e) < 0)
			return -1;
		while (s->part == NULL && s->next_bj < s->by &&
		    ready(s, s->next_bj, y))
			if (emit_row(s, c, s->next_bj++, e) < 0)
				return -1;
		tl_progress_step(pr, J1 - s->y0);
		if (s->L->progress != NULL)
			s->L->progress(s->L->progress_ctx, J1 - J0);
	}
	if (s->part != NULL)
		return lv_ensure(s, s->part->g1 - 1, e) < 0 ? -1 :
		    give_out(s, s->part->g1, e);
	return run_blocks(s, c, e);
}

/* A run set up by state_init, on a pool of its shares' threads. */
int
lv_run(state *s, level_stats *st, tl_err *e)
{
	const level_args *L = s->L;
	tl_progress pr;
	crew c = { 0 };
	int r;

	s->st = st;
	c.s = s;
	if ((c.pool = tl_pool_new(s->nshare, e)) == NULL)
		return -1;
	tl_progress_start(&pr, L->label ? L->label : "", s->y1 - s->y0);
	if (L->label == NULL)
		pr.on = 0;
	r = s->d != NULL ? run_rows(s, &c, &pr, e) : run_blocks(s, &c, e);
	if (r == 0)
		tl_progress_end(&pr);
	tl_pool_free(c.pool);
	return r;
}
