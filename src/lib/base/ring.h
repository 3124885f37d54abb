/* ring.h - a bounded ring of fixed-size slots between threads: one writer,
 * a fixed number of readers that each see every slot in order (a tee
 * without copies), and a cancel that wakes everyone.
 *
 * The writer starts the ring (its slot size and a pointer the readers
 * get, e.g. a header), fills slots and closes it; a slot is reused once
 * every reader still attached has released it, so the writer waits for
 * the slowest. A reader may leave early (it no longer holds the writer
 * back). Nothing ever ends a wait but the data, the close, a leave or
 * tl_ring_cancel: a writer that fails simply stops, and its readers wait
 * for the cancel that its failure brings (so that the failure is told
 * before any follow-on). All calls are thread-safe; the slots belong to
 * the ring. */
#ifndef TL_RING_H
#define TL_RING_H

#include <stddef.h>

#include "base/util.h"

#define TL_RING_MAXREADERS 8

typedef struct tl_ring tl_ring;

tl_ring *tl_ring_new(int readers, int slots, tl_err *e);
void tl_ring_free(tl_ring *q);

/* Writer: start (once), then for each slot put_begin (the slot to fill,
 * NULL when cancelled) and put_end; close when all is written. */
int tl_ring_start(tl_ring *q, size_t slotbytes, const void *meta, tl_err *e);
void *tl_ring_put_begin(tl_ring *q);
void tl_ring_put_end(tl_ring *q);
void tl_ring_close(tl_ring *q);

/* Reader k (0 .. readers-1): the writer's meta once started (NULL when
 * cancelled); each slot in order by get_begin (NULL at the close or when
 * cancelled: tl_ring_cancelled tells which) and get_end; leave when done
 * or giving up. */
const void *tl_ring_wait_start(tl_ring *q);
const void *tl_ring_get_begin(tl_ring *q, int k);
void tl_ring_get_end(tl_ring *q, int k);
void tl_ring_leave(tl_ring *q, int k);

void tl_ring_cancel(tl_ring *q);
int tl_ring_cancelled(tl_ring *q);

#endif
