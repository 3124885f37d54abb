/* graph_wait.c - the supervisor watching its stages: their stderr held,
 * progress passed on, exits reaped, the first failure ending the rest,
 * the cause told from its follow-ons (graph_impl.h). */
#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "jobs/graph_impl.h"

/* --- in the supervisor -------------------------------------------------- */

/* Reads what is there on fd into buf (up to max, the rest dropped);
 * closes fd at EOF and sets it to -1. Returns the bytes read. */
static ssize_t
drain(int *fd, char *buf, size_t *n, size_t max)
{
	char tmp[4096];
	ssize_t r = read(*fd, tmp, sizeof tmp);

	if (r < 0 && (errno == EINTR || errno == EAGAIN))
		return 0;
	if (r <= 0) {
		close(*fd);
		*fd = -1;
		return 0;
	}
	size_t k = (size_t)r < max - *n ? (size_t)r : max - *n;
	memcpy(buf + *n, tmp, k);
	*n += k;
	return r;
}

/* Lines "LABEL\tDONE\tTOTAL" from the stages (util.h), each passed on
 * whole; a line longer than the buffer is dropped. */
static void
read_progress(graph *g)
{
	char buf[4096], *tab1, *tab2;
	ssize_t r = read(g->prog_fd[0], buf, sizeof buf);

	if (r < 0 && (errno == EINTR || errno == EAGAIN))
		return;
	if (r <= 0) {
		close(g->prog_fd[0]);
		g->prog_fd[0] = -1;
		return;
	}
	for (ssize_t i = 0; i < r; i++) {
		if (buf[i] != '\n') {
			if (g->npline < sizeof g->pline - 1)
				g->pline[g->npline++] = buf[i];
			continue;
		}
		g->pline[g->npline] = '\0';
		g->npline = 0;
		if ((tab1 = strchr(g->pline, '\t')) == NULL ||
		    (tab2 = strchr(tab1 + 1, '\t')) == NULL)
			continue;
		*tab1 = '\0';
		g->progress(g->progress_ctx, g->pline, atoll(tab1 + 1),
		    atoll(tab2 + 1));
	}
}

/* Waits up to ms for the stages' output. With no pipe left to wait on
 * (a stage has closed its stderr on exiting but is not yet a zombie, the
 * usual moment), it sleeps *nap ms, doubled up to ms at each empty look
 * and set back to 1 when a stage is reaped: a stage that has just ended
 * is seen within a millisecond or two, not 50 later (the four checks
 * before dem2vgis's work waited 0.2 s so), and a long stage without
 * pipes costs a wake-up every ms. */
static void
poll_output(graph *g, int ms, int *nap)
{
	struct pollfd p[2 * GRAPH_MAXSTAGES + 1];
	int who[2 * GRAPH_MAXSTAGES + 1], np = 0;

	for (int k = 0; k < g->n; k++) {
		if (g->st[k].err >= 0)
			p[np] = (struct pollfd){ g->st[k].err, POLLIN, 0 },
			who[np++] = 2 * k;
		if (g->st[k].cap >= 0)
			p[np] = (struct pollfd){ g->st[k].cap, POLLIN, 0 },
			who[np++] = 2 * k + 1;
	}
	if (g->prog_fd[0] >= 0)
		p[np] = (struct pollfd){ g->prog_fd[0], POLLIN, 0 }, who[np++] = -1;
	if (np == 0) {
		if (ms > 0)
			nanosleep(&(struct timespec){ 0, *nap * 1000000L },
			    NULL);
		*nap = *nap * 2 < ms ? *nap * 2 : ms;
		return;
	}
	if (poll(p, np, ms) <= 0)
		return;
	for (int i = 0; i < np; i++) {
		if (!(p[i].revents & (POLLIN | POLLHUP | POLLERR)))
			continue;
		if (who[i] < 0) {
			read_progress(g);
			continue;
		}
		stage *s = &g->st[who[i] / 2];
		if (who[i] & 1)
			drain(&s->cap, s->capbuf, &s->ncap, s->capmax);
		else
			drain(&s->err, s->msg, &s->nmsg, sizeof s->msg - 1);
	}
}

/* Every stage's process group: what a stage started goes with it. */
/* A stage has ended: what it wrote is in its pipes now. Read that and
 * close them, rather than wait for an end of file that a process it
 * started and left behind could hold off. */
