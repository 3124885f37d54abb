/* pool.h - a loop's iterations on several threads: the caller and
 * threads - 1 more, kept between loops (a loop per row costs a
 * hand-over, not a thread start). */
#ifndef TL_POOL_H
#define TL_POOL_H

#include "base/util.h"

#define TL_POOL_MAXTHREADS 64

typedef struct tl_pool tl_pool;

/* A pool of `threads` (1 .. TL_POOL_MAXTHREADS); fewer when the system
 * gives fewer, the work the same. */
tl_pool *tl_pool_new(int threads, tl_err *e);
/* fn(arg, k, i0, i1) over [0, n) cut into one contiguous range per
 * thread, k = 0 .. tl_pool_threads(p) - 1 numbering the ranges in order;
 * returns when all are done. Ranges must not write the same memory. */
void tl_pool_for(tl_pool *p, int n,
    void (*fn)(void *arg, int k, int i0, int i1), void *arg);
int tl_pool_threads(const tl_pool *p);
void tl_pool_free(tl_pool *p);

#endif
