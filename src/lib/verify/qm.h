/* qm.h - the independent reader and checker of quantized-mesh-1.0
 * terrain (tilecheck --terrain, tilecheck(1) TERRAIN): a tileset's
 * layer.json and its {z}/{x}/{y}.terrain tiles on the global geographic
 * TMS quadtree (EPSG:4326, two roots at level 0, rows from the south).
 *
 *   qm_decode.c  a tile's bytes (gzip inflated) into its fields
 *   qm_tile.c    one tile against itself: header, indices, edges
 *   qm_layer.c   layer.json, the files present, availability, ancestors
 *   qm_seam.c    same-level neighbours along their shared edges
 *   qm_dem.c     the surface drawn against every valid DEM sample (any
 *                format's mesh, through a loader: t3c.h's too)
 *   qm_run.c     the report, --dump, the programs' entry
 *
 * It shares no code with any writer of these tiles: the format is read
 * from the quantized-mesh-1.0 specification, the geometry as CesiumJS
 * draws it (u, v, height interpolated linearly between the tile's
 * rectangle and its header's heights, then WGS84 to ECEF, flat
 * triangles in ECEF) and the horizon occlusion point as CesiumJS's
 * EllipsoidalOccluder computes and tests it. Library functions print
 * nothing but qm_run's report and dump. */
#ifndef TL_QM_H
#define TL_QM_H

#include <stdint.h>
#include <stdio.h>

#include "dem/dem.h"
#include "base/util.h"

#define QM_MAXZ 28     /* deepest level read (x < 2^29, y < 2^28) */
#define QM_MAXQ 32767  /* u, v, height quantised to 0 .. QM_MAXQ */

/* --- a decoded tile (qm_decode.c) ---------------------------------- */

enum { QM_WEST, QM_SOUTH, QM_EAST, QM_NORTH };

typedef struct {
	double center[3];
	float hmin, hmax;     /* the header's minimum, maximum height */
	double sphere[4];     /* centre x y z, radius */
	double occlusion[3];  /* horizon occlusion point, scaled space */
	uint32_t n;           /* vertices */
	int32_t *u, *v, *h;   /* zig-zag deltas summed (checked 0..32767
	                       * by qm_tile_check) */
	uint32_t ntri;
	int64_t *idx;         /* 3 ntri, high-water marks undone (a code
	                       * above the highest gives a negative index) */
	uint32_t nedge[4];    /* west, south, east, north */
	uint32_t *edge[4];
	int index32;          /* indices 32-bit (more than 65536 vertices) */
	int gzip;             /* the file was gzip'd */
	unsigned char *normals; /* extension 1: 2 n bytes, or NULL */
	long normals_len;     /* its length as written (-1: none) */
	long watermask_len;   /* extension 2 (-1: none) */
	char *metadata;       /* extension 4's JSON, NUL-terminated, or NULL */
	long metadata_len;    /* extension 4's length as written (-1: none) */
	int unknown_ext;      /* extensions of other ids, skipped */
} qm_tile;

/* Decodes len bytes (a gzip stream is inflated first). Fails with "what:
 * why" naming the part that is truncated or impossible (no room for
 * the header, the vertices, the indices, an edge list, an extension;
 * trailing bytes that make no extension). t is zeroed first; qm_free
 * it in any case. */
int qm_decode(const unsigned char *buf, size_t len, qm_tile *t, tl_err *e);
/* The file at path, read whole (regular files only), decoded. */
int qm_read(const char *path, qm_tile *t, tl_err *e);
void qm_free(qm_tile *t);

/* The tile's rectangle in degrees: west, south, east, north. */
void qm_rect(int z, int x, int y, double r[4]);
/* Vertex i as CesiumJS places it: longitude, latitude (degrees) and
 * height by linear interpolation, then WGS84 ECEF. */
void qm_vertex(const qm_tile *t, const double rect[4], uint32_t i,
    double llh[3], double ecef[3]);
/* The level's error budget CesiumJS assumes for quantized-mesh tiles:
 * 6378137 * 2 pi * 0.25 / (65 * 2) / 2^z = 77067.34 m / 2^z. */
double qm_level_error(int z);
/* FNV-1a 32 of the decoded u, v, heights (each as 2 bytes, little-
 * endian, all u then all v then all heights) and the triangle indices
 * (4 bytes each): what --dump prints, and tests/js/qmdecode.js. */
uint32_t qm_checksum(const qm_tile *t);

/* --- violations ---------------------------------------------------- */

enum qm_kind {
	QM_DECODE, QM_HEADER, QM_HEIGHTS, QM_SPHERE, QM_OCCLUSION, QM_INDEX,
	QM_WINDING, QM_DEGENERATE, QM_HOLE, QM_EDGES, QM_EXTENSION, QM_LAYER,
	QM_UNANNOUNCED, QM_MISSING, QM_ANCESTOR, QM_SEAM, QM_COVERAGE,
	QM_ERROR, QM_NKIND
};

