/* util.c - error reports, allocation, atomic output files, progress. */
#define _GNU_SOURCE
#include "core/util.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

int
tl_fail(tl_err *e, const char *fmt, ...)
{
	va_list ap;

	if (e == NULL)
		return -1;
	va_start(ap, fmt);
	vsnprintf(e->msg, sizeof e->msg, fmt, ap);
	va_end(ap);
	return -1;
}

int
tl_failsys(tl_err *e, const char *fmt, ...)
{
	va_list ap;
	int saved = errno;
	size_t n;

	if (e == NULL)
		return -1;
	va_start(ap, fmt);
	vsnprintf(e->msg, sizeof e->msg, fmt, ap);
	va_end(ap);
	n = strlen(e->msg);
	snprintf(e->msg + n, sizeof e->msg - n, ": %s", strerror(saved));
	errno = saved;
	return -1;
}

void
tl_warn(const char *prog, const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "%s: ", prog);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
}

/* 1 when in and out ("-": stdin, stdout) are one regular file: writing
 * the output would destroy the input. */
static int
same_file(const char *in, const char *out)
{
	struct stat a, b;

	if ((strcmp(in, "-") == 0 ? fstat(STDIN_FILENO, &a) : stat(in, &a)) != 0 ||
	    (strcmp(out, "-") == 0 ? fstat(STDOUT_FILENO, &b) :
	    stat(out, &b)) != 0)
		return 0;
	return S_ISREG(a.st_mode) && a.st_dev == b.st_dev &&
	    a.st_ino == b.st_ino;
}

int
tl_operands(const char *prog, int argc, char **argv, const char **in,
    const char **out)
{
	if (argc > 2)
		return 2;
	*in = argc > 0 ? argv[0] : "-";
	*out = argc > 1 ? argv[1] : "-";
	if (strcmp(*out, "-") == 0 && isatty(STDOUT_FILENO)) {
		tl_warn(prog, "stdout: refusing to write a stream to a terminal");
		return 1;
	}
	if (same_file(*in, *out)) {
		tl_warn(prog, "%s: is both the input and the output: refusing "
		    "to replace the input", tl_name(*out, 1));
		return 1;
	}
	return 0;
}

const char *
tl_name(const char *path, int output)
{
	if (strcmp(path, "-") == 0)
		return output ? "stdout" : "stdin";
	return path;
}

void *
tl_alloc(size_t n, size_t size, tl_err *e)
{
	void *p;

	if (size != 0 && n > SIZE_MAX / size) {
		tl_fail(e, "allocation of %zu x %zu bytes: too large", n, size);
		return NULL;
	}
	p = calloc(n ? n : 1, size ? size : 1);
	if (p == NULL)
		tl_fail(e, "allocation of %zu bytes: out of memory", n * size);
	return p;
}

/* --- temporaries removed on a fatal signal ---------------------------- */

/* The registry the signal handler walks. Threads change it under a lock
 * with signals blocked; a slot's path is published last with an atomic
 * store and read with an atomic load, so the handler (which cannot lock)
 * sees each slot empty or complete, never half-written. */
#define MAXTMP 64
static struct {
	const char *path; /* owned by the tl_outfile; atomic */
	int dir;
} tmps[MAXTMP];
static pthread_mutex_t tmps_lock = PTHREAD_MUTEX_INITIALIZER;

/* Remove a directory tree with system calls only (async-signal-safe). */
static void
rmtree_at(int parent, const char *name, int depth)
{
	char buf[4096];
	int fd;
	long n;

	/* depth bounds the stack (4 KiB a level); pyramids are 3 deep */
	if (unlinkat(parent, name, 0) == 0 || errno != EISDIR || depth > 64)
		return;
	fd = openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW);
	if (fd < 0)
		return;
	/* Passes from the start until one finds nothing left to remove
	 * (removal while reading may hide entries); a few at most. */
	for (int pass = 0, found = 1; found && pass < 4; pass++) {
		found = 0;
		lseek(fd, 0, SEEK_SET);
		while ((n = syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0)
			for (long off = 0; off < n;) {
				struct {
					uint64_t ino;
					int64_t off;
					unsigned short reclen;
					unsigned char type;
					char name[];
				} *d = (void *)(buf + off);
				if (strcmp(d->name, ".") != 0 &&
				    strcmp(d->name, "..") != 0) {
					rmtree_at(fd, d->name, depth + 1);
					found = 1;
				}
				off += d->reclen;
			}
	}
	close(fd);
	unlinkat(parent, name, AT_REMOVEDIR);
}

static void
on_signal(int sig)
{
	for (int i = 0; i < MAXTMP; i++) {
		const char *p = __atomic_load_n(&tmps[i].path, __ATOMIC_ACQUIRE);
		if (p == NULL)
			continue;
		if (tmps[i].dir)
			rmtree_at(AT_FDCWD, p, 0);
		else
			unlink(p);
	}
	signal(sig, SIG_DFL);
	raise(sig);
}

