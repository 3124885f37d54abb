/* t3_impl.h - the pieces of the 3D Tiles export (tiles3d.h). */
#ifndef TL_T3_IMPL_H
#define TL_T3_IMPL_H

#include <stdint.h>
#include <stdio.h>

#include <proj.h>

#include "pyramid/pyramid.h"
#include "tiles3d/tiles3d.h"

/* --- geodesy (geo.c): the DEM's CRS to WGS84 and ECEF --------------- */

/* One thread's PROJ: the DEM's CRS, heights ellipsoidal (promoted to
 * 3D), to EPSG:4979 longitude, latitude (degrees), height. */
typedef struct {
	PJ_CONTEXT *ctx;
	PJ *op;
} t3_proj;

int t3_proj_open(t3_proj *p, const georef *g, tl_err *e);
void t3_proj_close(t3_proj *p);
/* n points in place: x, y (CRS), z (m) in; lon, lat (deg), h (m) out. */
int t3_proj_geo(t3_proj *p, double *x, double *y, double *z, int n,
    tl_err *e);

/* Level-0 grid place (I, J) in the DEM's CRS (geo_vertex_crs), kept on
 * the globe for a geographic DEM: padding past a pole stops at the pole,
 * padding past a full turn of longitude from column 0 stops a turn away
 * (where the DEM's column 0 comes round again). Any other place, and
 * every place of a projected DEM, is geo_vertex_crs's. */
void t3_grid_crs(const georef *g, double I, double J, double *x, double *y);

/* WGS84 (EPSG:4979 -> EPSG:4978), closed form. */
void t3_ecef(double lon, double lat, double h, double out[3]);
/* The point of height 0 at (lon, lat) and the unit normal there: the
 * point of height h is foot + h up. */
void t3_ellipsoid(double lon, double lat, double foot[3], double up[3]);
/* The east, north, up unit vectors at (lon, lat), rows of r (9). */
void t3_enu(double lon, double lat, double r[9]);

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
	t3_proj proj;
	pyramid_block blk;
	t3_tris tris;
	const geo_metric *m;       /* QEM-3D offsets to grid steps, or NULL */
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

int t3_work_init(t3_work *w, const georef *g, const geo_metric *m,
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
int t3_plan(t3_set *s, const pyramid_index *ix, double tau0, t3_proj *p,
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
int t3_volume(const t3_set *s, t3_proj *p, const t3_tile *t, double *v,
    tl_err *e);

/* tileset.json into dir; raises an error below a child's to the child's
 * (counted in *raised). */
int t3_tileset_write(const t3_set *s, t3_proj *p, const char *dir,
    int *raised, tl_err *e);

#endif
