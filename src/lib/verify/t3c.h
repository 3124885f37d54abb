/* t3c.h - the independent reader and checker of the 3D Tiles terrain
 * profile (terrain-3dtiles(5); tilecheck --terrain on an OUTDIR holding
 * tileset.json): two implicit quadtrees, subtree files, one glb per
 * tile. It reports with qm.h's report and measures the DEM with its
 * qm_dem_measure (the mesh in ECEF and the sample loop), and shares no
 * code with any writer of the profile: the glb, glTF 2.0, 3D Tiles 1.1
 * implicit tiling and the CESIUM_tile_edges extension are read from
 * their specifications, the geometry as Cesium3DTilesTerrainProvider
 * draws it (POSITION through nodes[0].matrix, then Y up to Z up: ECEF).
 *
 *   t3c_glb.c   a glb's bytes: container, glTF JSON, accessors
 *   t3c_tile.c  one tile against itself and its TILE_* metadata
 *   t3c_set.c   tileset.json, the files present, announced against them
 *   t3c_subtree.c  the subtree files: availability, TILE_* rows
 *   t3c_seam.c  same-level neighbours along their shared edges
 *   t3c_run.c   every tile, the seams, the DEM, the report, --dump
 *
 * Positions are floats: a vertex is where its float puts it, within
 * t3c_tile.noise metres; every tolerance below is that plus 1 mm. */
#ifndef TL_T3C_H
#define TL_T3C_H

#include "verify/qm.h"

/* The profile's level error (Cesium3DTilesTerrainProvider): 78271.52
 * m / 2^z (getEstimatedLevelZeroGeometricErrorForAHeightmap, width 64,
 * two roots). */
double t3c_level_error(int z);

/* --- a decoded tile (t3c_glb.c) ------------------------------------ */

typedef struct {
	uint32_t n, ntri;
	double *p;          /* ECEF, 3 n */
	float *nrm;         /* NORMAL as written, 3 n */
	double noise;       /* metres: the positions' float rounding, bound */
	uint32_t *idx;      /* 3 ntri, as written (not checked < n) */
	uint32_t nedge[4];  /* QM_WEST, QM_SOUTH, QM_EAST, QM_NORTH: the */
	uint32_t *edge[4];  /* extension's left, bottom, right, top */
} t3c_tile;

/* Decodes a glb of the profile: the container (magic, version 2, the
 * length, a JSON chunk and a BIN chunk padded to 4 bytes), the glTF JSON
 * (nodes[0].matrix, meshes[0].primitives[0] of triangles with POSITION
 * and NORMAL float VEC3, indices and the four CESIUM_tile_edges lists
 * unsigned SCALAR; one mesh of one primitive; every accessor within its
 * buffer view, packed and aligned as CesiumJS reads it, within the BIN
 * chunk; POSITION's min and max its extremes; positions finite). Fails
 * with "what: why" naming the part; t is zeroed first: t3c_free it. */
int t3c_decode(const unsigned char *b, size_t len, t3c_tile *t, tl_err *e);
/* The file at path (a regular file), decoded. */
int t3c_read(const char *path, t3c_tile *t, tl_err *e);
void t3c_free(t3c_tile *t);

/* --- one tile (t3c_tile.c) ----------------------------------------- */

typedef struct {
	double hmin, hmax;  /* TILE_MINIMUM_HEIGHT, TILE_MAXIMUM_HEIGHT */
	double sphere[4];   /* TILE_BOUNDING_SPHERE: centre, radius */
	double hop[3];      /* TILE_HORIZON_OCCLUSION_POINT */
} t3c_meta;

/* Tile z/x/y's vertices on the globe: u, v in 0..QM_MAXQ over its
 * rectangle (within noise of it snapped to its edges), heights, and per
 * vertex pole 1 where its longitude is lost in the float rounding (at a
 * pole). -1: out of memory. */
int t3c_place(const t3c_tile *t, int z, int x, int y, double *uv,
    double *h, unsigned char *pole);
/* Everything the tile says about itself and what its metadata says of
 * it: vertices inside its rectangle; TILE_MINIMUM/MAXIMUM_HEIGHT the
 * vertices' extremes, the bounding sphere holding every vertex, the
 * horizon occlusion point at or above every vertex's horizon (as for
 * quantized-mesh, CesiumJS's EllipsoidalOccluder); indices in range,
 * triangles counter-clockwise seen from above and with area; each edge
 * list exactly the vertices on its edge, once, in the order the skirts
 * walk; normals unit and not into the ground. Violations go to r. */
