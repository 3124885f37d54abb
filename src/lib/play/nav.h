/* nav.h - the window's camera as the keys and mouse move it: an eye, a
 * heading (yaw from east, counter-clockwise), a pitch and the distance to
 * what it looks at, which orbiting turns about. Pure arithmetic. */
#ifndef TL_NAV_H
#define TL_NAV_H

#include "play/camera.h"

#define NAV_PITCH 1.55 /* never quite vertical: the heading stays defined */

typedef struct {
	double eye[3], yaw, pitch, dist;
	int orbit;         /* turning orbits the target; else looks about */
} nav;

/* Looking from eye at target (straight down: heading north). */
void nav_set(nav *v, const double eye[3], const double target[3]);
/* The unit vector it looks along. */
void nav_dir(const nav *v, double d[3]);
/* Turn: orbit about the target, or look about from the eye. */
void nav_turn(nav *v, double dyaw, double dpitch);
/* Moves the eye (and what it looks at) along the heading, sideways and
 * up, in metres. */
void nav_move(nav *v, double fwd, double side, double up);
/* Towards what it looks at (f < 1) or away, the target staying. */
void nav_zoom(nav *v, double f);
/* The camera it makes, up z, its depth range fitted to w. */
void nav_camera(const nav *v, camera *c, const world *w);

#endif
