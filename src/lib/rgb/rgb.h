/* rgb.h - MapLibre / Mapbox raster-dem tiles from a DEM (dem2rgb(1)):
 * the DEM warped onto the deepest zoom's Web Mercator pixel centres,
 * every coarser zoom's pixel centres from the quadric chain on that grid
 * (QEM-1D by default), each zoom cut into tiles whose pixels encode
 * heights (Terrarium or Mapbox Terrain-RGB, PNG or lossless WebP),
 * written as a z/x/y tree with a TileJSON 3.0.0 (raster-dem(5)) or as
 * one PMTiles v3 archive (pmtiles.h, pmtiles(5)), atomically; the error of the surface MapLibre draws from them measured
 * per zoom at every valid DEM sample.
 *
 * The grid: pixel i of a tile is its height at tile coordinate
 * (i + 0.5)/dim (MapLibre GL JS 6.17, terrain_coverage.ts
 * _createElevationSampler, DEM_CELL_CENTER_OFFSET = -0.5, pull request
 * 8420; bilinear between pixel centres, DEMData backfilling its border
 * from the neighbour tiles), so tile (x, y)'s pixel (i, j) is the centre
 * of global pixel (x dim + i, y dim + j) of its zoom; zoom z-1's centre
 * k lies between zoom z's centres 2k and 2k+1 (rg_centre.c places it on
 * the chain's vertex levels). */
#ifndef TL_RGB_H
#define TL_RGB_H

#include "dem/dem.h"
#include "qem/solve.h"

#define RG_MAXZOOM 22
#define RG_MAXJOBS 256

enum rg_encoding { RG_TERRARIUM, RG_MAPBOX };
enum rg_format { RG_PNG, RG_WEBP };

typedef struct {
	const char *dem, *out, *prog;
	int pmtiles;            /* -o: out is one PMTiles archive holding
	                         * the tree's tiles, byte-identical, and
	                         * tiles.json's fields as its metadata */
	dem_opts dopt;          /* -N -s -H -D (-e is ours) */
	int dim;                /* 512 or 256 */
	int minzoom, maxzoom;   /* maxzoom -1: the rule (rg_maxzoom) */
	enum rg_encoding enc;
	enum rg_format fmt;
	enum solve_mode mode;   /* QEM1D, FILTERED (-m average), SUBSAMPLE */
	int cubic;              /* the warp's resampling: 0 bilinear */
	int jobs;
	const char *url;        /* -u: the tree's URL, for absolute tile
	                         * URLs in tiles.json (NULL: relative) */
	const char *dump;       /* a directory for the zooms' intended
	                         * heights at their pixel centres (z.tif,
	                         * dem_warp.h's grids), or NULL: for tests */
	/* Each tile written, also handed here (NULL: none), e.g. to a
	 * PMTiles writer: the encoded bytes of tile z/x/y, the same for any
	 * thread count and in the same order (zooms interleaved as the
	 * chain streams; a container sorts them itself). 0, or -1 with e
	 * filled to fail the run. */
	int (*sink)(void *ctx, int z, long long x, long long y,
	    const unsigned char *p, size_t n, tl_err *e);
	void *sink_ctx;
	/* A plan's job (rg_plan.c): the tiles into the tree work (shared by
	 * the plan's jobs), only those of part `part` of `nparts` of each
	 * zoom; no tiles.json; the error measured by part 0 alone. NULL:
	 * the whole run. */
	const char *work;
	int part, nparts;
} rg_args;

typedef struct {
	int minzoom, maxzoom;
	long long tiles[RG_MAXZOOM + 1], bytes[RG_MAXZOOM + 1];
	long long n[RG_MAXZOOM + 1];    /* valid DEM samples measured */
	double max[RG_MAXZOOM + 1], rms[RG_MAXZOOM + 1]; /* metres */
	long long pad[2];               /* pixels of alignment added
	                                 * (columns, rows), all segments */
	int segments;                   /* of the chain */
	char vdatum[256];
} rg_report;

int rg_run(const rg_args *a, rg_report *r, tl_err *e);

/* --- a plan's jobs (rg_plan.c, rg_split.c; dem2rgb(1), PLANS) -------
 * The work split (QEM-1D, -m subsample): the warp job (rg_warp) puts the
 * DEM on the deepest zoom's grid once and fills its voids, into
 * WORK.grid/. Part k of n owns range k of the deepest zoom's tile
 * columns (n ranges as even as integers allow) and, at each zoom of the
 * chain's first segment (maxzoom .. maxzoom - 5), the tile columns whose
 * first pixel on the grid lies in that range: it runs that segment on a
 * window of the grid's columns (its own and a halo), writes its tiles
 * into the tree work exactly as one process writes them, and leaves its
 * columns of the zooms' codes and of the next segment's grid in
 * WORK.grid/K/. The gather joins them, runs the later segments (a grid
 * 32 times narrower) and the error pass as one process does.
 * -m average: each part runs the warp and the means whole and writes
 * range k of each zoom's tiles (row by row); part 0 measures the error.
 * Either way each part records its counts in WORK.parts/K; the gather
 * joins the n records into one process's report, writes tiles.json into
 * work and installs work as a->out (or, a->pmtiles, writes the archive
 * from work's tiles and removes work): byte for byte rg_run's output. */
#define RG_MAXPARTS 100000
#define RG_SPLIT(a) ((a)->mode != SOLVE_FILTERED) /* the work split */
int rg_warp(const rg_args *a, const char *work, tl_err *e);
/* The parts for about `tiles` tiles of the deepest zoom each (the work
 * split: whole columns of them, at least one); a->out checked as rg_run
 * checks it. */
int rg_plan_parts(const rg_args *a, long long tiles, int *n, tl_err *e);
int rg_part(const rg_args *a, const char *work, int k, int n, tl_err *e);
int rg_gather(const rg_args *a, const char *work, rg_report *r,
    tl_err *e);

/* --- the encodings (rg_encode.c) ---------------------------------------
 * Terrarium: h = R 256 + G + B / 256 - 32768 (steps of 1/256 m, heights
 * -32768 .. 32768 - 1/256); Mapbox Terrain-RGB: h = -10000 + (R 65536 +
 * G 256 + B) / 10 (steps of 0.1 m, -10000 .. 1667721.5). A height is
 * rounded to the nearest step (a half step up). */
double rg_step(enum rg_encoding enc);
const char *rg_encoding_name(enum rg_encoding enc); /* TileJSON's */
/* The 24-bit code of h, or -1 when h is outside the encoding's range
 * (or not finite). */
long rg_code(enum rg_encoding enc, double h);
double rg_decode(enum rg_encoding enc, long code);
/* The range, for messages. */
void rg_range(enum rg_encoding enc, double *lo, double *hi);

/* --- the images (rg_image.c) -------------------------------------------
 * A dim x dim RGB image (rows from the north, 3 bytes a pixel) as PNG or
 * lossless WebP in memory: *buf malloc'd, *n its bytes. The same pixels
 * give the same bytes. */
int rg_image(enum rg_format f, const unsigned char *rgb, int dim,
    unsigned char **buf, size_t *n, tl_err *e);
const char *rg_format_ext(enum rg_format f);

/* --- the zoom rule (rg_grid.c) ------------------------------------------
 * The first zoom whose pixel at latitude lat (its ground size, Web
 * Mercator's 2 PI R cos(lat) / (dim 2^z)) is finer than cell metres. */
int rg_maxzoom(double lat, double cell, int dim);

#endif
