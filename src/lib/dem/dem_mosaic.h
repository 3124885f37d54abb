/* dem_mosaic.h - what the files of the mosaic reader share
 * (dem_mosaic.c: the checks and the VRT; dem_mosaic_overlap.c: the
 * samples of overlapping tiles compared; dem_mosaic_tile.c: a tile
 * opened). Private to the GDAL side of the DEM layer. */
#ifndef TL_DEM_MOSAIC_H
#define TL_DEM_MOSAIC_H

#include <sys/types.h>

#include "dem/dem_gdal.h"

/* A tile's place in the mosaic's grid: columns col .. col+w-1, rows
 * row .. row+h-1. */
typedef struct {
	const char *path;
	int col, row, w, h;
	int dup;           /* the earlier entry naming the same file, or -1 */
	dev_t dev;         /* the file, to know it listed again */
	ino_t ino;
} tile;

/* A tile by one of its edges (or a span by its start), and its index. */
typedef struct {
	int at, k;
} key;

static inline int
cmp_key(const void *a, const void *b)
{
	const key *x = a, *y = b;

	return x->at != y->at ? (x->at > y->at) - (x->at < y->at) :
	    (x->k > y->k) - (x->k < y->k);
}

/* A tile's file opened by GDAL, with at least one band, or NULL. */
GDALDatasetH dem_mosaic_open(const char *path, tl_err *e);

/* Every pair of tiles that overlap compared there, sample by sample:
 * 0, or -1 naming the first pair that disagrees. */
int dem_mosaic_overlaps(const tile *tl, int n, const dem_head *r,
    const dem_opts *o, tl_err *e);

#endif
