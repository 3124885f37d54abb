/* cache.h - blocks loaded on demand, off the render thread, into a cache
 * with a hard memory cap.
 *
 * The render thread asks for blocks each frame; a block not in memory is
 * queued for a loader thread, which reads it (pyramid_block_read) and builds
 * its vertices (mesh_verts_build) and hands it back. A block's bytes (its
 * data, vertices, and what the renderer keeps with it) count against the
 * cap. The loader only loads a block when it fits: first by evicting
 * blocks not used in the current frame, least recently used first; if it
 * still does not fit it is dropped from the queue and asked again later,
 * and the view draws a coarser ancestor meanwhile. So the cache never
 * holds more than its cap, whatever the flight.
 *
 * A block (cblock) is the cache's: the renderer reads it through the
 * accessors and hangs its own state on it (cache_block_set_user), which
 * the cache hands back to the renderer's release function to free when
 * the block goes. Each side frees what it allocated. */
#ifndef TL_CACHE_H
#define TL_CACHE_H

#include <stddef.h>

#include "play/mesh.h"

typedef struct cache cache;
typedef struct cblock cblock;

/* release(user, ctx) frees the renderer's state of a block that goes
 * (its GPU buffers, triangles), on the render thread; may be NULL when
 * no block is ever given any. */
typedef void (*cache_release_fn)(void *user, void *ctx);

cache *cache_new(const world *w, size_t cap, cache_release_fn release,
    void *ctx, tl_err *e);
void cache_free(cache *c);

/* Render thread. The block when it is in memory (marked used in this
 * frame); else NULL, and it is queued for loading. */
cblock *cache_get(cache *c, int level, int bi, int bj);
/* Starts a frame: takes in the blocks the loader finished. */
void cache_frame(cache *c);
/* Blocks until the loader's queue is empty (headless shots). */
void cache_wait(cache *c);

/* The block as read (its level, bi, bj, heights, errors). */
const pyramid_block *cache_block_data(const cblock *b);
/* Its vertices; pos, nrm and val are NULL after cache_block_verts_done
 * (origin stays). */
const mesh_verts *cache_block_verts(const cblock *b);
/* The renderer has its own copy of the vertices (GPU buffers): the
 * cache frees its one. They stay counted once in the cap. */
void cache_block_verts_done(cblock *b);
/* The renderer's state of the block: NULL until set. */
void *cache_block_user(const cblock *b);
void cache_block_set_user(cblock *b, void *user);
/* The renderer's state of b now takes `bytes`: counted in the cap,
 * evicting other blocks if need be. Returns 1 when they fit; 0 when
 * nothing more can go: then they are counted as 0 and the renderer must
 * free them (and draw nothing of the block this frame). */
int cache_account(cache *c, cblock *b, size_t bytes);

typedef struct {
	size_t cap, bytes, peak; /* now and highest ever */
	long blocks, loads, evictions, refused;
	char error[1024];        /* the first load error, "" if none */
} cache_stats;
void cache_get_stats(cache *c, cache_stats *s);

#endif
