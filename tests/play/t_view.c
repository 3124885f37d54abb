/* t_view - the viewer's logic without GL, on real pyramids: the chosen
 * blocks tile the DEM exactly (no overlap, no gap), triangles fall as the
 * tolerance grows and are the full grid at 0, culling, geographic worlds
 * in metres without distortion, skirts, and the cache's hard cap. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "play/cache.h"
#include "core/fqm.h"
#include "tap.h"

static char tmp[256];

static int
make(const char *dem, const char *name, const char *opts)
{
	char cmd[2048];

	snprintf(cmd, sizeof cmd, "sh -c '\"$0\" -q %s \"$1\" \"$2\"' "
	    "scripts/dem2vgis %s %s/%s", opts, dem, tmp, name);
	return system(cmd);
}

static void
open_world(world *w, const char *name)
{
	char dir[512];
	tl_err e;

	snprintf(dir, sizeof dir, "%s/%s", tmp, name);
	if (world_open(w, dir, &e) < 0) {
		printf("# %s\n", e.msg);
		exit(1);
	}
}

static camera
cam(const world *w, const char *view)
{
	camera c = { .fovy = 50 * M_PI / 180, .width = 640, .height = 480 };

	cam_named(&c, w, view);
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

static void
test_lod(const char *name)
{
	world w;
	camera c;
	lod_block b[4096];
	int n, over, gap;
	long prev = -1, t, sk;
	int mono = 1;
	unsigned s = 3;

	open_world(&w, name);
	c = cam(&w, "overview");
	for (double px = 0.25; px <= 64; px *= 2) {
		n = lod_select(&w, &c, px, NULL, NULL, b, 4096);
		coverage(&w, b, n, &over, &gap);
		t = triangles(&w, b, n, &sk);
		if (over || gap)
			ok(0, "%s overview at %g px: %d blocks overlap %d "
			    "units, leave %d", name, px, n, over, gap);
		if (prev >= 0 && t > prev)
			mono = 0;
		prev = t;
	}
	ok(mono, "%s: triangles never grow with the tolerance (last %ld)",
	    name, prev);
	n = lod_select(&w, &c, 0, NULL, NULL, b, 4096);
	t = triangles(&w, b, n, &sk);
	int l0 = 1;
	for (int k = 0; k < n; k++)
		l0 &= b[k].level == 0;
	ok(l0 && n == w.ix.lev[0].blocks[0] * w.ix.lev[0].blocks[1] &&
	    t == 2L * BT_CELLS * BT_CELLS * n && sk == 1024L * n,
	    "%s at 0 px: all %d level-0 blocks, the full grid (%ld "
	    "triangles, %ld skirt triangles)", name, n, t, sk);
	/* random low views: never two blocks over one place */
	int bad = 0, levels = 0;
	double wlo[3], whi[3], ext;
	world_block_box(&w, 0, 0, 0, wlo, whi);
	{
		double a[3], z[3];
		const pyramid_level *L0 = &w.ix.lev[0];
		world_block_box(&w, 0, L0->blocks[0] - 1, L0->blocks[1] - 1, a, z);
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
		r.eye[2] = w.zmax + ext * (0.005 + 0.05 * fx * fy);
		r.target[0] = r.eye[0] + 0.2 * ext * (fy - 0.5);
		r.target[1] = r.eye[1] + 0.3 * ext;
		r.target[2] = w.zmin;
		r.up[0] = 0, r.up[1] = 0, r.up[2] = 1;
		n = lod_select(&w, &r, 2, NULL, NULL, b, 4096);
		coverage(&w, b, n, &over, &gap);
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
	/* looking at the sky: nothing */
	camera up = c;
	up.target[0] = up.eye[0], up.target[1] = up.eye[1] + 1;
	up.target[2] = up.eye[2] + 1000;
	up.up[0] = 0, up.up[1] = 0, up.up[2] = 1;
	ok(lod_select(&w, &up, 2, NULL, NULL, b, 4096) == 0, "%s: a view of "
	    "the sky culls every block", name);
	world_close(&w);
}

/* Geographic: neighbours in the world are as far apart as the metric
 * embedding says, in metres. */
