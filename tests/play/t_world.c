/* t_world - a pyramid in metres: geographic worlds without distortion
 * (neighbours as far apart as the metric embedding says), the DEM's box,
 * blocks' boxes and existence. */
#include <math.h>

#include "fixture.h"

/* Geographic: neighbours in the world are as far apart as the metric
 * embedding says, in metres. */
static void
test_metres(void)
{
	world w;
	double worst = 0;

	fx_world(&w, "n42");
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
	world_close(&w);
}

/* The origin is the centre sample; the box is the DEM's footprint; the
 * floor is under everything. */
static void
test_frame(void)
{
	world w;
	double o[3], lo[3], hi[3], p[3], q[3];

	fx_world(&w, "bt");
	world_pos(&w, w.ci, w.cj, 0, 0, 7, o);
	ok(fabs(o[0]) < 1e-9 && fabs(o[1]) < 1e-9 && o[2] == 7, "the centre "
	    "sample is the origin (%g, %g)", o[0], o[1]);
	world_pos(&w, w.ci + 1, w.cj + 1, 2, 3, 0, p);
	world_pos(&w, w.ci + 1, w.cj + 1, 0, 0, 0, q);
	ok(fabs(p[0] - q[0] - 2) < 1e-9 && fabs(p[1] - q[1] + 3) < 1e-9,
	    "a displacement moves x east and y against the rows");
	ok(q[0] > 0 && q[1] < 0, "columns run east, rows south");
	world_box(&w, lo, hi);
	world_pos(&w, 0, 0, 0, 0, 0, p);
	world_pos(&w, w.ix.size0[0] - 1, w.ix.size0[1] - 1, 0, 0, 0, q);
	ok(lo[0] == fmin(p[0], q[0]) && hi[1] == fmax(p[1], q[1]) &&
	    lo[2] == w.zmin && hi[2] == w.zmax && w.base < w.zmin,
	    "the box is the DEM's footprint, zmin to zmax, over the floor");
	world_close(&w);
}

static void
test_blocks(void)
{
	world w;
	int n = 0, inside = 1;

	fx_world(&w, "bt");
	for (int l = 0; l < w.ix.nlevels; l++) {
		const pyramid_level *L = &w.ix.lev[l];
		n += L->blocks[0] * L->blocks[1];
		inside &= world_block_exists(&w, l, L->blocks[0] - 1,
		    L->blocks[1] - 1) && !world_block_exists(&w, l,
		    L->blocks[0], 0) && !world_block_exists(&w, l, 0, -1);
	}
	ok(world_blocks(&w) == n && n > 1, "%d blocks in all", n);
	ok(inside && !world_block_exists(&w, w.ix.nlevels, 0, 0) &&
	    w.ix.lev[w.ix.nlevels - 1].blocks[0] == 1,
	    "blocks exist inside each level's grid only; the top is one");
	{
		double lo[3], hi[3], plo[3], phi[3];
		world_block_box(&w, 1, 0, 0, plo, phi);
		world_block_box(&w, 0, 1, 1, lo, hi);
		ok(lo[0] >= plo[0] && hi[0] <= phi[0] && lo[1] >= plo[1] &&
		    hi[1] <= phi[1], "a child's footprint is inside its "
		    "parent's");
	}
	world_close(&w);
}

int
main(int argc, char **argv)
{
	(void)argc;
	if (fx_init(argv[0], "t_world") < 0)
		return 1;
	ok(fx_make("N42E001.hgt", "n42", "") == 0, "pyramid of N42E001.hgt");
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	test_metres();
	test_frame();
	test_blocks();
	fx_done();
	return tap_done();
}
