/* tiles_impl.h - the state of a level's errors, shared by tiles.c (rows,
 * saturation, blocks, the general containment test) and tiles_scan.c (the
 * exact integer scan of undisplaced levels). Private to those two. */
#ifndef TL_TILES_IMPL_H
#define TL_TILES_IMPL_H

#include <assert.h>
#include <math.h>
#include <stddef.h>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "pyramid/bintree.h"
#include "pyramid/tiles.h"

/* A vertex's descendants lie within 126 rows of it (a scale-64 edge
 * vertex: 32+32+16+16+...+1+1), a block centre's within 190: saturating a
 * block row reads local errors 128 rows either side of it. */
#define REACH BT_CELLS
#define BAND (BT_CELLS + 2 * REACH + 1) /* rows saturated per block row */
#define RINGV 512   /* level rows of heights and offsets held; a power of 2 */
/* level rows of local errors held: a block row's band starts 128 rows
 * before it, and the rows loaded when it is handed out reach 484 past it
 * (ready at 322, a batch of 32, 130 below the DEM row): 612 at most */
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
	double *base;       /* by x bx base errors */
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
} strip;
#define VC_ROWS 8

/* DEM rows scanned between two meetings of the threads: the rings hold
 * what a batch reaches (a block row's band is final 322 rows past its
 * first, the rows loaded reach 130 past the DEM row: 452 + 32 < RINGV). */
#define BATCH 32

struct state {
	const tiles_level *L;
	dem *d;
	int P, Q;           /* padded level size: blocks x 128 + 1 */
	int W0;             /* DEM width */
	int bx, by;
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
	float *band;        /* BAND x P: saturated errors */
	float *rz, *rx, *ry; /* a real row from the caller */
	float *dz;
	unsigned char *dv;  /* a DEM row */
	tiles_stats *st;
	double *dd;         /* BATCH DEM rows as doubles (W0 + 1 apart) */
	int scan;           /* undisplaced and step <= SCAN_MAXSTEP */
	int nstrip;
	strip *strips;
};

/* Level row gj in the ring of heights and offsets: loaded, and not yet
 * overwritten by a row RINGV further on. */
static inline size_t
slot(const state *s, int gj)
{
	assert(gj >= 0 && gj < s->loaded && gj >= s->loaded - RINGV);
	return (size_t)(gj & (RINGV - 1)) * s->P;
}

/* Level row gj in the ring of local errors, likewise. */
static inline size_t
eslot(const state *s, int gj)
{
	assert(gj >= 0 && gj < s->loaded && gj >= s->loaded - RINGE);
	return (size_t)(gj % RINGE) * s->P;
}

/* max |z0 + dz * (i / step) - DEM[i]| over the valid i in [a, b]; -1
 * when none is. */
static inline double
sweep(const double *dd, long a, long b, double z0, double dz, double inv)
{
	double w = -1;
	long i = a;

#ifdef __SSE2__
	if (b - a >= 1) {
		const __m128d abs = _mm_castsi128_pd(
		    _mm_set1_epi64x(0x7fffffffffffffffLL));
		const __m128d vz0 = _mm_set1_pd(z0), vdz = _mm_set1_pd(dz);
		const __m128d vinv = _mm_set1_pd(inv), two = _mm_set1_pd(2);
		__m128d vi = _mm_set_pd((double)(a + 1), (double)a);
		__m128d vw = _mm_set1_pd(-1);
		for (; i + 1 <= b; i += 2) {
			__m128d x = _mm_mul_pd(vi, vinv);
			__m128d z = _mm_add_pd(vz0, _mm_mul_pd(vdz, x));
			__m128d d = _mm_and_pd(_mm_sub_pd(z,
			    _mm_loadu_pd(dd + i)), abs);
			vw = _mm_max_pd(d, vw); /* d NaN: vw */
			vi = _mm_add_pd(vi, two);
		}
		double l[2];
		_mm_storeu_pd(l, vw);
		w = l[0] > l[1] ? l[0] : l[1];
	}
#endif
	for (; i <= b; i++) {
		double d = fabs(z0 + dz * (i * inv) - dd[i]);
		if (d > w)
			w = d;
	}
	return w;
}

/* The exact integer scan (tiles_scan.c) applies to undisplaced levels up
 * to this step: there every chord end of a triangle is a whole DEM
 * column and the tolerances EPS change nothing (see tiles_scan.c). */
#define SCAN_MAXSTEP 1024

/* The local and base errors the DEM row J (t->dd) raises in t's
 * columns, as tri_row's loops in tiles.c would raise them, bit for bit. */
void tiles_scan_row(strip *t, int J);

#endif
