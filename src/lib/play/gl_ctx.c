/* gl_ctx.c - contexts, the offscreen framebuffer, shader programs (see
 * gl_ctx.h). */
#include "play/gl_ctx.h"

#include <dlfcn.h>
#include <stdlib.h>

#include <epoxy/egl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

struct gl_ctx {
	GLFWwindow *win;   /* a window, or: */
	EGLDisplay dpy;    /* headless */
	EGLContext egl;
	GLuint fbo, rb[2];
	int w, h;
};

/* Under AddressSanitizer (make check-asan): the GL driver (Mesa) is
 * unloaded at teardown with allocations LeakSanitizer can no longer name
 * or suppress, so a program with a GL context is not leak-checked there;
 * memory errors still are. Linked in with the context code only. */
const char *__asan_default_options(void);
const char *
__asan_default_options(void)
{
	return "detect_leaks=0";
}

static int
egl_fail(tl_err *e, const char *what)
{
	return tl_fail(e, "headless OpenGL (EGL): %s (EGL error 0x%04x)", what,
	    (unsigned)eglGetError());
}

/* libepoxy opens libEGL and the GL library on first use and aborts when
 * it cannot (too few descriptors: ulimit -n): opened here first, with the
 * reason told; epoxy then finds them loaded. */
static int
gl_libs(tl_err *e)
{
	if (dlopen("libEGL.so.1", RTLD_LAZY | RTLD_GLOBAL) == NULL ||
	    (dlopen("libOpenGL.so.0", RTLD_LAZY | RTLD_GLOBAL) == NULL &&
	    dlopen("libGL.so.1", RTLD_LAZY | RTLD_GLOBAL) == NULL))
		return tl_fail(e, "headless OpenGL (EGL): %s", dlerror());
	return 0;
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

	if (gl_libs(e) < 0)
		return -1;
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
gl_ctx_headless(int w, int h, tl_err *e)
{
	gl_ctx *g = tl_alloc(1, sizeof *g, e);

	if (g == NULL)
		return NULL;
	g->w = w, g->h = h;
	if (egl_context(g, e) < 0 || fbo_make(g, e) < 0) {
		gl_ctx_close(g);
		return NULL;
	}
	return g;
}

/* GLFW's last error, or the fallback. */
static const char *
glfw_why(const char *fallback)
{
	const char *why = NULL;

	glfwGetError(&why);
	return why != NULL ? why : fallback;
}

gl_ctx *
gl_ctx_window(int w, int h, const char *title, tl_err *e)
{
	gl_ctx *g = tl_alloc(1, sizeof *g, e);

	if (g == NULL)
		return NULL;
	if (!glfwInit()) {
		tl_fail(e, "cannot open a window: %s",
		    glfw_why("GLFW failed to start"));
		free(g);
		return NULL;
	}
	glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
	glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
	glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
	glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
	glfwWindowHint(GLFW_DEPTH_BITS, 24);
	if ((g->win = glfwCreateWindow(w, h, title, NULL, NULL)) == NULL) {
		tl_fail(e, "cannot open a window: %s",
		    glfw_why("no OpenGL 3.3 core context"));
		glfwTerminate();
		free(g);
		return NULL;
	}
	glfwMakeContextCurrent(g->win);
	glfwSwapInterval(1);
	return g;
}

void
gl_ctx_close(gl_ctx *g)
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
gl_ctx_glfw(gl_ctx *g)
{
	return g->win;
}

void
gl_ctx_size(gl_ctx *g, int *w, int *h)
{
	if (g->win != NULL)
		glfwGetFramebufferSize(g->win, &g->w, &g->h);
	*w = g->w, *h = g->h;
}

void
gl_ctx_present(gl_ctx *g)
{
	if (g->win != NULL)
		glfwSwapBuffers(g->win);
	else
		glFinish();
}

void
gl_ctx_read_rgb(gl_ctx *g, unsigned char *rgb)
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

GLuint
gl_ctx_program(const char *vs, const char *fs, tl_err *e)
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
