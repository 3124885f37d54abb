/* t_nav - the window's camera motion: a view set and read back, straight
 * down heading north, orbiting keeps the target, looking about keeps the
 * eye, moving along the heading, zooming towards the target, the pitch
 * never vertical. */
#include <math.h>

#include "play/nav.h"
#include "fixture.h"

static void
target(const nav *v, double t[3])
{
	double d[3];

	nav_dir(v, d);
	for (int a = 0; a < 3; a++)
		t[a] = v->eye[a] + v->dist * d[a];
}

static double
dist3(const double a[3], const double b[3])
{
	return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) *
	    (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

static void
test_set(void)
{
	double eye[3] = { -100, -200, 300 }, at[3] = { 50, 60, 70 }, t[3];
	double down[3] = { 5, 5, 1000 }, below[3] = { 5, 5, 0 };
	nav v = { .orbit = 1 };

	nav_set(&v, eye, at);
	target(&v, t);
	ok(dist3(t, at) < 1e-9 && fabs(v.dist - dist3(eye, at)) < 1e-9,
	    "set from eye and target, read back");
	nav_set(&v, down, below);
	ok(fabs(v.yaw - M_PI / 2) < 1e-12 && v.pitch == -NAV_PITCH,
	    "straight down: heading north, pitched to the limit");
}

static void
test_moves(void)
{
	double eye[3] = { 0, -1000, 500 }, at[3] = { 0, 0, 0 }, t[3], e0[3];
	nav v = { .orbit = 1 };

	nav_set(&v, eye, at);
	nav_turn(&v, 0.3, 0.2);
	target(&v, t);
	ok(dist3(t, at) < 1e-6 && dist3(v.eye, eye) > 1, "orbiting keeps "
	    "the target, moves the eye");
	memcpy(e0, v.eye, sizeof e0);
	v.orbit = 0;
	nav_turn(&v, 0.3, 0.1);
	ok(dist3(v.eye, e0) == 0, "looking about keeps the eye");
	nav_turn(&v, 0, 10);
	ok(v.pitch == NAV_PITCH, "the pitch stops short of vertical");
	nav_set(&v, eye, at);
	nav_move(&v, 10, 0, 0);
	ok(fabs(v.eye[1] + 990) < 1e-9 && fabs(v.eye[0]) < 1e-9,
	    "forward along the heading (north here)");
	nav_move(&v, 0, 10, 5);
	ok(fabs(v.eye[0] - 10) < 1e-9 && v.eye[2] == 505,
	    "sideways to the right (east), and up");
	nav_set(&v, eye, at);
	nav_zoom(&v, 0.5);
	target(&v, t);
	ok(dist3(t, at) < 1e-9 && fabs(v.dist - dist3(eye, at) / 2) < 1e-9,
	    "zooming halves the distance, the target stays");
}

static void
test_camera(void)
{
	double eye[3] = { -3000, -3000, 3000 }, at[3] = { 0, 0, 500 };
	camera c = { .fovy = CAMERA_FOVY, .width = 64, .height = 48 };
	nav v = { .orbit = 1 };
	world w;

	fx_world(&w, "bt");
	nav_set(&v, eye, at);
	nav_camera(&v, &c, &w);
	ok(dist3(c.eye, eye) < 1e-9 && dist3(c.target, at) < 1e-9 &&
	    c.up[2] == 1 && c.zfar > c.znear && c.znear > 0,
	    "the camera: eye, target, z up, a depth range");
	world_close(&w);
}

int
main(int argc, char **argv)
{
	(void)argc;
	if (fx_init(argv[0], "t_nav") < 0)
		return 1;
	test_set();
	test_moves();
	ok(fx_make("bigtujunga.tif", "bt", "") == 0,
	    "pyramid of bigtujunga.tif");
	test_camera();
	fx_done();
	return tap_done();
}
