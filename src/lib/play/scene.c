/* scene.c - the modes' shared scene (see scene.h). */
#include "play/scene.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void
scene_opts_init(scene_opts *o, const char *prog)
{
	memset(o, 0, sizeof *o);
	o->prog = prog;
	o->view = "oblique";
	o->pixels = 1;
	o->cache_mb = 256;
	o->width = 1024, o->height = 768;
	gl_style_init(&o->style);
}

double
scene_clock(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + t.tv_nsec * 1e-9;
}

void
scene_close(scene *sc)
{
	cache_free(sc->k);
	gl_text_free(sc->text);
	gl_render_free(sc->r);
	gl_ctx_close(sc->g);
	free(sc->sel);
	world_close(&sc->w);
}

int
scene_open(scene *sc, const scene_opts *o, int headless, tl_err *e)
{
	memset(sc, 0, sizeof *sc);
	if (world_open(&sc->w, o->dir, e) < 0)
		return -1;
	sc->maxsel = world_blocks(&sc->w);
	if ((sc->sel = tl_alloc(sc->maxsel, sizeof *sc->sel, e)) == NULL ||
	    (sc->g = headless ? gl_ctx_headless(o->width, o->height, e) :
	    gl_ctx_window(o->width, o->height, o->dir, e)) == NULL ||
	    (sc->r = gl_render_new(&sc->w, e)) == NULL ||
	    (sc->text = gl_text_new(e)) == NULL ||
	    (sc->k = cache_new(&sc->w, (size_t)(o->cache_mb * 1048576),
	    gl_render_release, sc->r, e)) == NULL) {
		scene_close(sc);
		return -1;
	}
	sc->cam.fovy = CAMERA_FOVY;
	gl_ctx_size(sc->g, &sc->cam.width, &sc->cam.height);
	return 0;
}

int
scene_start_camera(scene *sc, const scene_opts *o, tl_err *e)
{
	if (o->has_eye || o->has_target) {
		double eye[3], target[3];
		camera c = sc->cam;
		camera_named(&c, &sc->w, "oblique");
		memcpy(eye, o->has_eye ? o->eye : c.eye, sizeof eye);
		memcpy(target, o->has_target ? o->target : c.target,
		    sizeof target);
		camera_look(&sc->cam, &sc->w, eye, target);
		return 0;
	}
	if (camera_named(&sc->cam, &sc->w, o->view) < 0)
		return tl_fail(e, "--view %s: unknown view (overview, "
		    "oblique)", o->view);
	return 0;
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

void
scene_choose(scene *sc, double pixels)
{
	cache_frame(sc->k);
	sc->misses = 0;
	sc->nsel = lod_select(&sc->w, &sc->cam, pixels, ready, sc, sc->sel,
	    sc->maxsel);
	assert(sc->nsel <= sc->maxsel);
}

int
scene_cache_error(scene *sc, tl_err *e)
{
	cache_stats cs;

	cache_get_stats(sc->k, &cs);
	return cs.error[0] != '\0' ? tl_fail(e, "%s", cs.error) : 0;
}

int
scene_settle(scene *sc, double pixels, tl_err *e)
{
	cache_stats cs;
	long loads = -1;

	for (int stuck = 0; stuck < 3;) {
		scene_choose(sc, pixels);
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

int
scene_draw(scene *sc, const gl_style *s, tl_err *e)
{
	gl_render_begin(sc->r, &sc->cam, s, &sc->st);
	for (int k = 0; k < sc->nsel; k++) {
		const lod_block *b = &sc->sel[k];
		cblock *cb = cache_get(sc->k, b->level, b->bi, b->bj);
		if (cb != NULL && gl_render_draw(sc->r, sc->k, cb, b->tau,
		    e) < 0)
			return -1;
	}
	return 0;
}

void
scene_text(scene *sc, const char *text)
{
	gl_text_draw(sc->text, sc->cam.width, sc->cam.height, text);
}

void
scene_levels_text(const gl_render_stats *st, char *buf, size_t n)
{
	size_t len = 0;

	buf[0] = '\0';
	for (int l = 0; l < st->levels && len < n; l++)
		if (st->per_level[l] > 0)
			len += snprintf(buf + len, n - len, "%slevel %d: %ld",
			    len > 0 ? ", " : "", l, st->per_level[l]);
}

void
scene_print_stats(scene *sc, FILE *f, double first)
{
	cache_stats cs;
	char lv[512];

	cache_get_stats(sc->k, &cs);
	scene_levels_text(&sc->st, lv, sizeof lv);
	fprintf(f, "stats: %ld blocks (%s), %ld triangles, %ld skirt "
	    "triangles, first frame %.3f s, cache %.1f MB of %.1f MB, eye "
	    "%.3f,%.3f,%.3f target %.3f,%.3f,%.3f\n", sc->st.blocks, lv,
	    sc->st.tris, sc->st.skirts, first, cs.bytes / 1048576.0,
	    cs.cap / 1048576.0, sc->cam.eye[0], sc->cam.eye[1],
	    sc->cam.eye[2], sc->cam.target[0], sc->cam.target[1],
	    sc->cam.target[2]);
}
