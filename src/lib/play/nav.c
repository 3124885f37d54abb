/* nav.c - the window's camera motion (see nav.h). */
#include "play/nav.h"


void
nav_dir(const nav *v, double d[3])
{
	d[0] = cos(v->pitch) * cos(v->yaw);
	d[1] = cos(v->pitch) * sin(v->yaw);
	d[2] = sin(v->pitch);
}

void
nav_set(nav *v, const double eye[3], const double target[3])
{
	double d[3], n;

	for (int a = 0; a < 3; a++)
		d[a] = target[a] - eye[a], v->eye[a] = eye[a];
	n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	v->dist = n > 1 ? n : 1;
	/* straight down: heading north, so north is up on the screen */
	v->yaw = hypot(d[0], d[1]) > 1e-9 * v->dist ? atan2(d[1], d[0]) :
	    M_PI / 2;
	v->pitch = asin(fmax(-1, fmin(1, d[2] / v->dist)));
	v->pitch = fmax(-NAV_PITCH, fmin(NAV_PITCH, v->pitch));
}

void
nav_turn(nav *v, double dyaw, double dpitch)
{
	double d[3], t[3];

	nav_dir(v, d);
	for (int a = 0; a < 3; a++)
		t[a] = v->eye[a] + v->dist * d[a];
	v->yaw += dyaw;
	v->pitch = fmax(-NAV_PITCH, fmin(NAV_PITCH, v->pitch + dpitch));
	if (v->orbit) {
		nav_dir(v, d);
		for (int a = 0; a < 3; a++)
			v->eye[a] = t[a] - v->dist * d[a];
	}
}

void
nav_move(nav *v, double fwd, double side, double up)
{
	v->eye[0] += fwd * cos(v->yaw) + side * sin(v->yaw);
	v->eye[1] += fwd * sin(v->yaw) - side * cos(v->yaw);
	v->eye[2] += up;
}

void
nav_zoom(nav *v, double f)
{
	double d[3];

	nav_dir(v, d);
	for (int a = 0; a < 3; a++)
		v->eye[a] += (1 - f) * v->dist * d[a];
	v->dist *= f;
}

void
nav_camera(const nav *v, camera *c, const world *w)
{
	double d[3];

	nav_dir(v, d);
	for (int a = 0; a < 3; a++) {
		c->eye[a] = v->eye[a];
		c->target[a] = v->eye[a] + v->dist * d[a];
	}
	c->up[0] = 0, c->up[1] = 0, c->up[2] = 1;
	camera_fit_depth(c, w);
}
