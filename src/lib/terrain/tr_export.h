/* tr_export.h - the export's one unit of work, shared by the run in one
 * process (tr_run.c) and a plan's jobs (tr_plan.c): an open pyramid with
 * its threads, and a range of one level's tiles made at one try.
 *
 * Level z's tiles are those of its rectangle av[z], numbered row by row
 * from the south-west: tile i is (av[z][0] + i % nx, av[z][1] + i / nx).
 * Try t is the level's t-th choice (tr_choose, tighter as t grows); a
 * tile's bytes depend only on (z, t, x, y). A range holds at t when the
 * bound of every tile in it, max(tau, base) + its measured distance (or,
 * where that fits, the analytic bound of it: tr_bound), is within E_L. The level's try is the first at which every tile holds. */
#ifndef TL_TR_EXPORT_H
#define TL_TR_EXPORT_H

#include "base/pool.h"
#include "terrain/t3t.h"
#include "terrain/tr_impl.h"

#define TR_TRIES 8

/* What a range made at one try. */
typedef struct {
	int t;                  /* the try */
	int held;               /* every tile within E_L */
	double err;             /* largest measured distance (d[0]) */
	double direct;          /* largest distance to a sample (d[1]), over
	                         * the tiles measured */
	long long tiles, tris, bytes;
	long long nsamp, nmeas; /* level-0 samples in the tiles, in those
	                         * measured (not kept in a plan's records) */
} tr_part;

typedef struct {
	const tr_args *a;
	pyramid_index ix;
	tr_grid g;
	int nt;                 /* threads, each with its tr_work */
	tr_work *w;
	tl_err *err;
	int *failed;
	tl_pool *pool;
	int maxz;
	int av[TR_MAXZ + 1][4]; /* each level's tiles */
	t3t_set *t3;            /* -f 3dtiles: the tiles' metadata */
	/* the unit being made */
	const char *tmp;
	tr_choice c;
	int x0, y0, nx, i0;
	int ny;                 /* rows of a range of whole rows, else 0 */
	int count, next;        /* the loop's places; the next chunk a
	                         * thread takes (atomic: tr_take) */
	size_t keep;            /* > 0: tiles kept for one pass over level 0
	                         * (tr_batch), up to keep bytes a thread */
	const struct tr_keptz *kl; /* the pass: the kept tiles */
	double *dd;             /* per thread, per kept tile, d */
	int nkeep;
} tr_export;

/* Opens a->dir for export: its index read and checked, the grid, the
 * levels' rectangles (x->maxz, x->av), a->jobs threads. No output yet;
 * x->t3 is the caller's. */
int tr_open(tr_export *x, const tr_args *a, tl_err *e);
void tr_close(tr_export *x);
/* Tiles in level z. */
long long tr_count(const tr_export *x, int z);
/* Chunk after chunk of [0, n), chunk places each, taken by whichever
 * thread comes next (x->next, 0 at the loop's start) into [*i0, *i1):
 * tiles and blocks cost what their land and level make them, and the
 * pool's one range a thread (tl_pool_for) left one thread working alone
 * for most of a sweep. A tile's bytes depend on its level's choice alone
 * and the parts are sums and maxima: which thread takes what changes
 * nothing. 0 when none is left. */
int tr_take(tr_export *x, int n, int chunk, int *i0, int *i1);
/* Try t's choice for level z. */
void tr_choose(const pyramid_index *ix, int z, int t, tr_choice *c);
/* Level z's tile directories under tmp, those already there kept. */
int tr_dirs(const tr_export *x, const char *tmp, int z, tl_err *e);
/* Tiles i0 .. i1-1 of level z at try t into tmp (x->t3: their metadata
 * into it): *p. */
int tr_try(tr_export *x, const char *tmp, int z, int i0, int i1, int t,
    tr_part *p, tl_err *e);
/* Tries from, from + 1, ... of the range until it holds, the tiles left
 * made at that try (*p); fails when none of the tries holds. */
int tr_settle(tr_export *x, const char *tmp, int z, int i0, int i1,
    int from, tr_part *p, tl_err *e);
/* Levels 0 .. z1 (few tiles each), whole, into tmp: each at try 0 with
 * its tiles measured in one pass over level 0, then from try 1 on, one
 * at a time, the levels that did not hold; p[z] as tr_settle. The same
 * files and parts as tr_settle level by level. */
int tr_batch(tr_export *x, const char *tmp, int z1, tr_part *p, tl_err *e);
#define TR_KEEP (32 << 20) /* bytes of kept tiles, all threads */

/* Thread k's kept tiles measured in one pass over the level-0 blocks
 * they meet, their distances into p (per level), the tiles freed. */
int tr_batch_own(tr_export *x, int k, tr_part *p, tl_err *e);
/* The deepest level that tr_batch takes: of TR_BATCH tiles or fewer,
 * as are all those above it. */
int tr_batch_depth(const tr_export *x);
/* Levels g .. maxz, whole, into tmp at try 0 in one sweep over the DEM
 * (each tile with its ancestor at g, whose blocks a thread's cache
 * holds), then from try 1 on, one at a time, the levels that did not
 * hold; p[z] as tr_settle. The same files and parts as tr_settle level
 * by level. */
int tr_sweep(tr_export *x, const char *tmp, int g, tr_part *p, tl_err *e);
/* The first level tr_sweep takes (maxz + 1: none). */
int tr_sweep_level(const tr_export *x);

/* Level z's line of the report from its parts at one try. */
void tr_report_level(const tr_export *x, int z, const tr_part *p,
    tr_report *rep);
/* An existing OUTDIR may be replaced only when it is a terrain tileset. */
int tr_check_out(const char *out, tl_err *e);
/* layer.json, or the subtrees and tileset.json, into dir. */
int tr_finish(tr_export *x, const char *dir, tl_err *e);

#endif
