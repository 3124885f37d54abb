/* tileplay - the VGIS pyramid's player: an interactive OpenGL view of a
 * pyramid (GLFW), headless screenshots and scripted flights (EGL, no
 * display needed), and --verify, an alias of tilecheck(1). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/dem.h"
#include "play/gl.h"
#include "core/util.h"
#include "pyramid/verify.h"

static const char *prog = "tileplay";

#define MAXKEY 256 /* keyframes of a --path file */

static void
usage(FILE *f)
{
	fprintf(f, "usage: %s --verify dir [--dem dem] [--tau t,...] "
	    "[-D datum] [-e encoding]\n"
	    "                [-H datum] [-N nodata] [-n name] "
	    "[-s dx[,dy]]\n"
	    "       %s [view options] [--frames n] [--stats] dir\n"
	    "       %s --shot out.png [view options] [--stats] "
	    "[--probe i,j] dir\n"
	    "       %s --fly n [--path file] [--wait] [view options] dir\n"
	    "  --verify dir    check the pyramid in dir: index, blocks, "
	    "borders, saturation,\n"
	    "                  triangulations at a sweep of tolerances\n"
	    "  --dem dem       the DEM it was made from: check its errors "
	    "too\n"
	    "  --tau t,...     tolerances in metres instead of each level's "
	    "sweep\n"
	    "  -D, -e, -H, -N, -n, -s  how to read the DEM, as for "
	    "dem2fqm(1)\n"
	    "  dir             the pyramid to show in a window (keys: "
	    "tileplay(1))\n"
	    "  --shot file     render one picture headless (EGL) into a "
	    "PNG, then exit\n"
	    "  --fly n         fly n frames headless along a path, print "
	    "times and triangles\n"
	    "view options:\n"
	    "  --size WxH      frame size in pixels (1024x768; shots "
	    "640x480)\n"
	    "  --view name     overview (straight down) or oblique (from "
	    "the south-west)\n"
	    "  --eye x,y,z --target x,y,z  a camera in world metres "
	    "instead\n"
	    "  --pixels p      screen-space error tolerance (1; 0: full "
	    "resolution)\n"
	    "  --color mode    height, level or error\n"
	    "  --wire --no-skirts --no-light --readout\n"
	    "  --background r,g,b  clear colour, 0..255\n"
	    "  --cache mb      block cache cap in MB (256)\n"
	    "  --stats         --shot, the window: a line of statistics on "
	    "stderr\n"
	    "  --probe i,j     --shot: where DEM sample (i,j) lands and its "
	    "colour\n"
	    "  --path file     --fly: keyframes, one \"ex ey ez tx ty tz\" a "
	    "line\n"
	    "  --wait          --fly: every frame waits for its blocks\n"
	    "  --frames n      the window: exit after n frames\n",
	    prog, prog, prog, prog);
}

typedef struct {
	vf_args chk;    /* --verify dir, --dem, --tau, the DEM options */
	/* the player */
	const char *dir, *shot, *view, *path;
	int fly, wait, frames, stats, readout, size_set;
	int width, height;
	int has_eye, has_target, has_probe;
	double eye[3], target[3];
	int probe[2];
	double pixels, cache_mb;
	gl_style style;
} options;

/* --verify: tilecheck(1) under its old name, the same library call;
 * exit 1 when it cannot check, as it always did. */
static int
verify(const options *o)
{
	int r = vf_run(&o->chk, prog);

	return r < 0 ? 1 : r;
}

/* --- the player: what every mode shares ------------------------------- */

#define FOVY (50 * M_PI / 180)

typedef struct {
	world w;
	gl_ctx *g;
	gl_render *r;
	cache *k;
	camera cam;
	lod_block *sel;
	int maxsel, nsel;
	long misses;       /* blocks the last selection asked for in vain */
	gl_frame_stats st;
} scene;

static double
now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + t.tv_nsec * 1e-9;
}

static void
scene_close(scene *sc)
{
	cache_free(sc->k);
	gl_render_free(sc->r);
	gl_close(sc->g);
	free(sc->sel);
	world_close(&sc->w);
}

/* The world, a GL context (headless or a window), the renderer and the
 * cache (whose evictions free GPU buffers through gl_release). */
static int
scene_open(scene *sc, const options *o, int headless, tl_err *e)
{
	memset(sc, 0, sizeof *sc);
	if (world_open(&sc->w, o->dir, e) < 0)
		return -1;
	/* every block of every level: more than any selection */
	for (int l = 0; l < sc->w.ix.nlevels; l++)
		sc->maxsel += sc->w.ix.lev[l].blocks[0] *
		    sc->w.ix.lev[l].blocks[1];
	if ((sc->sel = tl_alloc(sc->maxsel, sizeof *sc->sel, e)) == NULL ||
	    (sc->g = headless ? gl_open_headless(o->width, o->height, e) :
	    gl_open_window(o->width, o->height, o->dir, e)) == NULL ||
	    (sc->r = gl_render_new(&sc->w, e)) == NULL ||
	    (sc->k = cache_new(&sc->w, (size_t)(o->cache_mb * 1048576),
	    gl_release, sc->r, e)) == NULL) {
		scene_close(sc);
		return -1;
	}
	sc->cam.fovy = FOVY;
	gl_size(sc->g, &sc->cam.width, &sc->cam.height);
	return 0;
}

