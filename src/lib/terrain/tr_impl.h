/* tr_impl.h - the pieces of the terrain export (terrain.h): the encoder
 * (qm_encode.c), a tile's mesh (tr_mesh.c, tr_clip.c), its measured
 * error (tr_measure.c), layer.json (tr_layer.c), the run (tr_run.c). */
#ifndef TL_TR_IMPL_H
#define TL_TR_IMPL_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "geo/wgs84.h"
#include "pyramid/pyramid.h"
#include "terrain/terrain.h"

#define QM_MAX 32767 /* u, v, height quantised to 0 .. QM_MAX */
#define TR_CACHE 64  /* blocks a thread holds: geographic DEMs */
#define TR_CACHE_PROJ 32 /* projected DEMs (a longitude, latitude each
                          * vertex: 3 times the bytes a block) */
#define TR_RMIN 6335439.0 /* m: WGS 84's least radius of curvature */

/* --- the encoder's pieces (qm_encode.c), exposed for the unit test --- */

/* Zig-zag of a delta in -32767 .. 32767: 2d for d >= 0, -2d-1 below. */
uint16_t qm_zigzag(int d);
/* High-water-mark code of index i given the highest so far (updated):
 * highest - i, highest incremented when the code is 0. i <= *highest. */
uint32_t qm_hwm(uint32_t i, uint32_t *highest);
/* Oct encoding of a unit vector into two bytes (CesiumJS's
 * AttributeCompression.octEncode, range 255). */
void qm_oct(const double n[3], uint8_t out[2]);
/* CesiumJS's EllipsoidalOccluder.computeHorizonCullingPointFromVertices
 * on WGS84 (scaled space), direction dir: 0, or -1 when no point exists
 * (a vertex at or past 90 degrees from dir on the horizon cone). */
int qm_horizon(const double dir[3], const double *p, int n, double out[3]);

/* --- a tile's mesh ------------------------------------------------- */

/* The DEM on the globe: level-0 grid place (I, J) to longitude and
 * latitude (degrees), affine for a geographic DEM (lon = ax + bx I,
 * lat = ay + by J), through PROJ for a projected one; the rectangle r
 * (west, south, east, north) of the terrain made from it: the DEM's
 * extent when geographic; when projected the box fp of its footprint
 * widened by level 0's band (tr_rim_band); and per pyramid level and
 * block the longitude, latitude box of its vertices (4 each). */
typedef struct {
	int projected;
	double ax, bx, ay, by;
	int w0, h0;             /* level-0 size */
	double r[4];
	double fp[4];           /* projected: the box of the side samples */
	double cell;            /* metres: the longest level-0 step */
	double **box;           /* per level: 4 per block */
	double d1psi, d2psi;    /* projected (tr_curve.c): bounds of the map
	                         * psi from longitude, latitude (degrees) to
	                         * level-0 places: |D psi| (cells a degree),
	                         * |D2 psi[d, d]|, d a unit (cells a square
	                         * degree); d2psi INFINITY: none known */
	double d1phi;           /* and |D phi| of its inverse (degrees a
	                         * cell) */
	struct tr_store *zs;    /* the blocks as decoded (tr_block), or NULL */
	struct tr_llfile *ll;   /* projected: the blocks' vertex longitudes
	                         * and latitudes, each through PROJ once a
	                         * run, for all threads (tr_block); NULL:
	                         * none, each load converts its own */
} tr_grid;

/* A run's records in a scratch file, shared by its threads
 * (tr_store.c): n of size bytes each; NULL when none can be made (then
 * every get fails). Get: record k into buf (size bytes) as put, or -1
 * (never put, or lost: make it again). Put: record k's bytes, the same
 * whoever puts them; dropped when the file is full or failed. */
struct tr_store *tr_store_new(long long n, size_t size);
/* A hash of n bytes (64-bit words in four lanes), to tell the bytes read
 * back from a scratch file from those written. */
uint64_t tr_hash(const void *p, size_t n);
void tr_store_free(struct tr_store *s);
int tr_store_get(struct tr_store *s, long long k, void *buf);
void tr_store_put(struct tr_store *s, long long k, const void *buf);

/* The grid of the pyramid ix (tr_grid.c); p: a PROJ for a projected
 * DEM. */
int tr_grid_init(tr_grid *g, const pyramid_index *ix, geo_proj *p,
    tl_err *e);
