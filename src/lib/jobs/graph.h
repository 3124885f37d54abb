/* graph.h - a supervised graph of processes joined by pipes: the stages of
 * a build (dem2fqm | fqmfilter ..., one fqmsolve per level, tilepack).
 *
 * The supervisor owns every stage. The first stage that fails ends all the
 * others (SIGTERM, SIGKILL a second later) and only its message is
 * printed: each stage's stderr is held until it ends, so follow-on errors
 * of the stages it takes down are never shown. A stage dies with its
 * supervisor, whatever kills the supervisor (PR_SET_PDEATHSIG: SIGTERM, so
 * that it still removes its temporary outputs). A signal to the supervisor
 * (INT, TERM, HUP) stops every stage the same way before it dies. */
#ifndef TL_GRAPH_H
#define TL_GRAPH_H

#include "base/util.h"

#define GRAPH_MAXSTAGES 96

typedef struct graph graph;

/* prog names the supervisor in its own messages; bindir, when not NULL,
 * is searched before PATH for the stages' programs. */
graph *graph_new(const char *prog, const char *bindir, tl_err *e);
void graph_free(graph *g);

/* A pipe whose ends the graph owns: fd[0] read, fd[1] write. Every end
 * is closed in the supervisor once the stages are started. */
int graph_pipe(graph *g, int fd[2], tl_err *e);
/* A file opened for the graph (the same ownership), e.g. a stage's
 * output: open(2) flags and mode. -1 on failure. */
int graph_open(graph *g, const char *path, int flags, int mode, tl_err *e);

/* A stage running argv (argv[0] a program name), stdin from fd in,
 * stdout to fd out (-1: /dev/null). argv is copied. Returns the stage's
 * index or -1. */
int graph_exec(graph *g, char *const argv[], int in, int out, tl_err *e);
/* A stage copying in to both out1 and out2 (tee without a program). */
int graph_tee(graph *g, int in, int out1, int out2, tl_err *e);
/* Keep stage k's stdout: its first n-1 bytes go to buf, NUL-ended, when
 * the graph has run (for a stage like "dem2fqm -I"). */
int graph_capture(graph *g, int k, char *buf, size_t n, tl_err *e);

/* Progress of the stages: each EXEC stage gets TL_PROGRESS_FD (util.h)
 * and fn is called with every line it reports ("LABEL", done, total), in
 * the supervisor, as they come. */
typedef void (*graph_progress_fn)(void *ctx, const char *label,
    long long done, long long total);
void graph_progress(graph *g, graph_progress_fn fn, void *ctx);

/* Starts every stage and waits for all. Returns 0 when all exit 0.
 * Otherwise -1 and e holds the failing stage's message (its stderr, or
 * how it died); *status (if not NULL) is its exit status (2 for a usage
 * error), or 128+n for a signal to the supervisor. Warnings of stages
 * that succeed are printed on stderr as they end; the failure's message
 * is the stage's own words, for the caller to print as they are. */
int graph_run(graph *g, int *status, tl_err *e);

/* The signal (INT, TERM, HUP) that has asked the supervisor to stop, or
 * 0. From the first graph_run on, such a signal no longer kills the
 * process: it stops the graph running and every later one, and the
 * caller cleans up and dies of it. */
int graph_signal(void);

#endif