/* eye and target in place: up is z, or north when looking straight
 * down or up. */
static void
cam_look(camera *c, const world *w, const double eye[3],
    const double target[3])
{
	double d[3], n = 0;

	for (int a = 0; a < 3; a++) {
		c->eye[a] = eye[a], c->target[a] = target[a];
		d[a] = target[a] - eye[a];
		n += d[a] * d[a];
	}
	n = sqrt(n);
	c->up[0] = 0, c->up[1] = 0, c->up[2] = 1;
	if (n > 0 && fabs(d[2]) > 0.999 * n)
		c->up[1] = 1, c->up[2] = 0;
	cam_fit_depth(c, w);
}

static int
ready(void *ctx, int level, int bi, int bj)
{
	scene *sc = ctx;

	if (cache_get(sc->k, level, bi, bj) != NULL)
		return 1;
	sc->misses++;
	return 0;
}

/* A frame's blocks: takes in the loaded blocks, then chooses, asking the
 * cache for every block the choice looks at (the missing ones load). */
static void
choose(scene *sc, double pixels)
{
	cache_frame(sc->k);
	sc->misses = 0;
	sc->nsel = lod_select(&sc->w, &sc->cam, pixels, ready, sc, sc->sel,
	    sc->maxsel);
}

static int
draw(scene *sc, const gl_style *s, tl_err *e)
{
	gl_begin(sc->r, &sc->cam, s, &sc->st);
	for (int k = 0; k < sc->nsel; k++) {
		const lod_block *b = &sc->sel[k];
		cblock *cb = cache_get(sc->k, b->level, b->bi, b->bj);
		if (cb != NULL && gl_draw(sc->r, sc->k, cb, b->tau, e) < 0)
			return -1;
	}
	return 0;
}

/* Chooses until every block the choice wants is in memory (or no more
 * can come: a cap too small, a broken block), for a complete picture. */
static int
settle(scene *sc, double pixels, tl_err *e)
{
	cache_stats cs;
	long loads = -1;

	for (int stuck = 0; stuck < 3;) {
		choose(sc, pixels);
		if (sc->misses == 0)
			break;
		cache_wait(sc->k);
		cache_get_stats(sc->k, &cs);
		if (cs.error[0] != '\0')
			return tl_fail(e, "%s", cs.error);
		stuck = cs.loads == loads ? stuck + 1 : 0;
		loads = cs.loads;
	}
	return 0;
}

static void
levels_text(const gl_frame_stats *st, char *buf, size_t n)
{
	size_t len = 0;

	buf[0] = '\0';
	for (int l = 0; l < st->levels && len < n; l++)
		if (st->per_level[l] > 0)
			len += snprintf(buf + len, n - len, "%slevel %d: %ld",
			    len > 0 ? ", " : "", l, st->per_level[l]);
}

/* The camera of the options: --eye/--target, else a named view. */
static int
start_camera(scene *sc, const options *o, tl_err *e)
{
	if (o->has_eye || o->has_target) {
		double eye[3], target[3];
		camera c = sc->cam;
		cam_named(&c, &sc->w, "oblique");
		memcpy(eye, o->has_eye ? o->eye : c.eye, sizeof eye);
		memcpy(target, o->has_target ? o->target : c.target,
		    sizeof target);
		cam_look(&sc->cam, &sc->w, eye, target);
		return 0;
	}
	if (cam_named(&sc->cam, &sc->w, o->view) < 0)
		return tl_fail(e, "--view %s: unknown view (overview, "
		    "oblique)", o->view);
	return 0;
}

/* --- headless: one picture --------------------------------------------- */

