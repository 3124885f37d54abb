/* pyramid.h - the VGIS block directory on disk (see vgis(5)): index.json
 * (pyramid_index.c) and, per level, one 129x129 EXR per block (pyramid.c):
 *
 *   DIR/index.json
 *   DIR/<level>/<row>_<col>.exr     channels E Z (+ X Y when displaced)
 *
 * Blocks of a level share their border rows and columns; block (i, j)
 * holds level vertices 128i .. 128i+128 by 128j .. 128j+128, vertices past
 * the level's size being padding (copies of the nearest edge vertex). */
#ifndef TL_PYRAMID_H
#define TL_PYRAMID_H

#include "core/georef.h"
#include "core/raster.h"
#include "pyramid/bintree.h"
#include "pyramid/vgis.h"

#define PYRAMID_N (BT_SIZE * BT_SIZE) /* vertices of a block */

typedef struct {
	int level;
	int size[2];    /* the level's vertices (before padding) */
	int blocks[2];  /* block columns, rows */
	int displaced;  /* X, Y channels (QEM-3D) */
	char mode[16];  /* fqm:mode of its vertex map */
	char kernel[16];
	/* per block, row-major (j * blocks[0] + i): */
	double *zmin, *zmax; /* range of Z over the block's vertices */
	double *base;        /* base error: the finest triangles' deviation
	                      * from the DEM over the block (0 on level 0) */
	double *emax;        /* largest finite E in the block */
} pyramid_level;

typedef struct {
	int version;
	int size0[2];
	georef geo;
	int nlevels;
	pyramid_level *lev;
} pyramid_index;

/* Blocks along one axis for a level of n vertices: ceil((n-1)/128), >= 1. */
int pyramid_nblocks(int n);
/* Level and block arrays for a level of the given size. */
int pyramid_level_init(pyramid_level *L, int level, int w, int h, tl_err *e);
void pyramid_index_free(pyramid_index *ix);

/* DIR/index.json, written atomically (ix->version is not read: this
 * program's VGIS_VERSION is written). */
int pyramid_index_write(const char *dir, const pyramid_index *ix, tl_err *e);
/* Reads DIR/index.json as untrusted input: sizes, the level count and
 * every level's size and block count are checked before anything is
 * allocated from them. */
int pyramid_index_read(const char *dir, pyramid_index *ix, tl_err *e);

/* "DIR/<level>/<row>_<col>.exr" */
void pyramid_block_path(char *buf, size_t n, const char *dir, int level, int bi,
    int bj);

/* A block in memory: 129x129 floats per channel, row-major. */
typedef struct {
	int level, bi, bj, displaced;
	double base, zmin, zmax;
	double emax;    /* largest E below FLT_MAX (set by its producer) */
	float *z, *e, *x, *y; /* x, y NULL unless displaced */
} pyramid_block;

int pyramid_block_alloc(pyramid_block *b, int displaced, tl_err *e);
void pyramid_block_free(pyramid_block *b);
/* Writes the block with the attributes of `attrs` (geo:*, fqm:*) and its
 * own vgis:* attributes, at a path inside a tree under construction
 * (rs_create_fresh). */
int pyramid_block_write(const char *path, const pyramid_block *b,
    const rs_header *attrs, tl_err *e);
/* Reads a block and checks its size, channels and vgis:* attributes
 * against what b->level, bi, bj, displaced say it must be. */
int pyramid_block_read(const char *path, pyramid_block *b, tl_err *e);

#endif
