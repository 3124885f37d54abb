/* util.h - plumbing every tool shares: error reports, checked allocation,
 * output files that appear complete or not at all, terminal progress. */
#ifndef TL_UTIL_H
#define TL_UTIL_H

#include <stddef.h>

#define TL_VERSION "0.1.0"

/* A failure report, "what: why". Library calls that fail fill it and return
 * -1 (or NULL); only programs print, as "prog: what: why". */
typedef struct {
	char msg[1024];
} tl_err;

int tl_fail(tl_err *e, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Like tl_fail, appending ": strerror(errno)". */
int tl_failsys(tl_err *e, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* For programs only: "prog: message" on stderr. */
void tl_warn(const char *prog, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* For the filters' "prog [in [out]]": the operands left after the
 * options, "-" by default. Returns 0, 2 (bad usage: more than two) or 1
 * (a stream to a terminal, refused with a message). */
int tl_operands(const char *prog, int argc, char **argv, const char **in,
    const char **out);

/* For programs: "-" names stdin or stdout in messages. */
const char *tl_name(const char *path, int output);

/* calloc(n, size) with overflow check; on failure fills e and returns NULL. */
void *tl_alloc(size_t n, size_t size, tl_err *e);

/* An output file built under a hidden temporary name beside its final path
 * and renamed onto it by tl_out_commit. A signal (INT, TERM, HUP, PIPE)
 * removes every uncommitted temporary before the process dies: that
 * registry is process-wide by nature, hence the one piece of static state.
 * What a signal cannot cover (SIGKILL, a crash) the next output to the
 * same path removes: the builder holds an flock(2) on its temporary for
 * as long as it lives, and tl_out_begin first removes the sibling
 * temporaries ".NAME.XXXXXX" whose lock it can take (their owner died). */
typedef struct {
	char *path; /* final name */
	char *tmp;  /* temporary name, same directory */
	int fd;     /* open for writing (a file); the lock (a directory) */
} tl_outfile;

int tl_out_begin(tl_outfile *o, const char *path, tl_err *e);
int tl_out_commit(tl_outfile *o, tl_err *e); /* fsync-free close + rename */
void tl_out_abort(tl_outfile *o);            /* close + unlink, never fails */

/* A temporary directory tree built under a hidden name and renamed at the
 * end (tilepack), atomically replacing an earlier one; removed
 * recursively (any depth, symbolic links removed, never followed) by
 * abort or by a signal. The caller decides whether an existing directory
 * may be replaced. While it is built the tree holds a lock file ".lock",
 * flock(2)ed by the builder and removed before the commit, so the result
 * holds exactly what the caller put there. tl_outdir_begin first removes
 * the sibling trees ".NAME.XXXXXX" of dead builders: those whose lock can
 * be taken, and those without a lock file older than a minute. */
int tl_outdir_begin(tl_outfile *o, const char *path, tl_err *e);
int tl_outdir_commit(tl_outfile *o, tl_err *e);
void tl_outdir_abort(tl_outfile *o);

/* An anonymous scratch file (unlinked at once) in $TMPDIR or /tmp. */
int tl_scratch(tl_err *e);

/* pread/pwrite that loop over short transfers; -1 with message on error,
 * pread also fails on a short file (what names the file). */
int tl_pread(int fd, void *buf, size_t n, long long off, const char *what,
    tl_err *e);
int tl_pwrite(int fd, const void *buf, size_t n, long long off,
    const char *what, tl_err *e);

/* Progress of a long loop, in one of two ways:
 * - for a supervisor (dem2vgis): when the environment has TL_PROGRESS_FD=n
 *   and n is an open descriptor writable by this process, one line
 *   "LABEL\tDONE\tTOTAL\n" goes to n each time the percentage changes
 *   and one (DONE = TOTAL) at the end, and nothing is drawn. Each line is
 *   a single write(2) shorter than PIPE_BUF (the label is cut to 200
 *   bytes, its tabs and newlines made spaces), so the lines of many
 *   processes sharing one pipe never interleave. An n that is not a
 *   number or not open for writing is ignored silently (the terminal rule
 *   then holds); a failed write ends the reports, never the work.
 * - otherwise a line "LABEL: NN%" drawn on stderr, only when stderr is a
 *   terminal.
 * Setting on to 0 after tl_progress_start silences both. */
typedef struct {
	const char *label;
	long long total, done;
	int on, last; /* last percentage drawn or reported */
	int fd;       /* TL_PROGRESS_FD, or -1: the terminal */
} tl_progress;

void tl_progress_start(tl_progress *p, const char *label, long long total);
void tl_progress_step(tl_progress *p, long long done);
void tl_progress_end(tl_progress *p);

/* Parse a whole decimal number; -1 when s is not one. */
int tl_parse_double(const char *s, double *v);
int tl_parse_int(const char *s, int *v);

#endif
