/* shot.h - tileplay --shot: one picture, headless, written as an image. */
#ifndef TL_SHOT_H
#define TL_SHOT_H

#include "play/scene.h"

typedef struct {
	const char *path;  /* the image, format by its extension */
	int stats;         /* the --stats line on stderr */
	int readout;       /* the window's readout drawn over it */
	int has_probe;
	int probe[2];      /* a level-0 column and row to locate */
} shot_opts;

/* Chooses (waiting for every block it wants), draws once, reads the
 * frame back and writes it; t0 is the program's start (scene_clock), for
 * the first frame's time. */
int shot_run(const scene_opts *so, const shot_opts *o, double t0,
    tl_err *e);

/* Where level-0 sample (i, j) of the pyramid lands in the frame, its
 * height and its colour in the height map, as the --probe line. */
int shot_probe(scene *sc, int i, int j, FILE *f, tl_err *e);

/* Writes w x h top-down RGB rows as an image (format from the name's
 * extension, e.g. .png) through the OpenImageIO plugin, atomically. */
int shot_write(const char *path, int w, int h, const unsigned char *rgb,
    tl_err *e);

#endif
