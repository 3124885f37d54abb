/* world.h - a pyramid placed in metres: its index, its blocks' bounds and
 * the DEM's grid as world positions.
 *
 * World frame: metres, x east (along the DEM's columns), y north (against
 * its rows), z up; origin at the DEM's centre column and row, height 0.
 * Every DEM uses the metric embedding of georef.h: x is the distance
 * along the row from the centre column, y along the column from the
 * centre row (geographic DEMs: per-row geodesic cell widths, centred on
 * the DEM's middle meridian, equal-area; projected ones: the CRS's true
 * ground scale), no degrees or CRS units anywhere. */
#ifndef TL_WORLD_H
#define TL_WORLD_H

#include "pyramid/pyramid.h"

typedef struct {
	pyramid_index ix;
	geo_ground m;
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

/* Does block (bi, bj) exist on level l? */
int world_block_exists(const world *w, int l, int bi, int bj);
/* Does the metre scale of a row vary more than twofold over block (bi,
 * bj)'s rows (a geographic block reaching far towards a pole)? Its
 * triangles cannot then stand straight in the world: it is drawn whole. */
int world_block_curved(const world *w, int l, int bi, int bj);
/* Bounds of block (bi, bj) of a level: its grid footprint (plus half a
 * level cell on displaced levels) and the index's z range. */
void world_block_box(const world *w, int level, int bi, int bj,
    double lo[3], double hi[3]);
/* Blocks of every level together: more than any selection holds. */
int world_blocks(const world *w);

/* The DEM's box: level 0's footprint without the blocks' padding, from
 * zmin to zmax. */
void world_box(const world *w, double lo[3], double hi[3]);

#endif
