/* view.h - a pyramid seen by a camera: its blocks placed in metres, the
 * frustum, and the two-stage level of detail of VGIS (per block, the
 * coarsest level whose base error projects under the pixel tolerance;
 * inside a block, the tolerance in metres for its saturated errors).
 *
 * World frame: metres, x east (along the DEM's columns), y north (against
 * its rows), z up; origin at the DEM's centre column and row, height 0.
 * Every DEM uses the metric embedding of georef.h: x is the distance
 * along the row from the centre column, y along the column from the
 * centre row (geographic DEMs: per-row geodesic cell widths, centred on
 * the DEM's middle meridian, equal-area; projected ones: the CRS's true
 * ground scale), no degrees or CRS units anywhere. */
#ifndef TL_VIEW_H
#define TL_VIEW_H

#include "pyramid/pyramid.h"

typedef struct {
	pyramid_index ix;
	geo_metric m;
	double ci, cj;     /* level-0 column and row of the world origin */
	double zmin, zmax; /* over every block of every level */
	double base;       /* a height below all terrain, for skirts */
	char dir[4096];
} world;

int world_open(world *w, const char *dir, tl_err *e);
void world_close(world *w);

/* World position of a point at level-0 grid position (I, J) displaced by
 * (X, Y) metres along the grid's x and y (a QEM-3D vertex), height z. */
void world_pos(const world *w, double I, double J, double X, double Y,
    double z, double out[3]);
/* Bounds of block (bi, bj) of a level: its grid footprint (plus half a
 * level cell on displaced levels) and the index's z range. */
void world_block_box(const world *w, int level, int bi, int bj,
    double lo[3], double hi[3]);

typedef struct {
	double eye[3], target[3], up[3];
	double fovy;      /* vertical field of view, radians */
	int width, height; /* viewport, pixels */
	double znear, zfar;
} camera;

/* Column-major 4x4 matrices for GL: view (world to eye) and projection. */
void cam_matrices(const camera *c, float view[16], float proj[16]);
/* The six frustum planes (a, b, c, d: inside when ax+by+cz+d >= 0). */
void cam_frustum(const camera *c, double planes[6][4]);
int box_outside(const double planes[6][4], const double lo[3],
    const double hi[3]);
/* Pixels per metre of a vertical error seen at distance d. */
double cam_pixels_per_metre(const camera *c, double d);
/* Nearest distance from the eye to a box (0 inside). */
double cam_box_distance(const camera *c, const double lo[3],
    const double hi[3]);
/* znear and zfar covering the whole world from where the eye is. */
void cam_fit_depth(camera *c, const world *w);
/* Named views: "overview" (straight down, the whole DEM in frame),
 * "oblique" (from the south-west, 30 degrees down). */
int cam_named(camera *c, const world *w, const char *name);

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
 * point; pixels == 0 draws the full grid. Returns the number of blocks
 * (at most max). */
int lod_select(const world *w, const camera *c, double pixels,
    lod_ready_fn ready, void *ctx, lod_block *out, int max);

#endif