const char *qm_kind_name(int kind); /* "decode", "header", ... */

typedef struct {
	int kind, z, x, y; /* z -1: the tileset as a whole */
	char text[224];
} qm_issue;

typedef struct {
	long long tiles, gzip, vertices, triangles;
	long long samples;  /* valid DEM samples checked in its tiles */
	double *ratio;      /* per tile with samples: max error / E_L */
	long nratio, capratio;
	double worst;       /* largest error, metres */
	int worst_tile[2];
} qm_level;

typedef struct {
	int dem;            /* the DEM check ran */
	double (*level_error)(int z); /* E_z (qm_level_error by default) */
	const char *const *names; /* kind names printed (NULL: the default) */
	/* tile z/x/y as the report names it (NULL: "z/x/y") */
	void (*tile_name)(const void *ctx, int z, int x, int y, char *b,
	    size_t n);
	const void *name_ctx;
	int maxz;           /* deepest level with a tile, -1: none */
	qm_level lev[QM_MAXZ + 1];
	long long count[QM_NKIND], total;
	int kept[QM_NKIND];
	int max_issues;     /* kept per kind (20); all are counted */
	qm_issue *issue;
	int nissue, capissue;
} qm_report;

void qm_report_init(qm_report *r);
void qm_report_free(qm_report *r);
/* Counts a violation of kind at tile z/x/y (z -1: none), keeping its
 * text while fewer than max_issues of its kind are kept. */
void qm_issue_add(qm_report *r, int kind, int z, int x, int y,
    const char *fmt, ...) __attribute__((format(printf, 6, 7)));

/* --- one tile (qm_tile.c) ------------------------------------------ */

/* CesiumJS's EllipsoidalOccluder: the magnitude along the unit
 * direction d (scaled space, divided by rad) at which a point hides
 * only what ECEF point p hides too; <= 0 or not finite: none does. */
double qm_horizon_magnitude(const double p[3], const double d[3],
    const double rad[3]);

/* Whether the surface a tile's triangles draw is closed (qm_closed.c):
 * vertices with equal keys (bit for bit) are one place; an edge inside
 * the tile (not along u or v = 0 or QM_MAXQ at both ends) of one
 * triangle is a crack (open), one of three or more or of two running the
 * same way an overlap (over); each counted, the first named by the
 * vertices of its places. Corners out of range and edges from a skip'd
 * vertex are left out. -1: out of memory. */
typedef struct {
	uint32_t n;                /* vertices */
	const double *key;         /* 3 n: the place of each vertex */
	const double *uv;          /* 2 n: u, v in 0 .. QM_MAXQ */
	size_t ncorner;            /* 3 triangles */
	const int64_t *corner;     /* the vertex of each corner, or NULL: */
	const uint32_t *corner32;  /* these */
	const unsigned char *skip; /* n, or NULL */
} qm_closure_in;

typedef struct {
	size_t open, over;
	uint32_t open_edge[2], over_edge[2];
} qm_closure;

int qm_closed(const qm_closure_in *in, qm_closure *out);

/* Everything a tile says about itself: u, v, heights in 0..32767;
 * header finite, the minimum and maximum heights the vertices' extremes,
 * the bounding sphere holding every vertex (1 mm), the horizon occlusion
 * point at or above every vertex's horizon as CesiumJS computes it
 * (1 mm); indices in range, triangles counter-clockwise in (u, v) (seen
 * from outside the ellipsoid), none without area; each edge list
 * exactly the vertices on its edge, once; extension lengths, normals
 * pointing up, metadata JSON. Violations go to r. */
void qm_tile_check(const qm_tile *t, int z, int x, int y, int normals,
    qm_report *r);
/* u, v, heights in 0..32767 and the header's heights finite: the tile
 * can be placed (what the checks of several tiles need). */
int qm_tile_sane(const qm_tile *t);

/* --- neighbours (qm_seam.c) ---------------------------------------- */

/* Every tile and its neighbours of the same level east (across the
 * antimeridian too) and north: the vertices on the shared edge at the
 * same places (no T-junction), and there the same heights up to half a
 * quantisation step of each tile's height range, + 1 mm. A seam
 * violation otherwise. Tiles that are not sane are left out. */
struct qm_set;
void qm_seam_check(const char *dir, const struct qm_set *s, qm_report *r);

/* --- the tileset (qm_layer.c) -------------------------------------- */

/* Tile keys: sorted, they run by level, then x, then y. */
typedef uint64_t qm_key;
#define QM_KEY(z, x, y) \
	(((qm_key)(z) << 57) | ((qm_key)(x) << 28) | (qm_key)(y))