/* Where level-0 sample (i, j) lands in the frame, and its colour. */
static int
probe(scene *sc, const options *o, tl_err *e)
{
	const pyramid_level *L = &sc->w.ix.lev[0];
	int i = o->probe[0], j = o->probe[1], bi, bj;
	double p[3], eye[4], clip[4];
	float view[16], proj[16];
	unsigned char rgb[3];
	char path[4096];
	pyramid_block b;
	float z;

	if (i < 0 || j < 0 || i >= sc->w.ix.size0[0] || j >= sc->w.ix.size0[1])
		return tl_fail(e, "--probe %d,%d: outside the %dx%d level 0", i,
		    j, sc->w.ix.size0[0], sc->w.ix.size0[1]);
	bi = i / BT_CELLS < L->blocks[0] ? i / BT_CELLS : L->blocks[0] - 1;
	bj = j / BT_CELLS < L->blocks[1] ? j / BT_CELLS : L->blocks[1] - 1;
	if (pyramid_block_alloc(&b, L->displaced, e) < 0)
		return -1;
	b.level = 0, b.bi = bi, b.bj = bj;
	pyramid_block_path(path, sizeof path, sc->w.dir, 0, bi, bj);
	if (pyramid_block_read(path, &b, e) < 0) {
		pyramid_block_free(&b);
		return -1;
	}
	z = b.z[(j - bj * BT_CELLS) * BT_SIZE + i - bi * BT_CELLS];
	pyramid_block_free(&b);
	world_pos(&sc->w, i, j, 0, 0, z, p);
	cam_matrices(&sc->cam, view, proj);
	/* column-major: clip = proj (view (p, 1)) */
	for (int r = 0; r < 4; r++) {
		eye[r] = view[12 + r];
		for (int a = 0; a < 3; a++)
			eye[r] += view[4 * a + r] * p[a];
	}
	for (int r = 0; r < 4; r++) {
		clip[r] = 0;
		for (int a = 0; a < 4; a++)
			clip[r] += proj[4 * a + r] * eye[a];
	}
	gl_height_rgb(sc->r, z, rgb);
	printf("probe %d,%d: height %.6g m, world %.3f,%.3f,%.3f, pixel %d "
	    "%d, colour %d %d %d\n", i, j, z, p[0], p[1], p[2],
	    (int)floor((clip[0] / clip[3] + 1) / 2 * sc->cam.width),
	    (int)floor((1 - clip[1] / clip[3]) / 2 * sc->cam.height),
	    rgb[0], rgb[1], rgb[2]);
	return 0;
}

static void
print_stats(scene *sc, double first)
{
	cache_stats cs;
	char lv[512];

	cache_get_stats(sc->k, &cs);
	levels_text(&sc->st, lv, sizeof lv);
	fprintf(stderr, "stats: %ld blocks (%s), %ld triangles, %ld skirt "
	    "triangles, first frame %.3f s, cache %.1f MB of %.1f MB, eye "
	    "%.3f,%.3f,%.3f target %.3f,%.3f,%.3f\n", sc->st.blocks, lv,
	    sc->st.tris, sc->st.skirts, first, cs.bytes / 1048576.0,
	    cs.cap / 1048576.0, sc->cam.eye[0], sc->cam.eye[1],
	    sc->cam.eye[2], sc->cam.target[0], sc->cam.target[1],
	    sc->cam.target[2]);
}

