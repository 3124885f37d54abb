/* util.c - error reports, allocation, operands, whole reads and writes,
 * numbers (util.h). */
#define _GNU_SOURCE
#include "base/util.h"

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
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
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

const char *
tl_errno_hint(int errnum)
{
	/* where the limit is the user's, what to do about it */
	switch (errnum) {
	case EMFILE:
		return " (too few descriptors: raise ulimit -n)";
	case EFBIG:
		return " (over ulimit -f or the file system's largest file)";
	}
	return "";
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
	snprintf(e->msg + n, sizeof e->msg - n, ": %s%s", strerror(saved),
	    tl_errno_hint(saved));
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
		tl_warn(prog, "%s: is both the input and the output%s%s%s: "
		    "refusing to replace the input", tl_name(*out, 1),
		    strcmp(*in, *out) != 0 ? " (the input " : "",
		    strcmp(*in, *out) != 0 ? tl_name(*in, 0) : "",
		    strcmp(*in, *out) != 0 ? ")" : "");
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

int
tl_open_regular(const char *path, tl_err *e)
{
	struct stat st;
	int fd, fl;

	if ((fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0)
		return tl_failsys(e, "%s", path);
	if (fstat(fd, &st) < 0) {
		tl_failsys(e, "%s", path);
		close(fd);
		return -1;
	}
	if (!S_ISREG(st.st_mode)) {
		tl_fail(e, "%s: not a regular file (%s)", path,
		    S_ISDIR(st.st_mode) ? "a directory" :
		    S_ISFIFO(st.st_mode) ? "a FIFO" :
		    S_ISSOCK(st.st_mode) ? "a socket" : "a device");
		close(fd);
		return -1;
	}
	if ((fl = fcntl(fd, F_GETFL)) < 0 ||
	    fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) < 0) {
		tl_failsys(e, "%s", path);
		close(fd);
		return -1;
	}
	return fd;
}

FILE *
tl_fopen_regular(const char *path, tl_err *e)
{
	FILE *f;
	int fd = tl_open_regular(path, e);

	if (fd < 0)
		return NULL;
	if ((f = fdopen(fd, "r")) == NULL) {
		tl_failsys(e, "%s", path);
		close(fd);
	}
	return f;
}

int
tl_scratch(tl_err *e)
{
	const char *dir = tl_tmpdir();
	char path[PATH_MAX];
	int fd;

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
tl_fds_exhausted(void)
{
	int fd = open("/dev/null", O_RDONLY | O_CLOEXEC);

	if (fd >= 0)
		close(fd);
	return fd < 0 && (errno == EMFILE || errno == ENFILE);
}

int
tl_fail_fds(tl_err *e, const char *what, const char *needed)
{
	errno = EMFILE;
	return tl_failsys(e, "%s: no descriptor left to open %s", what,
	    needed);
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

long long
tl_copy_fd(int in, const char *rwhat, int out, long long off,
    const char *wwhat, tl_err *e)
{
	char buf[1 << 16];
	long long start = off;
	ssize_t n;

	while ((n = read(in, buf, sizeof buf)) != 0) {
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return tl_failsys(e, "%s", rwhat);
		if (tl_pwrite(out, buf, (size_t)n, off, wwhat, e) < 0)
			return -1;
		off += n;
	}
	return off - start;
}

const char *
tl_tmpdir(void)
{
	const char *t = getenv("TMPDIR");

	return t != NULL && t[0] != '\0' ? t : "/tmp";
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

int
tl_parse_ll(const char *s, long long *v)
{
	char *end;
	long long l;

	errno = 0;
	l = strtoll(s, &end, 10);
	if (end == s || *end != '\0' || errno != 0)
		return -1;
	*v = l;
	return 0;
}

char *
tl_list_entry(char *line)
{
	char *end;

	line += strspn(line, " \t\r\f\v");
	end = line + strlen(line);
	while (end > line && strchr(" \t\r\f\v", end[-1]) != NULL)
		*--end = '\0';
	return *line == '\0' || *line == '#' ? NULL : line;
}

char *
tl_list_path(const char *dir, const char *ent, tl_err *e)
{
	size_t n;
	char *p;

	if (ent[0] == '/' || (dir != NULL && strcmp(dir, ".") == 0))
		dir = NULL;
	n = (dir != NULL ? strlen(dir) + 1 : 0) + strlen(ent) + 1;
	if ((p = tl_alloc(n, 1, e)) != NULL)
		snprintf(p, n, "%s%s%s", dir != NULL ? dir : "",
		    dir != NULL ? "/" : "", ent);
	return p;
}
