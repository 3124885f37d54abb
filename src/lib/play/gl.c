/* gl.c - contexts, the terrain renderer and the readout (see gl.h). */
#include "play/gl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>
#include <epoxy/egl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-braces"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#include "core/oiio_plugin.h"

/* --- contexts ---------------------------------------------------------- */

struct gl_ctx {
	GLFWwindow *win;   /* a window, or: */
	EGLDisplay dpy;    /* headless */
	EGLContext egl;
	GLuint fbo, rb[2];
	int w, h;
};

static int
egl_fail(tl_err *e, const char *what)
{
	return tl_fail(e, "headless OpenGL (EGL): %s (EGL error 0x%04x)", what,
	    (unsigned)eglGetError());
}

static int
egl_context(gl_ctx *g, tl_err *e)
{
	static const EGLint cfg[] = {
		EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
		EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
		EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
		EGL_DEPTH_SIZE, 24, EGL_NONE
	};
	static const EGLint ctx[] = {
		EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
		EGL_CONTEXT_OPENGL_PROFILE_MASK,
		EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE
	};
	EGLConfig conf;
	EGLint major, minor, n;

	/* Mesa's surfaceless platform needs no display server at all */
	if (!epoxy_has_egl_extension(EGL_NO_DISPLAY,
	    "EGL_MESA_platform_surfaceless"))
		return tl_fail(e, "headless OpenGL (EGL): no surfaceless "
		    "platform (EGL_MESA_platform_surfaceless; Mesa's libEGL)");
	g->dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
	    EGL_DEFAULT_DISPLAY, NULL);
	if (g->dpy == EGL_NO_DISPLAY || !eglInitialize(g->dpy, &major, &minor))
		return egl_fail(e, "cannot open the surfaceless display");
	if (!eglBindAPI(EGL_OPENGL_API))
		return egl_fail(e, "no desktop OpenGL");
	if (!eglChooseConfig(g->dpy, cfg, &conf, 1, &n) || n < 1)
		return egl_fail(e, "no RGB8 + depth 24 configuration");
	g->egl = eglCreateContext(g->dpy, conf, EGL_NO_CONTEXT, ctx);
	if (g->egl == EGL_NO_CONTEXT)
		return egl_fail(e, "no OpenGL 3.3 core context");
	if (!eglMakeCurrent(g->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, g->egl))
		return egl_fail(e, "cannot make the context current");
	return 0;
}

/* The offscreen framebuffer the headless context draws into. */
static int
fbo_make(gl_ctx *g, tl_err *e)
{
	glGenFramebuffers(1, &g->fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
	glGenRenderbuffers(2, g->rb);
	glBindRenderbuffer(GL_RENDERBUFFER, g->rb[0]);
	glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, g->w, g->h);
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
	    GL_RENDERBUFFER, g->rb[0]);
	glBindRenderbuffer(GL_RENDERBUFFER, g->rb[1]);
	glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, g->w,
	    g->h);
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
	    GL_RENDERBUFFER, g->rb[1]);
	if (glCheckFramebufferStatus(GL_FRAMEBUFFER) !=
	    GL_FRAMEBUFFER_COMPLETE)
		return tl_fail(e, "headless OpenGL: a %dx%d framebuffer is "
		    "not complete (too large?)", g->w, g->h);
	return 0;
}

gl_ctx *
gl_open_headless(int w, int h, tl_err *e)
{
	gl_ctx *g = tl_alloc(1, sizeof *g, e);

	if (g == NULL)
		return NULL;
	g->w = w, g->h = h;
	if (egl_context(g, e) < 0 || fbo_make(g, e) < 0) {
		gl_close(g);
		return NULL;
	}
	return g;
}

