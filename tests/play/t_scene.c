/* t_scene - what the modes share, headless on a real pyramid: the
 * default options, the start camera (a named view, --eye/--target, an
 * unknown view), settling until every wanted block is in memory, a
 * frame's stats, the --stats line; a missing pyramid. */
#include <math.h>

#include "play/scene.h"
#include "fixture.h"

static void
test_opts(void)
{
	scene_opts o;

	scene_opts_init(&o, "t_scene");
	ok(strcmp(o.view, "oblique") == 0 && o.pixels == 1 &&
	    o.cache_mb == 256 && o.width == 1024 && o.height == 768 &&
	    !o.has_eye && o.style.skirts, "defaults: oblique, 1 px, 256 MB, "
	    "1024x768");
}

static void
test_camera(scene *sc, scene_opts *o)
{
	camera named;
	tl_err e;

	o->view = "overview";
	ok(scene_start_camera(sc, o, &e) == 0 && sc->cam.up[1] == 1,
	    "--view overview: straight down, north up");
	named = sc->cam;
	o->has_eye = 1;
	o->eye[0] = -5000, o->eye[1] = -5000, o->eye[2] = 5000;
	ok(scene_start_camera(sc, o, &e) == 0 && sc->cam.eye[0] == -5000 &&
	    sc->cam.target[2] != named.target[2], "--eye alone: the target "
	    "of the oblique view");
	o->has_eye = 0;
	o->view = "side";
	ok(scene_start_camera(sc, o, &e) < 0 && strcmp(e.msg, "--view side: "
	    "unknown view (overview, oblique)") == 0, "an unknown view: %s",
	    e.msg);
	o->view = "oblique";
	scene_start_camera(sc, o, &e);
}

static void
test_frame(scene *sc, const scene_opts *o)
{
	char lv[512], path[512], line[1024];
	tl_err e;
	long sum = 0;
	int fd, r;

	r = scene_settle(sc, 1, &e);
	ok(r == 0 && sc->misses == 0 && sc->nsel > 0,
	    "settled: %d blocks chosen, none missing", sc->nsel);
	r = scene_draw(sc, &o->style, &e);
	ok(r == 0 && sc->st.blocks == sc->nsel && sc->st.tris > 0,
	    "drawn: %ld blocks, %ld triangles", sc->st.blocks, sc->st.tris);
	for (int l = 0; l < sc->st.levels; l++)
		sum += sc->st.per_level[l];
	scene_levels_text(&sc->st, lv, sizeof lv);
	ok(sum == sc->st.blocks && strncmp(lv, "level ", 6) == 0,
	    "per level: %s", lv);
	ok(scene_cache_error(sc, &e) == 0, "no load error");
	snprintf(path, sizeof path, "%s/stats", fx_tmp);
	fd = fx_redirect(2, path);
	scene_print_stats(sc, stderr, 0.25);
	fx_restore(2, fd);
	ok(fx_grep(path, "stats: ", line, sizeof line) == 0 &&
	    strstr(line, "first frame 0.250 s, cache ") != NULL &&
	    strstr(line, " MB of 256.0 MB, eye ") != NULL,
	    "the --stats line: %.60s...", line);
}

int
main(int argc, char **argv)
{
	scene_opts o;
	scene sc;
	tl_err e;
	char dir[512];
	gl_ctx *g;

	(void)argc;
	if (fx_init(argv[0], "t_scene") < 0)
		return 1;
	test_opts();
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	if ((g = fx_headless(16, 16)) == NULL)
		goto done;
	gl_ctx_close(g);
	scene_opts_init(&o, "t_scene");
	o.width = 320, o.height = 240;
	fx_dir("none", dir, sizeof dir);
	o.dir = dir;
	ok(scene_open(&sc, &o, 1, &e) < 0 && strstr(e.msg, "index.json") !=
	    NULL, "no pyramid: %s", e.msg);
	fx_dir("bt", dir, sizeof dir);
	if (!ok(scene_open(&sc, &o, 1, &e) == 0 && sc.cam.width == 320 &&
	    sc.cam.height == 240 && sc.maxsel == world_blocks(&sc.w),
	    "a headless scene, 320x240"))
		goto done;
	test_camera(&sc, &o);
	test_frame(&sc, &o);
	scene_close(&sc);
done:
	fx_done();
	return tap_done();
}
