/* outfile.h - outputs that appear complete or not at all: files and
 * directory trees built under hidden temporary names beside their final
 * paths and renamed at the end; removed on failure, on a fatal signal,
 * and, after a SIGKILL or a crash, by the next output begun in the same
 * directory. */
#ifndef TL_OUTFILE_H
#define TL_OUTFILE_H

#include "base/rmtree.h" /* tl_rmtree, as an abort removes a tree */
#include "base/util.h"

/* An output file built under a hidden temporary name beside its final path
 * and renamed onto it by tl_out_commit. A signal (INT, TERM, HUP, PIPE)
 * removes every uncommitted temporary before the process dies: that
 * registry is process-wide by nature, hence the one piece of static state.
 * What a signal cannot cover (SIGKILL, a crash) the next output begun in
 * the same directory removes: the builder holds an flock(2) on its
 * temporary for as long as it lives and marks it (the extended attribute
 * user.terrain-lod.tmp, removed before the rename), and tl_out_begin first
 * removes the temporaries ".NAME.XXXXXX" there whose lock it can take
 * (their owner died): its own path's, and any other marked one; another
 * tool's, unmarked, are never touched. The fatal signals wait while a
 * temporary is created, locked and registered. */
typedef struct {
	char *path; /* final name */
	char *tmp;  /* temporary name, same directory; NULL when the file
	             * is written under its final name (tl_out_begin_tree) */
	int fd;     /* open for writing (a file); the lock (a directory) */
} tl_outfile;

int tl_out_begin(tl_outfile *o, const char *path, tl_err *e);
/* tl_out_begin without the sweep, for a directory that no dead
 * builder's temporaries can be in or that the caller swept once
 * (tl_out_sweep_dir): looking for them costs a listing of the directory
 * per file, quadratic in a level of thousands of blocks. The file is
 * still made under a temporary name, locked, marked and renamed: a plan's
 * work directory outlives a killed job, and a later job takes the files
 * there under their final names for complete. */
int tl_out_begin_fresh(tl_outfile *o, const char *path, tl_err *e);
/* A new file inside a tree this process builds (tl_outdir_begin, not
 * yet committed), opened under its final name (O_EXCL: it must not
 * exist), mode 0666 less the umask: no temporary name, lock, mark or
 * rename. The tree's rename publishes it whole, and whatever removes
 * the tree (its abort, a fatal signal, the sweep after a SIGKILL)
 * removes it half-written. tl_out_commit closes it (a failed close
 * removes it), tl_out_abort removes it. */
int tl_out_begin_tree(tl_outfile *o, const char *path, tl_err *e);
int tl_out_commit(tl_outfile *o, tl_err *e); /* fsync-free close + rename */
void tl_out_abort(tl_outfile *o);            /* close + unlink, never fails */

/* A temporary directory tree built under a hidden name and renamed at the
 * end (tilepack), atomically replacing an earlier one; removed
 * recursively (any depth, symbolic links removed, never followed) by
 * abort or by a signal. The caller decides whether an existing directory
 * may be replaced. While it is built the tree holds a lock file ".lock",
 * flock(2)ed by the builder and removed before the commit, so the result
 * holds exactly what the caller put there. tl_outdir_begin first removes
 * the temporaries of dead builders as tl_out_begin does, and its own
 * path's trees without a lock file older than a minute. An abort closes
 * the lock first and a descriptor is held in reserve, so that a failure
 * for want of descriptors (EMFILE) still removes the tree. */
int tl_outdir_begin(tl_outfile *o, const char *path, tl_err *e);
/* Removes the temporaries ".NAME.XXXXXX" of dead writers (those whose
 * lock can be taken) from dir: once, before writing into a directory
 * that other processes build too (a plan's pieces). Best effort. */
void tl_out_sweep_dir(const char *dir);
/* The finished tree tmp becomes path, replacing an earlier directory
 * there atomically (tl_outdir_commit's last step). */
int tl_dir_install(const char *tmp, const char *path, tl_err *e);
int tl_outdir_commit(tl_outfile *o, tl_err *e);
void tl_outdir_abort(tl_outfile *o);
/* Installs the handler that removes the temporaries on INT, TERM, HUP
 * and PIPE (then dies of the signal, as by default). Every program calls
 * it at start (cli_init), before it has threads: a signal that finds the
 * default action ends the process at once, and a thread then inside the
 * system call that makes a temporary leaves it. Making an output calls
 * it too. */
void tl_out_catch(void);
/* A temporary is made and registered for the signal handler in one step:
 * the handler, in whatever thread a fatal signal (INT, TERM, HUP, PIPE)
 * runs it, first waits for the steps under way to end, so that it finds
 * every temporary registered, none made but not yet known. */

#endif
