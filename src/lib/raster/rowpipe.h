/* rowpipe.h - the filters' one drive (dem2fqm, fqmfilter, fqmsolve): an
 * output raster made row by row by a callback, a progress line on a
 * terminal, the output written under a temporary name and committed when
 * complete or removed on failure. The callback pulls whatever input it
 * needs; the program owns its input and its state. */
#ifndef TL_ROWPIPE_H
#define TL_ROWPIPE_H

#include "raster/raster.h"
#include "base/util.h"

/* Fills output row y (h->width x h->nch floats, channel-major, as
 * rs_write_row takes it), rows in order 0 .. h->height-1; 0 or -1. */
typedef int (*rowpipe_fn)(void *ctx, int y, float *row, tl_err *e);

/* Writes the raster of header h to out (EXR file, or "-" for the stream)
 * with compression comp; label names the progress line. 0 or -1. */
int rowpipe_run(const char *label, const char *out, const rs_header *h,
    enum rs_compression comp, rowpipe_fn fn, void *ctx, tl_err *e);

/* The same, keeping only the level's columns cut[0] .. cut[1]-1 of the
 * rows fn makes (a band job's own columns, -C): h is a level or a window
 * of one (fqm:x0) that holds them; the output is the window they are.
 * cut NULL: rowpipe_run. */
int rowpipe_run_cut(const char *label, const char *out, const rs_header *h,
    const int *cut, enum rs_compression comp, rowpipe_fn fn, void *ctx,
    tl_err *e);

#endif
