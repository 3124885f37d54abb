/* level.h - the errors of a level's blocks: exact local errors against
 * every valid DEM sample, saturated across block borders (vgis(5), "The
 * triangulation"), streamed.
 *
 * One pass over the DEM's rows: each valid sample is located, for every
 * scale and kind of the bintree, in the diamond(s) containing it (closed;
 * in the displaced triangles for QEM-3D levels) and raises that diamond
 * vertex's local error to the sample's vertical distance from the
 * diamond's two triangles without the vertex; it also raises its block's
 * base error (its distance from the finest triangles). On undisplaced
 * levels the triangles' chords along a DEM row are whole columns, found
 * once per scale, kind and centre row (undisplaced_scan.c); displaced
 * levels use the general chord with each vertex's position found once
 * per scale (exact_error.c, which maps the variants); both give the same
 * values bit for bit. Once no later DEM
 * row can reach the local errors a block row's saturation needs, its
 * errors are saturated, children before parents, over a band of 128 rows
 * either side (a vertex's descendants lie within 126 rows of it, a block
 * centre's within 190), and the blocks are handed out. Every local error
 * is an exact maximum, so E is exact on every level, not a bound.
 *
 * A level is made whole or in pieces: block columns with a window of
 * columns 128 wider either side, where every value is computed with the
 * level's own coordinates, so that pieces give the whole level's bits.
 *
 * The DEM rows are scanned in batches of 32; within a batch each thread
 * takes a share of the piece's columns (the diamonds centred there, the
 * leaves starting there), so no two write the same local error, and
 * keeps its own base errors, merged by max: the blocks are the same bits
 * whatever the thread count.
 *
 * Memory, per piece, all its window's width: rings of 512 level rows of
 * Z and offsets and of 640 rows of local errors, the saturation band
 * (385 rows), 32 DEM rows as doubles and, displaced, 8 rows of positions
 * per scale and thread; plus one whole row of the level from the row
 * callback. A part holds the same but the saturation band; a piece from
 * its parts the same but the DEM rows. */
#ifndef TL_PACK_LEVEL_H
#define TL_PACK_LEVEL_H

#include "dem/dem.h"
#include "pyramid/pyramid.h"

/* Columns c0 .. c0+n-1 of the level's real row r (r < size[1]) of
 * heights and, displaced, the X and Y offsets in metres (x, y NULL for
 * 1D levels), n entries each. Rows are asked for in order, once each,
 * always the same columns: a piece's window, or the whole row; from row
 * 0, or a part's first row r0. */
typedef int (*level_row_fn)(void *ctx, int r, int c0, int n, float *z,
    float *x, float *y, tl_err *e);
/* A finished block; the callee writes it (b is reused afterwards). With
 * threads > 1 it is called from several threads at once, for different
 * blocks of one block row (block rows come in order, a row's blocks in
 * any order). */
typedef int (*level_block_fn)(void *ctx, const pyramid_block *b, tl_err *e);

typedef struct {
	int level;
	int size[2];     /* the level's vertices */
	int displaced;
	const geo_ground *m;
	level_row_fn row;
	void *row_ctx;
	level_block_fn block;
	void *block_ctx;
	const char *label; /* progress on a terminal, or NULL */
	/* or, if not NULL, told the DEM rows scanned, batch by batch (from
	 * the thread running the piece) */
	void (*progress)(void *ctx, int rows);
	void *progress_ctx;
	int threads;       /* 1 .. LEVEL_MAXTHREADS: the columns in shares */
} level_args;

#define LEVEL_MAXTHREADS 64

typedef struct {
	double max_base;   /* largest base error of any block */
	double max_e;      /* largest finite E */
	long long samples; /* valid DEM samples measured */
} level_stats;

/* The whole level. */
int level_run(const level_args *L, dem *d, level_stats *st, tl_err *e);

/* A piece of a level: the blocks of block columns [b0, b1), all block
 * rows. Pieces are independent: run in any order, on threads or in
 * separate processes, they write the blocks the whole level would, bit
 * for bit; each holds its window of columns, not the level's width. */
typedef struct {
	int b0, b1;
} level_piece;

/* What a piece reads and writes: level columns [c0, c1) of every row of
 * the vertex map (the row callback still gives whole rows), DEM columns
 * [d0, d1) of every DEM row, blocks of block columns [b0, b1). The
 * window reaches 128 level columns past the blocks: what saturating
 * them reads (level.c, HALO). */
typedef struct {
	int b0, b1;
	int c0, c1;
	long d0, d1;
} level_window;

void level_piece_window(const level_args *L, int w0, const level_piece *p,
    level_window *w);
/* The level's block columns in n = ceil(blocks / cols) pieces of nearly
 * equal width, at most max of them written to p; returns n. */
int level_pieces(const level_args *L, int cols, level_piece *p, int max);
/* Piece p of the level: its blocks to L->block, its stats to st (the
 * samples counted are those of its own DEM columns). */
int level_run_piece(const level_args *L, const level_piece *p, dem *d,
    level_stats *st, tl_err *e);

/* A piece also runs in parts, so that no job scans more than a bound of
 * DEM samples however coarse the level: a part scans the piece's DEM
 * columns in the DEM rows [y0, y1) only and gives out, instead of
 * blocks, the local errors those rows raise at the centres the piece's
 * saturation reads (level columns [lo, hi) of level rows [g0, g1): every
 * centre a diamond of those rows has) and the piece's blocks' base
 * errors. Each is a maximum over the part's samples, so the maximum over
 * parts whose rows partition the DEM's is what the whole piece measures,
 * bit for bit; level_run_merged then saturates and hands out the blocks.
 * A part reads level rows [r0, r1) of the vertex map: its diamonds'
 * vertices. */
typedef struct {
	int y0, y1;
	int g0, g1;
	int lo, hi;
	int r0, r1;
} level_part;

void level_part_window(const level_args *L, const level_piece *p, int y0,
    int y1, level_part *q);
/* Local errors of level row g, level columns [lo, hi): a part's given out
 * (rows g0 .. g1-1 in order), or a piece's read back (rows 0 .. all of
 * the padded level, blocks x 128 + 1, in order; zero where no part
 * reaches). */
typedef int (*level_err_fn)(void *ctx, int g, float *err, tl_err *e);
/* Part q of piece p: its local errors to out, its blocks' base errors to
 * base ((b1 - b0) x block rows, a block row after another), the samples
 * of its own columns and rows to st->samples. */
int level_run_part(const level_args *L, const level_piece *p,
    const level_part *q, dem *d, level_err_fn out, void *ctx, double *base,
    level_stats *st, tl_err *e);
/* Piece p from its parts' local errors (in) and base errors (maxima over
 * the parts, laid out as level_run_part's): its blocks to L->block, its
 * stats but samples to st; w0 is the DEM's width. */
int level_run_merged(const level_args *L, const level_piece *p, int w0,
    level_err_fn in, void *ctx, const double *base, level_stats *st,
    tl_err *e);

#endif