void tr_grid_free(tr_grid *g, int nlevels);
/* g's d1psi, d2psi (tr_curve.c). */
void tr_curve(tr_grid *g, geo_proj *p, const georef *geo);
/* Longitude, latitude of level-0 places, n at once (x, y in place). */
int tr_lonlat(const tr_grid *g, geo_proj *p, const georef *geo, double *x,
    double *y, int n, tl_err *e);

/* A tile's vertices (longitude, latitude, height) and triangles. */
typedef struct {
	double *x, *y, *h;
	int nv, cv;
	int *tri;               /* 3 per triangle */
	int nt, ct;
	int *hash, hcap;        /* (x, y) -> vertex + 1 */
	unsigned char *rim;     /* projected DEMs: per triangle, 1 past the
	                         * footprint (tr_rim.c); else NULL */
	int crim;
	int *src;               /* projected DEMs: per triangle, the selection
	                         * triangle (w->sel) it is a piece of, -1 past
	                         * the footprint; with rim */
	int csrc;
} tr_mesh;

/* A selection triangle: longitudes, latitudes, heights; a projected
 * DEM's, its level-0 places too (tr_cut.c), and whether it lies on the
 * grid's outline (a vertex on or past a side: cut, or the band). */
typedef struct {
	double x[3], y[3], h[3];
	double lo[2], hi[2];    /* its box */
	double gx[3], gy[3];
	int edge;               /* 1 on the outline, 2 the band's */
} tr_tri;

/* One thread's state. */
typedef struct {
	const pyramid_index *ix;
	const char *dir;
	const tr_grid *g;
	geo_proj proj;          /* projected DEMs */
	pyramid_block cache[TR_CACHE];
	double *clon[TR_CACHE], *clat[TR_CACHE]; /* per block vertex
	                         * (one allocation: clat follows clon) */
	int ckey[TR_CACHE][3], cused[TR_CACHE];
	int cnll[TR_CACHE];     /* projected: a slot's vertices converted
	                         * (the others' clon, clat NaN: tr_ll_need) */
	int cnew[TR_CACHE];     /* those since it was loaded or saved */
	uint64_t csum[TR_CACHE]; /* the file's hash it was loaded at, or 0 */
	unsigned long cstamp[TR_CACHE], clock; /* least recently used goes */
	int ncache;             /* slots in use: TR_CACHE or TR_CACHE_PROJ */
	unsigned char *zrec;    /* a block's record in g->zs (tr_block) */
	double *cbox[TR_CACHE]; /* projected: a slot's squares' boxes
	                         * (tr_far_boxes), or NULL */
	unsigned char cboxok[TR_CACHE]; /* cbox holds the slot's block */
	tr_tri *sel;            /* the selection over the tile */
	int nsel, csel;
	int *row;               /* those meeting a row of cells (csel) */
	tr_mesh m;
	uint16_t *u, *v, *q;    /* quantised vertices */
	double *pos;            /* decoded ECEF, 3 each */
	int *order, *tmp;
	unsigned char *buf;     /* the encoded tile */
	size_t nbuf, cbuf;
	double err, direct;     /* largest d[0], d[1] of its tiles (pass) */
	long long nsamp, nmeas; /* samples in its tiles, in those measured */
	struct tr_keptz {       /* tiles kept for one pass (tr_batch.c) */
		struct tr_kept *k;
		int z;
	} *kept;
	int nkept, ckept;
	size_t kbytes;
	long long tiles, tris, bytes;
	double *fu;             /* projected: a block's feet (tr_block_feet)
	                         * for the passes over level 0, or NULL */
	unsigned char *fok;     /* per vertex, its feet in fu (tr_batch_own) */
	double *gsel;           /* projected: the tile's selected triangles
	                         * in the grid (tr_gsel.c), 11 each */
	int ngsel, cgsel;
} tr_work;

/* A level's choice: pyramid level p, tolerance tau, lattice n x n cells
 * per tile. */
typedef struct {
	int z, p, n;
	double tau, el;
	double base;            /* level p's largest base error */
} tr_choice;

/* Block (bi, bj) of pyramid level l through the thread's cache, with
 * its vertices' longitudes and latitudes (*lon, *lat: 129 x 129 for a
 * projected DEM; a geographic one's: 129 each, per column and per row;
 * tr_vlon, tr_vlat read either). */
const pyramid_block *tr_block(tr_work *w, int l, int bi, int bj,
    const double **lon, const double **lat, tl_err *e);
