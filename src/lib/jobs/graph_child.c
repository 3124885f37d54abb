/* graph_child.c - a stage's side of the fork: its pipes in place, dying
 * with the supervisor, then the program, or the tee (graph_impl.h). */
#define _GNU_SOURCE /* close_range */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "jobs/graph_impl.h"

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

/* The tee's first output closed: it dies of SIGPIPE, as a writer to a
 * closed pipe does; its second: exit 141. SIGPIPE is ignored while it
 * copies (tee_loop), so that the kernel's does not say which. */
static void __attribute__((noreturn))
first_closed(void)
{
	signal(SIGPIPE, SIG_DFL);
	raise(SIGPIPE);
	_exit(141);
}

/* The copying tee, for outputs that are not both pipes (/dev/null). */
static void __attribute__((noreturn))
tee_copy(void)
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
		if (write_all(1, buf, (size_t)r) < 0)
			first_closed();
		if (write_all(3, buf, (size_t)r) < 0)
			_exit(141); /* the second output: see tee_loop */
	}
	_exit(0);
}

/* tee: the kernel duplicates the pipe's pages into the first output
 * (tee(2)) and moves them to the second (splice(2)), never copying the
 * level-0 quadrics through user space. A closed reader means the graph
 * is failing anyway: a follow-on, said by dying as a writer to a closed
 * pipe does. */
static void __attribute__((noreturn))
tee_loop(void)
{
	struct stat a, b, c;

	signal(SIGPIPE, SIG_IGN); /* EPIPE: which output, first_closed */
	if (fstat(0, &a) < 0 || fstat(1, &b) < 0 || fstat(3, &c) < 0 ||
	    !S_ISFIFO(a.st_mode) || !S_ISFIFO(b.st_mode) ||
	    !S_ISFIFO(c.st_mode))
		tee_copy();
	for (;;) {
		ssize_t n = tee(0, 1, (size_t)1 << 30, 0), m;
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0 && errno == EPIPE)
			first_closed();
		if (n < 0) {
			dprintf(2, "tee: %s\n", strerror(errno));
			_exit(1);
		}
		if (n == 0)
			_exit(0);
		while (n > 0) { /* exactly what went to the first */
			m = splice(0, NULL, 3, NULL, (size_t)n, 0);
			if (m < 0 && errno == EINTR)
				continue;
			if (m <= 0) /* the second output closed: exit 141,
			             * where the first's is SIGPIPE itself, so
			             * the supervisor knows which reader left
			             * first (graph_wait.c, sibling_cause) */
				_exit(141);
			n -= m;
		}
	}
}

static void __attribute__((noreturn))
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

/* The stage could not get its descriptors in place (too few left): said,
 * on the supervisor's pipe when it got there, as an exec failure is. */
static void __attribute__((noreturn))
setup_failed(const graph *g, const stage *s)
{
	int saved = errno;

	dprintf(2, "%s: %s: %s%s\n", g->prog, s->kind == TEE ? "tee" :
	    s->argv[0], strerror(saved), tl_errno_hint(saved));
	_exit(1);
}

void
graph_child(const graph *g, const stage *s, int errw)
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
		setup_failed(g, s);
	if (s->kind == EXEC && g->prog_fd[1] >= 0) {
		if (place(g->prog_fd[1], PROGRESS_FD, O_WRONLY) < 0)
			setup_failed(g, s);
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
