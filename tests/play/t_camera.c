/* t_camera - the camera: the overview frames the whole DEM, projections
 * agree with the matrices GL gets, the up vector of a look, the depth
 * range, the named views. */
#include <math.h>

#include "play/camera.h"
#include "fixture.h"

static camera
cam(const world *w, const char *view)
{
	camera c = { .fovy = CAMERA_FOVY, .width = 640, .height = 480 };

	camera_named(&c, w, view);
	return c;
}

/* The DEM's corners in frame, filling it (geographic, in metres). */
static void
test_overview(void)
{
	world w;
	camera c;
	float V[16], P[16];
	int inside = 1;
	double fill = 0;

	fx_world(&w, "n42");
	c = cam(&w, "overview");
	camera_matrices(&c, V, P);
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

static void
test_project(void)
{
	world w;
	camera c;
	double p[3], right[3], up[3];
	int px[2], pr[2], pu[2];

	fx_world(&w, "bt");
	c = cam(&w, "oblique");
	camera_project(&c, c.target, px);
	/* the frame's centre is the corner of four pixels: the float
	 * matrices put the target in any of them */
	ok(px[0] >= 319 && px[0] <= 320 && px[1] >= 239 && px[1] <= 240,
	    "the target lands mid-frame (%d %d)", px[0], px[1]);
	/* straight down from 1000 m over the highest point, north up */
	p[0] = p[1] = 0, p[2] = w.zmax + 1000;
	right[0] = right[1] = right[2] = 0;
	camera_look(&c, &w, p, right);
	ok(c.up[1] == 1 && c.up[2] == 0, "looking straight down, up is north");
	right[0] = 100, up[1] = 100, up[0] = up[2] = 0;
	camera_project(&c, right, pr);
	camera_project(&c, up, pu);
	ok(pr[0] > 320 && pr[1] == 240 && pu[0] == 320 && pu[1] < 240,
	    "east lands right (%d %d), north up (%d %d)", pr[0], pr[1], pu[0],
	    pu[1]);
	ok(c.znear > 0 && c.znear < 1000 && c.zfar > p[2] - w.base,
	    "the depth range holds the world (%g to %g m)", c.znear, c.zfar);
	p[0] = -5000, right[0] = 0;
	camera_look(&c, &w, p, right);
	ok(c.up[2] == 1, "an oblique look keeps z up");
	world_close(&w);
}

static void
test_scale(void)
{
	camera c = { .fovy = CAMERA_FOVY, .width = 640, .height = 480 };
	double lo[3] = { 10, -1, -1 }, hi[3] = { 20, 1, 1 };
	double k = camera_pixels_per_metre(&c, 100);

	ok(fabs(k * 100 * 2 * tan(c.fovy / 2) - 480) < 1e-9, "at distance "
	    "d, the frame's height spans 2 d tan(fovy/2) metres");
	ok(camera_box_distance(&c, lo, hi) == 10, "the distance to a box is "
	    "to its nearest face");
	lo[0] = -1;
	ok(camera_box_distance(&c, lo, hi) == 0, "0 inside it");
}

static void
test_named(void)
{
	world w;
	camera c = { .fovy = CAMERA_FOVY, .width = 640, .height = 480 };

	fx_world(&w, "bt");
	ok(camera_view_known("overview") && camera_view_known("oblique") &&
	    !camera_view_known("side"), "two named views");
	ok(camera_named(&c, &w, "side") < 0, "another name: -1");
	c = cam(&w, "oblique");
	ok(c.eye[0] < c.target[0] && c.eye[1] < c.target[1] &&
	    c.eye[2] > c.target[2], "oblique: from the south-west, above");
	world_close(&w);
}

int
main(int argc, char **argv)
{
	(void)argc;
	if (fx_init(argv[0], "t_camera") < 0)
		return 1;
	ok(fx_make("N42E001.hgt", "n42", "") == 0, "pyramid of N42E001.hgt");
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	test_overview();
	test_project();
	test_scale();
	test_named();
	fx_done();
	return tap_done();
}
