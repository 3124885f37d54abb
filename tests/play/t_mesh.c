/* t_mesh - a block's drawable geometry: vertices relative to the block's
 * centre, unit normals, skirt floors under the border at the world's
 * floor; triangles of the full grid and fewer at a tolerance, skirts two
 * per border edge, none when off. */
#include <float.h>
#include <math.h>

#include "play/mesh.h"
#include "fixture.h"

static int
read_block(const world *w, int level, int bi, int bj, pyramid_block *b)
{
	char path[4096];
	tl_err e;

	if (pyramid_block_alloc(b, w->ix.lev[level].displaced, &e) < 0)
		return -1;
	b->level = level, b->bi = bi, b->bj = bj;
	pyramid_block_path(path, sizeof path, w->dir, level, bi, bj);
	return pyramid_block_read(path, b, &e);
}

static void
test_verts(const char *name)
{
	world w;
	pyramid_block b;
	mesh_verts v;
	tl_err e;
	double worst = 0, p[3];
	int units = 1, floors = 1, k;

	fx_world(&w, name);
	if (read_block(&w, 1, 0, 0, &b) < 0 ||
	    mesh_verts_build(&w, &b, &v, &e) < 0) {
		ok(0, "%s: block 1/0_0 and its vertices", name);
		return;
	}
	/* vertex (c, r) = (5, 7) where world_pos puts it */
	k = 7 * BT_SIZE + 5;
	world_pos(&w, 5 * 2, 7 * 2, b.displaced ? b.x[k] : 0,
	    b.displaced ? b.y[k] : 0, b.z[k], p);
	for (int a = 0; a < 3; a++)
		worst = fmax(worst, fabs(v.origin[a] + v.pos[3 * k + a] - p[a]));
	ok(worst < 0.01, "%s: a vertex at its world position (off %.2g m)",
	    name, worst);
	for (int q = 0; q < MESH_NV; q++) {
		const float *n = &v.nrm[3 * q];
		units &= fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1) < 1e-4;
	}
	ok(units, "%s: every normal is a unit vector", name);
	for (int q = PYRAMID_N; q < MESH_NV; q++)
		floors &= fabs(v.origin[2] + v.pos[3 * q + 2] - w.base) < 0.01;
	ok(floors, "%s: skirt floors at the world's floor", name);
	ok(v.val[2 * k] == b.z[k] && v.val[2 * k + 1] == b.e[k],
	    "%s: height and error kept per vertex", name);
	mesh_verts_free(&v);
	ok(v.pos == NULL && v.nrm == NULL && v.val == NULL, "%s: freed",
	    name);
	pyramid_block_free(&b);
	world_close(&w);
}

static void
test_tris(void)
{
	world w;
	pyramid_block b;
	mesh_tris all = { 0 }, bare = { 0 }, few = { 0 };
	tl_err e;
	int inrange = 1, r;

	fx_world(&w, "bt");
	if (read_block(&w, 0, 1, 1, &b) < 0) {
		ok(0, "bt: block 0/1_1");
		return;
	}
	r = mesh_tris_build(&b, -1, 1, &all, &e);
	ok(r == 0 && all.tris == 2L * BT_CELLS * BT_CELLS && all.skirts == 1024 &&
	    all.n == 3 * (size_t)(all.tris + all.skirts), "full grid: %ld "
	    "triangles, %ld skirt triangles", all.tris, all.skirts);
	for (size_t q = 0; q < all.n; q++)
		inrange &= all.idx[q] < MESH_NV;
	ok(inrange, "every index names a vertex");
	ok(mesh_tris_build(&b, -1, 0, &bare, &e) == 0 && bare.skirts == 0 &&
	    bare.tris == all.tris, "no skirts: the same terrain, no skirt");
	r = mesh_tris_build(&b, 10, 1, &few, &e);
	ok(r == 0 && few.tris < all.tris && few.tris >= 2 && few.skirts > 0,
	    "at 10 m: %ld triangles", few.tris);
	mesh_tris_free(&all), mesh_tris_free(&bare), mesh_tris_free(&few);
	ok(all.idx == NULL && all.n == 0 && all.cap == 0, "freed");
	pyramid_block_free(&b);
	world_close(&w);
}

int
main(int argc, char **argv)
{
	(void)argc;
	if (fx_init(argv[0], "t_mesh") < 0)
		return 1;
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	ok(fx_make("bigtujunga.tif", "bt3", "-3") == 0,
	    "QEM-3D pyramid of bigtujunga.tif");
	test_verts("bt");
	test_verts("bt3");
	test_tris();
	fx_done();
	return tap_done();
}
