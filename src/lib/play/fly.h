/* fly.h - tileplay --fly: a scripted flight, headless, timed frame by
 * frame. */
#ifndef TL_FLY_H
#define TL_FLY_H

#include "play/scene.h"

#define FLY_MAXKEY 256 /* keyframes of a path file */

typedef struct {
	double eye[3], target[3];
} fly_key;

typedef struct {
	int frames;        /* n >= 1 */
	const char *path;  /* keyframes, or NULL: the built-in circle */
	int wait;          /* every frame waits for its blocks */
} fly_opts;

/* The built-in path into k (FLY_MAXKEY): a low circle about the DEM's
 * centre, radius 0.35 of the smaller extent, 10 degrees above the
 * highest point's plane, looking at the centre 10 degrees down; one turn
 * from the south. Returns the keyframes (37). */
int fly_circle(const world *w, fly_key *k);
/* The keyframes of a path file into k (FLY_MAXKEY): "ex ey ez tx ty tz"
 * a line, '#' comments and blank lines skipped. Returns how many, or -1
 * (none, a bad line, too many). */
int fly_read_path(const char *path, fly_key *k, tl_err *e);
/* Eye and target of frame f of n spread evenly over nk keyframes, linear
 * between them. */
void fly_at(const fly_key *k, int nk, int f, int n, double eye[3],
    double target[3]);

/* Flies o->frames frames, printing a line a frame and a summary on
 * stdout; t0 is the program's start (scene_clock). */
int fly_run(const scene_opts *so, const fly_opts *o, double t0, tl_err *e);

#endif
