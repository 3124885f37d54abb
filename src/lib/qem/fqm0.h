/* fqm0.h - level 0 of the FQM from a DEM: the quadrics of the cells
 * (fqm0_kernel.c: fqm_band0, fqm_row0, fqm_step0), and their driver
 * (fqm0.c), streamed: a window of two DEM rows and, per vertex of the
 * current row, the sums of the cells above it, so every triangle's
 * quadric is computed once. */
#ifndef TL_FQM0_H
#define TL_FQM0_H

#include "dem/dem.h"
#include "qem/fqm.h"

/* Level 0, in two steps so that each triangle is computed once. Every
 * level-0 plane passes through its vertex, so a triangle's quadric is the
 * same A = w n n' (b = 0, c = 0 exactly) at each of its corners.
 *
 * fqm_band0: the cell band between DEM rows J and J+1 (valid[k] 1 for real
 * samples): for each of the w-1 cells, the sums of A over the triangles at
 * each of its 4 corners (0 (i,J) 1 (i+1,J) 2 (i+1,J+1) 3 (i,J+1)), band[]
 * holding (w-1) x 4 x 6 doubles. Each cell contributes both of its
 * triangulations at half weight (the FQM does not depend on a choice of
 * diagonal); a triangle with a void corner contributes nothing. The cell
 * is the symmetric trapezoid of the ground embedding (georef.h) at rows
 * J, J+1, its widths and height taken at its middle column.
 *
 * fqm_row0: level-0 FQM row J from the bands above and below it (NULL past
 * the edges) and the DEM row itself.
 *
 * fqm_step0: the same rows, bit for bit, streamed without the bands (a
 * band of a wide DEM outgrows the caches): row J from the DEM rows J (z0,
 * v0) and J+1 (z1, v1; NULL for the last row) and part[], 6 planes of w
 * doubles (a coefficient a plane) holding the sums of the band above (all
 * 0 for row 0), which it leaves holding those of row J+1.
 * fqm_step0_encode: that row as fqm_encode would encode it, layout L. */
#define FQM_BAND0_DOUBLES 24
void fqm_band0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_ground *m,
    double *band);
void fqm_row0(const double *above, const double *below, const float *z,
    const unsigned char *valid, int w, fqm_vertex *out);
void fqm_step0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_ground *m,
    double *part, fqm_vertex *out);
void fqm_step0_encode(const float *z0, const unsigned char *v0,
    const float *z1, const unsigned char *v1, int w, int J,
    const geo_ground *m, double *part, const fqm_layout *L, float *row);

typedef struct {
	dem *d;
	const geo_ground *m;
	int x0, w, h, next;          /* DEM columns x0 .. x0+w-1, its
	                              * height; the row expected next */
	float *z[2];                 /* DEM rows j, j+1 (by parity) */
	unsigned char *valid[2];
	double *part;                /* 6 planes of w: fqm_step0's sums */
} fqm0_state;

/* d of at least 3x3 samples, its metric m: both outlive the state. */
int fqm0_init(fqm0_state *s, dem *d, const geo_ground *m, tl_err *e);
/* Only the DEM's columns x0 .. x0+n-1 (n >= 3), as a band job's window:
 * m answers in the window's columns (geo_ground x0). The window's edge
 * vertices lack the cells beyond it: a band job drops them. */
int fqm0_init_cols(fqm0_state *s, dem *d, const geo_ground *m, int x0,
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
