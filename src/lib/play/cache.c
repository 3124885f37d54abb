/* cache.c - the block cache and its loader thread (see cache.h).
 *
 * Budget: bytes (blocks in memory) + reserved (blocks being loaded) never
 * passes cap. The loader reserves a block's bytes before reading it; it
 * never evicts (GPU buffers belong to the render thread): cache_frame
 * does, when the next queued block does not fit. */
#include "play/cache.h"

#include <assert.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define QMAX 1024 /* queued loads; more are asked again next frame */
#define FMAX 256  /* blocks that failed to load, never asked again */
/* A block's bookkeeping (this struct, the renderer's), a fixed count so
 * that the cap's arithmetic and the byte counts printed do not move with
 * struct layouts. */
#define BOOKKEEPING 224

struct cblock {
	int level, bi, bj;
	pyramid_block blk;
	mesh_verts v;
	size_t bytes;   /* block + vertices + the renderer's, in the cap */
	void *user;     /* the renderer's, freed by the release function */
	long used;      /* last frame it was asked for */
	cblock *next;   /* the loader's finished list */
};

typedef struct {
	int level, bi, bj;
} key;

struct cache {
	const world *w;
	size_t cap;
	cache_release_fn release;
	void *ctx;
	/* render thread only: */
	cblock **table; /* open addressing by key, tsize slots */
	size_t tsize, count;
	long frame;
	/* shared, under mu: */
	pthread_mutex_t mu;
	pthread_cond_t work, idle;
	key queue[QMAX];
	int qhead, qlen;
	int busy, quit;
	key loading;    /* the block the loader reads while busy */
	cblock *done;   /* loaded, not yet in the table */
	key failed[FMAX];
	int nfailed;
	size_t bytes, reserved, peak;
	size_t short_of; /* the largest load refused for room since a frame */
	long loads, evictions, refused;
	char error[1024];
	pthread_t thread;
};

static size_t
fixed_bytes(int displaced)
{
	return BOOKKEEPING + (size_t)PYRAMID_N * sizeof(float) *
	    (displaced ? 4 : 2) + (size_t)MESH_NV * sizeof(float) * 8;
}

static size_t
slot_of(const cache *c, int l, int bi, int bj)
{
	size_t h = (size_t)l * 73856093u ^ (size_t)bi * 19349663u ^
	    (size_t)bj * 83492791u;

	assert((c->tsize & (c->tsize - 1)) == 0); /* masks, not modulo */
	return h & (c->tsize - 1);
}

static cblock **
find(cache *c, int l, int bi, int bj)
{
	size_t s = slot_of(c, l, bi, bj);

	assert(c->count < c->tsize); /* a free slot ends every probe */
	for (;; s = (s + 1) & (c->tsize - 1)) {
		cblock *b = c->table[s];
		if (b == NULL || (b->level == l && b->bi == bi && b->bj == bj))
			return &c->table[s];
	}
}

/* Removes slot s, re-inserting the run after it (linear probing). */
static void
unlink_slot(cache *c, size_t s)
{
	assert(c->table[s] != NULL);
	c->table[s] = NULL;
	for (s = (s + 1) & (c->tsize - 1); c->table[s] != NULL;
	    s = (s + 1) & (c->tsize - 1)) {
		cblock *b = c->table[s];
		c->table[s] = NULL;
		*find(c, b->level, b->bi, b->bj) = b;
	}
}

/* The cache's part of a block; the renderer's went to release. */
static void
block_free(cblock *b)
{
	pyramid_block_free(&b->blk);
	mesh_verts_free(&b->v);
	free(b);
}

static void
release_user(cache *c, cblock *b)
{
	if (b->user != NULL) {
		assert(c->release != NULL);
		c->release(b->user, c->ctx);
		b->user = NULL;
	}
}

/* --- the loader ------------------------------------------------------ */

static cblock *
load(const world *w, key k, char *err, size_t n)
{
	cblock *b;
	tl_err e;
	const pyramid_level *L = &w->ix.lev[k.level];

	if ((b = calloc(1, sizeof *b)) == NULL) {
		snprintf(err, n, "out of memory");
		return NULL;
	}
	b->level = k.level, b->bi = k.bi, b->bj = k.bj;
	if (pyramid_block_alloc(&b->blk, L->displaced, &e) < 0)
		goto fail;
	b->blk.level = k.level, b->blk.bi = k.bi, b->blk.bj = k.bj;
	if (pyramid_block_load(w->dir, &w->ix, &b->blk, &e) < 0 ||
	    mesh_verts_build(w, &b->blk, &b->v, &e) < 0)
		goto fail;
	b->bytes = fixed_bytes(L->displaced);
	return b;
fail:
	snprintf(err, n, "%s", e.msg);
	block_free(b);
	return NULL;
}

