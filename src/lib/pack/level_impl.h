/* level_impl.h - the state of a level's run, shared by the files that
 * make a level's errors and blocks (level.h): level.c (set-up, pieces,
 * parts), level_crew.c (the pass, on the shares' threads), level_ring.c
 * (the rings of rows), exact_error.c (the kernel: the errors a DEM row
 * raises; its head maps the variants), undisplaced_scan.c (the kernel's
 * integer scan of undisplaced levels), level_saturate.c (saturation) and
 * level_blocks.c (the block hand-out). Private to those.
 *
 * Contract: a state is set up by level.c for one run (a piece, a part or
 * a piece from its parts) and used by one thread at a time but for its
 * shares, which the crew runs in parallel: a share writes only its own
 * fields, its columns' local errors and its own base errors, and reads
 * rows the ring has loaded (slot, eslot assert it). */
#ifndef TL_PACK_LEVEL_IMPL_H
#define TL_PACK_LEVEL_IMPL_H

#include <assert.h>
#include <math.h>
#include <stddef.h>

#include <string.h>

#include "pyramid/bintree.h"
#include "pack/level.h"

/* A vertex's descendants lie within 126 rows of it (a scale-64 edge
 * vertex: 32+32+16+16+...+1+1), a block centre's within 190: saturating a
 * block row reads local errors 128 rows either side of it. */
#define REACH BT_CELLS
/* the saturation band: the rows saturated per block row */
#define SAT_BAND (BT_CELLS + 2 * REACH + 1)
#define RINGV 512   /* level rows of heights and offsets held; a power of 2 */
/* level rows of local errors held: a block row's saturation band starts
 * 128 rows before it, and the rows loaded when it is handed out reach 484
 * past it (ready at 322, a batch of 32, 130 below the DEM row): 612 at
 * most */
#define RINGE 640
/* Closed containment, level units: 3D positions come from float32
 * offsets, so a sample on a shared edge must count on both sides; in 1D
 * samples are exactly on edges or a grid step away. */
#define EPS 1e-6

typedef struct state state;

/* A thread's share of a level: the diamonds centred, and the leaves
 * starting, in level columns [lo, hi). Shares partition the columns, so
 * no two threads write the same local error; each keeps its own base
 * errors, merged by max (whose order does not matter) when a block row
 * is handed out. */
typedef struct {
	state *s;
	const double *dd;   /* the DEM row being scanned, NaN where not valid */
	int lo, hi;
	double *base;       /* base errors: by x the piece's block columns */
	int blo, bhi;       /* the block columns it hands out */
	pyramid_block blk;
	double max_e, max_base; /* of its blocks */
	int failed;         /* the block callback failed: err says why */
	tl_err err;
	/* displaced levels: the positions vertex() finds, per scale h = 2^k
	 * (the vertices of its diamonds: multiples of h both ways), for
	 * VC_ROWS rows of such vertices, tagged with the row (multiple);
	 * only the columns this share reaches */
	struct {
		int n;          /* columns: (P - 1) / h + 1 */
		int tag[8];
		double *x, *y;  /* VC_ROWS x n */
	} vc[8];
	/* displaced levels: whether level row gj's offsets are all 0 in the
	 * window, by its ring slot: gj + 1 if so, -(gj + 1) if not, 0 not
	 * yet known */
	int flat[RINGV];
} share;
#define VC_ROWS 8

/* DEM rows scanned between two meetings of the threads: the rings hold
 * what a batch reaches (a block row's saturation band is final 322 rows
 * past its first, the rows loaded reach 130 past the DEM row: 452 + 32 <
 * RINGV). */
#define BATCH 32

/* A piece's window: what it holds of each row. Coordinates (columns,
 * positions, planes) are the level's and the DEM's, whatever the window,
 * so that every value is computed as the whole level would compute it;
 * only the memory is the window's: level column gi is at gi - c0 in the
 * rings, DEM column i at i - d0 in dd. */
