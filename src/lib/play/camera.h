/* camera.h - a perspective camera in the world's metres (world.h): its
 * GL matrices, frustum and screen-space scale, and the named views. */
#ifndef TL_CAMERA_H
#define TL_CAMERA_H

#include <math.h>

#include "play/world.h"

#define CAMERA_FOVY (50 * M_PI / 180) /* tileplay's field of view */

typedef struct {
	double eye[3], target[3], up[3];
	double fovy;       /* vertical field of view, radians */
	int width, height; /* viewport, pixels */
	double znear, zfar;
} camera;

/* Column-major 4x4 matrices for GL: view (world to eye) and projection. */
void camera_matrices(const camera *c, float view[16], float proj[16]);
/* The six frustum planes (a, b, c, d: inside when ax+by+cz+d >= 0). */
void camera_frustum(const camera *c, double planes[6][4]);
/* Pixels per metre of a vertical error seen at distance d. */
double camera_pixels_per_metre(const camera *c, double d);
/* Nearest distance from the eye to a box (0 inside). */
double camera_box_distance(const camera *c, const double lo[3],
    const double hi[3]);
/* Where world point p lands: px[0] from the left, px[1] from the top,
 * through the float matrices GL draws with. */
void camera_project(const camera *c, const double p[3], int px[2]);

/* znear and zfar covering the whole world from where the eye is. */
void camera_fit_depth(camera *c, const world *w);
/* Eye and target in place: up is z, or north when looking straight down
 * or up; then the depth range. */
void camera_look(camera *c, const world *w, const double eye[3],
    const double target[3]);
/* Named views: "overview" (straight down, the whole DEM in frame),
 * "oblique" (from the south-west, 30 degrees down); -1 for another
 * name. camera_view_known says whether there is one of that name. */
int camera_named(camera *c, const world *w, const char *name);
int camera_view_known(const char *name);

#endif
