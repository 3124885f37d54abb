/* t_gl_render - the terrain renderer, headless on a real pyramid: the
 * overview covers the DEM's footprint, stats count what was drawn, the
 * level colours unlit are exact, the wireframe draws lines, the height
 * map's ends, and the blocks' GPU state freed with the cache. */
#include <math.h>

#include "play/gl_render.h"
#include "play/lod.h"
#include "fixture.h"

#define W 160
#define H 120

typedef struct {
	world w;
	gl_ctx *g;
	gl_render *r;
	cache *k;
	camera c;
	lod_block sel[512];
	int n;
	long missing;
} bench;

static int
ready(void *ctx, int level, int bi, int bj)
{
	bench *b = ctx;

	if (cache_get(b->k, level, bi, bj) != NULL)
		return 1;
	b->missing++;
	return 0;
}

/* The overview's blocks at a quarter pixel, every one loaded. */
static void
choose(bench *b)
{
	for (int q = 0; q < 20; q++) {
		cache_frame(b->k);
		b->missing = 0;
		b->n = lod_select(&b->w, &b->c, 0.25, ready, b, b->sel, 512);
		if (b->missing == 0)
			break;
		cache_wait(b->k);
	}
}

/* Draws the choice in style s; returns the background pixels. */
static int
draw(bench *b, const gl_style *s, gl_render_stats *st, unsigned char *rgb)
{
	const unsigned char bg[3] = { 255, 0, 255 };
	tl_err e;
	int n = 0;

	gl_render_begin(b->r, &b->c, s, st);
	for (int k = 0; k < b->n; k++) {
		cblock *cb = cache_get(b->k, b->sel[k].level, b->sel[k].bi,
		    b->sel[k].bj);
		if (cb != NULL && gl_render_draw(b->r, b->k, cb, b->sel[k].tau,
		    &e) < 0)
			ok(0, "gl_render_draw: %s", e.msg);
	}
	gl_ctx_read_rgb(b->g, rgb);
	for (int q = 0; q < W * H; q++)
		n += memcmp(&rgb[3 * q], bg, 3) == 0;
	return n;
}

/* Is p one of the level colours (within 1)? */
static int
level_colour(const unsigned char *p)
{
	for (int l = 0; l < 8; l++) {
		const float *c = gl_style_level_rgb(l);
		int d = 0;
		for (int a = 0; a < 3; a++)
			d |= abs(p[a] - (int)lrintf(c[a] * 255)) > 1;
		if (!d)
			return 1;
	}
	return 0;
}

static void
test_draw(bench *b)
{
	static unsigned char rgb[W * H * 3], wire[W * H * 3];
	gl_render_stats st;
	gl_style s;
	int bg, exact = 1;
	long tris;

	gl_style_init(&s);
	s.background[0] = 1, s.background[1] = 0, s.background[2] = 1;
	choose(b);
	ok(b->missing == 0 && b->n > 0, "the overview's %d blocks loaded",
	    b->n);
	bg = draw(b, &s, &st, rgb);
	ok(bg < W * H / 2 && bg > 0, "the terrain covers the frame's middle, "
	    "the background its margins (%d of %d pixels)", bg, W * H);
	ok(st.blocks == b->n && st.tris > 0 && st.skirts > 0 &&
	    st.levels > 0, "stats: %ld blocks, %ld triangles, %ld skirt",
	    st.blocks, st.tris, st.skirts);
	tris = st.tris;
	s.colour = GL_BY_LEVEL, s.light = 0;
	draw(b, &s, &st, rgb);
	for (int y = H / 3; y < 2 * H / 3; y++)
		exact &= level_colour(&rgb[3 * (y * W + W / 2)]);
	ok(exact && st.tris == tris, "by level, unlit: the level colours "
	    "themselves");
	s.wire = 1;
	draw(b, &s, &st, wire);
	ok(memcmp(rgb, wire, sizeof rgb) != 0, "the wireframe draws lines");
}

static void
test_height(const bench *b)
{
	unsigned char lo[3], hi[3];
	const pyramid_level *L = &b->w.ix.lev[0];
	double zlo = INFINITY, zhi = -INFINITY;

	for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++)
		zlo = fmin(zlo, L->zmin[k]), zhi = fmax(zhi, L->zmax[k]);
	gl_render_height_rgb(b->r, zlo, lo);
	gl_render_height_rgb(b->r, zhi, hi);
	ok(lo[0] == 68 && lo[2] == 84 && hi[0] == 253 && hi[1] == 231,
	    "level 0's range spans the height map (%g to %g m)", zlo, zhi);
}

int
main(int argc, char **argv)
{
	static bench b;
	tl_err e;

	(void)argc;
	if (fx_init(argv[0], "t_gl_render") < 0)
		return 1;
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	fx_world(&b.w, "bt");
	if ((b.g = fx_headless(W, H)) != NULL) {
		b.c = (camera){ .fovy = CAMERA_FOVY, .width = W, .height = H };
		camera_named(&b.c, &b.w, "overview");
		ok((b.r = gl_render_new(&b.w, &e)) != NULL &&
		    (b.k = cache_new(&b.w, 64 << 20, gl_render_release, b.r,
		    &e)) != NULL, "a renderer and its cache");
		if (b.k != NULL) {
			test_draw(&b);
			test_height(&b);
		}
		cache_free(b.k); /* releases the blocks' GPU state */
		gl_render_free(b.r);
		gl_ctx_close(b.g);
	}
	world_close(&b.w);
	fx_done();
	return tap_done();
}