#define QM_KZ(k) ((int)((k) >> 57))
#define QM_KX(k) ((int)(((k) >> 28) & ((1u << 29) - 1)))
#define QM_KY(k) ((int)((k) & ((1u << 28) - 1)))

typedef struct qm_set {
	qm_key *key;      /* the tile files present, sorted */
	long n;
	qm_key *avail;    /* the tiles layer.json announces, sorted */
	long navail;
	int normals;      /* extensions lists "octvertexnormals" */
	int maxzoom;
} qm_set;

/* Reads dir/layer.json and lists dir/{z}/{x}/{y}.terrain; checks the
 * fields (tilejson, name, description, version, format
 * "quantized-mesh-1.0", scheme "tms", tiles with {z} {x} {y},
 * projection "EPSG:4326", bounds, minzoom, maxzoom, extensions,
 * available), every announced tile present and every present one
 * announced, every ancestor of a tile present up to both roots. Fails
 * (-1) only when it cannot check: no layer.json, not JSON, dir
 * unreadable. */
int qm_set_read(const char *dir, qm_set *s, qm_report *r, tl_err *e);
void qm_set_free(qm_set *s);
int qm_set_has(const qm_set *s, qm_key k);
/* A tile's metadata (extension 4) "available": every tile it announces
 * present. */
void qm_metadata_check(const qm_set *s, const qm_tile *t, int z, int x,
    int y, qm_report *r);

/* --- the DEM (qm_dem.c) -------------------------------------------- */

/* A tile as drawn, whatever its format: what the DEM is measured
 * against. */
typedef struct {
	uint32_t n, ntri;
	double *p;           /* ECEF, 3 n */
	double *uv;          /* u, v in 0..QM_MAXQ over the tile, 2 n */
	unsigned char *pole; /* n: the vertex is at a pole (its u is
	                      * unknown); NULL: none is */
	uint32_t *tri;       /* 3 ntri, each < n */
} qm_mesh;

/* A format's reader: tile k of the set into m (fields malloc'd): 0
 * done, 1 it cannot be placed (its own checks say why; its samples are
 * skipped), -1 out of memory. */
typedef int (*qm_mesh_load)(void *ctx, qm_key k, qm_mesh *m);
void qm_mesh_free(qm_mesh *m);

/* For every tile level, every valid DEM sample (heights as dem_open
 * gives them with o: -H ellipsoid as the pyramid was made) inside a
 * tile of that level (closed rectangles: a sample on a shared edge
 * counts in both): the vertical distance, along the ellipsoid's normal
 * at the sample, to the plane of the ECEF triangle whose (u, v) holds
 * it (for a triangle with a vertex at a pole, the triangle its
 * vertical passes through). Per tile the largest goes to r (error /
 * E_z per level, E_z r->level_error's); over E_z + 1 mm is an error
 * violation; a sample in no tile of a level up to the deepest, or in no
 * triangle of its tile, a coverage one. The DEM is read once, a row at
 * a time, holding per level only the tiles near that row, each loaded
 * by load. */
int qm_dem_measure(const qm_set *s, qm_mesh_load load, void *ctx,
    const char *dem_path, const dem_opts *o, qm_report *r, tl_err *e);
/* qm_dem_measure on the quantized-mesh tiles dir/{z}/{x}/{y}.terrain. */
int qm_dem_check(const char *dir, const qm_set *s, const char *dem_path,
    const dem_opts *o, qm_report *r, tl_err *e);

/* --- the programs' side (qm_run.c) --------------------------------- */

typedef struct {
	const char *dir;      /* the tileset */
	const char *dem_path; /* --dem, or NULL */
	dem_opts dem;
	int dump;             /* --dump: one line per tile, nothing else */
} qm_args;

/* Everything above on the tileset in dir, against the DEM when dem_path
 * is not NULL, into r and s (free both, whatever the result). -1: it
 * cannot check (qm_set_read, qm_dem_check). */
int qm_check(const char *dir, const char *dem_path, const dem_opts *o,
    qm_set *s, qm_report *r, tl_err *e);

/* Checks a->dir and prints the report on stdout ("result: pass" or
 * "result: FAIL, n violations: ..."), or with a->dump per tile, sorted,
 * "z/x/y vertices N triangles T checksum XXXXXXXX". Returns 0 pass, 1
 * violations (or a tile that does not decode in a dump), -1 when it
 * cannot check ("prog: what: why" on stderr). */
int qm_run(const qm_args *a, const char *prog);
/* The report of the tileset in dir (s its tiles) on f, as qm_run prints
 * it. */
void qm_report_print(FILE *f, const qm_report *r, const qm_set *s,
    const char *dir, const char *dem_path);

#endif
