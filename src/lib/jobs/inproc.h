/* inproc.h - stages as threads of this process joined by rings of rows
 * (raster/rs_ring.h): what dem2vgis runs on one machine instead of the
 * processes of graph.h, with the supervisor's promises kept.
 *
 * Each task is a function run in a thread of its own whose "-" is bound
 * to the rings given (its input, as reader k; its output). The first
 * task that fails cancels every ring, so that the others stop at their
 * next row, and only its message is kept (a task stopped by the cancel
 * fails after it, and is not heard). The caller blocks INT, TERM and HUP
 * in every thread (inproc_block) for the whole route; inproc_run takes
 * them: a run of tasks that all read or write rings stops as a failure
 * does and returns status 128+n; a run of others (tilepack's, which no
 * ring holds) cannot be stopped: the scratch directory is removed and the
 * process dies of the signal at once, the outputs' handler (outfile.h)
 * removing what the tasks had begun. A task that no ring holds learns
 * of the others' failure by polling (inproc_stopped), and waits for
 * those whose outputs it reads (inproc_ended). */
#ifndef TL_INPROC_H
#define TL_INPROC_H

#include <signal.h>

#include "base/scratch.h"
#include "base/util.h"
#include "raster/rs_ring.h"

#define INPROC_MAXTASKS 96

typedef int (*inproc_fn)(void *arg, tl_err *e);
typedef struct inproc inproc;

inproc *inproc_new(const char *prog, tl_err *e);
void inproc_free(inproc *p);
/* A ring owned by p, of `readers` readers. */
rs_ring *inproc_ring(inproc *p, int readers, tl_err *e);
/* A task: fn(arg) with "-" as reader k of in, and out (NULL: none) or
 * the file outfd (-1: none), which the task's end closes. */
int inproc_task(inproc *p, inproc_fn fn, void *arg, rs_ring *in, int k,
    rs_ring *out, int outfd, tl_err *e);
/* Runs every task and waits for all: 0, or -1 with e the first failure's
 * message, *status 1, or 128+n for a signal (stoppable: the tasks all
 * stop at a cancel). s: the scratch to remove before dying of a signal
 * when not stoppable. */
int inproc_run(inproc *p, int stoppable, scratch *s, int *status,
    tl_err *e);

/* From a task: whether tasks 0 .. n-1 have ended, waiting up to ms
 * milliseconds for them: 0 all ended and none failed (their outfds
 * closed), 1 not yet, -1 never (a task failed, or the rings were
 * cancelled). inproc_stopped: 1 once a task has failed or the rings were
 * cancelled, read without waiting (a row loop's poll). */
int inproc_ended(inproc *p, int n, int ms);
int inproc_stopped(inproc *p);

/* The stop signals (INT, TERM, HUP) blocked in the calling thread and the
 * threads it starts (old: the mask to restore); a stop signal that came
 * meanwhile, taken (0: none). */
void inproc_block(sigset_t *old);
int inproc_pending(void);

#endif