gl_ctx *
gl_open_window(int w, int h, const char *title, tl_err *e)
{
	gl_ctx *g = tl_alloc(1, sizeof *g, e);
	const char *why = NULL;

	if (g == NULL)
		return NULL;
	if (!glfwInit()) {
		glfwGetError(&why);
		tl_fail(e, "cannot open a window: %s", why ? why :
		    "GLFW failed to start");
		free(g);
		return NULL;
	}
	glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
	glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
	glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
	glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
	glfwWindowHint(GLFW_DEPTH_BITS, 24);
	if ((g->win = glfwCreateWindow(w, h, title, NULL, NULL)) == NULL) {
		glfwGetError(&why);
		tl_fail(e, "cannot open a window: %s", why ? why :
		    "no OpenGL 3.3 core context");
		glfwTerminate();
		free(g);
		return NULL;
	}
	glfwMakeContextCurrent(g->win);
	glfwSwapInterval(1);
	return g;
}

void
gl_close(gl_ctx *g)
{
	if (g == NULL)
		return;
	if (g->win != NULL) {
		glfwDestroyWindow(g->win);
		glfwTerminate();
	} else if (g->dpy != EGL_NO_DISPLAY && g->dpy != NULL) {
		if (g->fbo != 0) {
			glDeleteRenderbuffers(2, g->rb);
			glDeleteFramebuffers(1, &g->fbo);
		}
		eglMakeCurrent(g->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE,
		    EGL_NO_CONTEXT);
		if (g->egl != EGL_NO_CONTEXT && g->egl != NULL)
			eglDestroyContext(g->dpy, g->egl);
		eglTerminate(g->dpy);
		eglReleaseThread();
	}
	free(g);
}

void *
gl_window(gl_ctx *g)
{
	return g->win;
}

void
gl_size(gl_ctx *g, int *w, int *h)
{
	if (g->win != NULL)
		glfwGetFramebufferSize(g->win, &g->w, &g->h);
	*w = g->w, *h = g->h;
}

void
gl_present(gl_ctx *g)
{
	if (g->win != NULL)
		glfwSwapBuffers(g->win);
	else
		glFinish();
}

void
gl_read_rgb(gl_ctx *g, unsigned char *rgb)
{
	size_t row = (size_t)g->w * 3;

	glPixelStorei(GL_PACK_ALIGNMENT, 1);
	glReadPixels(0, 0, g->w, g->h, GL_RGB, GL_UNSIGNED_BYTE, rgb);
	/* GL's rows run bottom-up */
	for (int y = 0; y < g->h / 2; y++) {
		unsigned char *a = rgb + y * row, *b = rgb + (g->h - 1 - y) * row;
		for (size_t k = 0; k < row; k++) {
			unsigned char t = a[k];
			a[k] = b[k], b[k] = t;
		}
	}
}

/* --- style ------------------------------------------------------------- */

static const char *colour_names[GL_NCOLOUR] = { "height", "level", "error" };

void
gl_style_init(gl_style *s)
{
	s->colour = GL_BY_HEIGHT;
	s->light = 1, s->wire = 0, s->skirts = 1;
	s->background[0] = 0.62f, s->background[1] = 0.72f;
	s->background[2] = 0.82f;
}

const char *
gl_colour_name(enum gl_colour c)
{
	return c < GL_NCOLOUR ? colour_names[c] : "?";
}

int
gl_colour_parse(const char *name, enum gl_colour *c)
{
	for (int k = 0; k < GL_NCOLOUR; k++)
		if (strcmp(name, colour_names[k]) == 0) {
			*c = (enum gl_colour)k;
			return 0;
		}
	return -1;
}

/* --- colours ----------------------------------------------------------- */

#define RAMP 16

/* viridis (matplotlib, CC0) at t = k/15: perceptually uniform, readable
 * in grey and by colour-blind eyes; never near the crack test's magenta */
