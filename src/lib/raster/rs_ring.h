/* rs_ring.h - rasters between threads of one process: a ring of rows
 * (base/ring.h) that a thread bound to it reads or writes as "-", the
 * standard input or output of the filters, so that a stage's own code
 * (fqmfilter's, fqmsolve's) runs unchanged in a thread.
 *
 * The writer's rs_create("-") copies its header into the ring; each
 * reader's rs_open("-") gets that header and every row, in order, as the
 * fqm(5) stream would bring them (the same floats, no encoding, no
 * checksum: nothing leaves the process). rs_finish ends the rows;
 * rs_abort leaves the readers waiting for rs_ring_cancel, which the
 * writer's failure brings, so that only the failure itself is told. A
 * read or write after the cancel fails ("stdin: stopped"). */
#ifndef TL_RS_RING_H
#define TL_RS_RING_H

#include "raster/raster.h"

typedef struct rs_ring rs_ring;

/* rows: the slots, rows the writer may run ahead of the slowest reader */
rs_ring *rs_ring_new(int readers, int rows, tl_err *e);
void rs_ring_free(rs_ring *q);
void rs_ring_cancel(rs_ring *q);

/* The calling thread's "-": reader k of in (NULL: the real stdin) and
 * out, or else the fqm(5) stream on the descriptor outfd (-1: the real
 * stdout), until bound again. */
void rs_ring_bind(rs_ring *in, int k, rs_ring *out, int outfd);

#endif
