/* window.c - the window's events, keys, readout and loop (see
 * window.h); the camera's motion is nav.h's. */
#include "play/window.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "play/nav.h"
#include "play/shot.h"

typedef struct {
	scene *sc;
	const char *prog;
	gl_style style;
	double pixels;
	nav nav;
	double home[2][3]; /* eye and target of the start view */
	int readout, shots, drag;
	double mx, my;     /* the mouse when a drag moved last */
	int shoot;         /* a screenshot is asked for */
} viewer;

static void
view_named(viewer *v, const char *name)
{
	camera c = v->sc->cam;

	camera_named(&c, &v->sc->w, name);
	nav_set(&v->nav, c.eye, c.target);
}

static void
on_scroll(GLFWwindow *win, double dx, double dy)
{
	viewer *v = glfwGetWindowUserPointer(win);

	(void)dx;
	nav_zoom(&v->nav, pow(0.85, dy));
}

static void
on_button(GLFWwindow *win, int button, int action, int mods)
{
	viewer *v = glfwGetWindowUserPointer(win);

	(void)mods;
	v->drag = action == GLFW_PRESS ? button + 1 : 0;
	glfwGetCursorPos(win, &v->mx, &v->my);
}

static void
on_cursor(GLFWwindow *win, double x, double y)
{
	viewer *v = glfwGetWindowUserPointer(win);
	double dx = x - v->mx, dy = y - v->my;
	nav *n = &v->nav;

	v->mx = x, v->my = y;
	if (v->drag == GLFW_MOUSE_BUTTON_LEFT + 1)
		nav_turn(n, -dx * 0.005, (n->orbit ? 1 : -1) * dy * 0.005);
	else if (v->drag == GLFW_MOUSE_BUTTON_RIGHT + 1) {
		/* pan: the point under the mouse follows it, roughly */
		double k = 2 * n->dist * tan(CAMERA_FOVY / 2) /
		    v->sc->cam.height;
		nav_move(n, 0, -dx * k, 0);
		n->eye[2] += dy * k * cos(n->pitch);
	}
}

/* The style and tolerance keys; 1 when key was one of them. */
static int
style_key(viewer *v, int key)
{
	switch (key) {
	case GLFW_KEY_EQUAL: case GLFW_KEY_KP_ADD:
		v->pixels = v->pixels > 0 ? v->pixels * M_SQRT2 : 0.25;
		return 1;
	case GLFW_KEY_MINUS: case GLFW_KEY_KP_SUBTRACT:
		v->pixels = v->pixels > 0.25 ? v->pixels / M_SQRT2 : 0;
		return 1;
	case GLFW_KEY_C:
		v->style.colour = (v->style.colour + 1) % GL_NCOLOUR;
		return 1;
	case GLFW_KEY_G: v->style.wire = !v->style.wire; return 1;
	case GLFW_KEY_K: v->style.skirts = !v->style.skirts; return 1;
	case GLFW_KEY_L: v->style.light = !v->style.light; return 1;
	}
	return 0;
}

static void
on_key(GLFWwindow *win, int key, int code, int action, int mods)
{
	viewer *v = glfwGetWindowUserPointer(win);

	(void)code, (void)mods;
	if (action != GLFW_PRESS || style_key(v, key))
		return;
	switch (key) {
	case GLFW_KEY_ESCAPE: case GLFW_KEY_Q:
		glfwSetWindowShouldClose(win, 1);
		break;
	case GLFW_KEY_H: v->readout = !v->readout; break;
	case GLFW_KEY_P: v->shoot = 1; break;
	case GLFW_KEY_TAB: v->nav.orbit = !v->nav.orbit; break;
	case GLFW_KEY_HOME: case GLFW_KEY_Z:
		nav_set(&v->nav, v->home[0], v->home[1]);
		break;
	case GLFW_KEY_1: view_named(v, "overview"); break;
	case GLFW_KEY_2: view_named(v, "oblique"); break;
	}
}

/* The held keys move the eye, at a speed that grows with its height
 * over the terrain's lowest point (Shift: 5x). */