struct state {
	const level_args *L;
	dem *d;
	int Pl, Q;          /* padded level size: blocks x 128 + 1 */
	int W0;             /* DEM width */
	int bx, by;
	int b0, b1;         /* the piece: its block columns */
	int c0, P, cend;    /* its window of level columns: c0 .. cend-1, P of
	                     * them, c0 a multiple of 128 (saturation's
	                     * parities) */
	long d0, dend;      /* its DEM columns: d0 .. dend-1, d0 = c0 x step */
	int lo, hi;         /* the centres whose local errors it saturates */
	int y0, y1;         /* the DEM rows it scans (a part's, or all) */
	int r0, r1;         /* the level rows it may load (likewise) */
	/* a part (level_run_part): local errors given out, rows g0 .. g1-1,
	 * next_out the next; no blocks */
	const level_part *part;
	level_err_fn out;
	void *out_ctx;
	int next_out;
	int yfirst;         /* the level row of the batch's first DEM row */
	/* a piece from its parts (level_run_merged): local errors read */
	level_err_fn in;
	void *in_ctx;
	double step;        /* 2^level: level-0 samples per level cell */
	double margin;      /* how far a displaced vertex may stray */
	float *z, *ox, *oy; /* RINGV x P: heights, offsets in metres */
	int nn;             /* scales per row: geo_row_nodes */
	int *nk;            /* P, displaced levels of a lattice metric: the */
	double *nu;         /* node piece of each column, where in it */
	double *sx, *sy;    /* RINGV x nn: metres per level-0 step along the
	                     * row (geo_row_sx, geo_row_sy) */
	float *acc;         /* RINGE x P: local errors */
	int loaded;         /* level rows [0, loaded) have been loaded */
	int next_bj;        /* next block row to hand out */
	float *satband;     /* SAT_BAND x P: saturated errors */
	float *dz;
	unsigned char *dv;  /* a DEM row */
	level_stats *st;
	double *dd;         /* BATCH DEM rows as doubles: the window's
	                     * columns, dend - d0 + 1 apart */
	int scan;           /* undisplaced and step <= SCAN_MAXSTEP */
	int avx2;           /* the CPU has AVX2: the hot loops' AVX2 copies */
	int ref;            /* TL_EXACT_REF: displaced levels by exact_error.c's
	                     * reference, a triangle at a time (tests) */
	int nshare;
	share *shares;
};

/* The leaves a share measures: the cells starting in its columns and in
 * the piece's blocks (base errors are the piece's blocks' only). */
static inline int
leaf_lo(const share *t)
{
	int b = t->s->b0 * BT_CELLS;
	return t->lo > b ? t->lo : b;
}

static inline int
leaf_hi(const share *t)
{
	int b = t->s->b1 * BT_CELLS;
	return t->hi < b ? t->hi : b;
}

/* The base error of the block of cell (ci, cj), one of the piece's. */
static inline double *
base_at(const share *t, int cj, int ci)
{
	const state *s = t->s;
	int bi = ci / BT_CELLS;

	assert(bi >= s->b0 && bi < s->b1);
	return &t->base[(size_t)(cj / BT_CELLS) * (s->b1 - s->b0) + bi - s->b0];
}

/* Level row gj in the ring of heights and offsets: loaded, and not yet
 * overwritten by a row RINGV further on. */
static inline size_t
slot(const state *s, int gj)
{
	assert(gj >= s->r0 && gj < s->loaded && gj >= s->loaded - RINGV);
	return (size_t)(gj & (RINGV - 1)) * s->P;
}

/* Level row gj in the ring of local errors, likewise. */
static inline size_t
eslot(const state *s, int gj)
{
	assert(gj >= s->r0 && gj < s->loaded && gj >= s->loaded - RINGE);
	return (size_t)(gj % RINGE) * s->P;
}

/* fmin/fmax are library calls here; these inline. */
static inline __attribute__((always_inline)) double
dmin(double a, double b)
{
	return a < b ? a : b;
}

static inline __attribute__((always_inline)) double
dmax(double a, double b)
{
	return a > b ? a : b;
}

/* Four doubles as one value (GCC's vector extension): the operations are
 * lane by lane the scalar ones, in the same order, on AVX2 where a
 * function is compiled for it and as pairs of SSE2 ones elsewhere. No
 * FMA: -std=c11 contracts nothing, and "avx2" does not enable it.
 *
 * The hot loops exist twice, the body inlined into a copy compiled for
 * AVX2 and a plain one, chosen at run time by state.avx2: not GCC's
 * target_clones, whose ifunc resolvers run before the sanitizers'
 * runtimes and crash them. */
#define TL_AVX2 __attribute__((target("avx2")))
/* (the functions taking and returning them are inlined: no ABI to keep) */
#pragma GCC diagnostic ignored "-Wpsabi"
typedef double v4d __attribute__((vector_size(32)));
typedef long long v4l __attribute__((vector_size(32)));

static inline __attribute__((always_inline)) v4d
v4abs(v4d d)
{
	const v4l m = { 0x7fffffffffffffffLL, 0x7fffffffffffffffLL,
	    0x7fffffffffffffffLL, 0x7fffffffffffffffLL };
	return (v4d)((v4l)d & m);
}