static const float viridis[RAMP][3] = {
	{ 0.267004f, 0.004874f, 0.329415f }, { 0.282656f, 0.100196f, 0.422160f },
	{ 0.277134f, 0.185228f, 0.489898f }, { 0.253935f, 0.265254f, 0.529983f },
	{ 0.221989f, 0.339161f, 0.548752f }, { 0.190631f, 0.407061f, 0.556089f },
	{ 0.163625f, 0.471133f, 0.558148f }, { 0.139147f, 0.533812f, 0.555298f },
	{ 0.120565f, 0.596422f, 0.543611f }, { 0.134692f, 0.658636f, 0.517649f },
	{ 0.208030f, 0.718701f, 0.472873f }, { 0.327796f, 0.773980f, 0.406640f },
	{ 0.477504f, 0.821444f, 0.318195f }, { 0.647257f, 0.858400f, 0.209861f },
	{ 0.824940f, 0.884720f, 0.106217f }, { 0.993248f, 0.906157f, 0.143936f },
};

/* Moreland's cool-warm ends and middle: below tau blue, above red */
static const float coolwarm[3][3] = {
	{ 0.230f, 0.299f, 0.754f }, { 0.865f, 0.865f, 0.865f },
	{ 0.706f, 0.016f, 0.150f },
};

/* Okabe-Ito, colour-blind safe; a level's colour is [level % 8] */
static const float levels[8][3] = {
	{ 0.902f, 0.624f, 0.000f }, { 0.337f, 0.706f, 0.914f },
	{ 0.000f, 0.620f, 0.451f }, { 0.941f, 0.894f, 0.259f },
	{ 0.000f, 0.447f, 0.698f }, { 0.835f, 0.369f, 0.000f },
	{ 0.800f, 0.475f, 0.655f }, { 0.600f, 0.600f, 0.600f },
};

/* --- shaders ----------------------------------------------------------- */

#define STR_(x) #x
#define STR(x) STR_(x)

enum { MODE_RAMP_HEIGHT, MODE_FLAT, MODE_RAMP_ERROR };

static const char *terrain_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 pos;\n"
    "layout(location = 1) in vec3 nrm;\n"
    "layout(location = 2) in vec2 val; /* height, E */\n"
    "uniform mat4 proj, rot;\n"
    "uniform vec3 offset; /* block origin - eye */\n"
    "uniform int mode;\n"
    "uniform float zlo, zinv, tau;\n"
    "uniform vec2 corner; /* the block's (0, 0) in level units */\n"
    "uniform float scale; /* level-0 cells a level cell */\n"
    "out vec3 n;\n"
    "out vec2 grid; /* level-0 column, row */\n"
    "out float t, skirt;\n"
    "void main() {\n"
    "	int k = gl_VertexID, s = (k - " STR(PYRAMID_N) ") / " STR(BT_SIZE) ";\n"
    "	int u = (k - " STR(PYRAMID_N) ") % " STR(BT_SIZE) ";\n"
    "	ivec2 g = k < " STR(PYRAMID_N) " ? ivec2(k % " STR(BT_SIZE) ", k / "
    STR(BT_SIZE) ") :\n"
    "	    s == 0 ? ivec2(u, 0) : s == 1 ? ivec2(u, " STR(BT_CELLS) ") :\n"
    "	    s == 2 ? ivec2(0, u) : ivec2(" STR(BT_CELLS) ", u);\n"
    "	grid = (vec2(g) + corner) * scale;\n"
    "	gl_Position = proj * rot * vec4(pos + offset, 1.0);\n"
    "	n = nrm;\n"
    "	if (mode == 2)\n"
    "		t = clamp(0.5 + log2(max(val.y, 1e-30) / tau) / 8.0, 0.0, 1.0);\n"
    "	else\n"
    "		t = clamp((val.x - zlo) * zinv, 0.0, 1.0);\n"
    "	skirt = k >= " STR(PYRAMID_N) " ? 1.0 : 0.0;\n"
    "}\n";

