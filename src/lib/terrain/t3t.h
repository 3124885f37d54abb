/* t3t.h - the 3D Tiles terrain profile (vgis2terrain -f 3dtiles,
 * terrain-3dtiles(5)): the tiles of the quantized-mesh export, as
 * CesiumJS's Cesium3DTilesTerrainProvider and cesium-native read terrain:
 * OUTDIR/tileset.json, two implicit quadtrees (roots r0: west, r1: east)
 * with OUTDIR/r{0,1}/{level}/{x}/{y}.glb (x within the root, y from the
 * south) and their .subtree availability files with the TILE_* metadata
 * of every tile. One glb per tile: one primitive, POSITION (float, minus
 * the tile's centre, placed by the node's matrix), NORMAL (ECEF), the
 * triangles, CESIUM_tile_edges. The set keeps each tile's metadata (9
 * doubles) until the subtrees are written; tiles fill disjoint slots, so
 * threads need no lock. */
#ifndef TL_T3T_H
#define TL_T3T_H

#include "terrain/tr_impl.h"

#define T3T_E0 78271.52 /* m: the provider's level-0 error (64, 2 roots) */
#define T3T_SUBLEVELS 6 /* levels in a subtree file */

typedef struct t3t_set t3t_set;

/* The set for levels 0 .. maxz, the tiles of level z in the inclusive
 * rectangle av[z] (x0 y0 x1 y1, global x, TMS y). */
t3t_set *t3t_new(int maxz, const int (*av)[4], tl_err *e);
void t3t_free(t3t_set *s);
/* Level z's directories under tmp (r/z/x for both roots). */
int t3t_dirs(const char *tmp, int z, const int av[4], tl_err *e);
/* The path of tile (z, x, y)'s glb under tmp. */
void t3t_path(char *p, size_t n, const char *tmp, int z, int x, int y);
/* The glb of the quantised tile (z, x, y) (tr_quantise) into w->buf; its
 * metadata into s (t3t_glb.c). */
int t3t_glb(tr_work *w, t3t_set *s, int z, int x, int y, float minh,
    float maxh, tl_err *e);
/* Tile (z, x, y)'s metadata slot: min, max height, sphere (4), horizon
 * occlusion point (3). */
double *t3t_meta(t3t_set *s, int z, int x, int y);
/* The subtrees and tileset.json into dir (t3t_tileset.c). */
int t3t_finish(t3t_set *s, const char *dir, const tr_args *a,
    const char *datum, tl_err *e);

#endif
