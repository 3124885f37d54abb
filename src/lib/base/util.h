/* util.h - plumbing every tool shares: error reports, checked allocation,
 * operands, whole reads and writes, numbers. Output files that appear
 * complete or not at all are outfile.h's, progress progress.h's. */
#ifndef TL_UTIL_H
#define TL_UTIL_H

#include <stddef.h>
#include <stdio.h>

#define TL_VERSION "0.1.0"

/* A failure report, "what: why". Library calls that fail fill it and return
 * -1 (or NULL); only programs print, as "prog: what: why". */
typedef struct {
	char msg[1024];
} tl_err;

int tl_fail(tl_err *e, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Like tl_fail, appending ": strerror(errno)" and tl_errno_hint. */
int tl_failsys(tl_err *e, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* For EMFILE and EFBIG, the limit to raise, " (... ulimit -n)", " (...
 * ulimit -f ...)"; "" for the others. */
const char *tl_errno_hint(int errnum);

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

/* An input that must be a regular file, opened read-only: anything else
 * (a FIFO, a device, a directory, a socket) is refused at once, without
 * blocking on it (O_NONBLOCK open, then fstat). Returns the descriptor,
 * blocking again, or -1 with "path: not a regular file" or the system's
 * reason. tl_fopen_regular is the same as a stdio stream ("r"). */
int tl_open_regular(const char *path, tl_err *e);
FILE *tl_fopen_regular(const char *path, tl_err *e);

/* The directory for temporaries: $TMPDIR, or /tmp when unset or empty
 * (the one reading of TMPDIR). */
const char *tl_tmpdir(void);
/* An anonymous scratch file (unlinked at once) in tl_tmpdir(). */
int tl_scratch(tl_err *e);

/* 1 when this process cannot open one more descriptor (EMFILE, ENFILE):
 * a library that failed for want of one (PROJ opening its database) is
 * then reported for that, not for its input. */
int tl_fds_exhausted(void);
/* The message for it, "what: no descriptor left to open PROJ's database
 * (too few descriptors: raise ulimit -n)", always -1. */
int tl_fail_fds(tl_err *e, const char *what, const char *needed);

/* pread/pwrite that loop over short transfers; -1 with message on error,
 * pread also fails on a short file (what names the file). */
int tl_pread(int fd, void *buf, size_t n, long long off, const char *what,
    tl_err *e);
int tl_pwrite(int fd, const void *buf, size_t n, long long off,
    const char *what, tl_err *e);
/* Copies in (read(2) to its end: a pipe, stdin) into out from offset off
 * on: the bytes copied, or -1 with "rwhat: why" (a read) or tl_pwrite's
 * "wwhat: write: why". The one loop spooling a stream into a file. */
long long tl_copy_fd(int in, const char *rwhat, int out, long long off,
    const char *wwhat, tl_err *e);

/* Parse a whole decimal number; -1 when s is not one. */
int tl_parse_double(const char *s, double *v);
int tl_parse_int(const char *s, int *v);
int tl_parse_ll(const char *s, long long *v);

/* Lists of paths (a DEM list, dem2fqm(1); a band list, fqm(5)), one a
 * line: the line's entry, blanks around it cut in place; NULL for a blank
 * line or one whose first non-blank character is '#'. */
char *tl_list_entry(char *line);
/* An entry as a path from the current directory: relative ones are
 * relative to dir, the list's directory ("." or NULL: as they are). */
char *tl_list_path(const char *dir, const char *ent, tl_err *e);

#endif