static const char *terrain_fs =
    "#version 330 core\n"
    "in vec3 n;\n"
    "in vec2 grid;\n"
    "in float t, skirt;\n"
    "uniform int mode, lines;\n"
    "uniform vec2 edge; /* the DEM's last column and row */\n"
    "uniform vec3 ramp[" STR(RAMP) "], solid, light;\n"
    "uniform float ambient;\n"
    "out vec4 colour;\n"
    "void main() {\n"
    "	vec3 c;\n"
    "	/* blocks are padded past the DEM: cut them at its edge */\n"
    "	if (any(greaterThan(grid, edge + 1e-3)))\n"
    "		discard;\n"
    "	/* no skirts on the DEM's own edges: nothing to close there */\n"
    "	if (skirt > 0.0 && (any(lessThan(grid, vec2(1e-3))) ||\n"
    "	    any(greaterThan(grid, edge - 1e-3))))\n"
    "		discard;\n"
    "	if (lines == 1 && skirt > 0.0)\n"
    "		discard;\n"
    "	if (mode == 1) {\n"
    "		c = solid;\n"
    "	} else {\n"
    "		float x = t * float(" STR(RAMP) " - 1);\n"
    "		int i = min(int(x), " STR(RAMP) " - 2);\n"
    "		c = mix(ramp[i], ramp[i + 1], x - float(i));\n"
    "	}\n"
    "	float d = max(dot(normalize(n), light), 0.0);\n"
    "	colour = vec4(c * (ambient + (1.0 - ambient) * d), 1.0);\n"
    "}\n";

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

static GLuint
shader(GLenum kind, const char *src, tl_err *e)
{
	GLuint s = glCreateShader(kind);
	GLint ok;
	char log[512];

	glShaderSource(s, 1, &src, NULL);
	glCompileShader(s);
	glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
	if (!ok) {
		glGetShaderInfoLog(s, sizeof log, NULL, log);
		tl_fail(e, "OpenGL: shader: %s", log);
		glDeleteShader(s);
		return 0;
	}
	return s;
}

static GLuint
program(const char *vs, const char *fs, tl_err *e)
{
	GLuint v = shader(GL_VERTEX_SHADER, vs, e), f, p;
	GLint ok;
	char log[512];

	if (v == 0)
		return 0;
	if ((f = shader(GL_FRAGMENT_SHADER, fs, e)) == 0) {
		glDeleteShader(v);
		return 0;
	}
	p = glCreateProgram();
	glAttachShader(p, v);
	glAttachShader(p, f);
	glLinkProgram(p);
	glDeleteShader(v);
	glDeleteShader(f);
	glGetProgramiv(p, GL_LINK_STATUS, &ok);
	if (!ok) {
		glGetProgramInfoLog(p, sizeof log, NULL, log);
		tl_fail(e, "OpenGL: shader program: %s", log);
		glDeleteProgram(p);
		return 0;
	}
	return p;
}

/* --- the renderer ------------------------------------------------------ */

#define TEXT_QUADS 4000 /* the readout's glyph quads at most */
#define AMBIENT 0.3f

enum { U_PROJ, U_ROT, U_OFFSET, U_MODE, U_ZLO, U_ZINV, U_TAU, U_LINES,
	U_RAMP, U_SOLID, U_LIGHT, U_AMBIENT, U_CORNER, U_SCALE, U_EDGE, NU };
static const char *unames[NU] = { "proj", "rot", "offset", "mode", "zlo",
	"zinv", "tau", "lines", "ramp", "solid", "light", "ambient", "corner",
	"scale", "edge" };

struct gl_render {
	const world *w;
	GLuint prog, text, tvao, tvbo, tibo;
	GLint u[NU];
	float zlo, zinv;         /* the height map */
	/* this frame: */
	gl_style s;
	double eye[3];
	int width, height;
	gl_frame_stats *st;
	char *tbuf;              /* stb_easy_font vertices */
};

/* Per block, in cb->gpu. */
typedef struct {
	GLuint vao, vbo, ibo;
	GLsizei count;
	int skirts;              /* the index buffer has skirts */
} gpu;

