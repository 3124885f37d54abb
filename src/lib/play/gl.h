/* gl.h - tileplay's OpenGL: a context (a GLFW window, or headless through
 * EGL into an offscreen framebuffer) and the terrain renderer that draws
 * the cache's blocks at their tolerances.
 *
 * Everything here runs on the thread that made the context current (the
 * render thread), the cache's release callback included. Positions are
 * drawn relative to the eye: each block's floats are relative to its own
 * origin (mesh.h) and a per-block translation, origin - eye, is computed
 * in double, so a large world does not jitter in float32. */
#ifndef TL_GL_H
#define TL_GL_H

#include "play/cache.h"

typedef struct gl_ctx gl_ctx;

/* EGL on Mesa's surfaceless platform (no display; llvmpipe without a
 * GPU), an OpenGL 3.3 core context and a w x h framebuffer object (RGBA8,
 * DEPTH24) to draw into. */
gl_ctx *gl_open_headless(int w, int h, tl_err *e);
/* A GLFW window of w x h screen units with a 3.3 core context. */
gl_ctx *gl_open_window(int w, int h, const char *title, tl_err *e);
void gl_close(gl_ctx *g);
/* The GLFWwindow, or NULL when headless. */
void *gl_window(gl_ctx *g);
/* The framebuffer's size in pixels (a window's may change). */
void gl_size(gl_ctx *g, int *w, int *h);
/* Waits for the drawing, then shows it (a window) or does nothing. */
void gl_present(gl_ctx *g);
/* The drawn framebuffer as w x h top-down RGB rows (w * h * 3 bytes),
 * before gl_present. */
void gl_read_rgb(gl_ctx *g, unsigned char *rgb);

enum gl_colour { GL_BY_HEIGHT, GL_BY_LEVEL, GL_BY_ERROR, GL_NCOLOUR };

typedef struct {
	enum gl_colour colour;
	int light;         /* directional light + ambient; 0: flat colours */
	int wire;          /* triangle edges over the surface */
	int skirts;        /* draw the skirts (mesh.h) */
	float background[3]; /* clear colour, 0..1 */
} gl_style;

void gl_style_init(gl_style *s);
const char *gl_colour_name(enum gl_colour c);
int gl_colour_parse(const char *name, enum gl_colour *c);

typedef struct gl_render gl_render;

typedef struct {
	long blocks, tris, skirts;
	long per_level[32];
	int levels;          /* 1 + the highest level drawn */
} gl_frame_stats;

/* Shaders and state for one world; the context must be current. */
gl_render *gl_render_new(const world *w, tl_err *e);
void gl_render_free(gl_render *r);
/* The cache's release function: frees a block's GPU buffers. */
void gl_release(cblock *cb, void *r);

/* Starts a frame: viewport, clear, camera, style; zeroes the stats. */
void gl_begin(gl_render *r, const camera *c, const gl_style *s,
    gl_frame_stats *st);
/* Draws a block of the cache at tolerance tau (metres; < 0 the full
 * grid): its vertex buffer is made on first use, its triangles rebuilt
 * when tau moves to another step (tau is rounded down to a quarter
 * power of two, so the tolerance is kept and a moving camera does not
 * rebuild every frame) or the skirts are toggled. 1 when drawn, 0 when
 * the cache had no room for its triangles (nothing drawn this frame), -1
 * on error. */
int gl_draw(gl_render *r, cache *k, cblock *cb, double tau, tl_err *e);
/* Lines of text at the top left of the frame, on a dark band. */
void gl_text(gl_render *r, const char *text);

/* The height colour map (viridis over level 0's height range), 0..255. */
void gl_height_rgb(const gl_render *r, double z, unsigned char rgb[3]);

/* Writes w x h top-down RGB rows as an image (format from the name's
 * extension, e.g. .png) through the OpenImageIO plugin, atomically. */
int gl_write_image(const char *path, int w, int h, const unsigned char *rgb,
    tl_err *e);

#endif