/* max(d, w) lane by lane, w where d is NaN (an invalid sample): maxpd's
 * own rule, which GCC makes of this loop (one vmaxpd on AVX2, two maxpd
 * on SSE2) and not of a mask and a blend */
static inline __attribute__((always_inline)) v4d
v4max(v4d d, v4d w)
{
	v4d r;

	for (int k = 0; k < 4; k++)
		r[k] = d[k] > w[k] ? d[k] : w[k];
	return r;
}

/* |z0 + dz * (i / step) - DEM[i]| over the valid DEM columns i in
 * [a, b], DEM[i] being dd[i - d0], into the lanes of the maximum m
 * (which holds no NaN). Eight samples a step into two maxima, so that no
 * chain of dependent maxima sets the pace (a maximum's order does not
 * matter); i / step is i x inv, i exact as a double. */
static inline __attribute__((always_inline)) void
sweep_into(const double *dd, long d0, long a, long b, double z0, double dz,
    double inv, v4d *m)
{
	double w = -1;
	long i = a;

	if (b - a >= 7) {
		/* x0, x1: the columns times inv, stepped by 8 x inv: i / step
		 * and 8 / step are exact, so is their sum */
		v4d x0 = (v4d){ a, a + 1, a + 2, a + 3 } * inv;
		v4d x1 = (v4d){ a + 4, a + 5, a + 6, a + 7 } * inv;
		v4d w0 = *m, w1 = { -1, -1, -1, -1 };
		v4d s8 = { 8 * inv, 8 * inv, 8 * inv, 8 * inv };
		for (; i + 7 <= b; i += 8, x0 += s8, x1 += s8) {
			v4d v0, v1;
			memcpy(&v0, dd + (i - d0), sizeof v0);
			memcpy(&v1, dd + (i - d0) + 4, sizeof v1);
			w0 = v4max(v4abs(z0 + dz * x0 - v0), w0);
			w1 = v4max(v4abs(z0 + dz * x1 - v1), w1);
		}
		*m = v4max(w0, w1); /* neither holds a NaN */
	}
	if (i + 3 <= b) { /* four more at once */
		v4d x0 = { i, i + 1, i + 2, i + 3 }, v0;
		memcpy(&v0, dd + (i - d0), sizeof v0);
		*m = v4max(v4abs(z0 + dz * (x0 * inv) - v0), *m);
		i += 4;
	}
	for (; i <= b; i++) {
		double d = fabs(z0 + dz * (i * inv) - dd[i - d0]);
		if (d > w)
			w = d;
	}
	(*m)[0] = w > (*m)[0] ? w : (*m)[0];
}

/* The largest of those; -1 when none is valid. */
static inline __attribute__((always_inline)) double
sweep(const double *dd, long d0, long a, long b, double z0, double dz,
    double inv)
{
	v4d m = { -1, -1, -1, -1 };
	double w;

	sweep_into(dd, d0, a, b, z0, dz, inv, &m);
	w = m[0];
	for (int k = 1; k < 4; k++)
		w = m[k] > w ? m[k] : w;
	return w;
}

/* The exact integer scan (undisplaced_scan.c) applies to undisplaced
 * levels up to this step: there every chord end of a triangle is a whole
 * DEM column and the tolerances EPS change nothing (see
 * undisplaced_scan.c). */
#define SCAN_MAXSTEP 1024

/* exact_error.c: the local and base errors DEM rows J0 .. J1-1 (at most
 * BATCH, the state's dd) raise in t's columns, by the variant that
 * serves the level; where each column of the piece falls among the
 * lattice's nodes (state init, displaced levels of a lattice metric). */
void lv_error_rows(share *t, int J0, int J1);
void lv_node_columns(state *s);
/* undisplaced_scan.c: lv_error_rows on an undisplaced level (s->scan, or
 * a batch of flat rows), as tri_row's loops in exact_error.c would raise
 * them row by row, bit for bit. */
void lv_scan_undisplaced(share *t, int J0, int J1);
/* level_ring.c: level rows up to r (at most the run's last, r1 - 1)
 * loaded into the rings. */
int lv_ensure(state *s, int r, tl_err *e);
/* level_saturate.c: block row bj's saturation band saturated (its level
 * rows' local errors must be final). */
void lv_saturate(state *s, int bj);
/* level_blocks.c: t's blocks of block row bj (saturated) handed to the
 * block callback; a failure is t->failed and t->err. */
void lv_emit_share(share *t, int bj);
/* level_crew.c: a run set up by level.c, on a pool of its shares'
 * threads: its stats into st. */
int lv_run(state *s, level_stats *st, tl_err *e);

#endif
