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

#include "geo/georef.h"
#include "raster/raster.h"
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

/* The strict reader that the viewer and the exporters share (the checker
 * keeps its own, verify.h); it refuses what they could not honour, with
 * the field or block named, as strictly as tilecheck(1):
 *
 * pyramid_index_parse reads the n bytes of an index.json (name: for
 * messages) as untrusted input: no more bytes, and no more JSON values,
 * than the index of the pyramid its size0 claims can need (so jansson's
 * memory stays proportional to the pyramid), keys unique, every integer
 * in range before it is used (no truncation), every number finite,
 * the level count, sizes and block counts those of size0, the pixel size
 * sane, and per block zmin <= zmax, base_error and max_error >= 0.
 * pyramid_index_read reads DIR/index.json, which must be a regular file
 * (a FIFO or a directory is refused at once), the same way. Its users
 * then call pyramid_levels_probe: block (0,0) of every level must have that
 * level's channels (displaced or not) and the index's fqm:* and geo:*
 * attributes, so that a level the index misdescribes is refused before
 * anything is drawn or exported. */
int pyramid_index_parse(const char *text, size_t n, const char *name,
    pyramid_index *ix, tl_err *e);
int pyramid_index_read(const char *dir, pyramid_index *ix, tl_err *e);
int pyramid_levels_probe(const char *dir, const pyramid_index *ix, tl_err *e);
/* Resource guards that the checker's reader shares (they read no field
 * for use): pyramid_index_load reads a whole index.json that must be a
 * regular file, NUL-terminated, its size in *n; pyramid_index_bounded
 * refuses a text larger, or with more or fewer values, than the index of
 * the pyramid its root's "size0" claims can hold, before jansson parses
 * it. */
char *pyramid_index_load(const char *path, size_t *n, tl_err *e);
int pyramid_index_bounded(const char *text, size_t n, const char *what,
    tl_err *e);

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
 * own vgis:* attributes, at a path in a directory that holds no dead
 * writer's temporaries (rs_create_fresh). */
int pyramid_block_write(const char *path, const pyramid_block *b,
    const rs_header *attrs, tl_err *e);
/* ... compressed as comp says (pyramid_block_write: RS_ZIP, the default;
 * tilepack -z); in_tree: path is new, inside a tree this process builds,
 * and the block is written under its final name (rs_create_tree). */
int pyramid_block_write_z(const char *path, const pyramid_block *b,
    const rs_header *attrs, enum rs_compression comp, int in_tree,
    tl_err *e);
/* Reads a block, a regular file (a FIFO is refused at once), and checks
 * its size, its channels and vgis:* attributes against what b->level,
 * bi, bj, displaced say it must be, and its content as vgis(5) allows it:
 * Z (X, Y) finite and spanning vgis:zrange exactly, E FLT_MAX at the
 * corners and finite, >= 0 elsewhere; sets b->emax. */
int pyramid_block_read(const char *path, pyramid_block *b, tl_err *e);
/* Block (b->bi, b->bj) of level b->level of the pyramid in dir (b->displaced
 * the level's), read as above and checked against the index's entry for
 * it: zmin, zmax, base_error and max_error. */
int pyramid_block_load(const char *dir, const pyramid_index *ix,
    pyramid_block *b, tl_err *e);

#endif
