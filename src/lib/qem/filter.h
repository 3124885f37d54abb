/* filter.h - filter kernels and the streaming level filter of QEM-filtering:
 * quadrics low-pass filtered (translated into each coarse vertex's frame, in
 * double) and sub-sampled by 2; coarse vertex k at fine vertex 2k. */
#ifndef TL_FILTER_H
#define TL_FILTER_H

#include "qem/fqm.h"

/* A symmetric, non-negative kernel (a negative tap would make the filtered
 * quadric indefinite): w[0] centre, w[k] at +-k, taps sum to 1. */
#define FILTER_MAX_RADIUS 2
typedef struct {
	const char *name;
	int radius;
	double w[FILTER_MAX_RADIUS + 1];
} filter_kernel;

extern const filter_kernel filter_kernels[]; /* terminated by name == NULL */
const filter_kernel *filter_find(const char *name);

/* The level filter holds 2r+1 horizontally filtered rows of the coarse
 * width: memory O(coarse width x kernel height), never a level. Rows are
 * held field by field (FILTER_NF arrays of cw doubles, in fqm_vertex's
 * order: a[6] b[3] c z s v), so that the loops over a row's vertices run
 * on vectors. */
#define FILTER_NF 13
typedef struct {
	const filter_kernel *k;
	int level;         /* of the fine input */
	int fw, fh, cw, ch; /* fine and coarse sizes */
	int w0, h0;        /* level-0 size: vertices past it are padding */
	int x0;            /* a window (fqm:x0): its column 0 is fine column
	                    * x0, even, so that coarse column c is the
	                    * level's x0/2 + c; 0 after filter_init. The
	                    * window's edges are filtered as the level's
	                    * would be: a band job drops the columns near them */
	const geo_ground *m;
	int nring;
	double *ring;      /* nring x FILTER_NF x cw */
	int *tag;          /* fine row held by each ring slot */
	int next;          /* next fine row to push */
	int out;           /* next coarse row to pull */
	double *fine;      /* the fine row being pushed: its even columns
	                    * (FILTER_NF x cw), then its odd ones (same) */
	double *coarse;    /* the coarse row being pulled (FILTER_NF x cw) */
	double *tmp;       /* per column: reference heights, metric (2r+2 x cw) */
} filter_state;

int filter_init(filter_state *f, const filter_kernel *k, int level, int fw, int fh,
    int w0, int h0, const geo_ground *m, tl_err *e);
/* 1 when the next coarse row can be pulled, 0 when a fine row must be
 * pushed first. */
int filter_ready(const filter_state *f);
void filter_push(filter_state *f, const fqm_vertex *fine); /* fine row f->next */
void filter_pull(filter_state *f, fqm_vertex *coarse);      /* coarse row f->out */
/* The same from and into rows of an FQM's channels, channel-planar floats
 * of the fine and coarse widths as fqm_decode reads and fqm_encode writes
 * them: the same values, without the vertex structures. */
void filter_push_row(filter_state *f, const fqm_layout *L, const float *row);
void filter_pull_row(filter_state *f, const fqm_layout *L, float *row);
void filter_free(filter_state *f);

/* Value i of n samples, odd reflection (2h0 - h(-i)) past either end: it
 * keeps linear functions linear, so reference heights of padded vertices
 * and the vertex-filtered pyramid reproduce a plane exactly. */
double filter_extend(const double *h, size_t stride, int n, int i);

#endif
