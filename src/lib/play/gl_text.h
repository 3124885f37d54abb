/* gl_text.h - lines of text over a frame (the window's readout, a shot's
 * with --readout): stb_easy_font's glyph quads on a dark band. */
#ifndef TL_GL_TEXT_H
#define TL_GL_TEXT_H

#include "base/util.h"

typedef struct gl_text gl_text;

/* Its program and buffers; a context must be current. */
gl_text *gl_text_new(tl_err *e);
void gl_text_free(gl_text *t);
/* The text at the top left of a width x height frame (glyphs twice as
 * large from 700 pixels high), over what is drawn. */
void gl_text_draw(gl_text *t, int width, int height, const char *text);

#endif