static void
height_range(gl_render *r)
{
	const pyramid_level *L = &r->w->ix.lev[0];
	double lo = INFINITY, hi = -INFINITY;

	/* level 0 is the DEM: its range, whatever coarser levels solved */
	for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++)
		lo = fmin(lo, L->zmin[k]), hi = fmax(hi, L->zmax[k]);
	if (!(lo < hi))
		hi = lo + 1;
	r->zlo = (float)lo;
	r->zinv = (float)(1 / (hi - lo));
}

static int
text_make(gl_render *r, tl_err *e)
{
	GLuint *idx;

	if ((r->tbuf = tl_alloc(TEXT_QUADS, 64, e)) == NULL ||
	    (idx = tl_alloc(TEXT_QUADS, 6 * sizeof *idx, e)) == NULL)
		return -1;
	/* stb_easy_font gives quads; core profile draws triangles */
	for (GLuint q = 0; q < TEXT_QUADS; q++) {
		GLuint t[6] = { 0, 1, 2, 0, 2, 3 };
		for (int k = 0; k < 6; k++)
			idx[6 * q + k] = 4 * q + t[k];
	}
	glGenVertexArrays(1, &r->tvao);
	glBindVertexArray(r->tvao);
	glGenBuffers(1, &r->tvbo);
	glBindBuffer(GL_ARRAY_BUFFER, r->tvbo);
	glBufferData(GL_ARRAY_BUFFER, TEXT_QUADS * 64, NULL, GL_STREAM_DRAW);
	glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 16, (void *)0);
	glEnableVertexAttribArray(0);
	glGenBuffers(1, &r->tibo);
	glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->tibo);
	glBufferData(GL_ELEMENT_ARRAY_BUFFER, TEXT_QUADS * 6 * sizeof *idx,
	    idx, GL_STATIC_DRAW);
	glBindVertexArray(0);
	free(idx);
	return 0;
}

gl_render *
gl_render_new(const world *w, tl_err *e)
{
	gl_render *r = tl_alloc(1, sizeof *r, e);

	if (r == NULL)
		return NULL;
	r->w = w;
	if ((r->prog = program(terrain_vs, terrain_fs, e)) == 0 ||
	    (r->text = program(text_vs, text_fs, e)) == 0 ||
	    text_make(r, e) < 0) {
		gl_render_free(r);
		return NULL;
	}
	for (int k = 0; k < NU; k++)
		r->u[k] = glGetUniformLocation(r->prog, unames[k]);
	height_range(r);
	gl_style_init(&r->s);
	return r;
}

void
gl_render_free(gl_render *r)
{
	if (r == NULL)
		return;
	if (r->tvao != 0) {
		glDeleteVertexArrays(1, &r->tvao);
		glDeleteBuffers(1, &r->tvbo);
		glDeleteBuffers(1, &r->tibo);
	}
	if (r->prog != 0)
		glDeleteProgram(r->prog);
	if (r->text != 0)
		glDeleteProgram(r->text);
	free(r->tbuf);
	free(r);
}

void
gl_release(cblock *cb, void *ctx)
{
	gpu *g = cb->gpu;

	(void)ctx;
	if (g == NULL)
		return;
	glDeleteVertexArrays(1, &g->vao);
	glDeleteBuffers(1, &g->vbo);
	glDeleteBuffers(1, &g->ibo);
	free(g);
	cb->gpu = NULL;
}

static void
set_ramp(gl_render *r, enum gl_colour c)
{
	float ramp[RAMP][3];

	if (c == GL_BY_ERROR) {
		for (int k = 0; k < RAMP; k++) {
			double x = 2.0 * k / (RAMP - 1);
			int i = x >= 1 ? 1 : 0;
			for (int a = 0; a < 3; a++)
				ramp[k][a] = (float)(coolwarm[i][a] + (x - i) *
				    (coolwarm[i + 1][a] - coolwarm[i][a]));
		}
	} else
		memcpy(ramp, viridis, sizeof ramp);
	glUniform3fv(r->u[U_RAMP], RAMP, &ramp[0][0]);
}