/* A projected DEM's vertices come through PROJ as they are read: a
 * block from tr_block holds only those some reader asked for (the
 * others NaN); tr_ll_need converts vertices v[0 .. n-1] (r * 129 + c)
 * of block b (through the thread's cache) before they are read, once,
 * and tr_block_all, for the readers of whole blocks (the measure), is
 * tr_block with every vertex converted. Geographic: no work. */
int tr_ll_need(tr_work *w, const pyramid_block *b, const int *v, int n,
    tl_err *e);
const pyramid_block *tr_block_all(tr_work *w, int l, int bi, int bj,
    const double **lon, const double **lat, tl_err *e);

/* The lesser and greater of a and b, a kept when they tie or b is NaN
 * (the measure's and the bound's comparisons depend on it). */
static inline double
dmin(double a, double b)
{
	return b < a ? b : a;
}

static inline double
dmax(double a, double b)
{
	return b > a ? b : a;
}

static inline double
tr_vlon(const tr_grid *g, const double *lon, int r, int c)
{
	return g->projected ? lon[r * BT_SIZE + c] : lon[c];
}

static inline double
tr_vlat(const tr_grid *g, const double *lat, int r, int c)
{
	return g->projected ? lat[r * BT_SIZE + c] : lat[r];
}

/* The lon/lat rectangle of tile (z, x, y): west, south, east, north;
 * lattice line k of the tile (0 .. n) along x and y, exact for all
 * tiles sharing it. */
void tr_tile_rect(int z, int x, int y, double r[4]);
double tr_lattice_lon(int z, int x, int n, int k);
double tr_lattice_lat(int z, int y, int n, int k);
/* Tile i (0 .. nx ny - 1) of a level's nx x ny in the order the threads
 * take them: strips of tile columns about one level-0 block wide, each
 * row by row, every second one bottom up, so that consecutive tiles read
 * the blocks the thread's cache holds (row-major order reread every
 * block once per row of tiles). Every order writes the same files. */
void tr_tile_at(const tr_grid *g, int z, int nx, int ny, int i, int *x,
    int *y);

/* The mesh of tile (x, y) under choice c (tr_mesh.c). */
int tr_mesh_tile(tr_work *w, const tr_choice *c, int x, int y, tl_err *e);
void tr_mesh_free(tr_mesh *m);
/* Vertex of (x, y, h), shared with an earlier one at the same place. */
int tr_mesh_vertex(tr_mesh *m, double x, double y, double h, tl_err *e);
int tr_mesh_tri(tr_mesh *m, int a, int b, int c, tl_err *e);
/* Per vertex of m (ECEF positions pos, 3 a vertex) the sum of its
 * triangles' area vectors, the smooth normal both encoders write:
 * calloc'd, or NULL when out of memory. */
double *tr_area_normals(const tr_mesh *m, const double *pos);
/* The part of selection triangle t inside r (x0, y0, x1, y1), into m
 * (tr_clip.c). */
int tr_clip(tr_mesh *m, const tr_tri *t, const double r[4], tl_err *e);

/* A projected DEM (tr_rim.c): selection triangle t (level p, block b
 * and its vertices' lon, lat) cut to the DEM's grid rectangle, into
 * w->sel where it meets r; -1 when out of memory or PROJ fails. */
int tr_rim_sel(tr_work *w, const tr_choice *c, const pyramid_block *b,
    const double *lon, const double *lat, const int t[3][2],
    const double r[4]);
/* The width, in level-0 cells, of the band the terrain of level z (tr_grid.c)
 * carries a projected DEM's edge heights past its sides: a quarter cell
 * and eight quanta of u, v, so that no sample at the edge is drawn by
 * the ellipsoid and the band holds its turn through quantisation. */
double tr_rim_band(const tr_grid *g, int z);
/* The mesh of tile (x, y) from w->sel: the footprint's part of each
 * cell, the ellipsoid over the rest of it (m->rim marking it). */
int tr_rim_tile(tr_work *w, const tr_choice *c, int x, int y, tl_err *e);
/* The triangle just appended takes triangle from's m->rim mark. */
int tr_rim_inherit(tr_mesh *m, int from, tl_err *e);

