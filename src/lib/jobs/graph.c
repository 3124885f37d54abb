/* graph.c - the supervisor of a process graph (graph.h): building and
 * running a graph; the stop signal is graph_signal.c's. */
#define _GNU_SOURCE /* close_range */
#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "jobs/graph_impl.h"

graph *
graph_new(const char *prog, const char *bindir, tl_err *e)
{
	graph *g = tl_alloc(1, sizeof *g, e);

	if (g == NULL)
		return NULL;
	g->prog = prog, g->bindir = bindir, g->self = getpid();
	g->prog_fd[0] = g->prog_fd[1] = -1;
	return g;
}

static void
free_argv(char **argv)
{
	for (size_t i = 0; argv != NULL && argv[i] != NULL; i++)
		free(argv[i]);
	free(argv);
}

static void
close_owned(graph *g)
{
	for (int i = 0; i < g->nfds; i++)
		close(g->fds[i]);
	g->nfds = 0;
}

void
graph_progress(graph *g, graph_progress_fn fn, void *ctx)
{
	g->progress = fn, g->progress_ctx = ctx;
}

void
graph_free(graph *g)
{
	if (g == NULL)
		return;
	close_owned(g);
	for (int i = 0; i < 2; i++)
		if (g->prog_fd[i] >= 0)
			close(g->prog_fd[i]);
	for (int k = 0; k < g->n; k++) {
		free_argv(g->st[k].argv);
		if (g->st[k].err >= 0)
			close(g->st[k].err);
		if (g->st[k].cap >= 0)
			close(g->st[k].cap);
	}
	free(g);
}

/* A system call of the supervisor's own that failed (errno), as
 * "prog: what: why", and what to do when it is a limit. */
static int
sysfail(const graph *g, const char *what, tl_err *e)
{
	int no = errno;

	return tl_fail(e, "%s: %s: %s%s", g->prog, what, strerror(no),
	    no == EAGAIN && strcmp(what, "fork") == 0 ?
	    " (raise the limit of processes, ulimit -u)" : tl_errno_hint(no));
}

static int
own(graph *g, int fd, tl_err *e)
{
	if (g->nfds == MAXFDS) {
		close(fd);
		return tl_fail(e, "%s: too many pipes", g->prog);
	}
	g->fds[g->nfds++] = fd;
	return fd;
}

int
graph_pipe(graph *g, int fd[2], tl_err *e)
{
	if (pipe2(fd, O_CLOEXEC) < 0)
		return sysfail(g, "pipe", e);
	/* 1 MiB, the unprivileged limit: rows of level-0 quadrics (52 bytes
	 * a vertex) pass in a few wake-ups, not one per 64 KiB; the default
	 * stays when refused */
	(void)fcntl(fd[1], F_SETPIPE_SZ, 1 << 20);
	if (own(g, fd[0], e) < 0) {
		close(fd[1]);
		return -1;
	}
	if (own(g, fd[1], e) < 0)
		return -1;
	assert(g->npipes < MAXFDS); /* fewer than the fds owned */
	g->pipes[g->npipes][0] = fd[0], g->pipes[g->npipes++][1] = fd[1];
	return 0;
}

int
graph_open(graph *g, const char *path, int flags, int mode, tl_err *e)
{
	int fd = open(path, flags | O_CLOEXEC, mode);

	if (fd < 0)
		return tl_failsys(e, "%s: %s", g->prog, path);
	return own(g, fd, e);
}

static stage *
add(graph *g, enum kind kind, int in, int out, tl_err *e)
{
	stage *s;

	if (g->n == GRAPH_MAXSTAGES) {
		tl_fail(e, "%s: more than %d stages", g->prog, GRAPH_MAXSTAGES);
		return NULL;
	}
	s = &g->st[g->n++];
	memset(s, 0, sizeof *s);
	s->kind = kind, s->in = in, s->out = out, s->out2 = -1;
	s->err = s->cap = -1;
	return s;
}

