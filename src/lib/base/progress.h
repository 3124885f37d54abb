/* progress.h - one progress line on a terminal, or machine-readable
 * progress for a supervisor (dem2vgis). */
#ifndef TL_PROGRESS_H
#define TL_PROGRESS_H

/* Progress of a long loop, in one of two ways:
 * - for a supervisor (dem2vgis): when the environment has TL_PROGRESS_FD=n
 *   and n is an open descriptor writable by this process, one line
 *   "LABEL\tDONE\tTOTAL\n" goes to n each time the percentage changes
 *   and one (DONE = TOTAL) at the end, and nothing is drawn. Each line is
 *   a single write(2) shorter than PIPE_BUF (the label is cut to 200
 *   bytes, its tabs and newlines made spaces), so the lines of many
 *   processes sharing one pipe never interleave. An n that is not a
 *   number or not open for writing is ignored silently (the terminal rule
 *   then holds); a failed write ends the reports, never the work.
 * - otherwise a line "LABEL: NN%" drawn on stderr, only when stderr is a
 *   terminal.
 * Setting on to 0 after tl_progress_start silences both. */
typedef struct {
	const char *label;
	long long total, done;
	int on, last; /* last percentage drawn or reported */
	int fd;       /* TL_PROGRESS_FD, -1: the terminal, -2: the sink */
} tl_progress;

void tl_progress_start(tl_progress *p, const char *label, long long total);
/* A third way, for a supervisor whose stages are threads of its own
 * (dem2vgis): while a sink is set, the progresses started from then on
 * report to fn (from any thread: fn must be thread-safe) as they would
 * on TL_PROGRESS_FD, and draw nothing. NULL unsets it; set and unset it
 * while no other thread starts one. */
typedef void (*tl_progress_fn)(void *ctx, const char *label,
    long long done, long long total);
void tl_progress_sink(tl_progress_fn fn, void *ctx);
void tl_progress_step(tl_progress *p, long long done);
void tl_progress_end(tl_progress *p);

#endif
