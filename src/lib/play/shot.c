/* shot.c - one picture, headless (see shot.h). */
#include "play/shot.h"

#include <stdlib.h>

#include "base/outfile.h"
#include "raster/oiio_plugin.h"
#include "base/paths.h"

/* Level-0 sample (i, j)'s height, read from its block. */
static int
sample(const world *w, int i, int j, float *z, tl_err *e)
{
	const pyramid_level *L = &w->ix.lev[0];
	int bi = i / BT_CELLS < L->blocks[0] ? i / BT_CELLS : L->blocks[0] - 1;
	int bj = j / BT_CELLS < L->blocks[1] ? j / BT_CELLS : L->blocks[1] - 1;
	pyramid_block b;

	if (pyramid_block_alloc(&b, L->displaced, e) < 0)
		return -1;
	b.level = 0, b.bi = bi, b.bj = bj;
	if (pyramid_block_load(w->dir, &w->ix, &b, e) < 0) {
		pyramid_block_free(&b);
		return -1;
	}
	*z = b.z[(j - bj * BT_CELLS) * BT_SIZE + i - bi * BT_CELLS];
	pyramid_block_free(&b);
	return 0;
}

int
shot_probe(scene *sc, int i, int j, FILE *f, tl_err *e)
{
	const world *w = &sc->w;
	double p[3];
	unsigned char rgb[3];
	int px[2];
	float z;

	if (i < 0 || j < 0 || i >= w->ix.size0[0] || j >= w->ix.size0[1])
		return tl_fail(e, "--probe %d,%d: outside the %dx%d level 0", i,
		    j, w->ix.size0[0], w->ix.size0[1]);
	if (sample(w, i, j, &z, e) < 0)
		return -1;
	world_pos(w, i, j, 0, 0, z, p);
	camera_project(&sc->cam, p, px);
	gl_render_height_rgb(sc->r, z, rgb);
	fprintf(f, "probe %d,%d: height %.6g m, world %.3f,%.3f,%.3f, pixel "
	    "%d %d, colour %d %d %d\n", i, j, z, p[0], p[1], p[2], px[0],
	    px[1], rgb[0], rgb[1], rgb[2]);
	return 0;
}

/* Draws the picture into the scene's frame and reads it back into rgb;
 * the stats and the probe while the scene is there. */
static int
picture(scene *sc, const scene_opts *so, const shot_opts *o, double t0,
    unsigned char *rgb, tl_err *e)
{
	if (scene_start_camera(sc, so, e) < 0 ||
	    scene_settle(sc, so->pixels, e) < 0 ||
	    scene_draw(sc, &so->style, e) < 0)
		return -1;
	if (sc->misses > 0)
		tl_warn(so->prog, "%s: %ld blocks do not fit in the cache "
		    "(--cache %g): coarser ones drawn instead", so->dir,
		    sc->misses, so->cache_mb);
	if (o->readout) {
		char text[256];
		snprintf(text, sizeof text, "%ld triangles, %ld blocks, "
		    "%.3g px", sc->st.tris, sc->st.blocks, so->pixels);
		scene_text(sc, text);
	}
	gl_ctx_read_rgb(sc->g, rgb);
	if (o->stats)
		scene_print_stats(sc, stderr, scene_clock() - t0);
	if (o->has_probe && shot_probe(sc, o->probe[0], o->probe[1], stdout,
	    e) < 0)
		return -1;
	return 0;
}

int
shot_run(const scene_opts *so, const shot_opts *o, double t0, tl_err *e)
{
	unsigned char *rgb;
	scene sc;
	int r;

	/* the picture kept off the pyramid's files (paths.h) */
	if (tl_path_check(o->path, so->dir, "pyramid", TL_PATH_TREE, e) < 0 ||
	    (rgb = tl_alloc((size_t)so->width * so->height, 3, e)) == NULL)
		return -1;
	if (scene_open(&sc, so, 1, e) < 0) {
		free(rgb);
		return -1;
	}
	r = picture(&sc, so, o, t0, rgb, e);
	/* GL's memory goes before OpenImageIO's comes */
	scene_close(&sc);
	if (r == 0)
		r = shot_write(o->path, so->width, so->height, rgb, e);
	free(rgb);
	return r;
}

int
shot_write(const char *path, int w, int h, const unsigned char *rgb,
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