static void *
loader(void *arg)
{
	cache *c = arg;

	pthread_mutex_lock(&c->mu);
	for (;;) {
		key k;
		size_t need;
		cblock *b;
		char err[1024];
		while (c->qlen == 0 && !c->quit)
			pthread_cond_wait(&c->work, &c->mu);
		if (c->quit)
			break;
		k = c->queue[c->qhead];
		c->qhead = (c->qhead + 1) % QMAX, c->qlen--;
		need = fixed_bytes(c->w->ix.lev[k.level].displaced);
		if (c->bytes + c->reserved + need > c->cap) {
			/* asked again next frame, after cache_frame made room */
			c->refused++;
			if (need > c->short_of)
				c->short_of = need;
			if (c->qlen == 0)
				pthread_cond_broadcast(&c->idle);
			continue;
		}
		c->reserved += need, c->busy = 1, c->loading = k;
		pthread_mutex_unlock(&c->mu);
		b = load(c->w, k, err, sizeof err);
		pthread_mutex_lock(&c->mu);
		c->reserved -= need, c->busy = 0;
		if (b != NULL) {
			c->bytes += b->bytes;
			if (c->bytes > c->peak)
				c->peak = c->bytes;
			b->next = c->done, c->done = b;
			c->loads++;
		} else {
			if (c->error[0] == '\0')
				snprintf(c->error, sizeof c->error, "%s", err);
			if (c->nfailed < FMAX)
				c->failed[c->nfailed++] = k;
		}
		if (c->qlen == 0)
			pthread_cond_broadcast(&c->idle);
	}
	pthread_mutex_unlock(&c->mu);
	return NULL;
}

/* --- the render thread --------------------------------------------- */

cache *
cache_new(const world *w, size_t cap, cache_release_fn release, void *ctx,
    tl_err *e)
{
	cache *c = tl_alloc(1, sizeof *c, e);

	if (c == NULL)
		return NULL;
	c->w = w, c->cap = cap, c->release = release, c->ctx = ctx;
	c->tsize = 1024;
	if ((c->table = tl_alloc(c->tsize, sizeof *c->table, e)) == NULL) {
		free(c);
		return NULL;
	}
	pthread_mutex_init(&c->mu, NULL);
	pthread_cond_init(&c->work, NULL);
	pthread_cond_init(&c->idle, NULL);
	if (pthread_create(&c->thread, NULL, loader, c) != 0) {
		tl_fail(e, "cannot start the block loader thread");
		free(c->table), free(c);
		return NULL;
	}
	return c;
}

static void
drop(cache *c, size_t s)
{
	cblock *b = c->table[s];

	unlink_slot(c, s);
	c->count--;
	release_user(c, b);
	pthread_mutex_lock(&c->mu);
	c->bytes -= b->bytes;
	c->evictions++;
	pthread_mutex_unlock(&c->mu);
	block_free(b);
}

void
cache_free(cache *c)
{
	cblock *b, *n;

	if (c == NULL)
		return;
	pthread_mutex_lock(&c->mu);
	c->quit = 1;
	pthread_cond_broadcast(&c->work);
	pthread_mutex_unlock(&c->mu);
	pthread_join(c->thread, NULL);
	for (size_t s = 0; s < c->tsize; s++)
		if (c->table[s] != NULL) {
			release_user(c, c->table[s]);
			block_free(c->table[s]);
		}
	for (b = c->done; b != NULL; b = n)
		n = b->next, block_free(b);
	pthread_mutex_destroy(&c->mu);
	pthread_cond_destroy(&c->work);
	pthread_cond_destroy(&c->idle);
	free(c->table);
	free(c);
}

/* Evicts the least recently used block not used since frame `keep`;
 * 0 when there is none. */
static int
evict_one(cache *c, long keep)
{
	size_t best = c->tsize;

	for (size_t s = 0; s < c->tsize; s++) {
		cblock *b = c->table[s];
		if (b != NULL && b->used < keep &&
		    (best == c->tsize || b->used < c->table[best]->used))
			best = s;
	}
	if (best == c->tsize)
		return 0;
	drop(c, best);
	return 1;
}

/* Room for `need` more bytes, evicting blocks not used since `keep`. */
static int
make_room(cache *c, size_t need, long keep)
{
	for (;;) {
		int fits;
		pthread_mutex_lock(&c->mu);
		fits = c->bytes + c->reserved + need <= c->cap;
		pthread_mutex_unlock(&c->mu);
		if (fits)
			return 1;
		if (!evict_one(c, keep))
			return 0;
	}
}