/* The colouring and light of the style (after the wireframe's lines). */
static void
set_mode(gl_render *r)
{
	glUniform1i(r->u[U_MODE], r->s.colour == GL_BY_LEVEL ? MODE_FLAT :
	    r->s.colour == GL_BY_ERROR ? MODE_RAMP_ERROR : MODE_RAMP_HEIGHT);
	glUniform1f(r->u[U_AMBIENT], r->s.light ? AMBIENT : 1.0f);
}

void
gl_begin(gl_render *r, const camera *c, const gl_style *s,
    gl_frame_stats *st)
{
	/* the view turns about the eye; blocks are placed relative to it */
	camera rc = *c;
	float view[16], proj[16];
	/* towards the light: from the north-west, 45 degrees up, as in
	 * cartographic hill shading */
	float light[3] = { -0.5f, 0.5f, 0.70710678f };

	for (int k = 0; k < 3; k++) {
		r->eye[k] = c->eye[k];
		rc.target[k] = c->target[k] - c->eye[k];
		rc.eye[k] = 0;
	}
	cam_matrices(&rc, view, proj);
	r->s = *s;
	r->width = c->width, r->height = c->height;
	r->st = st;
	memset(st, 0, sizeof *st);
	glViewport(0, 0, c->width, c->height);
	glClearColor(s->background[0], s->background[1], s->background[2], 1);
	glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
	glEnable(GL_DEPTH_TEST);
	glDisable(GL_BLEND);
	/* bintree triangles alternate in orientation: no culling */
	glDisable(GL_CULL_FACE);
	glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
	if (s->wire) {
		glEnable(GL_POLYGON_OFFSET_FILL);
		glPolygonOffset(1, 1);
	} else
		glDisable(GL_POLYGON_OFFSET_FILL);
	glUseProgram(r->prog);
	glUniformMatrix4fv(r->u[U_PROJ], 1, GL_FALSE, proj);
	glUniformMatrix4fv(r->u[U_ROT], 1, GL_FALSE, view);
	glUniform3fv(r->u[U_LIGHT], 1, light);
	glUniform1f(r->u[U_ZLO], r->zlo);
	glUniform1f(r->u[U_ZINV], r->zinv);
	glUniform1i(r->u[U_LINES], 0);
	glUniform2f(r->u[U_EDGE], r->w->ix.size0[0] - 1.0f,
	    r->w->ix.size0[1] - 1.0f);
	set_mode(r);
	set_ramp(r, s->colour);
}

static gpu *
gpu_new(const mesh_verts *v, tl_err *e)
{
	gpu *g = tl_alloc(1, sizeof *g, e);
	GLsizeiptr n3 = MESH_NV * 3 * sizeof(float);
	GLsizeiptr n2 = MESH_NV * 2 * sizeof(float);

	if (g == NULL)
		return NULL;
	g->skirts = -1;
	glGenVertexArrays(1, &g->vao);
	glBindVertexArray(g->vao);
	glGenBuffers(1, &g->vbo);
	glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
	glBufferData(GL_ARRAY_BUFFER, 2 * n3 + n2, NULL, GL_STATIC_DRAW);
	glBufferSubData(GL_ARRAY_BUFFER, 0, n3, v->pos);
	glBufferSubData(GL_ARRAY_BUFFER, n3, n3, v->nrm);
	glBufferSubData(GL_ARRAY_BUFFER, 2 * n3, n2, v->val);
	glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, (void *)0);
	glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, (void *)n3);
	glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, (void *)(2 * n3));
	for (GLuint a = 0; a < 3; a++)
		glEnableVertexAttribArray(a);
	glGenBuffers(1, &g->ibo);
	glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo);
	return g;
}

