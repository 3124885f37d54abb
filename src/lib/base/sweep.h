/* sweep.h - the one sweep of dead owners' temporaries: outputs' hidden
 * ".NAME.XXXXXX" (outfile.h) and runs' scratch directories (scratch.h).
 *
 * An owner says it lives by holding an flock(2) for as long as it works:
 * on its temporary (a file) or on a lock file inside it (a directory);
 * the kernel drops the lock when the owner dies, however it dies. A
 * sweeper that can take that lock removes the temporary while holding it,
 * so no owner can believe in a temporary that is being removed. A
 * directory without a lock file (killed between its making and its lock)
 * goes when older than a minute, where the rule allows it. Names alone
 * prove nothing (other tools name theirs alike): where a rule asks for
 * it, only a temporary carrying the mark TL_SWEEP_MARK, the extended
 * attribute its owner set once it held the lock, is taken. */
#ifndef TL_SWEEP_H
#define TL_SWEEP_H

#include <stddef.h>

#define TL_SWEEP_MARK "user.terrain-lod.tmp"

/* What a rule takes of an entry, or 0 to leave it alone: */
enum {
	TL_SWEEP_FILE = 1,   /* a regular file, marked or not */
	TL_SWEEP_DIR = 2,    /* a directory, marked or not; one without a
	                      * lock file too, once older than a minute */
	TL_SWEEP_MARKED = 4  /* either, carrying the mark */
};
typedef int tl_sweep_rule(const char *name, void *arg);

/* Removes from the directory dfd (open, or -1: nothing to do; closed
 * here) each entry the rule takes whose owner is dead, never following a
 * symbolic link; lockname: the lock file in a temporary directory.
 * Returns how many went; best effort: what cannot be read or removed
 * stays, silently. */
int tl_sweep(int dfd, const char *lockname, tl_sweep_rule *rule, void *arg);
/* The owner's side: waits for the lock on fd, a temporary (or its lock
 * file) it has just created, which a sweeper may hold a moment: 0 held,
 * 1 when the sweeper removed it meanwhile (no link left: make another),
 * -1 no locks on this file system. */
int tl_sweep_hold(int fd);
/* 1 when x (n bytes) ends in ".XXXXXX", mkstemp's six letters and
 * digits. */
int tl_sweep_tail(const char *x, size_t n);

#endif