/* Blocks the signals whose handler reads the registry, takes the lock. */
static void
tmps_enter(sigset_t *old)
{
	sigset_t all;

	sigfillset(&all);
	pthread_sigmask(SIG_BLOCK, &all, old);
	pthread_mutex_lock(&tmps_lock);
}

static void
tmps_leave(const sigset_t *old)
{
	pthread_mutex_unlock(&tmps_lock);
	pthread_sigmask(SIG_SETMASK, old, NULL);
}

/* -1 (e set) when the registry is full: an output that a signal could
 * leave behind is refused rather than silently unguarded. */
static int
tmp_register(const char *path, int dir, tl_err *e)
{
	static const int sigs[] = { SIGINT, SIGTERM, SIGHUP, SIGPIPE };
	struct sigaction sa;
	sigset_t old;
	int i;

	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigfillset(&sa.sa_mask);
	tmps_enter(&old);
	for (size_t k = 0; k < sizeof sigs / sizeof sigs[0]; k++)
		sigaction(sigs[k], &sa, NULL);
	for (i = 0; i < MAXTMP && tmps[i].path != NULL; i++)
		;
	if (i < MAXTMP) {
		tmps[i].dir = dir;
		__atomic_store_n(&tmps[i].path, path, __ATOMIC_RELEASE);
	}
	tmps_leave(&old);
	return i < MAXTMP ? 0 : tl_fail(e, "%s: more than %d temporary "
	    "outputs at once", path, MAXTMP);
}

static void
tmp_unregister(const char *path)
{
	sigset_t old;

	tmps_enter(&old);
	for (int i = 0; i < MAXTMP; i++)
		if (tmps[i].path == path)
			__atomic_store_n(&tmps[i].path, NULL, __ATOMIC_RELEASE);
	tmps_leave(&old);
}

static mode_t
current_umask(void)
{
	mode_t m = umask(022);

	umask(m);
	return m;
}

/* "dir/.base.XXXXXX" beside path. */
static char *
tmp_name(const char *path, tl_err *e)
{
	const char *slash = strrchr(path, '/');
	size_t dlen = slash ? (size_t)(slash - path + 1) : 0;
	size_t n = strlen(path) + 16;
	char *t = tl_alloc(n, 1, e);

	if (t == NULL)
		return NULL;
	snprintf(t, n, "%.*s.%s.XXXXXX", (int)dlen, path, path + dlen);
	return t;
}

int
tl_out_begin(tl_outfile *o, const char *path, tl_err *e)
{
	struct stat st;

	memset(o, 0, sizeof *o);
	o->fd = -1;
	if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: is a directory", path);
	if ((o->path = strdup(path)) == NULL || (o->tmp = tmp_name(path, e)) == NULL) {
		free(o->path);
		return tl_fail(e, "%s: out of memory", path);
	}
	o->fd = mkstemp(o->tmp);
	if (o->fd < 0) {
		tl_failsys(e, "%s: cannot create", path);
		free(o->path), free(o->tmp);
		o->path = o->tmp = NULL;
		return -1;
	}
	fchmod(o->fd, 0666 & ~current_umask());
	if (tmp_register(o->tmp, 0, e) < 0) {
		close(o->fd);
		unlink(o->tmp);
		free(o->path), free(o->tmp);
		o->path = o->tmp = NULL;
		o->fd = -1;
		return -1;
	}
	return 0;
}

int
tl_out_commit(tl_outfile *o, tl_err *e)
{
	int r = 0;

	if (o->fd >= 0 && close(o->fd) != 0)
		r = tl_failsys(e, "%s: write", o->path);
	o->fd = -1;
	if (r == 0 && rename(o->tmp, o->path) != 0)
		r = tl_failsys(e, "%s: rename", o->path);
	if (r != 0)
		unlink(o->tmp);
	tmp_unregister(o->tmp);
	free(o->tmp), free(o->path);
	o->tmp = o->path = NULL;
	return r;
}

void
tl_out_abort(tl_outfile *o)
{
	if (o->tmp == NULL)
		return;
	if (o->fd >= 0)
		close(o->fd);
	unlink(o->tmp);
	tmp_unregister(o->tmp);
	free(o->tmp), free(o->path);
	o->tmp = o->path = NULL;
	o->fd = -1;
}