static void
finish_output(stage *s)
{
	if (s->err >= 0)
		fcntl(s->err, F_SETFL, O_NONBLOCK);
	if (s->cap >= 0)
		fcntl(s->cap, F_SETFL, O_NONBLOCK);
	while (s->err >= 0 && drain(&s->err, s->msg, &s->nmsg,
	    sizeof s->msg - 1) > 0)
		;
	while (s->cap >= 0 && drain(&s->cap, s->capbuf, &s->ncap,
	    s->capmax) > 0)
		;
	if (s->err >= 0)
		close(s->err), s->err = -1;
	if (s->cap >= 0)
		close(s->cap), s->cap = -1;
}

void
graph_signal_all(graph *g, int sig)
{
	for (int k = 0; k < g->n; k++) /* a group ended and reaped may be */
		if (g->st[k].pid > 0 && !g->st[k].done) /* another's now */
			kill(-g->st[k].pid, sig);
}

static int
failed(const stage *s)
{
	return !WIFEXITED(s->status) || WEXITSTATUS(s->status) != 0;
}

/* 1 when s died of a closed pipe (its reader gone). */
static int
piped(const stage *s)
{
	return (WIFSIGNALED(s->status) && WTERMSIG(s->status) == SIGPIPE) ||
	    (WIFEXITED(s->status) && WEXITSTATUS(s->status) == 128 + SIGPIPE);
}

/* Reaps what has ended; returns how many are still running. */
static int
reap(graph *g, int stopping)
{
	int running = 0;

	for (int k = 0; k < g->n; k++) {
		stage *s = &g->st[k];
		if (s->done)
			continue;
		pid_t r = waitpid(s->pid, &s->status, WNOHANG);
		if (r == 0) {
			running++;
			continue;
		}
		s->done = 1;
		/* follow-ons: a writer whose reader is gone (dead of SIGPIPE,
		 * or a shell saying so, 128 + SIGPIPE), a stage dead of the
		 * signals we sent */
		s->weak = (stopping && WIFSIGNALED(s->status)) || piped(s);
		finish_output(s);
	}
	return running;
}

static long long
now_ms(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return (long long)t.tv_sec * 1000 + t.tv_nsec / 1000000;
}

static void
trim(char *s, size_t *n)
{
	while (*n > 0 && (s[*n - 1] == '\n' || s[*n - 1] == ' '))
		(*n)--;
	s[*n] = '\0';
}

/* Prints the warnings of a stage that ended well, once. */
static void
say_warnings(stage *s)
{
	if (s->done != 1 || failed(s) || s->err >= 0)
		return;
	trim(s->msg, &s->nmsg);
	if (s->nmsg > 0) /* over a progress line on a terminal, not after it */
		fprintf(stderr, "%s%s\n", isatty(2) ? "\r\033[K" : "", s->msg);
	s->done = 2;
}

static int
strong_failure(const stage *s)
{
	return s->done && failed(s) && !s->weak;
}

/* Whether every stage upstream of k (its writer, the writer's writer...)
 * has ended: only then is k's failure known to be its own. */
static int
upstream_ended(const graph *g, int k)
{
	for (int j = g->st[k].up, n = 0; j >= 0; j = g->st[j].up, n++) {
		assert(n < g->n); /* pipes make no cycle */
		if (!g->st[j].done)
			return 0;
	}
	return 1;
}

/* The stage reading the pipe whose write end is fd, or -1. */
static int
reader_of(const graph *g, int fd)
{
	for (int p = 0; p < g->npipes; p++)
		if (g->pipes[p][1] == fd)
			for (int k = 0; k < g->n; k++)
				if (g->st[k].in == g->pipes[p][0])
					return k;
	return -1;
}

/* c may have failed on short input because a tee upstream of it died of
 * a closed pipe: its other reader ended first. The tee tells which
 * (graph_child.c: killed by SIGPIPE for its first output, exit 141 for
 * its second); that reader's own failure, where it has one, is the
 * cause (reaped in the same look, or on a loaded machine, c can come
 * first: dem2vgis's processes told fqmfilter's "truncated" for
 * fqmsolve's "File too large"). */