/* A projected DEM's selection spared what adds nothing (tr_far.c):
 * block b's (its vertices at lon, lat, through the thread's cache) boxes
 * of its squares, kept with it (NULL: no memory); whether split vertex
 * (c, r) of block (bi, bj) of level p, its boxes bx, holds only
 * triangles that add nothing to tile part t of level z. */
#define TR_FAR_K0 4 /* the boxes' least squares, cells a side: the first
                     * (BT_CELLS / TR_FAR_K0)^2, 4 doubles each (least
                     * lon, lat, greatest lon, lat), rows from the south */
const double *tr_far_boxes(tr_work *w, const pyramid_block *b,
    const double *lon, const double *lat);
int tr_far(const tr_grid *g, const double *bx, int p, int bi, int bj,
    int c, int r, int z, const double t[4]);

/* A projected DEM's selection in its grid (tr_gsel.c): selected
 * triangle x, y (level-0 places), h appended to w's tile (-1: out of
 * memory); the tile's triangles copied and bucketed; the terms
 * (tr_bary_flat's: the selection's height there) of the triangle holding
 * level-0 place (x, y), NULL where none does (*hint: the triangle found
 * last, or -1). */
typedef struct {
	double *t;              /* tr_bary.h's terms and heights */
	int nt, nb, *start, *list;
	double o[2], s[2];
	size_t bytes;
} tr_gsel;
int tr_gsel_add(tr_work *w, const double x[3], const double y[3],
    const double h[3]);
int tr_gsel_init(tr_gsel *g, const tr_work *w);
void tr_gsel_free(tr_gsel *g);
const double *tr_gsel_find(const tr_gsel *g, double x, double y,
    int *hint);
/* A selected triangle's (its tr_gsel terms t) box along x (k 0), y. */
void tr_gsel_box(const double *t, int k, double *lo, double *hi);
/* Bucket of coordinate c in a grid of nb buckets from o, s a unit:
 * floor((c - o) s) within 0 .. nb - 1. */
static inline int
tr_bucket(double c, double o, double s, int nb)
{
	double b = floor((c - o) * s);

	return b < 0 ? 0 : b >= nb ? nb - 1 : (int)b;
}

/* Quantise, order, decode w->m for tile (z, x, y): fills u, v, q, pos,
 * the triangles counter-clockwise in u, v; *minh, *maxh the header's
 * float heights (tr_quantise.c). */
int tr_quantise(tr_work *w, int z, int x, int y, float *minh, float *maxh,
    tl_err *e);
/* Over the level-0 samples in the tile, along the normal: d[0] the
 * largest distance between the decoded surface and the selection's, d[1]
 * between it and the samples (tr_measure.c). */
int tr_measure(tr_work *w, int z, int x, int y, double d[2], tl_err *e);
/* The same over a projected DEM's samples within band cells of the
 * grid's sides alone. */
int tr_measure_band(tr_work *w, int z, int x, int y, double band,
    double d[2], tl_err *e);

/* A tile's measure in two halves, so that many tiles share one pass
 * over level 0 (tr_batch.c): tr_keep, the quantised tile's locator,
 * *out NULL when the tile holds no sample; tr_kept_block, its samples in
 * level-0 block kb = (bi, bj), b with its vertices' lon, lat, folded
 * into d as tr_measure does. tr_measure is the two over every block. */
typedef struct tr_kept tr_kept;
int tr_keep(tr_work *w, int z, int x, int y, tr_kept **out, tl_err *e);
int tr_kept_block(const tr_grid *g, const tr_kept *k, int kb, int bi,
    int bj, const pyramid_block *b, const double *lon, const double *lat,
    double *fu, unsigned char *fok, const double *bx, double d[2],
    tl_err *e);
/* A projected level-0 block's vertices' feet and normals (the
 * ellipsoid's points under them and its unit normals there, 6 doubles
 * each, geo_ellipsoid) into fu, 6 x 129 x 129: once for all the kept
 * tiles that measure the block (tr_batch), the same doubles as each
 * computing its own; tr_kept_block takes them, or NULL. */
void tr_block_feet(const tr_grid *g, const double *lon, const double *lat,
    int bi, int bj, double *fu);
/* Only kept tile k's samples within band cells of the grid's sides
 * measured (a projected DEM's; INFINITY, as tr_keep makes it: all). */
void tr_kept_band(tr_kept *k, double band);
/* How many of the n kept tiles l meet level-0 block kb; *band the
 * widest of their bands (-1: none meets). */
int tr_kept_meeting(const tr_grid *g, const struct tr_keptz *l, int n,
    int kb, double *band);