static void
test_metres(void)
{
	world w;
	double worst = 0;

	open_world(&w, "n42");
	for (int J = 0; J < 1200; J += 97)
		for (int I = 0; I < 1200; I += 131) {
			double a[3], b[3], c[3];
			world_pos(&w, I, J, 0, 0, 0, a);
			world_pos(&w, I + 1, J, 0, 0, 0, b);
			world_pos(&w, I, J + 1, 0, 0, 0, c);
			worst = fmax(worst, fabs(hypot(b[0] - a[0], b[1] - a[1]) -
			    geo_sx(&w.m, I, J)));
			/* rows: the meridian spacing, up to the shear of a
			 * sinusoidal map away from its middle meridian */
			worst = fmax(worst, fabs(fabs(c[1] - a[1]) -
			    (geo_y(&w.m, I, J + 1) - geo_y(&w.m, I, J))));
		}
	ok(worst < 1e-6, "geographic world: cell sides in metres as the "
	    "geodesic metric gives them (max dev %.2g m)", worst);
	camera c = cam(&w, "overview");
	double view[16], lo[3], hi[3];
	(void)view, (void)lo, (void)hi;
	float V[16], P[16];
	cam_matrices(&c, V, P);
	int inside = 1;
	double fill = 0;
	for (int k = 0; k < 4; k++) {
		double p[3], e4[4], c4[4];
		world_pos(&w, k & 1 ? 1200 : 0, k & 2 ? 1200 : 0, 0, 0, w.zmin, p);
		for (int r = 0; r < 4; r++)
			e4[r] = V[r] * p[0] + V[4 + r] * p[1] + V[8 + r] * p[2] +
			    V[12 + r];
		for (int r = 0; r < 4; r++)
			c4[r] = P[r] * e4[0] + P[4 + r] * e4[1] + P[8 + r] * e4[2] +
			    P[12 + r] * e4[3];
		double x = c4[0] / c4[3], y = c4[1] / c4[3];
		inside &= fabs(x) <= 1 && fabs(y) <= 1;
		fill = fmax(fill, fmax(fabs(x), fabs(y)));
	}
	ok(inside && fill > 0.95, "overview: the DEM's corners in frame, "
	    "filling it (%.3f of the half-width)", fill);
	world_close(&w);
}

/* The cache never holds more than its cap, and still serves a frame. */
static void
test_cache(void)
{
	world w;
	tl_err e;
	cache *c;
	cache_stats st;
	size_t cap = 4 * 1024 * 1024; /* about five blocks */
	int served = 0;

	open_world(&w, "bt");
	if ((c = cache_new(&w, cap, NULL, NULL, &e)) == NULL) {
		ok(0, "cache_new: %s", e.msg);
		return;
	}
	for (int f = 0; f < 60; f++) {
		pyramid_level *L = &w.ix.lev[0];
		cache_frame(c);
		/* a moving window of 3 blocks over level 0 */
		for (int k = 0; k < 3; k++) {
			int q = (f / 4 + k) % (L->blocks[0] * L->blocks[1]);
			served += cache_get(c, 0, q % L->blocks[0],
			    q / L->blocks[0]) != NULL;
		}
		cache_wait(c);
		cache_get_stats(c, &st);
		if (st.bytes > cap || st.peak > cap)
			break;
	}
	cache_get_stats(c, &st);
	ok(st.peak <= cap && st.evictions > 0 && served > 100,
	    "cache: peak %zu <= cap %zu bytes over 60 frames (%ld loads, %ld "
	    "evictions, %d of 180 asks served)", st.peak, cap, st.loads,
	    st.evictions, served);
	cache_free(c);
	world_close(&w);
}

int
main(void)
{
	const char *data = getenv("DATA") ? getenv("DATA") : "../shared/data";
	char dem[1024], cmd[600];

	snprintf(tmp, sizeof tmp, "%s/t_view.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(tmp) == NULL)
		return 1;
	snprintf(dem, sizeof dem, "%s/bigtujunga.tif", data);
	ok(make(dem, "bt", "") == 0, "pyramid of bigtujunga.tif");
	ok(make(dem, "bt3", "-3") == 0, "QEM-3D pyramid of bigtujunga.tif");
	snprintf(dem, sizeof dem, "%s/N42E001.hgt", data);
	ok(make(dem, "n42", "") == 0, "pyramid of N42E001.hgt");
	test_lod("bt");
	test_lod("bt3");
	test_lod("n42");
	test_metres();
	test_cache();
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmp);
	system(cmd);
	return tap_done();
}