int
tl_outdir_begin(tl_outfile *o, const char *path, tl_err *e)
{
	memset(o, 0, sizeof *o);
	o->fd = -1;
	if ((o->path = strdup(path)) == NULL || (o->tmp = tmp_name(path, e)) == NULL) {
		free(o->path);
		return tl_fail(e, "%s: out of memory", path);
	}
	if (mkdtemp(o->tmp) == NULL) {
		tl_failsys(e, "%s: cannot create", path);
		free(o->path), free(o->tmp);
		o->path = o->tmp = NULL;
		return -1;
	}
	chmod(o->tmp, 0777 & ~current_umask());
	if (tmp_register(o->tmp, 1, e) < 0) {
		rmdir(o->tmp);
		free(o->path), free(o->tmp);
		o->path = o->tmp = NULL;
		return -1;
	}
	return 0;
}

int
tl_outdir_commit(tl_outfile *o, tl_err *e)
{
	struct stat st;
	int r = 0;

	/* Replace an earlier directory by swapping the two atomically
	 * (renameat2 RENAME_EXCHANGE), then remove the old one: readers
	 * see the old tree or the new one, never a mix or nothing. */
	if (lstat(o->path, &st) == 0) {
		if (!S_ISDIR(st.st_mode))
			r = tl_fail(e, "%s: exists and is not a directory", o->path);
		else if (syscall(SYS_renameat2, AT_FDCWD, o->tmp, AT_FDCWD,
		    o->path, 2 /* RENAME_EXCHANGE */) != 0)
			r = tl_failsys(e, "%s: replace", o->path);
		else
			rmtree_at(AT_FDCWD, o->tmp, 0); /* now the old tree */
	} else if (rename(o->tmp, o->path) != 0)
		r = tl_failsys(e, "%s: rename", o->path);
	if (r != 0)
		rmtree_at(AT_FDCWD, o->tmp, 0);
	tmp_unregister(o->tmp);
	free(o->tmp), free(o->path);
	o->tmp = o->path = NULL;
	return r;
}

void
tl_outdir_abort(tl_outfile *o)
{
	if (o->tmp == NULL)
		return;
	rmtree_at(AT_FDCWD, o->tmp, 0);
	tmp_unregister(o->tmp);
	free(o->tmp), free(o->path);
	o->tmp = o->path = NULL;
}

int
tl_scratch(tl_err *e)
{
	const char *dir = getenv("TMPDIR");
	char path[PATH_MAX];
	int fd;

	if (dir == NULL || *dir == '\0')
		dir = "/tmp";
	/* O_TMPFILE leaves no name at all; fall back to mkstemp + unlink. */
	fd = open(dir, O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
	if (fd >= 0)
		return fd;
	snprintf(path, sizeof path, "%s/tl-scratch.XXXXXX", dir);
	fd = mkstemp(path);
	if (fd < 0)
		return tl_failsys(e, "%s: cannot create a scratch file", dir);
	unlink(path);
	return fd;
}

int
tl_pread(int fd, void *buf, size_t n, long long off, const char *what,
    tl_err *e)
{
	char *p = buf;

	while (n > 0) {
		ssize_t r = pread(fd, p, n, (off_t)off);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return tl_failsys(e, "%s: read", what);
		if (r == 0)
			return tl_fail(e, "%s: unexpected end of file", what);
		p += r, n -= (size_t)r, off += r;
	}
	return 0;
}

int
tl_pwrite(int fd, const void *buf, size_t n, long long off,
    const char *what, tl_err *e)
{
	const char *p = buf;

	while (n > 0) {
		ssize_t r = pwrite(fd, p, n, (off_t)off);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return tl_failsys(e, "%s: write", what);
		p += r, n -= (size_t)r, off += r;
	}
	return 0;
}

void
tl_progress_start(tl_progress *p, const char *label, long long total)
{
	p->label = label;
	p->total = total > 0 ? total : 1;
	p->done = 0;
	p->last = -1;
	p->on = isatty(STDERR_FILENO);
}

void
tl_progress_step(tl_progress *p, long long done)
{
	int pct;

	if (!p->on)
		return;
	p->done = done;
	pct = (int)(100 * done / p->total);
	if (pct == p->last)
		return;
	p->last = pct;
	fprintf(stderr, "\r%s: %3d%%", p->label, pct);
}

void
tl_progress_end(tl_progress *p)
{
	if (p->on && p->last >= 0)
		fprintf(stderr, "\r%s: 100%%\n", p->label);
	p->on = 0;
}

int
tl_parse_double(const char *s, double *v)
{
	char *end;

	errno = 0;
	*v = strtod(s, &end);
	if (end == s || *end != '\0' || errno != 0 || !isfinite(*v))
		return -1;
	return 0;
}

int
tl_parse_int(const char *s, int *v)
{
	char *end;
	long l;

	errno = 0;
	l = strtol(s, &end, 10);
	if (end == s || *end != '\0' || errno != 0 || l < INT_MIN || l > INT_MAX)
		return -1;
	*v = (int)l;
	return 0;
}
