/* graph.c - the supervisor of a process graph (graph.h). */
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

#include "jobs/graph.h"

#define MAXFDS (4 * GRAPH_MAXSTAGES)
#define ERRMAX 8192 /* stderr kept per stage: its message and warnings */

enum kind { EXEC, TEE };

typedef struct {
	enum kind kind;
	char **argv;        /* EXEC: a copy */
	int in, out, out2;  /* fds the graph owns; -1: /dev/null */
	pid_t pid;
	int err;            /* read end of its stderr pipe, -1 at EOF */
	char msg[ERRMAX];   /* what it said on stderr (truncated) */
	size_t nmsg;
	int cap;            /* read end of a captured stdout, or -1 */
	char *capbuf;
	size_t ncap, capmax;
	int done, status;   /* waitpid status once done */
	int weak;           /* a follow-on failure: SIGPIPE, or stopped */
} stage;

struct graph {
	const char *prog, *bindir;
	int fds[MAXFDS], nfds;
	stage st[GRAPH_MAXSTAGES];
	int n;
	pid_t self;
	graph_progress_fn progress;  /* or NULL */
	void *progress_ctx;
	int prog_fd[2];              /* the stages' progress pipe, or -1 */
	char pline[512];             /* a progress line being read */
	size_t npline;
};

/* The fd a stage reports progress on (TL_PROGRESS_FD). */
#define PROGRESS_FD 3

/* The one piece of process state: the signal that asks the supervisor to
 * stop, set by its handler (a handler can reach nothing else). */
static volatile sig_atomic_t stop_signal;

static void
on_signal(int sig)
{
	stop_signal = sig;
}

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
		return tl_failsys(e, "pipe");
	if (own(g, fd[0], e) < 0) {
		close(fd[1]);
		return -1;
	}
	return own(g, fd[1], e) < 0 ? -1 : 0;
}

int
graph_open(graph *g, const char *path, int flags, int mode, tl_err *e)
{
	int fd = open(path, flags | O_CLOEXEC, mode);

	if (fd < 0)
		return tl_failsys(e, "%s", path);
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
		return tl_failsys(e, "pipe");
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

/* --- in the child ------------------------------------------------------ */

static int
write_all(int fd, const char *p, size_t n)
{
	while (n > 0) {
		ssize_t w = write(fd, p, n);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0)
			return -1;
		p += w, n -= (size_t)w;
	}
	return 0;
}

/* tee: a closed reader means the graph is failing anyway: a follow-on,
 * said by dying as a writer to a closed pipe does. */
static void
tee_loop(void)
{
	static char buf[1 << 17];
	ssize_t r;

	while ((r = read(0, buf, sizeof buf)) != 0) {
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			dprintf(2, "tee: %s\n", strerror(errno));
			_exit(1);
		}
		if (write_all(1, buf, (size_t)r) < 0 ||
		    write_all(3, buf, (size_t)r) < 0)
			raise(SIGPIPE), _exit(141);
	}
	_exit(0);
}

static void
exec_stage(const graph *g, const stage *s)
{
	char path[4096];

	if (g->bindir != NULL && strchr(s->argv[0], '/') == NULL &&
	    snprintf(path, sizeof path, "%s/%s", g->bindir, s->argv[0]) <
	    (int)sizeof path && access(path, X_OK) == 0)
		execv(path, s->argv);
	execvp(s->argv[0], s->argv);
	dprintf(2, "%s: %s: %s\n", g->prog, s->argv[0], strerror(errno));
	_exit(127);
}

/* fd to target, or /dev/null when fd is -1. */
static int
place(int fd, int target, int flags)
{
	if (fd < 0 && (fd = open("/dev/null", flags)) < 0)
		return -1;
	if (fd == target) /* dup2 would keep its close-on-exec */
		return fcntl(fd, F_SETFD, 0);
	return dup2(fd, target) < 0 ? -1 : 0;
}

static void
child(const graph *g, const stage *s, int errw)
{
	sigset_t none;

	/* dies with the supervisor, even by SIGKILL: SIGTERM lets the stage
	 * remove its temporaries; a group of its own, so that stopping it
	 * stops whatever it started too */
	if (prctl(PR_SET_PDEATHSIG, SIGTERM) < 0 || getppid() != g->self ||
	    setpgid(0, 0) < 0)
		_exit(1);
	if (dup2(errw, 2) < 0 || place(s->in, 0, O_RDONLY) < 0 ||
	    place(s->out, 1, O_WRONLY) < 0 ||
	    (s->kind == TEE && place(s->out2, 3, O_WRONLY) < 0))
		_exit(1);
	if (s->kind == EXEC && g->prog_fd[1] >= 0) {
		if (place(g->prog_fd[1], PROGRESS_FD, O_WRONLY) < 0)
			_exit(1);
		setenv("TL_PROGRESS_FD", "3", 1);
	} else
		unsetenv("TL_PROGRESS_FD"); /* not the supervisor's own */
	close_range(s->kind == TEE || g->prog_fd[1] >= 0 ? 4 : 3, ~0U, 0);
	for (int sig = 1; sig < NSIG; sig++)
		signal(sig, SIG_DFL);
	sigemptyset(&none);
	sigprocmask(SIG_SETMASK, &none, NULL);
	if (s->kind == TEE)
		tee_loop();
	exec_stage(g, s);
}