int
graph_exec(graph *g, char *const argv[], int in, int out, tl_err *e)
{
	size_t n = 0;
	stage *s;

	while (argv[n] != NULL)
		n++;
	if ((s = add(g, EXEC, in, out, e)) == NULL)
		return -1;
	if ((s->argv = tl_alloc(n + 1, sizeof *s->argv, e)) == NULL)
		return -1;
	for (size_t i = 0; i < n; i++)
		if ((s->argv[i] = strdup(argv[i])) == NULL)
			return tl_failsys(e, "%s", argv[0]);
	return g->n - 1;
}

int
graph_tee(graph *g, int in, int out1, int out2, tl_err *e)
{
	stage *s = add(g, TEE, in, out1, e);

	if (s == NULL)
		return -1;
	s->out2 = out2;
	return g->n - 1;
}

int
graph_capture(graph *g, int k, char *buf, size_t n, tl_err *e)
{
	int fd[2];

	assert(k >= 0 && k < g->n && n > 0);
	if (pipe2(fd, O_CLOEXEC) < 0)
		return sysfail(g, "pipe", e);
	if (own(g, fd[1], e) < 0) {
		close(fd[0]);
		return -1;
	}
	g->st[k].out = fd[1];
	g->st[k].cap = fd[0];
	g->st[k].capbuf = buf, g->st[k].capmax = n - 1;
	buf[0] = '\0';
	return 0;
}

/* The stage writing into the pipe stage k reads, or -1: a reader's
 * failure may be only the end of what a failed writer gave it. */
static int
writer_of(const graph *g, int k)
{
	for (int p = 0; p < g->npipes; p++) {
		if (g->pipes[p][0] != g->st[k].in)
			continue;
		for (int j = 0; j < g->n; j++)
			if (g->st[j].out == g->pipes[p][1] ||
			    g->st[j].out2 == g->pipes[p][1])
				return j;
	}
	return -1;
}

/* --- in the supervisor -------------------------------------------------- */

static int
start(graph *g, stage *s, tl_err *e)
{
	sigset_t all, old;
	int errp[2];

	if (pipe2(errp, O_CLOEXEC) < 0)
		return sysfail(g, "pipe", e);
	/* Signals wait until the child has its default dispositions back:
	 * a SIGTERM for it (its parent's death) must not run the handler
	 * it inherited from us and be lost. */
	sigfillset(&all);
	sigprocmask(SIG_BLOCK, &all, &old);
	if ((s->pid = fork()) < 0) {
		sigprocmask(SIG_SETMASK, &old, NULL);
		close(errp[0]), close(errp[1]);
		return sysfail(g, "fork", e);
	}
	if (s->pid == 0)
		graph_child(g, s, errp[1]);
	sigprocmask(SIG_SETMASK, &old, NULL);
	setpgid(s->pid, s->pid); /* as the child does: no race either way */
	close(errp[1]);
	s->err = errp[0];
	return 0;
}

int
graph_run(graph *g, int *status, tl_err *e)
{
	int st = 1, r = 0;
	tl_err later;

	graph_catch_signals();
	if (g->progress != NULL && pipe2(g->prog_fd, O_CLOEXEC) < 0)
		r = sysfail(g, "pipe", e);
	for (int k = 0; k < g->n; k++)
		g->st[k].up = g->st[k].in >= 0 ? writer_of(g, k) : -1;
	for (int k = 0; k < g->n && r == 0 && !graph_signal(); k++)
		r = start(g, &g->st[k], e);
	close_owned(g); /* the stages hold their ends now */
	if (g->prog_fd[1] >= 0)
		close(g->prog_fd[1]), g->prog_fd[1] = -1;
	if (r < 0) { /* the stages started are stopped; e says why */
		graph_signal_all(g, SIGTERM);
		graph_supervise(g, &st, &later);
		st = 1;
	} else
		r = graph_supervise(g, &st, e);
	for (int k = 0; k < g->n; k++)
		if (g->st[k].capbuf != NULL)
			g->st[k].capbuf[g->st[k].ncap] = '\0';
	if (status != NULL)
		*status = r < 0 ? st : 0;
	return r;
}