/* Level-0 block (bi, bj) for the measure, through w's cache: with the
 * longitudes and latitudes of its samples within band cells of the
 * grid's sides (INFINITY: all, tr_block_all). */
const pyramid_block *tr_block_band(tr_work *w, int bi, int bj,
    double band, const double **lon, const double **lat, tl_err *e);
/* Whether level-0 block kb meets the tile's part of the terrain (and
 * its band). */
int tr_kept_meets(const tr_grid *g, const tr_kept *k, int kb);
/* Its samples in every level-0 block, through the thread's cache. */
int tr_kept_walk(tr_work *w, const tr_kept *k, double d[2], tl_err *e);
size_t tr_kept_bytes(const tr_kept *k);
void tr_kept_free(tr_kept *k);
/* Check mode: each sample of kept tile k fails the measure when farther
 * from the selection than its triangle's b[t] (tr_bound's, nt), or, a
 * projected DEM's, drawn by a triangle b leaves unbounded deeper than
 * claim cells from the grid's sides (tr_bound's band). */
int tr_kept_check(tr_kept *k, const double *b, int nt, double claim,
    tl_err *e);

/* An upper bound of d[0] over the quantised tile (z, x, y), minh, maxh
 * its header heights (tr_bound.c): the largest of its triangles' (their
 * own, without the factor, into b when not NULL), times TR_BOUND_SAFETY,
 * plus 1 um; INFINITY where a triangle is not boundable (tilted 89.9
 * degrees or more; a projected DEM whose map has no bound, tr_curve.c),
 * or, b NULL, as soon as the bound passes lim. A projected DEM's
 * triangles past the footprint or in the band are not bounded (b NaN):
 * the samples they may draw lie within *band cells of the grid's sides,
 * to be measured (-1: none may). */
#define TR_BOUND_SAFETY 2.0
double tr_bound(tr_work *w, int z, int x, int y, float minh,
    float maxh, double lim, double *b, double *band);
/* The CRS term (tr_crs.c) of a piece of selection triangle f (pre its
 * tr_crs_prep) whose decoded corners lie at xd, yd (degrees), gmax the
 * steepest selected
 * triangle of the tile (metres a cell): a bound of the selection's
 * height at a sample's grid place against F_S at its longitude,
 * latitude; *reach, cells, how far outside S that place may lie. */
#define TR_CRS_PRE 6
double tr_crs(const tr_grid *g, const tr_tri *f,
    const double pre[TR_CRS_PRE], const double xd[3], const double yd[3],
    double gmax, double margin, double *reach);
/* How deep in the grid (cells from its nearest side) a sample drawn
 * by the quantised tile's pieces past the footprint or in the band
 * (tile rectangle r) may lie: -1 when it has none, INFINITY when not
 * known (PROJ's inverse). */
double tr_crs_claim(tr_work *w, const double r[4]);
/* The least circle's radius squared of a triangle of sides squared l
 * (any dimension): half the longest when right or obtuse, else the
 * circumradius (16 area^2 by Heron). */
double tr_encl(const double l[3]);
/* The steepest of a tile's selected triangles in the grid (w->gsel),
 * all (metres a cell) and by bucket. */
typedef struct {
	double o[2], s[2], *mx, all;
	int nb;
} tr_steep;
int tr_steep_init(tr_steep *st, const tr_work *w);
void tr_steep_free(tr_steep *st);
/* f's own terms for tr_crs, pre: |D A_S|, |grad P| (-1: degenerate), the
 * reach of its pieces whose corners lie on it, the steepest triangle
 * within pre[4] cells of it, how far D A_S may differ from D psi. */
void tr_crs_prep(const tr_grid *g, const tr_steep *st, const tr_tri *f,
    double pre[TR_CRS_PRE]);
/* About the number of level-0 samples in tile (z, x, y) (geographic; 1
 * for a projected DEM), for the share measured. */
long long tr_tile_samples(const tr_grid *g, int z, int x, int y);

/* The quantized-mesh bytes of the quantised tile into w->buf
 * (qm_encode.c). */
int qm_encode(tr_work *w, float minh, float maxh, int gzip, tl_err *e);

/* layer.json into dir (tr_layer.c). */
int tr_layer_write(const char *dir, const tr_args *a, int maxzoom,
    const int (*avail)[4], const char *datum, tl_err *e);

#endif
