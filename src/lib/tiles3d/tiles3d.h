/* tiles3d.h - a VGIS pyramid as an OGC 3D Tiles 1.1 tileset
 * (vgis2tiles(1)): tileset.json, an explicit quadtree on the pyramid's
 * blocks, and one binary glTF per block, its bintree selection at the
 * level's tolerance in ECEF, with a geometricError bounded from the
 * block's saturated errors. */
#ifndef TL_TILES3D_H
#define TL_TILES3D_H

#include "base/util.h"

#define T3_TAU0 1.0 /* metres: level 0's tolerance, doubled per level */
#define T3_MAXJOBS 64

typedef struct {
	const char *dir;  /* the pyramid */
	const char *out;  /* the tileset directory to make */
	double tau0;      /* tolerance of level l: tau0 * 2^l metres */
	int jobs;         /* threads */
	const char *prog; /* for warnings and the progress line; NULL: none */
	int quiet;        /* no warnings, no report */
} t3_args;

/* What was written, for the report. */
typedef struct {
	int tiles, raised; /* tiles; errors raised to a child's */
	long long verts, tris, bytes; /* in the glbs (skirts included) */
	double root_error, max_curve; /* root's error; largest flat-triangle
	                               * and float32 term in a tile's error */
} t3_report;

int t3_run(const t3_args *a, t3_report *rep, tl_err *e);

#endif
