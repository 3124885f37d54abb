/* gl_render.h - the terrain renderer: draws the cache's blocks at their
 * tolerances, in a style (gl_style.h), on the current context.
 *
 * Positions are drawn relative to the eye: each block's floats are
 * relative to its own origin (mesh.h) and a per-block translation,
 * origin - eye, is computed in double, so a large world does not jitter
 * in float32. A block's GPU buffers and triangles are the renderer's
 * state of it in the cache (cache_block_set_user), freed by
 * gl_render_release when the cache lets the block go. */
#ifndef TL_GL_RENDER_H
#define TL_GL_RENDER_H

#include "play/cache.h"
#include "play/camera.h"
#include "play/gl_style.h"

typedef struct gl_render gl_render;

typedef struct {
	long blocks, tris, skirts;
	long per_level[32];
	int levels;          /* 1 + the highest level drawn */
} gl_render_stats;

/* Shaders and state for one world; a context must be current. */
gl_render *gl_render_new(const world *w, tl_err *e);
void gl_render_free(gl_render *r);
/* The cache's release function (ctx: the renderer): frees a block's GPU
 * buffers and triangles. */
void gl_render_release(void *user, void *ctx);

/* Starts a frame: viewport, clear, camera, style; zeroes the stats. */
void gl_render_begin(gl_render *r, const camera *c, const gl_style *s,
    gl_render_stats *st);
/* Draws a block of the cache at tolerance tau (metres; < 0 the full
 * grid): its vertex buffer is made on first use, its triangles rebuilt
 * when tau moves to another step (tau is rounded down to a quarter
 * power of two, so the tolerance is kept and a moving camera does not
 * rebuild every frame) or the skirts are toggled. 1 when drawn, 0 when
 * the cache had no room for its triangles (nothing drawn this frame), -1
 * on error. */
int gl_render_draw(gl_render *r, cache *k, cblock *cb, double tau,
    tl_err *e);

/* The height colour map (viridis over level 0's height range), 0..255. */
void gl_render_height_rgb(const gl_render *r, double z, unsigned char rgb[3]);

#endif
