/* scene.h - what tileplay's modes share: a pyramid's world, a GL context
 * (a window or headless), the renderer, the text, the block cache, a
 * camera, and the frame's choice of blocks. The modes (shot.h, fly.h,
 * window.h) are the program's work functions: they print its output and
 * its warnings, prefixed with the program's name. */
#ifndef TL_SCENE_H
#define TL_SCENE_H

#include <stdio.h>

#include "play/gl_ctx.h"
#include "play/gl_render.h"
#include "play/gl_text.h"
#include "play/lod.h"

/* The options every mode takes: the view options of tileplay(1). */
typedef struct {
	const char *prog;        /* for messages */
	const char *dir;         /* the pyramid */
	int width, height;       /* the frame, pixels */
	const char *view;        /* a named view (camera.h) ... */
	int has_eye, has_target; /* ... unless these are given */
	double eye[3], target[3];
	double pixels;           /* the screen-space tolerance */
	double cache_mb;         /* the cache's cap */
	gl_style style;
} scene_opts;

/* The defaults: oblique, 1 px, 256 MB, 1024x768 (the window's). */
void scene_opts_init(scene_opts *o, const char *prog);

typedef struct {
	world w;
	gl_ctx *g;
	gl_render *r;
	gl_text *text;
	cache *k;
	camera cam;
	lod_block *sel;
	int maxsel, nsel;
	long misses;       /* blocks the last choice asked for in vain */
	gl_render_stats st;
} scene;

/* Seconds on a monotonic clock. */
double scene_clock(void);

/* The world, a GL context (headless or a window), the renderer, the text
 * and the cache (whose evictions free GPU buffers); the camera sized to
 * the frame but not placed. */
int scene_open(scene *sc, const scene_opts *o, int headless, tl_err *e);
void scene_close(scene *sc);
/* The camera of the options: --eye/--target (the one not given from the
 * oblique view), else the named view. */
int scene_start_camera(scene *sc, const scene_opts *o, tl_err *e);

/* A frame's blocks: takes in the loaded blocks, then chooses, asking the
 * cache for every block the choice looks at (the missing ones load;
 * sc->misses counts them). */
void scene_choose(scene *sc, double pixels);
/* Chooses until every block the choice wants is in memory (or no more
 * can come: a cap too small, a broken block), for a complete picture. */
int scene_settle(scene *sc, double pixels, tl_err *e);
/* Starts a frame and draws the chosen blocks. */
int scene_draw(scene *sc, const gl_style *s, tl_err *e);
/* Text over the frame drawn. */
void scene_text(scene *sc, const char *text);
/* -1 with the cache's first load error, else 0. */
int scene_cache_error(scene *sc, tl_err *e);

/* "level 0: n, level 1: m" of the blocks drawn. */
void scene_levels_text(const gl_render_stats *st, char *buf, size_t n);
/* The --stats line: blocks, triangles, first frame, cache, camera. */
void scene_print_stats(scene *sc, FILE *f, double first);

#endif
