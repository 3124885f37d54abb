/* pack.c - a DEM's pyramid from its levels' vertex maps (see pack.h). */
#include "pack/pack_impl.h"

#include <assert.h>
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"
#include "base/progress.h"
#include "pyramid/pyramid.h"

int
pack_check_level(const fqm_info *fi, int l, const georef *g,
    const char *name, tl_err *e)
{
	const char *what;

	if (fi->level != l)
		return tl_fail(e, "%s: is level %d, expected level %d (levels "
		    "go in order from 0)", name, fi->level, l);
	if (fi->size0[0] != g->width || fi->size0[1] != g->height)
		return tl_fail(e, "%s: made from a %dx%d DEM, the DEM is %dx%d",
		    name, fi->size0[0], fi->size0[1], g->width, g->height);
	if ((what = geo_differs(&fi->geo, g)) != NULL)
		return tl_fail(e, "%s: georeferencing (%s) differs from the "
		    "DEM's: made with other DEM options?", name, what);
	return 0;
}

/* Levels 0 .. the first that fits one block, no fewer, no more: the
 * rule viewers and the checker hold a pyramid to. */
int
pack_check_count(int nlevels, int w0, int h0, tl_err *e)
{
	int want = geo_levels(w0, h0);

	if (nlevels == want)
		return 0;
	return tl_fail(e, "%d levels given, a %dx%d DEM's pyramid has %d "
	    "(0 .. the first that fits one %dx%d block)", nlevels, w0, h0,
	    want, GEO_LEVEL_BLOCK, FQM_BLOCK);
}

