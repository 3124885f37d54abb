/* pack.c - a DEM's pyramid from its levels' vertex maps (see pack.h). */
#include "pyramid/pack.h"

#include <assert.h>
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/outfile.h"
#include "core/progress.h"
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
	int want = fqm_levels(w0, h0);

	if (nlevels == want)
		return 0;
	return tl_fail(e, "%d levels given, a %dx%d DEM's pyramid has %d "
	    "(0 .. the first that fits one %dx%d block)", nlevels, w0, h0,
	    want, FQM_BLOCK, FQM_BLOCK);
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

/* The vertex map being read, for the row callback. */
typedef struct {
	rs_reader *r;
	const rs_header *h;
	const char *name;
	int cz, cx, cy; /* channels Z, X, Y (X, Y -1 on 1D levels) */
	float *row;     /* the span asked for, every channel */
	int next;       /* the next row to read */
} vmap;

/* Columns c0 .. c0+n-1 of row r: of a vertex map on file only those
 * bytes (a piece reads its window, not the level), checked for NaN. */
static int
read_row(void *ctx, int r, int c0, int n, float *z, float *x, float *y,
    tl_err *e)
{
	vmap *v = ctx;

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
static int
vmap_open(vmap *v, const char *path, int l, const georef *g, tl_err *e)
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

static void
vmap_close(vmap *v)
{
	rs_close(v->r);
	free(v->row);
}

/* Where finished blocks go, and what the index learns from them. */
typedef struct {
	const char *dir;
	const rs_header *attrs; /* the vertex map's fqm:* and geo:* */
	pyramid_level *L;
} sink;

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
	return pyramid_block_write(path, b, k->attrs, e);
}

/* What every level reads. */
typedef struct {
	const pack_args *a;
	dem *d;
	const char *tmp; /* the directory being built */
	pyramid_index *ix;
	const geo_metric *m;
	pack_level *out;
	int fifo;           /* a level comes through a FIFO: read once */
	pthread_mutex_t mu; /* the stats in out, the progress */
	tl_progress pr;
	long long done;     /* DEM samples scanned (all pieces, all levels) */
} work;

/* The index's entry for a level, from its vertex map's header. */
static int
level_entry(pyramid_level *pl, int l, const vmap *v, tl_err *e)
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

	if (level_entry(&w->ix->lev[l], l, v, e) < 0)
		return -1;
	snprintf(path, sizeof path, "%s/%d", w->tmp, l);
	if (mkdir(path, 0777) != 0)
		return tl_failsys(e, "%s", path);
	return 0;
}

/* Every level begun before any work, a bad vertex map failing at once
 * (files only: a FIFO is read once, by its level's one piece). */
