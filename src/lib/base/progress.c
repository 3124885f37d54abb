/* progress.c - a progress line on a terminal, or lines for a supervisor
 * (progress.h). */
#include "base/progress.h"
#include "base/util.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The descriptor TL_PROGRESS_FD names, when it is a number and open for
 * writing; -1 otherwise (silently: progress is never worth failing for). */
static int
progress_fd(void)
{
	const char *s = getenv("TL_PROGRESS_FD");
	int fd, fl;

	if (s == NULL || *s == '\0' || tl_parse_int(s, &fd) < 0 || fd < 0 ||
	    (fl = fcntl(fd, F_GETFL)) < 0 || (fl & O_ACCMODE) == O_RDONLY)
		return -1;
	return fd;
}

static tl_progress_fn sink;
static void *sink_ctx;

void
tl_progress_sink(tl_progress_fn fn, void *ctx)
{
	sink = fn, sink_ctx = ctx;
}

/* One line "LABEL\tDONE\tTOTAL\n" in one write(2) of less than PIPE_BUF
 * bytes, so that the lines of processes sharing the pipe never mix. The
 * label is cut to 200 bytes and loses its tabs and newlines. */
static void
progress_line(tl_progress *p, long long done)
{
	char buf[320];
	size_t n = 0;
	ssize_t r;

	if (p->fd == -2) {
		sink(sink_ctx, p->label, done, p->total);
		return;
	}
	_Static_assert(sizeof buf <= PIPE_BUF, "one atomic write");
	for (const char *c = p->label; *c != '\0' && n < 200; c++)
		buf[n++] = *c == '\t' || *c == '\n' ? ' ' : *c;
	n += (size_t)snprintf(buf + n, sizeof buf - n, "\t%lld\t%lld\n", done,
	    p->total);
	do
		r = write(p->fd, buf, n);
	while (r < 0 && errno == EINTR);
	if (r < 0)
		p->on = 0; /* the reader has gone: stop reporting */
}

void
tl_progress_start(tl_progress *p, const char *label, long long total)
{
	p->label = label != NULL ? label : "";
	p->total = total > 0 ? total : 1;
	p->done = 0;
	p->last = -1;
	p->fd = sink != NULL ? -2 : progress_fd();
	p->on = p->fd != -1 || isatty(STDERR_FILENO);
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
	if (p->fd != -1)
		progress_line(p, done);
	else
		fprintf(stderr, "\r%s: %3d%%", p->label, pct);
}

void
tl_progress_end(tl_progress *p)
{
	if (!p->on)
		return;
	if (p->fd == -1 && p->last >= 0)
		fprintf(stderr, "\r%s: 100%%\n", p->label);
	else if (p->fd != -1 && (p->last != 100 || p->done != p->total))
		progress_line(p, p->total); /* unless just said */
	p->on = 0;
}
