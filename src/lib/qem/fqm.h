/* fqm.h - the fundamental quadric map (FQM) and the vertex map as rasters:
 * channels, levels, header attributes (fqm.c), rows decoded, encoded and
 * checked (fqm_rows.c). The byte-level formats are in raster.h; their
 * meaning is documented in fqm(5). Level 0's quadrics are fqm0.h's. */
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
/* 1 when every channel of L was found (fqm_layout_of's): the invariant of
 * the row coders. */
int fqm_layout_ok(const fqm_layout *L);

#endif
