/* solve.h - placing the vertices of a level: QEM-1D (z minimising the
 * vertex's quadric on its grid position), QEM-3D (x, y, z), or the
 * comparison heights carried by the FQM (vertex-filtered, sub-sampled). */
#ifndef TL_SOLVE_H
#define TL_SOLVE_H

#include "qem/fqm.h"

enum solve_mode { SOLVE_QEM1D, SOLVE_QEM3D, SOLVE_FILTERED, SOLVE_SUBSAMPLE };

typedef struct {
	double z;    /* height, metres */
	double x, y; /* 3D: offsets from the grid position, metres */
	double v;    /* validity, passed through */
} solve_vertex;

typedef struct {
	enum solve_mode mode;
	double rel;   /* 3D: eigenvalue cut (quadric_min_3d) */
	double shrink; /* 3D: a cell's triangles keep at least this fraction
	                * of their grid area (no fold-over, no slivers) */
	int level, w, h;
	const geo_ground *m;
	solve_vertex *hist[2]; /* 3D: the two previous rows (j-1, j-2), final */
	solve_vertex *grid;    /* 3D: a row of zero offsets (later rows) */
	double *msx[5], *my[5]; /* 3D: geo_sx and geo_y at the vertices of
	                         * rows j-2 .. j+2 (the fold fix's reach) */
	int mfin[5];            /* 3D: each of those rows bounded (1e100) */
	int hzero[2];           /* 3D: hist[k]'s offsets all zero */
	double *mbuf;           /* their memory */
	unsigned char *mark; /* 3D: the fold fix's marks, this round's and the last's */
	struct tl_pool *pool; /* 3D: the placements and the fold checks on
	                       * its threads, or NULL: this one; set with
	                       * solve_pool */
	unsigned char *markt; /* 3D on a pool: a row of marks per thread */
	int known;       /* 3D: the known answers taken (b = 0: the vertex;
	                  * rows on the grid: no fold fix); 0 where
	                  * TL_SOLVE_FULL is set, for the tests */
	int row;         /* next row expected */
	long long reduced; /* 3D: vertices whose offset the fold fix reduced */
	long long zeroed;  /* ... of which set back onto the grid */
} solve_state;

int solve_mode_parse(const char *s, enum solve_mode *m);
const char *solve_mode_name(enum solve_mode m);

int solve_init(solve_state *s, enum solve_mode mode, int level, int w, int h,
    const geo_ground *m, tl_err *e);
/* Solves the next row (rows in order). 3D rows are final when returned:
 * each row is fixed so that every foldable triangle touching it (the four
 * of each cell, and the two-cell triangles of scale-1 edge diamonds) keeps
 * `shrink` of its grid area with earlier rows as they are and later rows
 * on the grid; so the next row can always be fixed by moving only itself,
 * which is what makes a one-pass, streaming fix possible. */
void solve_row(solve_state *s, const fqm_vertex *in, solve_vertex *out);

/* The vertex map's header (fqm(5)): the FQM's attributes, channels Z V
 * (and X Y for QEM-3D), kind "vertices" and the mode. */
int solve_header(rs_header *oh, const rs_header *fqm, enum solve_mode mode,
    tl_err *e);
/* One row of solved vertices into a row of that header's channels. */
void solve_encode(const rs_header *oh, const solve_vertex *v, float *row);
/* solve_row then solve_encode for every mode but QEM-3D, from the FQM
 * row's channels (layout L, channel-planar floats as fqm_decode reads
 * them) into the vertex map's (header oh): the same values, without
 * decoding the vertices. The FQM row holds finite values only
 * (fqm_check_row). */
void solve_row_direct(solve_state *s, const fqm_layout *L, const float *in,
    const rs_header *oh, float *row);
/* 3D: the work on p's threads (NULL: this one); p outlives s's use. */
int solve_pool(solve_state *s, struct tl_pool *p, tl_err *e);
void solve_free(solve_state *s);

/* 1 when the cell with corners p[0] (i,j), p[1] (i+1,j), p[2] (i+1,j+1),
 * p[3] (i,j+1) (x right, y down) has all four of its triangles (both
 * diagonals) positively oriented with at least `min` times the area
 * they have on the grid `g` (same corner order). */
int solve_cell_ok(const double p[4][2], const double g[4][2], double min);

#endif
