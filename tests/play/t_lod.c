/* t_lod - the level of detail on real pyramids, without GL: the chosen
 * blocks tile the DEM exactly (no overlap, no gap), triangles fall as
 * the tolerance grows and are the full grid at 0, culling; the frustum
 * test of a box. */
#include <math.h>

#include "play/lod.h"
#include "play/mesh.h"
#include "fixture.h"

static camera
cam(const world *w, const char *view)
{
	camera c = { .fovy = CAMERA_FOVY, .width = 640, .height = 480 };

	camera_named(&c, w, view);
	return c;
}

/* Level-0 units of 128 cells covered by the chosen blocks. */
static int
coverage(const world *w, const lod_block *b, int n, int *over, int *gap)
{
	int ux = w->ix.lev[0].blocks[0], uy = w->ix.lev[0].blocks[1];
	int *cnt = calloc((size_t)ux * uy, sizeof *cnt);

	for (int k = 0; k < n; k++) {
		int s = 1 << b[k].level;
		for (int j = b[k].bj * s; j < (b[k].bj + 1) * s; j++)
			for (int i = b[k].bi * s; i < (b[k].bi + 1) * s; i++)
				if (i < ux && j < uy)
					cnt[j * ux + i]++;
	}
	*over = *gap = 0;
	for (int q = 0; q < ux * uy; q++)
		*over += cnt[q] > 1, *gap += cnt[q] == 0;
	free(cnt);
	return 0;
}

static long
triangles(const world *w, const lod_block *b, int n, long *skirts)
{
	long t = 0;
	tl_err e;

	*skirts = 0;
	for (int k = 0; k < n; k++) {
		pyramid_block blk;
		mesh_tris tr = { 0 };
		char path[4096];
		pyramid_block_alloc(&blk, w->ix.lev[b[k].level].displaced, &e);
		blk.level = b[k].level, blk.bi = b[k].bi, blk.bj = b[k].bj;
		pyramid_block_path(path, sizeof path, w->dir, b[k].level, b[k].bi,
		    b[k].bj);
		if (pyramid_block_read(path, &blk, &e) == 0 &&
		    mesh_tris_build(&blk, b[k].tau, 1, &tr, &e) == 0)
			t += tr.tris, *skirts += tr.skirts;
		mesh_tris_free(&tr);
		pyramid_block_free(&blk);
	}
	return t;
}

/* Overviews from 0.25 to 64 px tile the DEM; triangles never grow. */
static void
test_sweep(const world *w, const char *name, lod_block *b)
{
	camera c = cam(w, "overview");
	long prev = -1, t, sk;
	int n, over, gap, mono = 1;

	for (double px = 0.25; px <= 64; px *= 2) {
		n = lod_select(w, &c, px, NULL, NULL, b, 4096);
		coverage(w, b, n, &over, &gap);
		t = triangles(w, b, n, &sk);
		if (over || gap)
			ok(0, "%s overview at %g px: %d blocks overlap %d "
			    "units, leave %d", name, px, n, over, gap);
		if (prev >= 0 && t > prev)
			mono = 0;
		prev = t;
	}
	ok(mono, "%s: triangles never grow with the tolerance (last %ld)",
	    name, prev);
	n = lod_select(w, &c, 0, NULL, NULL, b, 4096);
	t = triangles(w, b, n, &sk);
	int l0 = 1;
	for (int k = 0; k < n; k++)
		l0 &= b[k].level == 0;
	ok(l0 && n == w->ix.lev[0].blocks[0] * w->ix.lev[0].blocks[1] &&
	    t == 2L * BT_CELLS * BT_CELLS * n && sk == 1024L * n,
	    "%s at 0 px: all %d level-0 blocks, the full grid (%ld "
	    "triangles, %ld skirt triangles)", name, n, t, sk);
}

