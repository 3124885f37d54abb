/* gl_text.c - text over a frame (see gl_text.h). */
#include "play/gl_text.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "play/gl_ctx.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-braces"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#define TEXT_QUADS 4000 /* glyph quads at most */
#define QUAD 64         /* bytes of a quad: 4 vertices of x, y, z, colour */

struct gl_text {
	GLuint prog, vao, vbo, ibo;
	GLint u_px, u_scale, u_shift, u_col;
	char *buf;      /* stb_easy_font vertices; quad 0 the band */
};

static const char *text_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec2 xy;\n"
    "uniform vec2 px, shift;\n"
    "uniform float scale;\n"
    "void main() {\n"
    "	vec2 p = xy * scale + shift;\n"
    "	gl_Position = vec4(p.x * px.x - 1.0, 1.0 - p.y * px.y, 0.0, 1.0);\n"
    "}\n";

static const char *text_fs =
    "#version 330 core\n"
    "uniform vec4 col;\n"
    "out vec4 colour;\n"
    "void main() { colour = col; }\n";

/* The vertex buffer for the quads and the index buffer that draws each
 * as two triangles (stb_easy_font gives quads; core profile draws
 * triangles). */
static int
buffers(gl_text *t, tl_err *e)
{
	GLuint *idx;

	if ((t->buf = tl_alloc(TEXT_QUADS, QUAD, e)) == NULL ||
	    (idx = tl_alloc(TEXT_QUADS, 6 * sizeof *idx, e)) == NULL)
		return -1;
	for (GLuint q = 0; q < TEXT_QUADS; q++) {
		GLuint tri[6] = { 0, 1, 2, 0, 2, 3 };
		for (int k = 0; k < 6; k++)
			idx[6 * q + k] = 4 * q + tri[k];
	}
	glGenVertexArrays(1, &t->vao);
	glBindVertexArray(t->vao);
	glGenBuffers(1, &t->vbo);
	glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
	glBufferData(GL_ARRAY_BUFFER, TEXT_QUADS * QUAD, NULL, GL_STREAM_DRAW);
	glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 16, (void *)0);
	glEnableVertexAttribArray(0);
	glGenBuffers(1, &t->ibo);
	glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t->ibo);
	glBufferData(GL_ELEMENT_ARRAY_BUFFER, TEXT_QUADS * 6 * sizeof *idx,
	    idx, GL_STATIC_DRAW);
	glBindVertexArray(0);
	free(idx);
	return 0;
}

gl_text *
gl_text_new(tl_err *e)
{
	gl_text *t = tl_alloc(1, sizeof *t, e);

	if (t == NULL)
		return NULL;
	if ((t->prog = gl_ctx_program(text_vs, text_fs, e)) == 0 ||
	    buffers(t, e) < 0) {
		gl_text_free(t);
		return NULL;
	}
	t->u_px = glGetUniformLocation(t->prog, "px");
	t->u_scale = glGetUniformLocation(t->prog, "scale");
	t->u_shift = glGetUniformLocation(t->prog, "shift");
	t->u_col = glGetUniformLocation(t->prog, "col");
	return t;
}

void
gl_text_free(gl_text *t)
{
	if (t == NULL)
		return;
	if (t->vao != 0) {
		glDeleteVertexArrays(1, &t->vao);
		glDeleteBuffers(1, &t->vbo);
		glDeleteBuffers(1, &t->ibo);
	}
	if (t->prog != 0)
		glDeleteProgram(t->prog);
	free(t->buf);
	free(t);
}

/* Quads first .. first+n-1 of the buffer, scaled, shifted, in col. */
static void
quads(gl_text *t, int first, int n, float dx, float dy, const float col[4])
{
	glUniform2f(t->u_shift, dx, dy);
	glUniform4fv(t->u_col, 1, col);
	glDrawElementsBaseVertex(GL_TRIANGLES, 6 * n, GL_UNSIGNED_INT, 0,
	    4 * first);
}

/* The glyphs of text into quads 1.., the band behind them, as large as
 * they are, into quad 0; returns the glyph quads. */
static int
layout(gl_text *t, const char *text)
{
	char s[2048];
	float wmax = 0, hmax = 0;
	int n;

	snprintf(s, sizeof s, "%s", text);
	n = stb_easy_font_print(0, 0, s, NULL, t->buf + QUAD,
	    (TEXT_QUADS - 1) * QUAD);
	for (int q = 0; q < 4 * n; q++) {
		const float *v = (const float *)(t->buf + QUAD + 16 * q);
		wmax = fmaxf(wmax, v[0]), hmax = fmaxf(hmax, v[1]);
	}
	{
		float band[4][4] = { { -3, -3 }, { wmax + 3, -3 },
			{ wmax + 3, hmax + 3 }, { -3, hmax + 3 } };
		memcpy(t->buf, band, sizeof band);
	}
	return n;
}

void
gl_text_draw(gl_text *t, int width, int height, const char *text)
{
	static const float band[4] = { 0, 0, 0, 0.55f };
	static const float shadow[4] = { 0, 0, 0, 1 };
	static const float ink[4] = { 1, 1, 1, 1 };
	float scale = height >= 700 ? 2 : 1;
	int n = layout(t, text);

	glDisable(GL_DEPTH_TEST);
	glEnable(GL_BLEND);
	glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
	glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
	glUseProgram(t->prog);
	glUniform2f(t->u_px, 2.0f / width, 2.0f / height);
	glUniform1f(t->u_scale, scale);
	glBindVertexArray(t->vao);
	glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
	glBufferSubData(GL_ARRAY_BUFFER, 0, QUAD * (n + 1), t->buf);
	quads(t, 0, 1, 8 * scale, 8 * scale, band);
	quads(t, 1, n, 9 * scale, 9 * scale, shadow);
	quads(t, 1, n, 8 * scale, 8 * scale, ink);
	glEnable(GL_DEPTH_TEST);
	glDisable(GL_BLEND);
}