static void
held_keys(viewer *v, GLFWwindow *win, double dt)
{
	double sp = fmax(20, v->nav.eye[2] - v->sc->w.zmin) * dt;
	static const int k[6] = { GLFW_KEY_W, GLFW_KEY_S, GLFW_KEY_A,
		GLFW_KEY_D, GLFW_KEY_R, GLFW_KEY_F };
	int on[6];

	if (glfwGetKey(win, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
	    glfwGetKey(win, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS)
		sp *= 5;
	for (int q = 0; q < 6; q++)
		on[q] = glfwGetKey(win, k[q]) == GLFW_PRESS;
	on[0] |= glfwGetKey(win, GLFW_KEY_UP) == GLFW_PRESS;
	on[1] |= glfwGetKey(win, GLFW_KEY_DOWN) == GLFW_PRESS;
	on[2] |= glfwGetKey(win, GLFW_KEY_LEFT) == GLFW_PRESS;
	on[3] |= glfwGetKey(win, GLFW_KEY_RIGHT) == GLFW_PRESS;
	nav_move(&v->nav, sp * (on[0] - on[1]), sp * (on[3] - on[2]),
	    sp * (on[4] - on[5]));
}

static void
readout(viewer *v, double ms)
{
	const gl_render_stats *st = &v->sc->st;
	cache_stats cs;
	char text[1024], lv[512];

	cache_get_stats(v->sc->k, &cs);
	scene_levels_text(st, lv, sizeof lv);
	snprintf(text, sizeof text, "frame %.1f ms   tolerance %.3g px   "
	    "colour: %s   %s\n"
	    "%ld triangles (+%ld skirt)   %ld blocks: %s\n"
	    "cache %.1f of %.0f MB, %ld waiting",
	    ms, v->pixels, gl_style_colour_name(v->style.colour),
	    v->nav.orbit ? "orbit" : "fly", st->tris, st->skirts, st->blocks,
	    lv, cs.bytes / 1048576.0, cs.cap / 1048576.0, v->sc->misses);
	scene_text(v->sc, text);
}

/* The next free tileplay-NNN.png in the current directory. */
static int
screenshot(viewer *v, tl_err *e)
{
	char name[64];
	unsigned char *rgb;
	FILE *f;
	int w = v->sc->cam.width, h = v->sc->cam.height, r;

	do {
		snprintf(name, sizeof name, "tileplay-%03d.png", ++v->shots);
		f = fopen(name, "r");
		if (f != NULL)
			fclose(f);
	} while (f != NULL && v->shots < 999);
	if ((rgb = tl_alloc((size_t)w * h, 3, e)) == NULL)
		return -1;
	gl_ctx_read_rgb(v->sc->g, rgb);
	r = shot_write(name, w, h, rgb, e);
	free(rgb);
	if (r == 0)
		fprintf(stderr, "%s: wrote %s\n", v->prog, name);
	return r;
}

static int
frame(viewer *v, double ms, tl_err *e)
{
	scene *sc = v->sc;

	gl_ctx_size(sc->g, &sc->cam.width, &sc->cam.height);
	if (sc->cam.width < 1 || sc->cam.height < 1)
		return 0; /* minimised */
	nav_camera(&v->nav, &sc->cam, &sc->w);
	scene_choose(sc, v->pixels);
	if (scene_draw(sc, &v->style, e) < 0)
		return -1;
	if (v->shoot) {
		v->shoot = 0;
		if (screenshot(v, e) < 0)
			tl_warn(v->prog, "%s", e->msg); /* the view goes on */
	}
	if (v->readout)
		readout(v, ms);
	gl_ctx_present(sc->g);
	return 0;
}

/* Frames until the window closes (or o->frames); *first: seconds from
 * t0 to the first frame with every block it wanted. */
static int
loop(viewer *v, GLFWwindow *win, const window_opts *o, double t0,
    double *first, tl_err *e)
{
	double last = scene_clock(), ms;

	for (int f = 0; !glfwWindowShouldClose(win) &&
	    (o->frames == 0 || f < o->frames); f++) {
		double t = scene_clock();
		ms = (t - last) * 1000, last = t;
		glfwPollEvents();
		held_keys(v, win, ms / 1000);
		if (frame(v, ms, e) < 0)
			return -1;
		if (isnan(*first) && v->sc->misses == 0)
			*first = scene_clock() - t0;
		if (scene_cache_error(v->sc, e) < 0)
			return -1;
	}
	return 0;
}

static void
attach(GLFWwindow *win, viewer *v)
{
	glfwSetWindowUserPointer(win, v);
	glfwSetKeyCallback(win, on_key);
	glfwSetMouseButtonCallback(win, on_button);
	glfwSetCursorPosCallback(win, on_cursor);
	glfwSetScrollCallback(win, on_scroll);
}

int
window_run(const scene_opts *so, const window_opts *o, double t0,
    tl_err *e)
{
	double first = NAN;
	scene sc;
	viewer v;
	int r;

	if (scene_open(&sc, so, 0, e) < 0)
		return -1;
	memset(&v, 0, sizeof v);
	v.sc = &sc, v.prog = so->prog;
	v.style = so->style, v.pixels = so->pixels;
	v.nav.orbit = 1, v.readout = 1;
	if (scene_start_camera(&sc, so, e) < 0) {
		scene_close(&sc);
		return -1;
	}
	memcpy(v.home[0], sc.cam.eye, sizeof v.home[0]);
	memcpy(v.home[1], sc.cam.target, sizeof v.home[1]);
	nav_set(&v.nav, v.home[0], v.home[1]);
	attach(gl_ctx_glfw(sc.g), &v);
	r = loop(&v, gl_ctx_glfw(sc.g), o, t0, &first, e);
	if (r == 0 && o->stats)
		scene_print_stats(&sc, stderr, first);
	scene_close(&sc);
	return r;
}
