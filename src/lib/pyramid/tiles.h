/* tiles.h - the errors of a level's blocks: exact local errors against
 * every valid DEM sample, saturated across block borders (vgis(5), "The
 * triangulation"), streamed.
 *
 * One pass over the DEM's rows: each valid sample is located, for every
 * scale and kind of the bintree, in the diamond(s) containing it (closed;
 * in the displaced triangles for QEM-3D levels) and raises that diamond
 * vertex's local error to the sample's vertical distance from the
 * diamond's two triangles without the vertex; it also raises its block's
 * base error (its distance from the finest triangles). On undisplaced
 * levels the triangles' chords along a DEM row are whole columns, found
 * once per scale, kind and centre row (tiles_scan.c); displaced levels
 * use the general chord with each vertex's position found once per
 * scale; both give the same values bit for bit. Once no later DEM
 * row can reach the local errors a block row's saturation needs, its
 * errors are saturated, children before parents, over a band of 128 rows
 * either side (a vertex's descendants lie within 126 rows of it, a block
 * centre's within 190), and the blocks are handed out. Every local error
 * is an exact maximum, so E is exact on every level, not a bound.
 *
 * The DEM rows are scanned in batches of 32; within a batch each thread
 * takes a share of the level's columns (the diamonds centred there, the
 * leaves starting there), so no two write the same local error, and
 * keeps its own base errors, merged by max: the blocks are the same bits
 * whatever the thread count.
 *
 * Memory: rings of 512 level rows of Z and offsets and of 640 rows of
 * local errors, the saturation band (385 rows), 32 DEM rows as doubles
 * and, displaced, 8 rows of positions per scale and thread. */
#ifndef TL_TILES_H
#define TL_TILES_H

#include "core/dem.h"
#include "pyramid/pyramid.h"

/* The level's real row r (r < size[1]) of heights and, displaced, the X
 * and Y offsets in metres (x, y NULL for 1D levels). Rows are asked for in
 * order, once each. */
typedef int (*tiles_row_fn)(void *ctx, int r, float *z, float *x, float *y,
    tl_err *e);
/* A finished block; the callee writes it (b is reused afterwards). With
 * threads > 1 it is called from several threads at once, for different
 * blocks of one block row (block rows come in order, a row's blocks in
 * any order). */
typedef int (*tiles_block_fn)(void *ctx, const pyramid_block *b, tl_err *e);

typedef struct {
	int level;
	int size[2];     /* the level's vertices */
	int displaced;
	const geo_metric *m;
	tiles_row_fn row;
	void *row_ctx;
	tiles_block_fn block;
	void *block_ctx;
	const char *label; /* progress on a terminal, or NULL */
	int threads;       /* 1 .. TILES_MAXTHREADS: the columns in shares */
} tiles_level;

#define TILES_MAXTHREADS 64

typedef struct {
	double max_base;   /* largest base error of any block */
	double max_e;      /* largest finite E */
	long long samples; /* valid DEM samples measured */
} tiles_stats;

int tiles_run(const tiles_level *L, dem *d, tiles_stats *st, tl_err *e);

#endif