/* Random low views: never two blocks over one place. */
static void
test_low(const world *w, const char *name, lod_block *b)
{
	camera c = cam(w, "overview");
	int bad = 0, levels = 0, n, over, gap;
	double wlo[3], whi[3], ext;
	unsigned s = 3;

	world_block_box(w, 0, 0, 0, wlo, whi);
	{
		double a[3], z[3];
		const pyramid_level *L0 = &w->ix.lev[0];
		world_block_box(w, 0, L0->blocks[0] - 1, L0->blocks[1] - 1, a, z);
		wlo[1] = a[1], whi[0] = z[0];
	}
	ext = fmax(whi[0] - wlo[0], whi[1] - wlo[1]);
	for (int q = 0; q < 200; q++) {
		/* eyes over the DEM, low, looking north and down */
		s = s * 1103515245u + 12345u;
		double fx = (s >> 8 & 1023) / 1023.0;
		s = s * 1103515245u + 12345u;
		double fy = (s >> 8 & 1023) / 1023.0;
		camera r = c;
		r.eye[0] = wlo[0] + fx * (whi[0] - wlo[0]);
		r.eye[1] = wlo[1] + fy * (whi[1] - wlo[1]);
		r.eye[2] = w->zmax + ext * (0.005 + 0.05 * fx * fy);
		r.target[0] = r.eye[0] + 0.2 * ext * (fy - 0.5);
		r.target[1] = r.eye[1] + 0.3 * ext;
		r.target[2] = w->zmin;
		r.up[0] = 0, r.up[1] = 0, r.up[2] = 1;
		n = lod_select(w, &r, 2, NULL, NULL, b, 4096);
		coverage(w, b, n, &over, &gap);
		bad += over > 0;
		int seen[32] = { 0 }, nl = 0;
		for (int k = 0; k < n; k++)
			if (!seen[b[k].level]++)
				nl++;
		if (nl > levels)
			levels = nl;
	}
	ok(bad == 0 && levels >= 2, "%s: 200 random low views never overlap "
	    "blocks (up to %d levels in one view)", name, levels);
}

static void
test_lod(const char *name)
{
	lod_block b[4096];
	world w;
	camera up;

	fx_world(&w, name);
	test_sweep(&w, name, b);
	test_low(&w, name, b);
	/* looking at the sky: nothing */
	up = cam(&w, "overview");
	up.target[0] = up.eye[0], up.target[1] = up.eye[1] + 1;
	up.target[2] = up.eye[2] + 1000;
	up.up[0] = 0, up.up[1] = 0, up.up[2] = 1;
	ok(lod_select(&w, &up, 2, NULL, NULL, b, 4096) == 0, "%s: a view of "
	    "the sky culls every block", name);
	world_close(&w);
}

/* A block is drawn only when all its children can be: refusing every
 * block below the top keeps the top; the cap on the count holds. */
static int
only_top(void *ctx, int level, int bi, int bj)
{
	(void)bi, (void)bj;
	return level == *(int *)ctx;
}

static void
test_ready(void)
{
	lod_block b[4096];
	world w;
	camera c;
	int top, n, all = 1;

	fx_world(&w, "bt");
	c = cam(&w, "overview");
	top = w.ix.nlevels - 1;
	n = lod_select(&w, &c, 0, only_top, &top, b, 4096);
	for (int k = 0; k < n; k++)
		all &= b[k].level == top;
	ok(n == w.ix.lev[top].blocks[0] * w.ix.lev[top].blocks[1] && all,
	    "children not ready: the top level's %d blocks stay", n);
	ok(lod_select(&w, &c, 0, NULL, NULL, b, 3) == 3, "at most max "
	    "blocks are chosen");
	world_close(&w);
}

static void
test_box(void)
{
	/* the half-space x >= 0, five planes that never cut */
	double planes[6][4] = { { 1, 0, 0, 0 } };
	double lo[3] = { -2, 0, 0 }, hi[3] = { -1, 1, 1 };

	for (int i = 1; i < 6; i++)
		planes[i][3] = 1;
	ok(lod_box_outside(planes, lo, hi), "a box behind a plane is outside");
	hi[0] = 0.5;
	ok(!lod_box_outside(planes, lo, hi), "a box across it is not");
}

int
main(int argc, char **argv)
{
	(void)argc;
	if (fx_init(argv[0], "t_lod") < 0)
		return 1;
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	ok(fx_make("bigtujunga.tif", "bt3", "-3") == 0,
	    "QEM-3D pyramid of bigtujunga.tif");
	ok(fx_make("N42E001.hgt", "n42", "") == 0, "pyramid of N42E001.hgt");
	test_lod("bt");
	test_lod("bt3");
	test_lod("n42");
	test_ready();
	test_box();
	fx_done();
	return tap_done();
}
