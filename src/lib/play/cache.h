/* cache.h - blocks loaded on demand, off the render thread, into a cache
 * with a hard memory cap.
 *
 * The render thread asks for blocks each frame; a block not in memory is
 * queued for a loader thread, which reads it (pyramid_block_read) and builds
 * its vertices (mesh_verts_build) and hands it back. A block's bytes (its
 * data, vertices, and the triangles the renderer keeps with it) count
 * against the cap. The loader only loads a block when it fits: first by
 * evicting blocks not used in the current frame, least recently used
 * first; if it still does not fit it is dropped from the queue and asked
 * again later, and the view draws a coarser ancestor meanwhile. So the
 * cache never holds more than its cap, whatever the flight. */
#ifndef TL_CACHE_H
#define TL_CACHE_H

#include <stddef.h>

#include "play/mesh.h"

typedef struct cblock cblock;
struct cblock {
	int level, bi, bj;
	pyramid_block blk;
	mesh_verts v;
	size_t bytes;   /* block + vertices + tris.cap, counted in the cap */
	/* the renderer's own, kept with the block: */
	mesh_tris tris; /* triangles at tau (rebuilt when tau changes) */
	double tau;     /* the tau tris was built for; NAN: none yet */
	void *gpu;      /* GPU buffers, or NULL */
	/* the cache's own: */
	long used;      /* last frame it was asked for */
	cblock *next;
};

typedef struct cache cache;

/* release(cb, ctx) frees the renderer's part of an evicted block (its GPU
 * buffers) on the render thread; may be NULL. */
typedef void (*cache_release_fn)(cblock *cb, void *ctx);

cache *cache_new(const world *w, size_t cap, cache_release_fn release,
    void *ctx, tl_err *e);
void cache_free(cache *c);

/* Render thread. The block when it is in memory (marked used in this
 * frame); else NULL, and it is queued for loading. */
cblock *cache_get(cache *c, int level, int bi, int bj);
/* The renderer changed cb->tris: recount cb->bytes (evicting others if
 * that would pass the cap; if nothing can go, the triangles are freed
 * and 0 returned: draw nothing of it this frame). Returns 1 when kept. */
int cache_account(cache *c, cblock *cb);
/* Starts a frame: takes in the blocks the loader finished. */
void cache_frame(cache *c);
/* Blocks until the loader's queue is empty (headless shots). */
void cache_wait(cache *c);

typedef struct {
	size_t cap, bytes, peak; /* now and highest ever */
	long blocks, loads, evictions, refused;
	char error[1024];        /* the first load error, "" if none */
} cache_stats;
void cache_get_stats(cache *c, cache_stats *s);

#endif
