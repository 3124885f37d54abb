/* fqm.h - the fundamental quadric map (FQM) and the vertex map as rasters:
 * channels, levels, header attributes, row decoding. The byte-level formats
 * are in raster.h; their meaning is documented in fqm(5). */
#ifndef TL_FQM_H
#define TL_FQM_H

#include "raster/attr_names.h"
#include "geo/georef.h"
#include "geo/levels.h"
#include "qem/quadric.h"
#include "raster/raster.h"

#define FQM_VERSION 1

/* One decoded FQM vertex: its quadric (own frame), reference height Z,
 * sub-sampled DEM height S and validity V. */
typedef struct {
	quadric q;
	double z, s, v;
} fqm_vertex;

/* What every level's header says about where it stands. */
typedef struct {
	int level;
	int size0[2]; /* level-0 width, height */
	int x0;       /* a window of the level (fqm:x0): its column 0 is
	               * level column x0, its width any up to the level's
	               * end; 0 for a whole level */
	georef geo;
} fqm_info;

/* Channel indices of an FQM in its (sorted) header. */
typedef struct {
	int q[10]; /* a11 a12 a13 a22 a23 a33 b1 b2 b3 c */
	int z, s, v;
} fqm_layout;

/* The pyramid's blocks: levels 0 .. the first that fits one (geo/levels.h). */
#define FQM_BLOCK GEO_LEVEL_BLOCK

/* A fresh FQM header for a level: channels, fqm:* and geo:* attributes;
 * width from fi->x0 to the level's end. */
int fqm_header(rs_header *h, const fqm_info *fi, const char *kernel,
    tl_err *e);
/* Reads fqm:* and geo:* attributes; checks that kind is want ("fqm" or
 * "vertices") and that the raster's size is that of its level (its height;
 * a window's columns x0 .. x0+width-1 inside the level's). */
int fqm_info_of(const rs_header *h, const char *want, fqm_info *fi,
    const char *what, tl_err *e);
/* 0, or -1 with "what: columns A..B of level L, not the whole level (a
 * band: give the band list)" for a window: for readers of whole levels. */
int fqm_whole(const rs_header *h, const fqm_info *fi, const char *what,
    tl_err *e);
int fqm_layout_of(const rs_header *h, fqm_layout *L, const char *what,
    tl_err *e);
/* Opens an FQM (path or "-") and reads its info and layout: the filters'
 * input. NULL with e filled on failure. */
rs_reader *fqm_open(const char *path, fqm_info *fi, fqm_layout *L,
    tl_err *e);
void fqm_decode(const fqm_layout *L, const float *row, int w,
    fqm_vertex *out);
/* Every value of a row read from an intermediate file (an FQM, a vertex
 * map; w x nch floats, channel-planar as raster.h reads them, its first
 * column x0 of the raster's: a span, or 0) is finite:
 * no writer of ours makes NaN or an infinity there, so one is damage
 * that a format without checksums (EXR NONE, RLE, PIZ) let through, and
 * it must stop the work rather than spread. 0, or -1 with "what: row Y,
 * channel C: NaN at column X (damaged?)" (or "infinite value"). */
int fqm_check_row(const float *row, int x0, int w, int nch, int y,
    const char *what, tl_err *e);
void fqm_encode(const fqm_layout *L, const fqm_vertex *in, int w,
    float *row);

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
 * is the symmetric trapezoid of the metric embedding (georef.h) at rows
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
    const unsigned char *v1, int w, int J, const geo_metric *m,
    double *band);
void fqm_row0(const double *above, const double *below, const float *z,
    const unsigned char *valid, int w, fqm_vertex *out);
void fqm_step0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_metric *m,
    double *part, fqm_vertex *out);
void fqm_step0_encode(const float *z0, const unsigned char *v0,
    const float *z1, const unsigned char *v1, int w, int J,
    const geo_metric *m, double *part, const fqm_layout *L, float *row);

#endif
