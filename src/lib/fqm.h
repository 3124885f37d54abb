/* fqm.h - the fundamental quadric map (FQM) and the vertex map as rasters:
 * channels, levels, header attributes, row decoding. The byte-level formats
 * are in raster.h; their meaning is documented in fqm(5). */
#ifndef TL_FQM_H
#define TL_FQM_H

#include "georef.h"
#include "quadric.h"
#include "raster.h"

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
	georef geo;
} fqm_info;

/* Channel indices of an FQM in its (sorted) header. */
typedef struct {
	int q[10]; /* a11 a12 a13 a22 a23 a33 b1 b2 b3 c */
	int z, s, v;
} fqm_layout;

/* Columns (or rows) of level l for a level-0 extent of n0: ceil((n0-1)/2^l)+1. */
int fqm_level_size(int n0, int level);

/* A fresh FQM header for a level: channels, fqm:* and geo:* attributes. */
int fqm_header(rs_header *h, const fqm_info *fi, const char *kernel,
    tl_err *e);
/* Reads fqm:* and geo:* attributes; checks that kind is want ("fqm" or
 * "vertices") and that the raster's size is that of its level. */
int fqm_info_of(const rs_header *h, const char *want, fqm_info *fi,
    const char *what, tl_err *e);
int fqm_layout_of(const rs_header *h, fqm_layout *L, const char *what,
    tl_err *e);
void fqm_decode(const fqm_layout *L, const float *row, int w,
    fqm_vertex *out);
void fqm_encode(const fqm_layout *L, const fqm_vertex *in, int w,
    float *row);

/* The metric embedding (georef.h) at any level-0 row J >= 0: rows past the
 * DEM's last one (padding of coarse levels) continue its last spacing. */
double fqm_dx(const geo_metric *m, long J);
double fqm_y(const geo_metric *m, long J);


/* Level-0 FQM row j from DEM rows j-1, j, j+1 (z[0] / z[2] NULL past the
 * edges; valid[k] 1 for real samples). Each grid cell contributes both of
 * its triangulations at half weight (the FQM does not depend on a choice
 * of diagonal); a triangle with a void corner contributes nothing. Every
 * plane passes through the vertex, so b = 0 and c = 0 exactly. */
void fqm_row0(const float *const z[3], const unsigned char *const valid[3],
    int w, int j, const geo_metric *m, fqm_vertex *out);

#endif
