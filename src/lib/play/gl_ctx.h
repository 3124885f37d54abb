/* gl_ctx.h - an OpenGL 3.3 core context: a GLFW window, or headless
 * through EGL into an offscreen framebuffer; and its shader programs.
 *
 * Everything drawn with it runs on the thread that made it current (the
 * render thread). */
#ifndef TL_GL_CTX_H
#define TL_GL_CTX_H

#include <epoxy/gl.h>

#include "base/util.h"

typedef struct gl_ctx gl_ctx;

/* EGL on Mesa's surfaceless platform (no display; llvmpipe without a
 * GPU), an OpenGL 3.3 core context and a w x h framebuffer object (RGBA8,
 * DEPTH24) to draw into. */
gl_ctx *gl_ctx_headless(int w, int h, tl_err *e);
/* A GLFW window of w x h screen units with a 3.3 core context. */
gl_ctx *gl_ctx_window(int w, int h, const char *title, tl_err *e);
void gl_ctx_close(gl_ctx *g);
/* The GLFWwindow, or NULL when headless. */
void *gl_ctx_glfw(gl_ctx *g);
/* The framebuffer's size in pixels (a window's may change). */
void gl_ctx_size(gl_ctx *g, int *w, int *h);
/* Waits for the drawing, then shows it (a window) or does nothing. */
void gl_ctx_present(gl_ctx *g);
/* The drawn framebuffer as w x h top-down RGB rows (w * h * 3 bytes),
 * before gl_ctx_present. */
void gl_ctx_read_rgb(gl_ctx *g, unsigned char *rgb);

/* A program linked from a vertex and a fragment shader's sources; 0 on
 * error (e says the compiler's why). The context must be current. */
GLuint gl_ctx_program(const char *vs, const char *fs, tl_err *e);

#endif