int
pack_check_dir(const char *dir, int force, tl_err *e)
{
	char path[4096];
	struct stat st;

	if (stat(dir, &st) != 0)
		return errno == ENOENT ? 0 : tl_failsys(e, "%s", dir);
	if (!S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: exists and is not a directory", dir);
	snprintf(path, sizeof path, "%s/" VGIS_INDEX, dir);
	if (!force && access(path, F_OK) != 0 && rmdir(dir) != 0)
		return tl_fail(e, "%s: exists and is not a pyramid (no "
		    "index.json); use -f to replace it", dir);
	return 0;
}

/* --- one level ---------------------------------------------------------- */

/* Columns c0 .. c0+n-1 of row r: of a vertex map on file only those
 * bytes (a piece reads its window, not the level), checked for NaN. */
static int
read_row(void *ctx, int r, int c0, int n, float *z, float *x, float *y,
    tl_err *e)
{
	vmap *v = ctx;

	if (v->gate != NULL && v->gate->stopped(v->gate->ctx))
		return tl_fail(e, "%s: stopped", v->name);
	if (v->d != NULL) { /* known: the DEM's heights, zero offsets */
		if (x != NULL) {
			memset(x, 0, (size_t)n * sizeof *x);
			memset(y, 0, (size_t)n * sizeof *y);
		}
		return dem_read_span(v->d, r, c0, n, z, NULL, e);
	}
	if (v->row == NULL &&
	    (v->row = tl_alloc((size_t)n * v->h->nch, sizeof *v->row, e)) == NULL)
		return -1;
	/* a part starts further down */
	for (; v->next < r; v->next++)
		if (rs_read_span(v->r, c0, n, v->row, e) < 0)
			return -1;
	v->next++;
	/* a NaN that a format without checksums let through stops here */
	if (rs_read_span(v->r, c0, n, v->row, e) < 0 ||
	    fqm_check_row(v->row, c0, n, v->h->nch, r, v->name, e) < 0)
		return -1;
	memcpy(z, v->row + (size_t)v->cz * n, (size_t)n * sizeof *z);
	if (x != NULL) {
		memcpy(x, v->row + (size_t)v->cx * n, (size_t)n * sizeof *x);
		memcpy(y, v->row + (size_t)v->cy * n, (size_t)n * sizeof *y);
	}
	return 0;
}

/* Opens level l's vertex map and checks it against the DEM. */
int
pk_vmap_open(vmap *v, const char *path, int l, const georef *g, tl_err *e)
{
	const char *name = tl_name(path, 0);
	fqm_info fi;

	memset(v, 0, sizeof *v);
	v->name = name;
	if ((v->r = rs_open(path, e)) == NULL)
		return -1;
	v->h = rs_header_of(v->r);
	if (fqm_info_of(v->h, "vertices", &fi, name, e) < 0 ||
	    fqm_whole(v->h, &fi, name, e) < 0 ||
	    pack_check_level(&fi, l, g, name, e) < 0 ||
	    (v->cz = rs_need_channel(v->h, "Z", name, e)) < 0)
		return -1;
	v->cx = rs_channel(v->h, "X"), v->cy = rs_channel(v->h, "Y");
	if ((v->cx < 0) != (v->cy < 0))
		return tl_fail(e, "%s: has only one of channels X and Y", name);
	return 0;
}

/* Level 0's known vertex map (pack_args known0): its header, the DEM's
 * rows. */
static void
known_vmap(vmap *v, const work *w)
{
	memset(v, 0, sizeof *v);
	v->name = "level 0";
	v->h = w->a->known0;
	v->d = w->d;
	v->cz = rs_channel(v->h, "Z");
	v->cx = rs_channel(v->h, "X"), v->cy = rs_channel(v->h, "Y");
}

/* Level l's vertex map: open and checked, or level 0's known one. */
static int
vmap_open(vmap *v, const work *w, int l, tl_err *e)
{
	if (l == 0 && w->known0) {
		known_vmap(v, w);
		return 0;
	}
	return pk_vmap_open(v, w->a->levels[l], l, dem_georef(w->d), e);
}

/* Whether some sample of d is -0, where the solver's Z + 0 may give +0:
 * level 0 then is not known (pack_args known0). */
static int
negative_zero(dem *d, tl_err *e)
{
	int w = dem_georef(d)->width, h = dem_georef(d)->height, r = 0;
	float *z = tl_alloc((size_t)w, sizeof *z, e);
	uint32_t u;

	if (z == NULL)
		return -1;
	for (int j = 0; r == 0 && j < h; j++) {
		if (dem_read_row(d, j, z, NULL, e) < 0)
			r = -1;
		for (int i = 0; r == 0 && i < w; i++)
			if (memcpy(&u, &z[i], sizeof u), u == 0x80000000u)
				r = 1;
	}
	free(z);
	return r;
}

void
pk_vmap_close(vmap *v)
{
	rs_close(v->r);
	free(v->row);
}

static int
write_block(void *ctx, const pyramid_block *b, tl_err *e)
{
	sink *k = ctx;
	char path[4096];
	size_t i = (size_t)b->bj * k->L->blocks[0] + b->bi;

	assert(b->bi < k->L->blocks[0] && b->bj < k->L->blocks[1]);
	pyramid_block_path(path, sizeof path, k->dir, b->level, b->bi, b->bj);
	k->L->zmin[i] = b->zmin, k->L->zmax[i] = b->zmax;
	k->L->base[i] = b->base, k->L->emax[i] = b->emax;
	return pyramid_block_write_z(path, b, k->attrs, k->comp, k->tree, e);
}

/* The index's entry for a level, from its vertex map's header. */
int
pk_level_entry(pyramid_level *pl, int l, const vmap *v, tl_err *e)
{
	const char *s;

	if (pyramid_level_init(pl, l, v->h->width, v->h->height, e) < 0)
		return -1;
	pl->displaced = v->cx >= 0;
	snprintf(pl->mode, sizeof pl->mode, "%s",
	    (s = rs_get_string(v->h, FQM_ATTR_MODE)) ? s : "");
	snprintf(pl->kernel, sizeof pl->kernel, "%s",
	    (s = rs_get_string(v->h, FQM_ATTR_KERNEL)) ? s : "");
	return 0;
}

/* Level l's index entry filled, from its open vertex map, and its
 * directory made. */
static int
level_begin(work *w, int l, const vmap *v, tl_err *e)
{
	char path[4096];

	if (pk_level_entry(&w->ix->lev[l], l, v, e) < 0)
		return -1;
	snprintf(path, sizeof path, "%s/%d", w->tmp, l);
	if (mkdir(path, 0777) != 0)
		return tl_failsys(e, "%s", path);
	return 0;
}

/* Levels l0 .. l1-1 begun before their work, a bad vertex map failing
 * at once (files only: a FIFO is read once, by its level's one piece). */
static int
levels_begin(work *w, int l0, int l1, tl_err *e)
{
	for (int l = l0; !w->fifo && l < l1; l++) {
		vmap v;
		int r = vmap_open(&v, w, l, e);
		if (r == 0)
			r = level_begin(w, l, &v, e);
		pk_vmap_close(&v);
		if (r < 0)
			return -1;
	}
	return 0;
}

/* One piece of a level in the making: the DEM columns it scans, for the
 * progress. */
typedef struct {
	work *w;
	long width;
} meter;

static void
on_rows(void *ctx, int rows)
{
	meter *m = ctx;

	pthread_mutex_lock(&m->w->mu);
	m->w->done += (long long)rows * m->width;
	tl_progress_step(&m->w->pr, m->w->done);
	pthread_mutex_unlock(&m->w->mu);
}

void
pk_merge_stats(work *w, int l, const level_stats *st)
{
	level_stats *o = &w->out[l].st;

	pthread_mutex_lock(&w->mu);
	o->max_e = st->max_e > o->max_e ? st->max_e : o->max_e;
	o->max_base = st->max_base > o->max_base ? st->max_base : o->max_base;
	o->samples += st->samples;
	pthread_mutex_unlock(&w->mu);
}

/* Piece p of level l on `threads` threads, or with a FIFO the whole
 * level (p NULL): its own reader of the level's vertex map (pieces read
 * it independently), its blocks written into the directory being built. */
/* Level l over its open vertex map v, its blocks into k. */
void
pk_level_setup(work *w, int l, vmap *v, sink *k, int threads, level_args *L)
{
	v->gate = w->a->gate;
	k->dir = w->tmp, k->attrs = v->h, k->L = &w->ix->lev[l];
	k->comp = w->a->comp, k->tree = w->tree;
	memset(L, 0, sizeof *L);
	L->level = l;
	L->size[0] = v->h->width, L->size[1] = v->h->height;
	L->displaced = k->L->displaced;
	L->m = w->m;
	L->row = read_row, L->row_ctx = v;
	L->block = write_block, L->block_ctx = k;
	L->threads = threads;
}

int
pk_run_piece(work *w, int l, const level_piece *p, int threads, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	level_args L;
	level_stats st;
	meter mt;
	vmap v;
	sink k;
	int r = -1;

	if (vmap_open(&v, w, l, e) < 0 ||
	    (p == NULL && level_begin(w, l, &v, e) < 0))
		goto done;
	pk_level_setup(w, l, &v, &k, threads, &L);
	mt.w = w, mt.width = g->width;
	if (p != NULL) {
		level_window win;
		level_piece_window(&L, g->width, p, &win);
		mt.width = win.d1 - win.d0;
	}
	L.progress = on_rows, L.progress_ctx = &mt;
	r = p != NULL ? level_run_piece(&L, p, w->d, &st, e) :
	    level_run(&L, w->d, &st, e);
	if (r == 0)
		pk_merge_stats(w, l, &st);
done:
	pk_vmap_close(&v);
	return r;
}

/* The pieces of every level, level 0 (the largest) first. */
typedef struct {
	int l;
	int whole;         /* the whole level (a FIFO), not piece p */
	level_piece p;
} job;

typedef struct {
	work *w;
	job *job;
	int n, cap, threads; /* jobs, room for them; threads per job */
	int next;          /* the next job to hand out */
	int failed;        /* the lowest job that failed, or INT_MAX */
	tl_err err;        /* its error */
	/* levels rest .. nlevels-1 are queued once the gate opens (their
	 * vertex maps complete: the chain has ended, even with none left,
	 * so that no pyramid is made before it), by the worker that finds
	 * no job left (opening); shut until then */
	int rest, shut, opening;
	int early;         /* workers 0 .. early-1 take jobs before that */
	long long guess;   /* their DEM samples, guessed for the progress */
	pthread_cond_t cv; /* the rest queued, or a failure */
} queue;

/* Job k failed with e (w->mu held): the lowest failure is kept. */
static void
job_failed(queue *q, int k, const tl_err *e)
{
	if (k < q->failed)
		q->failed = k, q->err = *e;
	pthread_cond_broadcast(&q->cv);
}

/* The DEM samples level pl's pieces scan, and (jobs not NULL) its
 * pieces appended to jobs: their count, or -1. */
static int
level_jobs(const work *w, int l, const pyramid_level *pl, job *jobs,
    long long *samples, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	level_piece *p;
	int m;

	*samples = 0;
	if (w->fifo) {
		if (jobs != NULL)
			jobs[0] = (job){ .l = l, .whole = 1 };
		*samples = (long long)g->height * g->width;
		return 1;
	}
	if ((p = pk_level_cut(pl, &m, e)) == NULL)
		return -1;
	for (int k = 0; k < m; k++) {
		level_args L = { .level = pl->level };
		level_window win;
		L.size[0] = pl->size[0];
		level_piece_window(&L, g->width, &p[k], &win);
		if (jobs != NULL)
			jobs[k] = (job){ .l = l, .p = p[k] };
		*samples += (long long)g->height * (win.d1 - win.d0);
	}
	free(p);
	return m;
}

/* Levels l0 .. l1-1, begun, queued (w->mu held when the workers run):
 * their samples added to *samples. */
static int
queue_levels(queue *q, int l0, int l1, long long *samples, tl_err *e)
{
	work *w = q->w;

	for (int l = l0; l < l1; l++) {
		long long s;
		int m = level_jobs(w, l, &w->ix->lev[l], NULL, &s, e);
		if (m < 0)
			return -1;
		if (q->n + m > q->cap) {
			int cap = 2 * (q->n + m);
			job *j = realloc(q->job, (size_t)cap * sizeof *j);
			if (j == NULL)
				return tl_failsys(e, "malloc");
			q->job = j, q->cap = cap;
		}
		level_jobs(w, l, &w->ix->lev[l], q->job + q->n, &s, e);
		q->n += m;
		*samples += s;
	}
	return 0;
}

/* The levels after the gate: waits for their vertex maps (or a failure,
 * the run's or a job's), begins and queues them. */
static int
open_rest(queue *q, tl_err *e)
{
	work *w = q->w;
	const pack_gate *g = w->a->gate;
	long long s = 0;
	int r, failed;

	do {
		r = g != NULL ? g->ended(g->ctx, 50) : 0;
		pthread_mutex_lock(&w->mu);
		failed = q->failed != INT_MAX;
		pthread_mutex_unlock(&w->mu);
	} while (r == 1 && !failed);
	if (r != 0 || failed)
		return tl_fail(e, "%s: stopped", w->a->prog ? w->a->prog :
		    "tilepack");
	if (levels_begin(w, q->rest, w->a->nlevels, e) < 0)
		return -1;
	pthread_mutex_lock(&w->mu);
	r = queue_levels(q, q->rest, w->a->nlevels, &s, e);
	if (r == 0)
		w->pr.total += s - q->guess; /* the guess made good */
	pthread_mutex_unlock(&w->mu);
	return r;
}

/* The next job (w->mu held): its number and *j; -1 none left, -2 wait
 * (another worker is opening the rest), -3 open the rest. Jobs are
 * handed out in order and none below a failed one is abandoned, so the
 * failure reported, the lowest job's, is the same whatever the threads'
 * timing. */
static int
take(queue *q, int id, job *j)
{
	int lim = q->failed < q->n ? q->failed : q->n;
	int shut = q->shut;

	if (q->next < lim && (id < q->early || !shut)) {
		*j = q->job[q->next];
		return q->next++;
	}
	if (q->failed != INT_MAX || !shut)
		return -1;
	return q->opening ? -2 : -3;
}

typedef struct {
	queue *q;
	int id;
} crew;

/* Takes jobs in order until none is left or one has failed. */
static void *
worker(void *arg)
{
	queue *q = ((crew *)arg)->q;
	int id = ((crew *)arg)->id;
	work *w = q->w;

	for (;;) {
		tl_err e;
		job j;
		int k;
		pthread_mutex_lock(&w->mu);
		while ((k = take(q, id, &j)) == -2)
			pthread_cond_wait(&q->cv, &w->mu);
		if (k == -3) {
			int n = q->n, r;
			q->opening = 1;
			pthread_mutex_unlock(&w->mu);
			r = open_rest(q, &e);
			pthread_mutex_lock(&w->mu);
			q->opening = 0;
			q->rest = w->a->nlevels, q->shut = 0;
			if (r < 0)
				job_failed(q, n, &e); /* after the jobs then */
			pthread_cond_broadcast(&q->cv);
			pthread_mutex_unlock(&w->mu);
			continue;
		}
		pthread_mutex_unlock(&w->mu);
		if (k < 0)
			return NULL;
		if (pk_run_piece(w, j.l, j.whole ? NULL : &j.p, q->threads,
		    &e) < 0) {
			pthread_mutex_lock(&w->mu);
			job_failed(q, k, &e);
			pthread_mutex_unlock(&w->mu);
		}
	}
}

/* The jobs on `workers` threads (this one and workers - 1 more). */
static int
run_queue(queue *q, int workers, tl_err *e)
{
	pthread_t t[PACK_MAXJOBS];
	crew c[PACK_MAXJOBS];
	int started = 0;

	q->failed = INT_MAX;
	c[0] = (crew){ q, 0 };
	for (; started < workers - 1 && started < PACK_MAXJOBS - 1; started++) {
		c[started + 1] = (crew){ q, started + 1 };
		if (pthread_create(&t[started], NULL, worker, &c[started + 1]))
			break; /* fewer threads: the same blocks */
	}
	worker(&c[0]);
	for (int k = 0; k < started; k++)
		pthread_join(t[k], NULL);
	if (q->failed != INT_MAX) {
		*e = q->err;
		return -1;
	}
	return 0;
}

/* Piece width, in block columns: 16 (2305 level columns with the halos)
 * holds a piece's rings in about 14 MB in 1D, 12 (1793 columns) in
 * about 18 MB in 3D, whose offsets add two rings; the halos cost 12 to
 * 16 % more local errors than the whole level's. */
#define PIECE_BLOCKS(displaced) ((displaced) ? 12 : 16)

/* Level pl's pieces, as every mode cuts them (threads, -l, -p, -g): how
 * many, and (pk_level_cut) the pieces themselves, allocated. */
static int
level_npieces(const pyramid_level *pl, level_piece *p, int max)
{
	level_args L = { .level = pl->level };

	L.size[0] = pl->size[0];
	return level_pieces(&L, PIECE_BLOCKS(pl->displaced), p, max);
}

level_piece *
pk_level_cut(const pyramid_level *pl, int *n, tl_err *e)
{
	level_piece *p;

	*n = level_npieces(pl, NULL, 0);
	if ((p = tl_alloc(*n, sizeof *p, e)) != NULL)
		level_npieces(pl, p, *n);
	return p;
}

void
pk_window(const work *w, int l, const level_piece *p, level_window *win)
{
	level_args L = { .level = l };

	L.size[0] = w->ix->lev[l].size[0];
	level_piece_window(&L, w->ix->geo.width, p, win);
}

/* Whether some level comes through a FIFO (or stdin): a pipeline
 * feeding several must have them all read at once. */
static int
fifo_inputs(const pack_args *a)
{
	struct stat st;

	for (int l = 0; l < a->nlevels; l++)
		if (strcmp(a->levels[l], "-") == 0 ||
		    (stat(a->levels[l], &st) == 0 && S_ISFIFO(st.st_mode)))
			return 1;
	return 0;
}

/* The jobs: files are read again by each piece, so every level is cut in
 * pieces, all in one queue, jobs threads taking them (one piece in memory
 * per thread); a level coming through a FIFO can be read only once, so
 * then each level is one piece and all levels run at once, one thread
 * each. Levels 0 .. ready-1 are begun; the others are begun and queued
 * once the gate opens, after level 0's pieces (pack_args gate). */
static int
run_levels(work *w, int ready, tl_err *e)
{
	int nl = w->a->nlevels, r;
	long long total = 0;
	queue q = { .w = w, .rest = ready, .shut = w->a->gate != NULL };

	pthread_cond_init(&q.cv, NULL);
	/* the levels to come, guessed from the DEM's size and level 0's
	 * displacement, for the progress (their headers say later) */
	for (int l = ready; l < nl; l++) {
		pyramid_level pl = { .level = l };
		long long s = 0;
		pl.size[0] = geo_level_size(w->ix->geo.width, l);
		pl.displaced = w->known0 && w->ix->lev[0].displaced;
		if (level_jobs(w, l, &pl, NULL, &s, e) < 0)
			return -1;
		q.guess += s;
	}
	if ((r = queue_levels(&q, 0, ready, &total, e)) == 0) {
		tl_progress_start(&w->pr, w->a->prog ? w->a->prog : "",
		    total + q.guess);
		if (w->a->prog == NULL)
			w->pr.on = 0;
		q.threads = 1;
		q.early = w->a->gate_jobs;
		r = run_queue(&q, w->fifo ? nl : w->a->jobs, e);
	}
	if (r == 0)
		tl_progress_end(&w->pr);
	free(q.job);
	pthread_cond_destroy(&q.cv);
	return r;
}

void
pk_report_levels(const pyramid_index *ix, pack_level *out)
{
	for (int l = 0; l < ix->nlevels; l++) {
		const pyramid_level *pl = &ix->lev[l];
		out[l].size[0] = pl->size[0], out[l].size[1] = pl->size[1];
		out[l].blocks[0] = pl->blocks[0];
		out[l].blocks[1] = pl->blocks[1];
		out[l].displaced = pl->displaced;
	}
}

int
pack_run(const pack_args *a, pack_level *out, tl_err *e)
{
	pyramid_index ix = { 0 };
	geo_ground m = { 0 };
	tl_outfile dir = { 0 };
	work w = { 0 };
	dem *d;
	int r = -1, ready, z;

	assert(a->nlevels >= 1 && a->jobs >= 1);
	if (pack_check_dir(a->dir, a->force, e) < 0 || (d = a->opened ?
	    a->opened : dem_open(a->dem_path, &a->dem, e)) == NULL)
		return -1;
	memset(out, 0, (size_t)a->nlevels * sizeof *out);
	ix.version = VGIS_VERSION;
	ix.geo = *dem_georef(d);
	ix.size0[0] = ix.geo.width, ix.size0[1] = ix.geo.height;
	ix.nlevels = a->nlevels;
	w.a = a, w.d = d, w.ix = &ix, w.m = &m, w.out = out;
	w.mu = (pthread_mutex_t)PTHREAD_MUTEX_INITIALIZER;
	if ((ix.lev = tl_alloc(a->nlevels, sizeof *ix.lev, e)) == NULL ||
	    geo_ground_init(&m, &ix.geo, e) < 0 ||
	    tl_outdir_begin(&dir, a->dir, e) < 0)
		goto done;
	w.tmp = dir.tmp, w.tree = 1;
	w.fifo = fifo_inputs(a);
	if (a->known0 != NULL && !w.fifo) {
		if ((z = negative_zero(d, e)) < 0)
			goto done;
		w.known0 = z == 0;
	}
	/* with a gate, the levels whose vertex maps are still being made
	 * are begun once they are complete */
	ready = a->gate == NULL ? a->nlevels : w.known0;
	/* the count after the levels, whose own faults say more */
	if (levels_begin(&w, 0, ready, e) < 0 || run_levels(&w, ready, e) < 0 ||
	    pack_check_count(ix.nlevels, ix.size0[0], ix.size0[1], e) < 0 ||
	    pyramid_index_write(dir.tmp, &ix, e) < 0)
		goto done;
	pk_report_levels(&ix, out);
	r = tl_outdir_commit(&dir, e);
done:
	if (r < 0)
		tl_outdir_abort(&dir);
	if (d != a->opened)
		dem_close(d);
	geo_ground_free(&m);
	pyramid_index_free(&ix);
	return r;
}

void
pack_report(FILE *f, const char *prog, const pack_level *L, int n)
{
	for (int l = 0; l < n; l++)
		fprintf(f, "%s: level %d: %dx%d vertices, %dx%d blocks, %s, "
		    "max E %.3f m, max base error %.3f m\n", prog, l,
		    L[l].size[0], L[l].size[1], L[l].blocks[0],
		    L[l].blocks[1], L[l].displaced ? "3D" : "1D",
		    L[l].st.max_e, L[l].st.max_base);
}

