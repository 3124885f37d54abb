/* rmtree.h - the one removal of a directory tree (rm -r): at any depth,
 * never following a symbolic link (removed like a file) nor entering a
 * mount point, with system calls only (async-signal-safe: outfile.c's
 * fatal-signal handler uses it), no recursion and two descriptors at
 * most, plus one held in reserve so that a failure for want of
 * descriptors (EMFILE) can still be cleaned up. Best effort: what cannot
 * be removed stays. */
#ifndef TL_RMTREE_H
#define TL_RMTREE_H

/* Removes path and everything under it; 0, or -1 when some of it stays. */
int tl_rmtree(const char *path);
/* The same for name relative to the directory parent (or AT_FDCWD);
 * async-signal-safe. */
void tl_rmtree_at(int parent, const char *name);
/* Opens the descriptor in reserve (once; before a tree that may need
 * removing after EMFILE is begun). */
void tl_rmtree_reserve(void);

#endif
