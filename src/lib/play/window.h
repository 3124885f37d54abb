/* window.h - tileplay's window (GLFW): fly over the pyramid with the
 * keys and the mouse of tileplay(1). */
#ifndef TL_WINDOW_H
#define TL_WINDOW_H

#include "play/scene.h"

typedef struct {
	int frames;        /* close after this many; 0: when asked */
	int stats;         /* the --stats line on stderr at the end */
} window_opts;

/* Opens the window and runs its loop until closed; t0 is the program's
 * start (scene_clock), for the first complete frame's time. */
int window_run(const scene_opts *so, const window_opts *o, double t0,
    tl_err *e);

#endif
