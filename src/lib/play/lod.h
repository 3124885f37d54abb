/* lod.h - the two-stage level of detail of VGIS: per block, the coarsest
 * level whose base error projects under the pixel tolerance; inside a
 * block, the tolerance in metres for its saturated errors. */
#ifndef TL_LOD_H
#define TL_LOD_H

#include "play/camera.h"

/* A block chosen for a frame, with its tolerance in metres (< 0: every
 * vertex, the full grid). */
typedef struct {
	int level, bi, bj;
	double tau;
} lod_block;

/* Is a block ready to draw (loaded)? Also a chance to ask for it. */
typedef int (*lod_ready_fn)(void *ctx, int level, int bi, int bj);

/* Stage 1 from the top block down: a block is drawn when its base error
 * projects under `pixels` at its nearest point (or it is on level 0),
 * else its children are (all of them ready: else the block itself stays,
 * so no area is ever left empty). Culled blocks are skipped. Stage 2:
 * each drawn block's tau = pixels / pixels-per-metre at its nearest
 * point; pixels == 0 draws the full grid. ready may be NULL (every block
 * is). Returns the number of blocks (at most max). */
int lod_select(const world *w, const camera *c, double pixels,
    lod_ready_fn ready, void *ctx, lod_block *out, int max);

/* Is the box wholly outside one of the frustum's planes (camera_frustum)? */
int lod_box_outside(const double planes[6][4], const double lo[3],
    const double hi[3]);

#endif
