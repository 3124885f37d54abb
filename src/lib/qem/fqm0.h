/* fqm0.h - level 0 of the FQM from a DEM, streamed: a window of two DEM
 * rows and, per vertex of the current row, the sums of the cells above it
 * (fqm_step0 in fqm.h), so every triangle's quadric is computed once. */
#ifndef TL_FQM0_H
#define TL_FQM0_H

#include "dem/dem.h"
#include "qem/fqm.h"

typedef struct {
	dem *d;
	const geo_metric *m;
	int x0, w, h, next;          /* DEM columns x0 .. x0+w-1, its
	                              * height; the row expected next */
	float *z[2];                 /* DEM rows j, j+1 (by parity) */
	unsigned char *valid[2];
	double *part;                /* 6 planes of w: fqm_step0's sums */
} fqm0_state;

/* d of at least 3x3 samples, its metric m: both outlive the state. */
int fqm0_init(fqm0_state *s, dem *d, const geo_metric *m, tl_err *e);
/* Only the DEM's columns x0 .. x0+n-1 (n >= 3), as a band job's window:
 * m answers in the window's columns (geo_metric x0). The window's edge
 * vertices lack the cells beyond it: a band job drops them. */
int fqm0_init_cols(fqm0_state *s, dem *d, const geo_metric *m, int x0,
    int n, tl_err *e);
/* FQM row j of level 0 (w vertices); rows strictly in order from 0. */
int fqm0_row(fqm0_state *s, int j, fqm_vertex *out, tl_err *e);

/* The same rows encoded (fqm_step0_encode), as a row source for
 * rowpipe_run (rowpipe.h): ctx an fqm0_source whose state is initialised
 * and layout L that of the output header. */
typedef struct {
	fqm0_state s;
	fqm_layout L;
} fqm0_source;
int fqm0_encoded_row(void *ctx, int y, float *row, tl_err *e);
void fqm0_free(fqm0_state *s);

#endif