/* Rounded down to a quarter power of two: the tolerance is kept, and a
 * camera moving smoothly rebuilds a block's triangles only now and then. */
static double
tau_step(double tau)
{
	return tau > 0 ? exp2(floor(4 * log2(tau)) / 4) : -1;
}

/* New triangles at tau q, counted in the cache, into the index buffer:
 * 1, 0 when the cache has no room for them, -1 on error. */
static int
rebuild(gl_render *r, cache *k, cblock *cb, gpu *g, double q, tl_err *e)
{
	uint32_t *p;

	if (mesh_tris_build(&cb->blk, q, r->s.skirts, &cb->tris, e) < 0)
		return -1;
	/* the builder doubles its array: give back what it did not use */
	if (cb->tris.n < cb->tris.cap &&
	    (p = realloc(cb->tris.idx, cb->tris.n * sizeof *p)) != NULL)
		cb->tris.idx = p, cb->tris.cap = cb->tris.n;
	cb->tau = q;
	if (!cache_account(k, cb)) {
		cb->tau = NAN;
		return 0;
	}
	glBindVertexArray(g->vao);
	glBufferData(GL_ELEMENT_ARRAY_BUFFER,
	    (GLsizeiptr)(cb->tris.n * sizeof *cb->tris.idx), cb->tris.idx,
	    GL_STATIC_DRAW);
	g->count = (GLsizei)cb->tris.n;
	g->skirts = r->s.skirts;
	return 1;
}

int
gl_draw(gl_render *r, cache *k, cblock *cb, double tau, tl_err *e)
{
	double q = tau_step(tau);
	gpu *g = cb->gpu;
	float off[3];
	int rc;

	if (g == NULL) {
		if ((g = cb->gpu = gpu_new(&cb->v, e)) == NULL)
			return -1;
		/* the vertices live on in the buffer (on llvmpipe in RAM
		 * too): counted once in the cap, kept once */
		mesh_verts_free(&cb->v);
	}
	if (!(cb->tau == q) || cb->tris.idx == NULL || g->skirts != r->s.skirts)
		if ((rc = rebuild(r, k, cb, g, q, e)) <= 0)
			return rc;
	for (int a = 0; a < 3; a++)
		off[a] = (float)(cb->v.origin[a] - r->eye[a]);
	glUniform3fv(r->u[U_OFFSET], 1, off);
	glUniform2f(r->u[U_CORNER], (float)(cb->bi * BT_CELLS),
	    (float)(cb->bj * BT_CELLS));
	glUniform1f(r->u[U_SCALE], (float)(1L << cb->level));
	glUniform1f(r->u[U_TAU], (float)(q > 0 ? q : 0.01));
	glUniform3fv(r->u[U_SOLID], 1, levels[cb->level % 8]);
	glBindVertexArray(g->vao);
	glDrawElements(GL_TRIANGLES, g->count, GL_UNSIGNED_INT, 0);
	if (r->s.wire) {
		static const float ink[3] = { 0.08f, 0.08f, 0.08f };
		glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
		glUniform1i(r->u[U_LINES], 1);
		glUniform1i(r->u[U_MODE], MODE_FLAT);
		glUniform3fv(r->u[U_SOLID], 1, ink);
		glUniform1f(r->u[U_AMBIENT], 1);
		glDrawElements(GL_TRIANGLES, g->count, GL_UNSIGNED_INT, 0);
		glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
		glUniform1i(r->u[U_LINES], 0);
		set_mode(r);
	}
	r->st->blocks++;
	r->st->tris += cb->tris.tris;
	r->st->skirts += cb->tris.skirts;
	if (cb->level < 32)
		r->st->per_level[cb->level]++;
	if (cb->level + 1 > r->st->levels)
		r->st->levels = cb->level + 1;
	return 1;
}

/* --- the readout ------------------------------------------------------- */