static int
levels_begin(work *w, tl_err *e)
{
	for (int l = 0; !w->fifo && l < w->a->nlevels; l++) {
		vmap v;
		int r = vmap_open(&v, w->a->levels[l], l, dem_georef(w->d), e);
		if (r == 0)
			r = level_begin(w, l, &v, e);
		vmap_close(&v);
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

static void
merge_stats(work *w, int l, const tiles_stats *st)
{
	tiles_stats *o = &w->out[l].st;

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
static void
level_setup(work *w, int l, vmap *v, sink *k, int threads, tiles_level *L)
{
	k->dir = w->tmp, k->attrs = v->h, k->L = &w->ix->lev[l];
	memset(L, 0, sizeof *L);
	L->level = l;
	L->size[0] = v->h->width, L->size[1] = v->h->height;
	L->displaced = k->L->displaced;
	L->m = w->m;
	L->row = read_row, L->row_ctx = v;
	L->block = write_block, L->block_ctx = k;
	L->threads = threads;
}

static int
run_piece(work *w, int l, const tiles_piece *p, int threads, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	tiles_level L;
	tiles_stats st;
	meter mt;
	vmap v;
	sink k;
	int r = -1;

	if (vmap_open(&v, w->a->levels[l], l, g, e) < 0 ||
	    (p == NULL && level_begin(w, l, &v, e) < 0))
		goto done;
	level_setup(w, l, &v, &k, threads, &L);
	mt.w = w, mt.width = g->width;
	if (p != NULL) {
		tiles_window win;
		tiles_piece_window(&L, g->width, p, &win);
		mt.width = win.d1 - win.d0;
	}
	L.progress = on_rows, L.progress_ctx = &mt;
	r = p != NULL ? tiles_run_piece(&L, p, w->d, &st, e) :
	    tiles_run(&L, w->d, &st, e);
	if (r == 0)
		merge_stats(w, l, &st);
done:
	vmap_close(&v);
	return r;
}

/* The pieces of every level, level 0 (the largest) first. */
typedef struct {
	int l;
	int whole;         /* the whole level (a FIFO), not piece p */
	tiles_piece p;
} job;

typedef struct {
	work *w;
	job *job;
	int n, threads;    /* jobs; threads per job */
	int next;          /* the next job to hand out */
	int failed;        /* the lowest job that failed, or n */
	tl_err err;        /* its error */
} queue;

/* Takes jobs in order until none is left or one has failed. Jobs are
 * handed out in order and none is abandoned, so the failure reported,
 * the lowest job's, is the same whatever the threads' timing. */
static void *
worker(void *arg)
{
	queue *q = arg;
	work *w = q->w;

	for (;;) {
		tl_err e;
		int k;
		pthread_mutex_lock(&w->mu);
		k = q->failed == q->n && q->next < q->n ? q->next++ : -1;
		pthread_mutex_unlock(&w->mu);
		if (k < 0)
			return NULL;
		if (run_piece(w, q->job[k].l, q->job[k].whole ? NULL :
		    &q->job[k].p, q->threads, &e) < 0) {
			pthread_mutex_lock(&w->mu);
			if (k < q->failed)
				q->failed = k, q->err = e;
			pthread_mutex_unlock(&w->mu);
		}
	}
}

/* The jobs on `workers` threads (this one and workers - 1 more). */
static int
run_queue(queue *q, int workers, tl_err *e)
{
	pthread_t t[PACK_MAXJOBS];
	int started = 0;

	q->failed = q->n;
	for (; started < workers - 1 && started < PACK_MAXJOBS; started++)
		if (pthread_create(&t[started], NULL, worker, q) != 0)
			break; /* fewer threads: the same blocks */
	worker(q);
	for (int k = 0; k < started; k++)
		pthread_join(t[k], NULL);
	if (q->failed < q->n) {
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
 * many, and (level_cut) the pieces themselves, allocated. */
static int
level_npieces(const pyramid_level *pl, tiles_piece *p, int max)
{
	tiles_level L = { .level = pl->level };

	L.size[0] = pl->size[0];
	return tiles_pieces(&L, PIECE_BLOCKS(pl->displaced), p, max);
}

static tiles_piece *
level_cut(const pyramid_level *pl, int *n, tl_err *e)
{
	tiles_piece *p;

	*n = level_npieces(pl, NULL, 0);
	if ((p = tl_alloc(*n, sizeof *p, e)) != NULL)
		level_npieces(pl, p, *n);
	return p;
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
 * each. */
static int
run_levels(work *w, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	int nl = w->a->nlevels, n = 0, r;
	long long total = 0;
	queue q = { .w = w };

	for (int l = 0; l < nl; l++)
		n += w->fifo ? 1 : level_npieces(&w->ix->lev[l], NULL, 0);
	if ((q.job = tl_alloc(n, sizeof *q.job, e)) == NULL)
		return -1;
	for (int l = 0; l < nl; l++) {
		tiles_level L = { .level = l };
		tiles_piece *p;
		int m;
		if (w->fifo) {
			q.job[q.n++] = (job){ .l = l, .whole = 1 };
			total += (long long)g->height * g->width;
			continue;
		}
		if ((p = level_cut(&w->ix->lev[l], &m, e)) == NULL) {
			free(q.job);
			return -1;
		}
		L.size[0] = w->ix->lev[l].size[0];
		for (int k = 0; k < m; k++) {
			tiles_window win;
			q.job[q.n++] = (job){ .l = l, .p = p[k] };
			tiles_piece_window(&L, g->width, &p[k], &win);
			total += (long long)g->height * (win.d1 - win.d0);
		}
		free(p);
	}
	assert(q.n == n);
	tl_progress_start(&w->pr, w->a->prog ? w->a->prog : "", total);
	if (w->a->prog == NULL)
		w->pr.on = 0;
	q.threads = 1;
	r = run_queue(&q, w->fifo ? n : w->a->jobs, e);
	if (r == 0)
		tl_progress_end(&w->pr);
	free(q.job);
	return r;
}

static void
report_levels(const pyramid_index *ix, pack_level *out)
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
	geo_metric m = { 0 };
	tl_outfile dir = { 0 };
	work w = { 0 };
	dem *d;
	int r = -1;

	assert(a->nlevels >= 1 && a->jobs >= 1);
	if (pack_check_dir(a->dir, a->force, e) < 0 ||
	    (d = dem_open(a->dem_path, &a->dem, e)) == NULL)
		return -1;
	memset(out, 0, (size_t)a->nlevels * sizeof *out);
	ix.version = VGIS_VERSION;
	ix.geo = *dem_georef(d);
	ix.size0[0] = ix.geo.width, ix.size0[1] = ix.geo.height;
	ix.nlevels = a->nlevels;
	w.a = a, w.d = d, w.ix = &ix, w.m = &m, w.out = out;
	w.mu = (pthread_mutex_t)PTHREAD_MUTEX_INITIALIZER;
	if ((ix.lev = tl_alloc(a->nlevels, sizeof *ix.lev, e)) == NULL ||
	    geo_metric_init(&m, &ix.geo, e) < 0 ||
	    tl_outdir_begin(&dir, a->dir, e) < 0)
		goto done;
	w.tmp = dir.tmp;
	w.fifo = fifo_inputs(a);
	/* the count after the levels, whose own faults say more */
	if (levels_begin(&w, e) < 0 || run_levels(&w, e) < 0 ||
	    pack_check_count(ix.nlevels, ix.size0[0], ix.size0[1], e) < 0 ||
	    pyramid_index_write(dir.tmp, &ix, e) < 0)
		goto done;
	report_levels(&ix, out);
	r = tl_outdir_commit(&dir, e);
done:
	if (r < 0)
		tl_outdir_abort(&dir);
	dem_close(d);
	geo_metric_free(&m);
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

/* --- a pyramid in separate processes -------------------------------------- */

/* Where a work directory keeps its finished pieces' records. */
#define PIECES ".pieces"

static int
mkdir_ok(const char *path, tl_err *e)
{
	return mkdir(path, 0777) == 0 || errno == EEXIST ? 0 :
	    tl_failsys(e, "%s", path);
}

/* Level l's index entry from its vertex map, checked against the DEM. */
static int
level_read(work *w, int l, tl_err *e)
{
	vmap v;
	int r = vmap_open(&v, w->a->levels[l], l, dem_georef(w->d), e);

	if (r == 0)
		r = level_entry(&w->ix->lev[l], l, &v, e);
	vmap_close(&v);
	return r;
}

/* 1 when (b0, b1) is one of level pl's pieces, -1 out of memory. */
static int
is_piece(const pyramid_level *pl, int b0, int b1, int *n, tl_err *e)
{
	tiles_piece *p = level_cut(pl, n, e);
	int r = 0;

	if (p == NULL)
		return -1;
	for (int k = 0; k < *n; k++)
		r |= p[k].b0 == b0 && p[k].b1 == b1;
	free(p);
	return r;
}

static void
record_path(char *buf, size_t n, const char *dir, int l, int b0, int b1)
{
	snprintf(buf, n, "%s/" PIECES "/%d-%d-%d", dir, l, b0, b1);
}

/* The piece's record, written last: its blocks' index entries and its
 * stats, exact (%.17g). */
static int
record_write(const work *w, int l, int b0, int b1, tl_err *e)
{
	const pyramid_level *pl = &w->ix->lev[l];
	const tiles_stats *st = &w->out[l].st;
	char path[4096];
	tl_outfile o;
	FILE *f;

	record_path(path, sizeof path, w->tmp, l, b0, b1);
	if (tl_out_begin(&o, path, e) < 0)
		return -1;
	if ((f = fdopen(dup(o.fd), "w")) == NULL) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	fprintf(f, "piece %d %d %d\nstats %.17g %.17g %lld\n", l, b0, b1,
	    st->max_e, st->max_base, st->samples);
	for (int bj = 0; bj < pl->blocks[1]; bj++)
		for (int bi = b0; bi < b1; bi++) {
			size_t i = (size_t)bj * pl->blocks[0] + bi;
			fprintf(f, "%d %d %.17g %.17g %.17g %.17g\n", bi, bj,
			    pl->zmin[i], pl->zmax[i], pl->base[i], pl->emax[i]);
		}
	if (fclose(f) != 0) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	return tl_out_commit(&o, e);
}

/* Reads piece (l, b0, b1)'s record from work into the index and stats. */
static int
record_read(work *w, const char *dir, int l, int b0, int b1, tl_err *e)
{
	pyramid_level *pl = &w->ix->lev[l];
	tiles_stats st = { 0 };
	char path[4096];
	int rl, r0, r1, n = 0;
	FILE *f;

	record_path(path, sizeof path, dir, l, b0, b1);
	if ((f = fopen(path, "r")) == NULL)
		return errno == ENOENT ? tl_fail(e, "%s: level %d, block "
		    "columns %d..%d: piece not made", dir, l, b0, b1 - 1) :
		    tl_failsys(e, "%s", path);
	if (fscanf(f, "piece %d %d %d stats %lf %lf %lld", &rl, &r0, &r1,
	    &st.max_e, &st.max_base, &st.samples) != 6 || rl != l ||
	    r0 != b0 || r1 != b1)
		goto bad;
	for (;;) {
		double z0, z1, b, em;
		int bi, bj, k = fscanf(f, "%d %d %lf %lf %lf %lf", &bi, &bj, &z0,
		    &z1, &b, &em);
		if (k == EOF)
			break;
		if (k != 6 || bi < b0 || bi >= b1 || bj < 0 ||
		    bj >= pl->blocks[1])
			goto bad;
		size_t i = (size_t)bj * pl->blocks[0] + bi;
		pl->zmin[i] = z0, pl->zmax[i] = z1, pl->base[i] = b;
		pl->emax[i] = em;
		n++;
	}
	if (n != (b1 - b0) * pl->blocks[1])
		goto bad;
	fclose(f);
	merge_stats(w, l, &st);
	return 0;
bad:
	fclose(f);
	return tl_fail(e, "%s: not a record of piece %d:%d:%d", path, l, b0,
	    b1);
}

/* --- pieces in parts of rows ---------------------------------------------- */

/* Where a work directory keeps its parts: each part's local errors
 * (L-B0-B1-Y0.exr), then its record (L-B0-B1-Y0). */
#define PARTS ".parts"

/* How many parts piece p of level pl runs in: enough row bands of
 * nearly equal height that none holds more than a->part_samples DEM
 * samples of the piece's window (and a row more), at most a band a row;
 * 1, the piece whole, when it holds no more or part_samples is 0. */
static int
piece_nparts(const work *w, const pyramid_level *pl, const tiles_piece *p)
{
	const georef *g = &w->ix->geo;
	tiles_level L = { .level = pl->level };
	long long n, bound = w->a->part_samples;
	tiles_window win;

	if (bound <= 0)
		return 1;
	L.size[0] = pl->size[0];
	tiles_piece_window(&L, g->width, p, &win);
	n = ((long long)(win.d1 - win.d0) * g->height + bound - 1) / bound;
	return n < 1 ? 1 : n > g->height ? g->height : (int)n;
}

/* Part k of n: DEM rows [y0, y1). */
static void
part_rows(int height, int n, int k, int *y0, int *y1)
{
	*y0 = (int)((long long)height * k / n);
	*y1 = (int)((long long)height * (k + 1) / n);
}

static void
part_path(char *buf, size_t n, const char *dir, int l, const tiles_piece *p,
    int y0, const char *ext)
{
	snprintf(buf, n, "%s/" PARTS "/%d-%d-%d-%d%s", dir, l, p->b0, p->b1, y0,
	    ext);
}

/* The local errors of a part, into its EXR. */
static int
part_out(void *ctx, int g, float *err, tl_err *e)
{
	(void)g;
	return rs_write_row(ctx, err, e);
}

/* The part's record, written last: its rows, its samples, its blocks'
 * base errors (%.17g: exact). */
static int
part_record(const char *path, int l, const tiles_piece *p, int y0, int y1,
    const double *base, int by, long long samples, tl_err *e)
{
	tl_outfile o;
	FILE *f;

	if (tl_out_begin(&o, path, e) < 0)
		return -1;
	if ((f = fdopen(dup(o.fd), "w")) == NULL) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	fprintf(f, "part %d %d %d %d %d\nsamples %lld\n", l, p->b0, p->b1, y0,
	    y1, samples);
	for (int bj = 0; bj < by; bj++)
		for (int bi = p->b0; bi < p->b1; bi++)
			fprintf(f, "%d %d %.17g\n", bi, bj,
			    base[(size_t)bj * (p->b1 - p->b0) + bi - p->b0]);
	if (fclose(f) != 0) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	return tl_out_commit(&o, e);
}

/* Reads part (l, p, y0, y1)'s record: its base errors raised into base,
 * its samples added to *samples. */
static int
part_read(const char *dir, int l, const tiles_piece *p, int y0, int y1,
    double *base, int by, long long *samples, tl_err *e)
{
	char path[4096];
	int rl, r0, r1, ry0, ry1, n = 0, nb = p->b1 - p->b0;
	long long k;
	FILE *f;

	part_path(path, sizeof path, dir, l, p, y0, "");
	if ((f = fopen(path, "r")) == NULL)
		return errno == ENOENT ? tl_fail(e, "%s: piece %d:%d:%d: its "
		    "part of DEM rows %d..%d not made", dir, l, p->b0, p->b1,
		    y0, y1 - 1) : tl_failsys(e, "%s", path);
	if (fscanf(f, "part %d %d %d %d %d samples %lld", &rl, &r0, &r1, &ry0,
	    &ry1, &k) != 6 || rl != l || r0 != p->b0 || r1 != p->b1 ||
	    ry0 != y0 || ry1 != y1)
		goto bad;
	for (;;) {
		int bi, bj, m = 0;
		double b;
		if ((m = fscanf(f, "%d %d %lf", &bi, &bj, &b)) == EOF)
			break;
		if (m != 3 || bi < p->b0 || bi >= p->b1 || bj < 0 || bj >= by)
			goto bad;
		double *o = &base[(size_t)bj * nb + bi - p->b0];
		*o = b > *o ? b : *o;
		n++;
	}
	if (n != nb * by)
		goto bad;
	fclose(f);
	*samples += k;
	return 0;
bad:
	fclose(f);
	return tl_fail(e, "%s: not a record of part %d:%d:%d:%d:%d", path, l,
	    p->b0, p->b1, y0, y1);
}

/* Part (y0, y1) of piece p of level l: the DEM's window of its rows, the
 * vertex map from the part's first row, its local errors into an EXR
 * (channel E, level columns lo.., rows g0..), then its record. */
static int
run_part(work *w, int l, const tiles_piece *p, int y0, int y1, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	char exr[4096], rec[4096];
	int by = pyramid_nblocks(w->ix->lev[l].size[1]), r = -1;
	double *base = tl_alloc((size_t)(p->b1 - p->b0) * by, sizeof *base, e);
	rs_writer *out = NULL;
	tiles_level L;
	tiles_window win;
	tiles_part q;
	tiles_stats st;
	rs_header h;
	dem *d = NULL;
	vmap v = { 0 };
	sink k;

	rs_header_init(&h, 1, 1);
	if (base == NULL || vmap_open(&v, w->a->levels[l], l, g, e) < 0)
		goto done;
	level_setup(w, l, &v, &k, w->a->jobs, &L);
	tiles_piece_window(&L, g->width, p, &win);
	tiles_part_window(&L, p, y0, y1, &q);
	rs_header_init(&h, q.hi - q.lo, q.g1 - q.g0);
	part_path(exr, sizeof exr, w->tmp, l, p, y0, ".exr");
	part_path(rec, sizeof rec, w->tmp, l, p, y0, "");
	if ((d = dem_open_window(w->a->dem_path, &w->a->dem, (int)win.d0,
	    (int)win.d1, y0, y1, e)) == NULL ||
	    rs_add_channel(&h, "E", e) < 0 ||
	    rs_set_int(&h, RS_ATTR_X0, q.lo, e) < 0 ||
	    (out = rs_create(exr, &h, RS_ZIP, e)) == NULL)
		goto done;
	if (tiles_run_part(&L, p, &q, d, part_out, out, base, &st, e) < 0)
		goto done;
	r = rs_finish(out, e);
	out = NULL;
	if (r == 0)
		r = part_record(rec, l, p, y0, y1, base, by, st.samples, e);
done:
	rs_abort(out);
	rs_header_free(&h);
	dem_close(d);
	vmap_close(&v);
	free(base);
	return r;
}

/* A piece's parts' local errors, read back: each part's EXR opened when
 * its first row is reached, closed after its last (parts come in order
 * of rows, overlapping by about 130 level rows), the maximum taken. */
typedef struct {
	const char *dir;
	int l;
	const tiles_piece *p;
	int n;             /* parts */
	tiles_part *q;     /* their windows */
	rs_reader **r;
	int first;         /* parts before it are done with */
	float *row;
} merge;

static int
merge_open(merge *m, int k, tl_err *e)
{
	const rs_header *h;
	char path[4096];
	int x0;

	part_path(path, sizeof path, m->dir, m->l, m->p, m->q[k].y0, ".exr");
	if ((m->r[k] = rs_open(path, e)) == NULL)
		return -1;
	h = rs_header_of(m->r[k]);
	if (h->width != m->q[k].hi - m->q[k].lo ||
	    h->height != m->q[k].g1 - m->q[k].g0 || h->nch != 1 ||
	    rs_get_int(h, RS_ATTR_X0, &x0) < 0 || x0 != m->q[k].lo)
		return tl_fail(e, "%s: not the local errors of part %d:%d:%d:"
		    "%d:%d", path, m->l, m->p->b0, m->p->b1, m->q[k].y0,
		    m->q[k].y1);
	return 0;
}

static int
merge_row(void *ctx, int g, float *err, tl_err *e)
{
	merge *m = ctx;
	int n = m->q[0].hi - m->q[0].lo;

	memset(err, 0, (size_t)n * sizeof *err);
	for (; m->first < m->n && m->q[m->first].g1 <= g; m->first++) {
		rs_close(m->r[m->first]);
		m->r[m->first] = NULL;
	}
	for (int k = m->first; k < m->n && m->q[k].g0 <= g; k++) {
		if ((m->r[k] == NULL && merge_open(m, k, e) < 0) ||
		    rs_read_row(m->r[k], m->row, e) < 0)
			return -1;
		for (int i = 0; i < n; i++)
			err[i] = m->row[i] > err[i] ? m->row[i] : err[i];
	}
	return 0;
}

/* Piece p of level l from its n parts in the work directory: their
 * records' base errors and samples, their local errors merged as the
 * piece's blocks are made. */
static int
run_merged(work *w, int l, const tiles_piece *p, int n, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	int by = pyramid_nblocks(w->ix->lev[l].size[1]), r = -1;
	double *base = tl_alloc((size_t)(p->b1 - p->b0) * by, sizeof *base, e);
	merge m = { w->tmp, l, p, n, NULL, NULL, 0, NULL };
	long long samples = 0;
	tiles_level L;
	tiles_stats st;
	vmap v = { 0 };
	sink k;

	m.q = tl_alloc(n, sizeof *m.q, e);
	m.r = tl_alloc(n, sizeof *m.r, e);
	if (base == NULL || m.q == NULL || m.r == NULL ||
	    vmap_open(&v, w->a->levels[l], l, g, e) < 0)
		goto done;
	level_setup(w, l, &v, &k, w->a->jobs, &L);
	for (int i = 0; i < n; i++) {
		int y0, y1;
		part_rows(g->height, n, i, &y0, &y1);
		tiles_part_window(&L, p, y0, y1, &m.q[i]);
		if (part_read(w->tmp, l, p, y0, y1, base, by, &samples, e) < 0)
			goto done;
	}
	if ((m.row = tl_alloc(m.q[0].hi - m.q[0].lo, sizeof *m.row,
	    e)) == NULL ||
	    tiles_run_merged(&L, p, g->width, merge_row, &m, base, &st, e) < 0)
		goto done;
	st.samples = samples;
	merge_stats(w, l, &st);
	r = 0;
done:
	for (int i = 0; m.r != NULL && i < n; i++)
		rs_close(m.r[i]);
	vmap_close(&v);
	free(m.q), free(m.r), free(m.row), free(base);
	return r;
}

/* What -p, -g and -l share: the DEM's header, the index's levels from
 * the vertex maps' headers. */
static int
work_open(work *w, pyramid_index *ix, geo_metric *m, const pack_args *a,
    pack_level *out, tl_err *e)
{
	memset(w, 0, sizeof *w);
	w->a = a, w->ix = ix, w->m = m, w->out = out;
	w->mu = (pthread_mutex_t)PTHREAD_MUTEX_INITIALIZER;
	memset(out, 0, (size_t)a->nlevels * sizeof *out);
	if ((w->d = dem_open_info(a->dem_path, &a->dem, e)) == NULL)
		return -1;
	ix->version = VGIS_VERSION;
	ix->geo = *dem_georef(w->d);
	ix->size0[0] = ix->geo.width, ix->size0[1] = ix->geo.height;
	ix->nlevels = a->nlevels;
	if ((ix->lev = tl_alloc(a->nlevels, sizeof *ix->lev, e)) == NULL ||
	    geo_metric_init(m, &ix->geo, e) < 0)
		return -1;
	for (int l = 0; l < a->nlevels; l++)
		if (level_read(w, l, e) < 0)
			return -1;
	return pack_check_count(ix->nlevels, ix->size0[0], ix->size0[1], e);
}

static void
work_close(work *w, pyramid_index *ix, geo_metric *m)
{
	dem_close(w->d);
	geo_metric_free(m);
	pyramid_index_free(ix);
}

/* The DEM of a piece in a process of its own: only the columns its
 * window scans, so that a job's disk and time do not grow with the
 * DEM's width (the header, opened by work_open, is replaced). */
static int
open_window(work *w, int l, const tiles_piece *p, tl_err *e)
{
	tiles_level L = { .level = l };
	tiles_window win;
	dem *d;

	L.size[0] = w->ix->lev[l].size[0];
	tiles_piece_window(&L, dem_georef(w->d)->width, p, &win);
	if ((d = dem_open_cols(w->a->dem_path, &w->a->dem, (int)win.d0,
	    (int)win.d1, e)) == NULL)
		return -1;
	dem_close(w->d);
	w->d = d;
	return 0;
}

/* The work directory's subdirectory name, made if missing, what killed
 * runs left there swept. */
static int
work_subdir(const char *dir, const char *name, tl_err *e)
{
	char path[4096];

	snprintf(path, sizeof path, "%s/%s", dir, name);
	if (mkdir_ok(path, e) < 0)
		return -1;
	tl_out_sweep_dir(path);
	return 0;
}

/* Which job (l, b0, b1) with rows (y0, y1) is (y1 0: the piece): one
 * of pack_list's, checked. Returns the piece's parts, 1 when whole. */
static int
job_check(work *w, int l, const tiles_piece *p, int y0, int y1, tl_err *e)
{
	int k, n, np;

	if ((k = is_piece(&w->ix->lev[l], p->b0, p->b1, &n, e)) <= 0)
		return k == 0 ? tl_fail(e, "piece %d:%d:%d: not one of level "
		    "%d's %d pieces", l, p->b0, p->b1, l, n) : -1;
	np = piece_nparts(w, &w->ix->lev[l], p);
	if (y1 == 0)
		return np;
	for (k = 0; np > 1 && k < np; k++) {
		int a, b;
		part_rows(w->ix->geo.height, np, k, &a, &b);
		if (a == y0 && b == y1)
			return np;
	}
	return tl_fail(e, "part %d:%d:%d:%d:%d: not one of the piece's %d "
	    "parts%s", l, p->b0, p->b1, y0, y1, np, np == 1 ?
	    " (it is made whole: -b sets how many samples a part holds)" : "");
}

int
pack_piece(const pack_args *a, int l, int b0, int b1, int y0, int y1,
    tl_err *e)
{
	pack_level *out = tl_alloc(a->nlevels, sizeof *out, e);
	tiles_piece p = { b0, b1 };
	pyramid_index ix = { 0 };
	geo_metric m = { 0 };
	work w = { 0 };
	int r = -1, np;
	char sub[16];

	if (out == NULL)
		return -1;
	if (l < 0 || l >= a->nlevels) {
		tl_fail(e, "piece %d:%d:%d: no level %d (levels 0..%d)", l, b0,
		    b1, l, a->nlevels - 1);
		goto done;
	}
	if (work_open(&w, &ix, &m, a, out, e) < 0 ||
	    (np = job_check(&w, l, &p, y0, y1, e)) < 0)
		goto done;
	w.tmp = a->dir;
	if (mkdir_ok(a->dir, e) < 0)
		goto done;
	if (y1 > 0) { /* a part: its errors, then its record */
		r = work_subdir(a->dir, PARTS, e) < 0 ? -1 :
		    run_part(&w, l, &p, y0, y1, e);
		goto done;
	}
	snprintf(sub, sizeof sub, "%d", l);
	if (work_subdir(a->dir, sub, e) < 0 ||
	    work_subdir(a->dir, PIECES, e) < 0)
		goto done;
	/* whole: only the columns its window scans, so that a job's disk
	 * and time do not grow with the DEM's width */
	if (np > 1 ? run_merged(&w, l, &p, np, e) == 0 :
	    open_window(&w, l, &p, e) == 0 &&
	    run_piece(&w, l, &p, a->jobs, e) == 0)
		r = record_write(&w, l, b0, b1, e);
done:
	if (w.a != NULL)
		work_close(&w, &ix, &m);
	free(out);
	return r;
}

int
pack_gather(const pack_args *a, const char *dir, pack_level *out, tl_err *e)
{
	pyramid_index ix = { 0 };
	geo_metric m = { 0 };
	char path[4096];
	work w = { 0 };
	int r = -1;

	if (pack_check_dir(a->dir, a->force, e) < 0 ||
	    work_open(&w, &ix, &m, a, out, e) < 0)
		goto done;
	for (int l = 0; l < a->nlevels; l++) {
		tiles_piece *p;
		int n;
		if ((p = level_cut(&ix.lev[l], &n, e)) == NULL)
			goto done;
		for (int k = 0; k < n; k++)
			if (record_read(&w, dir, l, p[k].b0, p[k].b1, e) < 0) {
				free(p);
				goto done;
			}
		free(p);
	}
	snprintf(path, sizeof path, "%s/" PIECES, dir);
	tl_rmtree(path);
	snprintf(path, sizeof path, "%s/" PARTS, dir);
	tl_rmtree(path);
	if (pyramid_index_write(dir, &ix, e) < 0 ||
	    tl_dir_install(dir, a->dir, e) < 0)
		goto done;
	report_levels(&ix, out);
	r = 0;
done:
	if (w.a != NULL)
		work_close(&w, &ix, &m);
	return r;
}

int
pack_list(const pack_args *a, FILE *f, tl_err *e)
{
	pack_level *out = tl_alloc(a->nlevels, sizeof *out, e);
	pyramid_index ix = { 0 };
	geo_metric m = { 0 };
	work w = { 0 };
	int r = -1;

	if (out == NULL || work_open(&w, &ix, &m, a, out, e) < 0)
		goto done;
	for (int l = 0; l < a->nlevels; l++) {
		tiles_piece *p;
		int n;
		if ((p = level_cut(&ix.lev[l], &n, e)) == NULL)
			goto done;
		for (int k = 0; k < n; k++) {
			int np = piece_nparts(&w, &ix.lev[l], &p[k]);
			for (int i = 0; np > 1 && i < np; i++) {
				int y0, y1;
				part_rows(ix.geo.height, np, i, &y0, &y1);
				fprintf(f, "%d:%d:%d:%d:%d\n", l, p[k].b0,
				    p[k].b1, y0, y1);
			}
			fprintf(f, "%d:%d:%d\n", l, p[k].b0, p[k].b1);
		}
		free(p);
	}
	r = fflush(f) == 0 ? 0 : tl_failsys(e, "stdout");
done:
	if (w.a != NULL)
		work_close(&w, &ix, &m);
	free(out);
	return r;
}
