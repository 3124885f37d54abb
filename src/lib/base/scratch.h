/* scratch.h - a private scratch directory in $TMPDIR (or /tmp) for one
 * run, and the removal of what killed runs left behind.
 *
 * The directory, PREFIX.XXXXXX, holds a file "lock" that its run keeps
 * locked (flock) while alive; the kernel drops the lock however the run
 * dies, SIGKILL included. A later run with the same prefix takes the lock
 * of every such directory it finds; where it can, the owner is dead and
 * the directory goes (sweep.h); removed with rmtree.h's tl_rmtree. */
#ifndef TL_SCRATCH_H
#define TL_SCRATCH_H

#include <stddef.h>

#include "base/rmtree.h" /* tl_rmtree, to remove one */
#include "base/util.h"

typedef struct {
	char path[4096];
	int lock; /* fd holding the lock, -1 when none */
} scratch;

/* Removes the dead runs' directories of prefix, then makes one of ours. */
int scratch_begin(scratch *s, const char *prefix, tl_err *e);
/* Removes ours (recursively); never fails. */
void scratch_end(scratch *s);
/* Removes the directories of prefix whose run is dead; returns how many
 * (directories without a lock file count when older than a minute). */
int scratch_sweep(const char *prefix);

#endif