static int
shot(const options *o, double t0)
{
	scene sc;
	tl_err e;
	unsigned char *rgb = NULL;

	if (scene_open(&sc, o, 1, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		return 1;
	}
	if (start_camera(&sc, o, &e) < 0 || settle(&sc, o->pixels, &e) < 0 ||
	    draw(&sc, &o->style, &e) < 0 ||
	    (rgb = tl_alloc((size_t)o->width * o->height, 3, &e)) == NULL)
		goto fail;
	if (sc.misses > 0)
		tl_warn(prog, "%s: %ld blocks do not fit in the cache (--cache "
		    "%g): coarser ones drawn instead", o->dir, sc.misses,
		    o->cache_mb);
	if (o->readout) {
		char text[256];
		snprintf(text, sizeof text, "%ld triangles, %ld blocks, "
		    "%.3g px", sc.st.tris, sc.st.blocks, o->pixels);
		gl_text(sc.r, text);
	}
	gl_read_rgb(sc.g, rgb);
	if (o->stats)
		print_stats(&sc, now() - t0);
	if (o->has_probe && probe(&sc, o, &e) < 0)
		goto fail;
	/* GL's memory goes before OpenImageIO's comes */
	scene_close(&sc);
	if (gl_write_image(o->shot, o->width, o->height, rgb, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		free(rgb);
		return 1;
	}
	free(rgb);
	return 0;
fail:
	tl_warn(prog, "%s", e.msg);
	free(rgb);
	scene_close(&sc);
	return 1;
}

/* --- headless: a scripted flight ----------------------------------------- */

typedef struct {
	double eye[3], target[3];
} keyframe;

/* The built-in path: a low circle about the DEM's centre, radius 0.35 of
 * the smaller extent, 10 degrees above the highest point's plane,
 * looking at the centre 10 degrees down; one turn from the south. */
static int
builtin_path(const world *w, keyframe *k)
{
	double a[3], b[3], r, alt, drop;
	int n = 0;

	world_pos(w, 0, 0, 0, 0, 0, a);
	world_pos(w, w->ix.size0[0] - 1, w->ix.size0[1] - 1, 0, 0, 0, b);
	r = 0.35 * fmin(fabs(b[0] - a[0]), fabs(b[1] - a[1]));
	alt = w->zmax + r * tan(10 * M_PI / 180);
	drop = r * tan(10 * M_PI / 180);
	for (int q = 0; q <= 36; q++, n++) {
		double t = -M_PI / 2 + 2 * M_PI * q / 36;
		k[n].eye[0] = r * cos(t), k[n].eye[1] = r * sin(t);
		k[n].eye[2] = alt;
		k[n].target[0] = k[n].target[1] = 0;
		k[n].target[2] = alt - drop;
	}
	return n;
}

static int
read_path(const char *path, keyframe *k, tl_err *e)
{
	FILE *f = fopen(path, "r");
	char line[1024];
	int n = 0, no = 0;

	if (f == NULL)
		return tl_failsys(e, "%s", path);
	while (fgets(line, sizeof line, f) != NULL) {
		keyframe *q = &k[n];
		char *s = line + strspn(line, " \t");
		no++;
		if (*s == '#' || *s == '\n' || *s == '\0')
			continue;
		if (n == MAXKEY || sscanf(s, "%lf %lf %lf %lf %lf %lf",
		    &q->eye[0], &q->eye[1], &q->eye[2], &q->target[0],
		    &q->target[1], &q->target[2]) != 6) {
			fclose(f);
			return tl_fail(e, "%s:%d: expected \"ex ey ez tx ty tz\" "
			    "(at most %d lines)", path, no, MAXKEY);
		}
		n++;
	}
	fclose(f);
	if (n == 0)
		return tl_fail(e, "%s: no keyframes", path);
	return n;
}

/* The camera of frame f of n, linear between the keyframes. */
static void
fly_camera(scene *sc, const keyframe *k, int nk, int f, int n)
{
	double s = n > 1 ? (double)f / (n - 1) * (nk - 1) : 0, t, eye[3],
	    target[3];
	int a = (int)floor(s);

	if (a >= nk - 1)
		a = nk > 1 ? nk - 2 : 0;
	t = nk > 1 ? s - a : 0;
	for (int q = 0; q < 3; q++) {
		const keyframe *b = &k[nk > 1 ? a + 1 : a];
		eye[q] = k[a].eye[q] + t * (b->eye[q] - k[a].eye[q]);
		target[q] = k[a].target[q] + t * (b->target[q] - k[a].target[q]);
	}
	cam_look(&sc->cam, &sc->w, eye, target);
}

typedef struct {
	double sum, max, tris;
} flight;

/* Frame f: chosen and drawn as the window would, the missing blocks
 * loading behind; with --wait (and always for frame 0, the first
 * complete picture) after waiting for them. ms is the drawing's time:
 * choosing, drawing and glFinish; wait_ms the waiting's. */
static int
fly_frame(scene *sc, const options *o, const keyframe *k, int nk, int f,
    flight *fl, tl_err *e)
{
	double t = now(), tw, ms;
	cache_stats cs;

	fly_camera(sc, k, nk, f, o->fly);
	if ((f == 0 || o->wait) && settle(sc, o->pixels, e) < 0)
		return -1;
	tw = now();
	choose(sc, o->pixels);
	if (draw(sc, &o->style, e) < 0)
		return -1;
	gl_present(sc->g);
	ms = (now() - tw) * 1000;
	cache_get_stats(sc->k, &cs);
	if (cs.error[0] != '\0')
		return tl_fail(e, "%s", cs.error);
	printf("%d %.2f %.2f %ld %ld %zu %ld\n", f, ms, (tw - t) * 1000,
	    sc->st.tris, sc->st.blocks, cs.bytes, sc->misses);
	fl->sum += ms, fl->tris += sc->st.tris;
	fl->max = fmax(fl->max, ms);
	return 0;
}

static int
fly(const options *o, double t0)
{
	static keyframe k[MAXKEY];
	scene sc;
	flight fl = { 0, 0, 0 };
	cache_stats cs;
	double first = 0;
	tl_err e;
	int nk;

	if (scene_open(&sc, o, 1, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		return 1;
	}
	nk = o->path ? read_path(o->path, k, &e) : builtin_path(&sc.w, k);
	if (nk < 0)
		goto fail;
	printf("# frame ms wait_ms triangles blocks cache_bytes missing\n");
	for (int f = 0; f < o->fly; f++) {
		if (fly_frame(&sc, o, k, nk, f, &fl, &e) < 0)
			goto fail;
		if (f == 0)
			first = now() - t0;
	}
	cache_get_stats(sc.k, &cs);
	printf("# %d frames at %.3g px, %dx%d: frame time mean %.2f ms, max "
	    "%.2f ms; triangles mean %.0f; first frame %.3f s; cache peak "
	    "%zu of %zu bytes (%.1f of %.1f MB), %ld loads, %ld evictions\n",
	    o->fly, o->pixels, o->width, o->height, fl.sum / o->fly, fl.max,
	    fl.tris / o->fly, first, cs.peak, cs.cap, cs.peak / 1048576.0,
	    cs.cap / 1048576.0, cs.loads, cs.evictions);
	scene_close(&sc);
	return 0;
fail:
	tl_warn(prog, "%s", e.msg);
	scene_close(&sc);
	return 1;
}

/* --- the window ---------------------------------------------------------- */

/* The camera as the keys and mouse move it: an eye, a heading (yaw from
 * east, counter-clockwise), a pitch and the distance to what it looks
 * at, which orbiting turns about. */
typedef struct {
	scene *sc;
	gl_style style;
	double pixels;
	double eye[3], yaw, pitch, dist;
	double home[2][3]; /* eye and target of the start view */
	int orbit, readout, shots, drag;
	double mx, my;     /* the mouse when a drag moved last */
	int shoot;         /* a screenshot is asked for */
} viewer;

static void
look_dir(const viewer *v, double d[3])
{
	d[0] = cos(v->pitch) * cos(v->yaw);
	d[1] = cos(v->pitch) * sin(v->yaw);
	d[2] = sin(v->pitch);
}

static void
view_set(viewer *v, const double eye[3], const double target[3])
{
	double d[3], n;

	for (int a = 0; a < 3; a++)
		d[a] = target[a] - eye[a], v->eye[a] = eye[a];
	n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	v->dist = n > 1 ? n : 1;
	/* straight down: heading north, so north is up on the screen */
	v->yaw = hypot(d[0], d[1]) > 1e-9 * v->dist ? atan2(d[1], d[0]) :
	    M_PI / 2;
	v->pitch = asin(fmax(-1, fmin(1, d[2] / v->dist)));
	/* never exactly vertical: the heading stays defined */
	v->pitch = fmax(-1.55, fmin(1.55, v->pitch));
}

static void
view_camera(viewer *v)
{
	double d[3], t[3];

	look_dir(v, d);
	for (int a = 0; a < 3; a++)
		t[a] = v->eye[a] + v->dist * d[a];
	v->sc->cam.up[0] = 0, v->sc->cam.up[1] = 0, v->sc->cam.up[2] = 1;
	memcpy(v->sc->cam.eye, v->eye, sizeof v->eye);
	memcpy(v->sc->cam.target, t, sizeof t);
	cam_fit_depth(&v->sc->cam, &v->sc->w);
}

/* Turn: orbit about the target, or look about from the eye. */
static void
view_turn(viewer *v, double dyaw, double dpitch)
{
	double d[3], t[3];

	look_dir(v, d);
	for (int a = 0; a < 3; a++)
		t[a] = v->eye[a] + v->dist * d[a];
	v->yaw += dyaw;
	v->pitch = fmax(-1.55, fmin(1.55, v->pitch + dpitch));
	if (v->orbit) {
		look_dir(v, d);
		for (int a = 0; a < 3; a++)
			v->eye[a] = t[a] - v->dist * d[a];
	}
}

/* Moves the eye (and what it looks at) along the heading, sideways and
 * up, in metres. */
static void
view_move(viewer *v, double fwd, double side, double up)
{
	v->eye[0] += fwd * cos(v->yaw) + side * sin(v->yaw);
	v->eye[1] += fwd * sin(v->yaw) - side * cos(v->yaw);
	v->eye[2] += up;
}

static void
view_named(viewer *v, const char *name)
{
	camera c = v->sc->cam;

	cam_named(&c, &v->sc->w, name);
	view_set(v, c.eye, c.target);
}

static void
on_scroll(GLFWwindow *win, double dx, double dy)
{
	viewer *v = glfwGetWindowUserPointer(win);
	double d[3], f = pow(0.85, dy);

	(void)dx;
	/* towards what it looks at, which stays */
	look_dir(v, d);
	for (int a = 0; a < 3; a++)
		v->eye[a] += (1 - f) * v->dist * d[a];
	v->dist *= f;
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

	v->mx = x, v->my = y;
	if (v->drag == GLFW_MOUSE_BUTTON_LEFT + 1)
		view_turn(v, -dx * 0.005, (v->orbit ? 1 : -1) * dy * 0.005);
	else if (v->drag == GLFW_MOUSE_BUTTON_RIGHT + 1) {
		/* pan: the point under the mouse follows it, roughly */
		double k = 2 * v->dist * tan(FOVY / 2) / v->sc->cam.height;
		view_move(v, 0, -dx * k, 0);
		v->eye[2] += dy * k * cos(v->pitch);
	}
}

static void
on_key(GLFWwindow *win, int key, int code, int action, int mods)
{
	viewer *v = glfwGetWindowUserPointer(win);

	(void)code, (void)mods;
	if (action != GLFW_PRESS)
		return;
	switch (key) {
	case GLFW_KEY_ESCAPE: case GLFW_KEY_Q:
		glfwSetWindowShouldClose(win, 1);
		break;
	case GLFW_KEY_EQUAL: case GLFW_KEY_KP_ADD:
		v->pixels = v->pixels > 0 ? v->pixels * M_SQRT2 : 0.25;
		break;
	case GLFW_KEY_MINUS: case GLFW_KEY_KP_SUBTRACT:
		v->pixels = v->pixels > 0.25 ? v->pixels / M_SQRT2 : 0;
		break;
	case GLFW_KEY_C:
		v->style.colour = (v->style.colour + 1) % GL_NCOLOUR;
		break;
	case GLFW_KEY_G: v->style.wire = !v->style.wire; break;
	case GLFW_KEY_K: v->style.skirts = !v->style.skirts; break;
	case GLFW_KEY_L: v->style.light = !v->style.light; break;
	case GLFW_KEY_H: v->readout = !v->readout; break;
	case GLFW_KEY_P: v->shoot = 1; break;
	case GLFW_KEY_TAB: v->orbit = !v->orbit; break;
	case GLFW_KEY_HOME: case GLFW_KEY_Z:
		view_set(v, v->home[0], v->home[1]);
		break;
	case GLFW_KEY_1: view_named(v, "overview"); break;
	case GLFW_KEY_2: view_named(v, "oblique"); break;
	}
}

/* The held keys move the eye, at a speed that grows with its height
 * over the terrain's lowest point (Shift: 5x). */
static void
view_keys(viewer *v, GLFWwindow *win, double dt)
{
	double sp = fmax(20, v->eye[2] - v->sc->w.zmin) * dt;
	int k[6] = { GLFW_KEY_W, GLFW_KEY_S, GLFW_KEY_A, GLFW_KEY_D,
		GLFW_KEY_R, GLFW_KEY_F };
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
	view_move(v, sp * (on[0] - on[1]), sp * (on[3] - on[2]),
	    sp * (on[4] - on[5]));
}

static void
readout(viewer *v, double ms)
{
	const gl_frame_stats *st = &v->sc->st;
	cache_stats cs;
	char text[1024], lv[512];

	cache_get_stats(v->sc->k, &cs);
	levels_text(st, lv, sizeof lv);
	snprintf(text, sizeof text, "frame %.1f ms   tolerance %.3g px   "
	    "colour: %s   %s\n"
	    "%ld triangles (+%ld skirt)   %ld blocks: %s\n"
	    "cache %.1f of %.0f MB, %ld waiting",
	    ms, v->pixels, gl_colour_name(v->style.colour),
	    v->orbit ? "orbit" : "fly", st->tris, st->skirts, st->blocks, lv,
	    cs.bytes / 1048576.0, cs.cap / 1048576.0, v->sc->misses);
	gl_text(v->sc->r, text);
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
	gl_read_rgb(v->sc->g, rgb);
	r = gl_write_image(name, w, h, rgb, e);
	free(rgb);
	if (r == 0)
		fprintf(stderr, "%s: wrote %s\n", prog, name);
	return r;
}

static int
view_frame(viewer *v, double ms, tl_err *e)
{
	gl_size(v->sc->g, &v->sc->cam.width, &v->sc->cam.height);
	if (v->sc->cam.width < 1 || v->sc->cam.height < 1)
		return 0; /* minimised */
	view_camera(v);
	choose(v->sc, v->pixels);
	if (draw(v->sc, &v->style, e) < 0)
		return -1;
	if (v->shoot) {
		v->shoot = 0;
		if (screenshot(v, e) < 0)
			tl_warn(prog, "%s", e->msg); /* the view goes on */
	}
	if (v->readout)
		readout(v, ms);
	gl_present(v->sc->g);
	return 0;
}

static int
view(const options *o, double t0)
{
	scene sc;
	viewer v;
	GLFWwindow *win;
	double last, ms = 0, first = NAN;
	tl_err e;
	int r = 0;

	if (scene_open(&sc, o, 0, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		return 1;
	}
	memset(&v, 0, sizeof v);
	v.sc = &sc, v.style = o->style, v.pixels = o->pixels;
	v.orbit = 1, v.readout = 1;
	if (start_camera(&sc, o, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		scene_close(&sc);
		return 1;
	}
	memcpy(v.home[0], sc.cam.eye, sizeof v.home[0]);
	memcpy(v.home[1], sc.cam.target, sizeof v.home[1]);
	view_set(&v, v.home[0], v.home[1]);
	win = gl_window(sc.g);
	glfwSetWindowUserPointer(win, &v);
	glfwSetKeyCallback(win, on_key);
	glfwSetMouseButtonCallback(win, on_button);
	glfwSetCursorPosCallback(win, on_cursor);
	glfwSetScrollCallback(win, on_scroll);
	last = now();
	for (int f = 0; !glfwWindowShouldClose(win) &&
	    (o->frames == 0 || f < o->frames); f++) {
		double t = now();
		cache_stats cs;
		ms = (t - last) * 1000, last = t;
		glfwPollEvents();
		view_keys(&v, win, ms / 1000);
		if ((r = view_frame(&v, ms, &e)) < 0)
			break;
		if (isnan(first) && sc.misses == 0)
			first = now() - t0; /* the first complete picture */
		cache_get_stats(sc.k, &cs);
		if (cs.error[0] != '\0') {
			tl_fail(&e, "%s", cs.error);
			r = -1;
			break;
		}
	}
	if (r < 0)
		tl_warn(prog, "%s", e.msg);
	else if (o->stats)
		print_stats(&sc, first);
	scene_close(&sc);
	return r < 0;
}

/* --- options -------------------------------------------------------- */

/* Exactly n numbers separated by sep: "x,y,z", "WxH". */
static int
parse_nums(const char *s, int sep, double *v, int n)
{
	char buf[256], *p = buf, *q;

	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	for (int k = 0; k < n; k++, p = q + 1) {
		q = k < n - 1 ? strchr(p, sep) : p + strlen(p);
		if (q == NULL)
			return -1;
		*q = '\0';
		if (tl_parse_double(p, &v[k]) < 0)
			return -1;
	}
	return 0;
}

enum { OPT_VERIFY = 256, OPT_DEM, OPT_TAU, OPT_SHOT, OPT_FLY, OPT_PATH,
	OPT_FRAMES, OPT_SIZE, OPT_VIEW, OPT_EYE, OPT_TARGET, OPT_PIXELS,
	OPT_COLOR, OPT_WIRE, OPT_NOSKIRTS, OPT_NOLIGHT, OPT_BACKGROUND,
	OPT_CACHE, OPT_STATS, OPT_PROBE, OPT_READOUT, OPT_WAIT };

static int
bad(const char *opt, const char *arg, const char *want)
{
	tl_warn(prog, "%s %s: expected %s", opt, arg, want);
	return 3;
}

/* The player's options, as option(). */
static int
player_option(int c, const char *arg, options *o)
{

	double v[3];

	switch (c) {
	case OPT_SHOT: o->shot = arg; return 0;
	case OPT_PATH: o->path = arg; return 0;
	case OPT_VIEW: o->view = arg; return 0;
	case OPT_WIRE: o->style.wire = 1; return 0;
	case OPT_NOSKIRTS: o->style.skirts = 0; return 0;
	case OPT_NOLIGHT: o->style.light = 0; return 0;
	case OPT_STATS: o->stats = 1; return 0;
	case OPT_READOUT: o->readout = 1; return 0;
	case OPT_WAIT: o->wait = 1; return 0;
	case OPT_FLY:
		if (tl_parse_int(arg, &o->fly) < 0 || o->fly < 1)
			return bad("--fly", arg, "a number of frames >= 1");
		return 0;
	case OPT_FRAMES:
		if (tl_parse_int(arg, &o->frames) < 0 || o->frames < 1)
			return bad("--frames", arg, "a number of frames >= 1");
		return 0;
	case OPT_SIZE:
		if (parse_nums(arg, 'x', v, 2) < 0 || v[0] < 16 || v[1] < 16 ||
		    v[0] > 16384 || v[1] > 16384 || v[0] != floor(v[0]) ||
		    v[1] != floor(v[1]))
			return bad("--size", arg, "WxH, 16 to 16384 pixels");
		o->width = (int)v[0], o->height = (int)v[1], o->size_set = 1;
		return 0;
	case OPT_EYE: case OPT_TARGET:
		if (parse_nums(arg, ',', c == OPT_EYE ? o->eye : o->target,
		    3) < 0)
			return bad(c == OPT_EYE ? "--eye" : "--target", arg,
			    "x,y,z in world metres");
		*(c == OPT_EYE ? &o->has_eye : &o->has_target) = 1;
		return 0;
	case OPT_PIXELS:
		if (tl_parse_double(arg, &o->pixels) < 0 || o->pixels < 0)
			return bad("--pixels", arg, "a tolerance >= 0");
		return 0;
	case OPT_COLOR:
		if (gl_colour_parse(arg, &o->style.colour) < 0)
			return bad("--color", arg, "height, level or error");
		return 0;
	case OPT_BACKGROUND:
		if (parse_nums(arg, ',', v, 3) < 0)
			return bad("--background", arg, "r,g,b, 0 to 255");
		for (int k = 0; k < 3; k++) {
			if (v[k] < 0 || v[k] > 255)
				return bad("--background", arg, "r,g,b, 0 to 255");
			o->style.background[k] = (float)(v[k] / 255);
		}
		return 0;
	case OPT_CACHE:
		if (tl_parse_double(arg, &o->cache_mb) < 0 || o->cache_mb < 1 ||
		    o->cache_mb > 1048576)
			return bad("--cache", arg, "megabytes, >= 1");
		return 0;
	case OPT_PROBE:
		if (parse_nums(arg, ',', v, 2) < 0 || v[0] != floor(v[0]) ||
		    v[1] != floor(v[1]) || fabs(v[0]) > 1e9 || fabs(v[1]) > 1e9)
			return bad("--probe", arg, "i,j: a level-0 column and row");
		o->probe[0] = (int)v[0], o->probe[1] = (int)v[1];
		o->has_probe = 1;
		return 0;
	}
	usage(stderr);
	return 3;
}

/* 0: go on; else the exit status + 1. */
static int
option(int c, const char *arg, options *o)
{
	tl_err e;

	switch (c) {
	case OPT_VERIFY:
		o->chk.dir = arg;
		return 0;
	case OPT_DEM:
		o->chk.dem_path = arg;
		return 0;
	case OPT_TAU:
		if (vf_parse_taus(&o->chk, arg) == 0)
			return 0;
		tl_warn(prog, "--tau %s: expected up to %d numbers >= 0, "
		    "comma-separated", arg, VF_MAXTAU);
		return 3;
	case 'h':
		usage(stdout);
		return 1;
	case 'V':
		printf("%s %s\n", prog, TL_VERSION);
		return 1;
	}
	switch (dem_option(&o->chk.dem, c, arg, &e)) {
	case 1:
		return 0;
	case -1:
		tl_warn(prog, "%s", e.msg);
		return 3;
	}
	return player_option(c, arg, o);
}

static void
defaults(options *o)
{
	memset(o, 0, sizeof *o);
	o->view = "oblique";
	o->pixels = 1;
	o->cache_mb = 256;
	o->width = 1024, o->height = 768;
	gl_style_init(&o->style);
}

/* The player's options that only make sense together. */
static int
player_usage(options *o)
{
	if (o->shot != NULL && o->fly > 0) {
		tl_warn(prog, "--shot and --fly: one at a time");
		return 2;
	}
	if (o->has_eye && o->has_target && o->eye[0] == o->target[0] &&
	    o->eye[1] == o->target[1] && o->eye[2] == o->target[2]) {
		tl_warn(prog, "--eye and --target: the same point");
		return 2;
	}
	if (o->has_probe && o->shot == NULL) {
		tl_warn(prog, "--probe: only with --shot");
		return 2;
	}
	if (o->stats && o->fly > 0) {
		tl_warn(prog, "--stats: not with --fly (it prints its own)");
		return 2;
	}
	if (o->frames > 0 && (o->shot != NULL || o->fly > 0)) {
		tl_warn(prog, "--frames: only with the window");
		return 2;
	}
	if ((o->path != NULL || o->wait) && o->fly == 0) {
		tl_warn(prog, "%s: only with --fly", o->wait ? "--wait" :
		    "--path");
		return 2;
	}
	if (o->view != NULL && strcmp(o->view, "overview") != 0 &&
	    strcmp(o->view, "oblique") != 0) {
		tl_warn(prog, "--view %s: unknown view (overview, oblique)",
		    o->view);
		return 2;
	}
	if ((o->shot != NULL || o->fly > 0) && !o->size_set)
		o->width = 640, o->height = 480;
	return 0;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "verify", required_argument, NULL, OPT_VERIFY },
		{ "dem", required_argument, NULL, OPT_DEM },
		{ "tau", required_argument, NULL, OPT_TAU },
		{ "shot", required_argument, NULL, OPT_SHOT },
		{ "fly", required_argument, NULL, OPT_FLY },
		{ "path", required_argument, NULL, OPT_PATH },
		{ "frames", required_argument, NULL, OPT_FRAMES },
		{ "size", required_argument, NULL, OPT_SIZE },
		{ "view", required_argument, NULL, OPT_VIEW },
		{ "eye", required_argument, NULL, OPT_EYE },
		{ "target", required_argument, NULL, OPT_TARGET },
		{ "pixels", required_argument, NULL, OPT_PIXELS },
		{ "color", required_argument, NULL, OPT_COLOR },
		{ "wire", no_argument, NULL, OPT_WIRE },
		{ "no-skirts", no_argument, NULL, OPT_NOSKIRTS },
		{ "no-light", no_argument, NULL, OPT_NOLIGHT },
		{ "background", required_argument, NULL, OPT_BACKGROUND },
		{ "cache", required_argument, NULL, OPT_CACHE },
		{ "stats", no_argument, NULL, OPT_STATS },
		{ "probe", required_argument, NULL, OPT_PROBE },
		{ "readout", no_argument, NULL, OPT_READOUT },
		{ "wait", no_argument, NULL, OPT_WAIT },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	double t0 = now();
	options o;
	int c, r;

	defaults(&o);
	while ((c = getopt_long(argc, argv, DEM_OPTS "hV", longopts, NULL)) !=
	    -1)
		if ((r = option(c, optarg, &o)) != 0)
			return r - 1;
	if (o.chk.dir != NULL) {
		if (optind < argc) {
			usage(stderr);
			return 2;
		}
		return verify(&o);
	}
	if (optind != argc - 1) {
		usage(stderr);
		return 2;
	}
	o.dir = argv[optind];
	if ((r = player_usage(&o)) != 0)
		return r;
	return o.shot ? shot(&o, t0) : o.fly ? fly(&o, t0) : view(&o, t0);
}