static void
grow(cache *c)
{
	cblock **old = c->table;
	size_t n = c->tsize;

	if (2 * (c->count + 1) < c->tsize)
		return;
	if ((c->table = calloc(2 * n, sizeof *c->table)) == NULL) {
		c->table = old;
		return;
	}
	c->tsize = 2 * n;
	for (size_t s = 0; s < n; s++)
		if (old[s] != NULL)
			*find(c, old[s]->level, old[s]->bi, old[s]->bj) = old[s];
	free(old);
}

void
cache_frame(cache *c)
{
	cblock *b, *n;
	size_t next = 0;

	c->frame++;
	pthread_mutex_lock(&c->mu);
	b = c->done, c->done = NULL;
	if (c->qlen > 0) {
		key k = c->queue[c->qhead];
		next = fixed_bytes(c->w->ix.lev[k.level].displaced);
	}
	if (c->short_of > next)
		next = c->short_of;
	c->short_of = 0;
	pthread_mutex_unlock(&c->mu);
	for (; b != NULL; b = n) {
		cblock **at;
		n = b->next;
		grow(c);
		at = find(c, b->level, b->bi, b->bj);
		if (*at != NULL) { /* cannot happen (cache_get checks); no leak */
			pthread_mutex_lock(&c->mu);
			c->bytes -= b->bytes;
			pthread_mutex_unlock(&c->mu);
			block_free(b);
			continue;
		}
		b->used = c->frame;
		*at = b;
		c->count++;
	}
	/* the loader waits for room: make it from blocks the last frame
	 * did not use */
	if (next > 0)
		make_room(c, next, c->frame - 1);
}

cblock *
cache_get(cache *c, int level, int bi, int bj)
{
	cblock *b;

	assert(world_block_exists(c->w, level, bi, bj));
	b = *find(c, level, bi, bj);
	if (b != NULL) {
		b->used = c->frame;
		return b;
	}
	pthread_mutex_lock(&c->mu);
	for (int q = 0; q < c->nfailed; q++)
		if (c->failed[q].level == level && c->failed[q].bi == bi &&
		    c->failed[q].bj == bj)
			goto queued; /* a broken block: not again */
	if (c->busy && c->loading.level == level && c->loading.bi == bi &&
	    c->loading.bj == bj)
		goto queued; /* being read right now */
	for (int q = 0; q < c->qlen; q++) {
		key *k = &c->queue[(c->qhead + q) % QMAX];
		if (k->level == level && k->bi == bi && k->bj == bj)
			goto queued;
	}
	for (cblock *d = c->done; d != NULL; d = d->next)
		if (d->level == level && d->bi == bi && d->bj == bj)
			goto queued;
	if (c->qlen < QMAX) {
		c->queue[(c->qhead + c->qlen) % QMAX] = (key){ level, bi, bj };
		c->qlen++;
		pthread_cond_signal(&c->work);
	}
queued:
	pthread_mutex_unlock(&c->mu);
	return NULL;
}

int
cache_account(cache *c, cblock *b, size_t bytes)
{
	size_t fixed = fixed_bytes(b->blk.displaced), want = fixed + bytes;
	int kept = 1;

	assert(*find(c, b->level, b->bi, b->bj) == b);
	if (want > b->bytes && !make_room(c, want - b->bytes, c->frame)) {
		/* no room even for these: the renderer frees them */
		want = fixed;
		kept = 0;
	}
	pthread_mutex_lock(&c->mu);
	c->bytes = c->bytes - b->bytes + want;
	if (c->bytes > c->peak)
		c->peak = c->bytes;
	pthread_mutex_unlock(&c->mu);
	b->bytes = want;
	return kept;
}

const pyramid_block *
cache_block_data(const cblock *b)
{
	return &b->blk;
}

const mesh_verts *
cache_block_verts(const cblock *b)
{
	return &b->v;
}

void
cache_block_verts_done(cblock *b)
{
	mesh_verts_free(&b->v);
}

void *
cache_block_user(const cblock *b)
{
	return b->user;
}

void
cache_block_set_user(cblock *b, void *user)
{
	b->user = user;
}

void
cache_wait(cache *c)
{
	pthread_mutex_lock(&c->mu);
	while (c->qlen > 0 || c->busy)
		pthread_cond_wait(&c->idle, &c->mu);
	pthread_mutex_unlock(&c->mu);
}

void
cache_get_stats(cache *c, cache_stats *s)
{
	pthread_mutex_lock(&c->mu);
	s->cap = c->cap, s->bytes = c->bytes, s->peak = c->peak;
	s->loads = c->loads, s->evictions = c->evictions;
	s->refused = c->refused;
	snprintf(s->error, sizeof s->error, "%s", c->error);
	pthread_mutex_unlock(&c->mu);
	s->blocks = (long)c->count;
}
