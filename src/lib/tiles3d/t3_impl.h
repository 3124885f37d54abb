/* t3_impl.h - the pieces of the 3D Tiles export (tiles3d.h). */
#ifndef TL_T3_IMPL_H
#define TL_T3_IMPL_H

#include <stdint.h>
#include <stdio.h>

#include "geo/wgs84.h"
#include "pyramid/pyramid.h"
#include "tiles3d/tiles3d.h"

/* --- one tile: a block's mesh (tile.c, cut.c, glb.c) --------------- */

/* A tile's frame: ECEF = c + R^T p for p = (east, north, up) metres;
 * r holds the rows e, n, u. */
typedef struct {
	double c[3], r[9];
} t3_frame;

/* The triangles of a block's selection (cut.c). */
typedef struct {
	uint16_t *idx;   /* 3 per triangle: grid indices r * 129 + c */
	double *bound;   /* per triangle: E of its hypotenuse midpoint, or the
	                  * block's base error for a leaf */
	int n, cap;      /* triangles */
} t3_tris;

/* The selection of block b: the vertices with E > tau or whose
 * hypotenuse is longer than lmax cells (the Earth's curve: plan.c),
 * triangles wholly past the level's last real column cmax or row rmax
 * (block coordinates) dropped. */
int t3_cut(const pyramid_block *b, double tau, double lmax, int cmax,
    int rmax, t3_tris *t, tl_err *e);

/* One thread's buffers for a tile. */
typedef struct t3_work t3_work;
typedef struct t3_tile t3_tile;

struct t3_work {
	geo_proj proj;
	pyramid_block blk;
	t3_tris tris;
	const geo_ground *m;       /* QEM-3D offsets to grid steps, or NULL */
	double *px, *py;           /* per grid vertex: level-0 grid place */
	double *lon, *lat, *h, *x; /* per grid vertex; x: ECEF, 3 each */
	double *foot, *up;         /* per grid vertex: ECEF at height 0 and
	                            * the ellipsoid's normal, 3 each */
	int *map;                  /* grid and skirt vertex -> glb vertex */
	float *pos, *nrm;          /* glb vertices, 3 each */
	uint16_t *idx;             /* glb indices */
	double curve;              /* largest flat-triangle/float term */
	long long nverts, ntris, nbytes;
};

int t3_work_init(t3_work *w, const georef *g, const geo_ground *m,
    tl_err *e);
void t3_work_free(t3_work *w);

/* A tile as the tileset needs it. */
struct t3_tile {
	int level, bi, bj;
	int cmax, rmax;     /* last real vertex in block coordinates */
	int displaced;      /* QEM-3D level: vertices offset in x, y */
	double tau, skirt;  /* metres */
	double lmax;        /* cells: longer hypotenuses split (t3_cut) */
	t3_frame f;
	double error;       /* written by t3_tile */
};

/* Reads block t of the pyramid in dir, writes its glb to path and sets
 * t->error: the bound of its mesh's vertical distance from the DEM. */
int t3_tile_write(t3_work *w, const char *dir, const pyramid_index *ix,
    t3_tile *t, const char *path, tl_err *e);

/* The bound of the distance between the drawn triangle p (ECEF of its
 * float32 vertices) over grid vertices k and the grid-linear one, along
 * the normal (bound.c). */
int t3_flat_bound(t3_work *w, const georef *g, const t3_tile *t,
    const uint16_t k[3], const double p[3][3], double *out, tl_err *e);

/* The glb of nv vertices (pos, nrm: y-up) and ni uint16 indices. */
int t3_glb_write(FILE *f, const float *pos, const float *nrm, int nv,
    const uint16_t *idx, int ni, long long *bytes, tl_err *e);

/* --- the tileset (tileset.c, volume.c) ------------------------------ */

typedef struct {
	const pyramid_index *ix;
	t3_tile *tile;  /* every block, level by level, row-major */
	int *first;     /* index of each level's first tile */
	double *zlo, *zhi; /* per tile: heights its subtree spans (skirts in) */
	int region;     /* geographic DEM: regions, else boxes */
} t3_set;

/* Tiles, tolerances, skirts, frames and heights from the index. */
int t3_plan(t3_set *s, const pyramid_index *ix, double tau0, geo_proj *p,
    tl_err *e);
void t3_set_free(t3_set *s);

/* Refuses a pyramid that cannot go on a globe (datum.c). */
int t3_check_datum(const t3_args *a, const pyramid_index *ix, tl_err *e);

/* The tile of block (bi, bj) of level l. */
static inline t3_tile *
t3_at(const t3_set *s, int l, int bi, int bj)
{
	return &s->tile[s->first[l] + bj * s->ix->lev[l].blocks[0] + bi];
}

/* The tile's bounding volume in its frame (box, 12) or as a region (6). */
int t3_volume(const t3_set *s, geo_proj *p, const t3_tile *t, double *v,
    tl_err *e);

/* tileset.json into dir; raises an error below a child's to the child's
 * (counted in *raised). */
int t3_tileset_write(const t3_set *s, geo_proj *p, const char *dir,
    int *raised, tl_err *e);

#endif