void t3c_tile_check(const t3c_tile *t, const t3c_meta *m, int z, int x,
    int y, qm_report *r);

/* --- subtrees (t3c_subtree.c) ------------------------------------- */

typedef struct {
	qm_key k;
	t3c_meta m;
} t3c_ent;

typedef struct {
	t3c_ent *e;
	long n, cap;
} t3c_ents;

/* k (and m, unless NULL) appended: 0, or -1 out of memory. */
int t3c_push(t3c_ents *s, qm_key k, const t3c_meta *m);

/* TILE_MINIMUM_HEIGHT, TILE_MAXIMUM_HEIGHT, TILE_BOUNDING_SPHERE,
 * TILE_HORIZON_OCCLUSION_POINT: t3c_walk's prop[] and psize[] order. */
extern const char *const t3c_semantic[4];

/* One root's walk: what tileset.json says of it, what its subtrees
 * announce. */
typedef struct {
	const char *dir;
	const char *prefix;  /* the root's folder */
	qm_report *r;
	char prop[4][128];   /* the class's property of each semantic */
	int psize[4];        /* its component's bytes: 8, 4 (0: none) */
	int levels, k;       /* availableLevels, subtreeLevels */
	t3c_ents tiles, subs; /* announced: global keys (x from -180) */
	long budget;         /* tiles and subtrees it may still announce */
} t3c_walk;

/* Subtree (s, sx, sy) of root rt (its tile coordinates) and every one
 * below it whose file exists: each file parsed and checked (header
 * "subt" version 1, lengths, the JSON padded to 8, buffer views
 * 8-aligned in its binary, bitstreams or constants, availableCount,
 * content availability the tile availability with its root available,
 * a property table row per available tile, nothing at or past
 * availableLevels), its tiles with their metadata and its child
 * subtrees announced into w. Violations go to w->r; -1 only out of
 * memory or past the budget. */
int t3c_walk_subtree(t3c_walk *w, int rt, int s, int sx, int sy);

/* --- the tileset (t3c_set.c) --------------------------------------- */

typedef struct {
	qm_set s;           /* key: the glbs present; avail: announced */
	t3c_meta *meta;     /* per announced tile, as s.avail */
	char prefix[2][64]; /* root r's folder: its glbs are
	                     * prefix/{level}/{x}/{y}.glb */
	double region[2][6];
} t3c_set;

/* Reads dir/tileset.json (asset 1.1; a schema whose class has the four
 * TILE_* semantics; a root with exactly two children with regions of
 * the western and eastern hemispheres, geometric error 78271.52, REPLACE,
 * content and subtree uris prefix/{level}/{x}/{y}.glb and .subtree,
 * implicit QUADTREE tiling), walks every subtree (header, JSON, buffer
 * views in its binary, availability bitstreams or constants and their
 * counts, content availability the tile availability, a property table
 * row per available tile) and lists the files present: every announced
 * glb and subtree present, every one present announced, every ancestor
 * of a tile available up to both roots, the regions' heights holding
 * every tile's. -1 only when it cannot check (no tileset.json, not
 * JSON, not the profile's layout). */
int t3c_set_read(const char *dir, t3c_set *s, qm_report *r, tl_err *e);
void t3c_set_free(t3c_set *s);
/* The metadata of announced tile k, NULL if none. */
const t3c_meta *t3c_set_meta(const t3c_set *s, qm_key k);
/* dir/prefix/{z}/{x - r 2^z}/{y}.glb of global tile z/x/y. */
void t3c_path(const char *dir, const t3c_set *s, int z, int x, int y,
    char *b, size_t n);

/* --- neighbours (t3c_seam.c) -------------------------------------- */

/* Every tile and its neighbours of the same level east (across the
 * antimeridian and between the roots too) and north: the vertices on
 * the shared edge at the same places (no T-junction), and there the
 * same heights up to half a quantisation step of each tile's TILE_*
 * height range, the rounding of the positions, + 1 mm. Tiles that do
 * not decode or lie outside their rectangle are left out. */
void t3c_seam_check(const char *dir, const t3c_set *s, qm_report *r);

/* --- the programs' side (t3c_run.c) -------------------------------- */

/* qm_run for the 3D Tiles profile: the report (issues named by their
 * glb, per level error / E_L with t3c_level_error) or the dump (per tile
 * "z/x/y vertices N triangles T checksum X", x global, the checksum
 * qm_checksum's of the vertices quantised back to u, v, height). */
int t3c_run(const qm_args *a, const char *prog);

#endif