/* --- in the supervisor -------------------------------------------------- */

static int
start(graph *g, stage *s, tl_err *e)
{
	int errp[2];

	if (pipe2(errp, O_CLOEXEC) < 0)
		return tl_failsys(e, "pipe");
	if ((s->pid = fork()) < 0) {
		close(errp[0]), close(errp[1]);
		return tl_failsys(e, "fork");
	}
	if (s->pid == 0)
		child(g, s, errp[1]);
	setpgid(s->pid, s->pid); /* as the child does: no race either way */
	close(errp[1]);
	s->err = errp[0];
	return 0;
}

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

static void
poll_output(graph *g, int ms)
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
			nanosleep(&(struct timespec){ 0, ms * 1000000L }, NULL);
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

static void
signal_all(graph *g, int sig)
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
		/* a writer whose reader is gone: dead of SIGPIPE, or a shell
		 * saying so (128 + SIGPIPE) */
		s->weak = stopping || (WIFSIGNALED(s->status) &&
		    WTERMSIG(s->status) == SIGPIPE) || (WIFEXITED(s->status) &&
		    WEXITSTATUS(s->status) == 128 + SIGPIPE);
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

/* The failure to report: the first that is not a follow-on (a stage
 * stopped by us, or by a closed pipe), else the first. */
static const stage *
root_cause(const graph *g, const int *order, int nfail)
{
	for (int i = 0; i < nfail; i++)
		if (!g->st[order[i]].weak)
			return &g->st[order[i]];
	return nfail > 0 ? &g->st[order[0]] : NULL;
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
static int
supervise(graph *g, int *status, tl_err *e)
{
	int order[GRAPH_MAXSTAGES], nfail = 0, stopping = 0, running;
	long long deadline = 0;

	for (;;) {
		poll_output(g, 50);
		running = reap(g, stopping);
		for (int k = 0; k < g->n; k++) {
			stage *s = &g->st[k];
			if (s->done == 1 && failed(s) && s->err < 0) {
				order[nfail++] = k;
				s->done = 2;
			}
			say_warnings(s);
		}
		if (!stopping && (nfail > 0 || stop_signal)) {
			stopping = 1, deadline = now_ms() + 1000;
			signal_all(g, SIGTERM);
		}
		if (stopping && deadline > 0 && now_ms() > deadline) {
			signal_all(g, SIGKILL);
			deadline = 0;
		}
		int open = g->prog_fd[0] >= 0;
		for (int k = 0; k < g->n; k++)
			open += g->st[k].err >= 0 || g->st[k].cap >= 0;
		if (running == 0 && open == 0)
			break;
	}
	if (stop_signal) {
		*status = 128 + stop_signal;
		return tl_fail(e, "%s: stopped by signal %d", g->prog,
		    (int)stop_signal);
	}
	const stage *s = root_cause(g, order, nfail);
	if (s == NULL)
		return 0;
	describe(s, g->prog, e);
	*status = WIFEXITED(s->status) ? WEXITSTATUS(s->status) : 1;
	return -1;
}

int
graph_run(graph *g, int *status, tl_err *e)
{
	struct sigaction sa = { .sa_handler = on_signal };
	const int sigs[3] = { SIGINT, SIGTERM, SIGHUP };
	int st = 1, r = 0;
	tl_err later;

	/* installed for good: a signal between two graphs must still stop
	 * the next one and reach the caller */
	sigemptyset(&sa.sa_mask);
	for (int i = 0; i < 3; i++)
		sigaction(sigs[i], &sa, NULL);
	if (g->progress != NULL && pipe2(g->prog_fd, O_CLOEXEC) < 0)
		r = tl_failsys(e, "pipe");
	for (int k = 0; k < g->n && r == 0 && !stop_signal; k++)
		r = start(g, &g->st[k], e);
	close_owned(g); /* the stages hold their ends now */
	if (g->prog_fd[1] >= 0)
		close(g->prog_fd[1]), g->prog_fd[1] = -1;
	if (r < 0) { /* the stages started are stopped; e says why */
		signal_all(g, SIGTERM);
		supervise(g, &st, &later);
		st = 1;
	} else
		r = supervise(g, &st, e);
	for (int k = 0; k < g->n; k++)
		if (g->st[k].capbuf != NULL)
			g->st[k].capbuf[g->st[k].ncap] = '\0';
	if (status != NULL)
		*status = r < 0 ? st : 0;
	return r;
}

int
graph_signal(void)
{
	return stop_signal;
}
