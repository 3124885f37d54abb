/* graph_impl.h - the supervisor's insides, shared by graph.c (building
 * and running a graph), graph_child.c (a stage's side of the fork),
 * graph_wait.c (watching the stages) and graph_signal.c (the stop
 * signal). */
#ifndef TL_GRAPH_IMPL_H
#define TL_GRAPH_IMPL_H

#include <stddef.h>
#include <sys/types.h>

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
	int up;             /* the stage writing its stdin, or -1 */
} stage;

struct graph {
	const char *prog, *bindir;
	int fds[MAXFDS], nfds;
	int pipes[MAXFDS][2], npipes; /* every graph_pipe: who feeds whom */
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

/* In the child, after fork: never returns. */
void graph_child(const graph *g, const stage *s, int errw)
    __attribute__((noreturn));
/* Waits for every stage; the first failure or a signal stops the rest
 * (graph_run's contract). */
int graph_supervise(graph *g, int *status, tl_err *e);
/* Sends sig to every stage still running, and what it started. */
void graph_signal_all(graph *g, int sig);
/* graph_signal.c: INT, TERM and HUP caught from now on, for good, each
 * recorded for graph_signal. */
void graph_catch_signals(void);

#endif