/* Quads first .. first+n-1 of the text buffer, scaled, shifted, in col. */
static void
quads_draw(gl_render *r, int first, int n, float dx, float dy,
    const float col[4])
{
	glUniform2f(glGetUniformLocation(r->text, "shift"), dx, dy);
	glUniform4fv(glGetUniformLocation(r->text, "col"), 1, col);
	glDrawElementsBaseVertex(GL_TRIANGLES, 6 * n, GL_UNSIGNED_INT, 0,
	    4 * first);
}

void
gl_text(gl_render *r, const char *text)
{
	static const float band[4] = { 0, 0, 0, 0.55f };
	static const float shadow[4] = { 0, 0, 0, 1 };
	static const float ink[4] = { 1, 1, 1, 1 };
	float scale = r->height >= 700 ? 2 : 1, wmax = 0, hmax = 0;
	char buf[2048];
	int n;

	snprintf(buf, sizeof buf, "%s", text);
	/* quad 0: a band behind the glyphs, as large as they are */
	n = stb_easy_font_print(0, 0, buf, NULL, r->tbuf + 64,
	    (TEXT_QUADS - 1) * 64);
	for (int q = 0; q < 4 * n; q++) {
		const float *v = (const float *)(r->tbuf + 64 + 16 * q);
		wmax = fmaxf(wmax, v[0]), hmax = fmaxf(hmax, v[1]);
	}
	{
		float quad[4][4] = { { -3, -3 }, { wmax + 3, -3 },
			{ wmax + 3, hmax + 3 }, { -3, hmax + 3 } };
		memcpy(r->tbuf, quad, sizeof quad);
	}
	glDisable(GL_DEPTH_TEST);
	glEnable(GL_BLEND);
	glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
	glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
	glUseProgram(r->text);
	glUniform2f(glGetUniformLocation(r->text, "px"), 2.0f / r->width,
	    2.0f / r->height);
	glUniform1f(glGetUniformLocation(r->text, "scale"), scale);
	glBindVertexArray(r->tvao);
	glBindBuffer(GL_ARRAY_BUFFER, r->tvbo);
	glBufferSubData(GL_ARRAY_BUFFER, 0, 64 * (n + 1), r->tbuf);
	quads_draw(r, 0, 1, 8 * scale, 8 * scale, band);
	quads_draw(r, 1, n, 9 * scale, 9 * scale, shadow);
	quads_draw(r, 1, n, 8 * scale, 8 * scale, ink);
	glEnable(GL_DEPTH_TEST);
	glDisable(GL_BLEND);
	glUseProgram(r->prog);
}

/* --- colours for the probe, images --------------------------------------- */

void
gl_height_rgb(const gl_render *r, double z, unsigned char rgb[3])
{
	double t = (z - r->zlo) * r->zinv, x;
	int i;

	t = t < 0 ? 0 : t > 1 ? 1 : t;
	x = t * (RAMP - 1);
	i = (int)x < RAMP - 2 ? (int)x : RAMP - 2;
	for (int a = 0; a < 3; a++) {
		double c = viridis[i][a] + (x - i) *
		    (viridis[i + 1][a] - viridis[i][a]);
		rgb[a] = (unsigned char)lrint(c * 255);
	}
}

int
gl_write_image(const char *path, int w, int h, const unsigned char *rgb,
    tl_err *e)
{
	char why[512];
	const tl_oiio_api *api = tl_oiio_load(why, sizeof why);
	tl_outfile o;

	if (api == NULL)
		return tl_fail(e, "%s: writing images needs the OpenImageIO "
		    "plugin tl_oiio.so: %s", path, why);
	if (tl_out_begin(&o, path, e) < 0)
		return -1;
	/* the format from the final name: the temporary's has no extension */
	if (api->write_u8(o.tmp, path, w, h, 3, rgb, why, sizeof why) < 0) {
		tl_out_abort(&o);
		return tl_fail(e, "%s: %s", path, why);
	}
	return tl_out_commit(&o, e);
}