static int
sibling_cause(const graph *g, const int *order, int nfail, int c)
{
	for (int j = g->st[c].up; j >= 0; j = g->st[j].up) {
		const stage *t = &g->st[j];
		if (t->kind != TEE || !t->done || !piped(t))
			continue;
		int x = reader_of(g, WIFSIGNALED(t->status) ? t->out : t->out2);
		for (int i = 0; x >= 0 && x != c && i < nfail; i++)
			if (order[i] == x && !g->st[x].weak)
				return x;
		return c;
	}
	return c;
}

/* The failure to report: the first that is not a follow-on (a stage
 * stopped by us, or by a closed pipe, or a tee's reader cut short by
 * the other reader's failure), else the first; and of that, the
 * failure furthest upstream, whose end a reader saw as short input. */
static const stage *
root_cause(const graph *g, const int *order, int nfail)
{
	int c = nfail > 0 ? order[0] : -1;

	for (int i = 0; i < nfail; i++)
		if (!g->st[order[i]].weak) {
			c = sibling_cause(g, order, nfail, order[i]);
			break;
		}
	if (c >= 0 && !g->st[c].weak)
		for (int j = g->st[c].up; j >= 0; j = g->st[j].up)
			if (strong_failure(&g->st[j]))
				c = j;
	return c >= 0 ? &g->st[c] : NULL;
}

static void
describe(const stage *s, const char *prog, tl_err *e)
{
	const char *name = s->kind == TEE ? "tee" : s->argv[0];
	char *m = (char *)s->msg;
	size_t n = s->nmsg;

	trim(m, &n);
	if (n > 0) { /* the end, where a failure's message is */
		size_t k = n < sizeof e->msg ? n : sizeof e->msg - 1;
		memcpy(e->msg, m + n - k, k);
		e->msg[k] = '\0';
	}
	else if (WIFSIGNALED(s->status))
		snprintf(e->msg, sizeof e->msg, "%s: %s: killed by signal %d "
		    "(%s)", prog, name, WTERMSIG(s->status),
		    strsignal(WTERMSIG(s->status)));
	else
		snprintf(e->msg, sizeof e->msg, "%s: %s: exit status %d",
		    prog, name, WEXITSTATUS(s->status));
}

/* Waits for every stage; the first failure or a signal stops the rest. */
int
graph_supervise(graph *g, int *status, tl_err *e)
{
	int order[GRAPH_MAXSTAGES], nfail = 0, stopping = 0;
	int running, cause, nap = 1, was = g->n + 1;
	long long deadline = 0, first_fail = 0;

	for (;;) {
		poll_output(g, 50, &nap);
		running = reap(g, stopping);
		if (running < was)
			nap = 1, was = running;
		cause = 0;
		for (int k = 0; k < g->n; k++) {
			stage *s = &g->st[k];
			if (s->done == 1 && failed(s) && s->err < 0) {
				order[nfail++] = k;
				first_fail = first_fail ? first_fail : now_ms();
				s->done = 2;
			}
			cause |= s->done == 2 && strong_failure(s) &&
			    upstream_ended(g, k);
			say_warnings(s);
		}
		/* A follow-on alone waits a little for its cause: a writer dead
		 * of SIGPIPE for the reader that closed the pipe (which closes
		 * its files before it can be reaped), a reader that saw short
		 * input for the writer still ending upstream of it. */
		if (!stopping && (cause || graph_signal() ||
		    (nfail > 0 && now_ms() - first_fail > 500))) {
			stopping = 1, deadline = now_ms() + 1000;
			graph_signal_all(g, SIGTERM);
		}
		if (stopping && deadline > 0 && now_ms() > deadline) {
			graph_signal_all(g, SIGKILL);
			deadline = 0;
		}
		int open = g->prog_fd[0] >= 0;
		for (int k = 0; k < g->n; k++)
			open += g->st[k].err >= 0 || g->st[k].cap >= 0;
		if (running == 0 && open == 0)
			break;
	}
	if (graph_signal()) {
		*status = 128 + graph_signal();
		return tl_fail(e, "%s: stopped by signal %d", g->prog,
		    (int)graph_signal());
	}
	const stage *s = root_cause(g, order, nfail);
	if (s == NULL)
		return 0;
	describe(s, g->prog, e);
	*status = WIFEXITED(s->status) ? WEXITSTATUS(s->status) : 1;
	return -1;
}
