/* pipeline_inproc.c - a run's stages as threads of this process
 * (pipeline.h, o->work; inproc.h): the quadric chain with rings for its
 * pipes and tees, each level's vertex map the stream into the scratch
 * file the processes' route writes, and tilepack's work over them, the
 * DEM converted once for both (pipeline_work's open). tilepack's work
 * runs beside the chain: level 0, whose vertex map is known (the DEM's
 * heights), from the start, the other levels once the chain has ended;
 * after it only when the DEM was not converted beforehand. */
#include <fcntl.h>
#include <malloc.h>
#include <pthread.h>
#include <stdlib.h>
#include <sys/prctl.h>
#include <unistd.h>

#include "jobs/inproc.h"
#include "jobs/pipeline_impl.h"

/* What a task is given: the work, and a path (its DEM or output). */
typedef struct {
	const pipeline_work *w;
	const char *path, *out;
	char *const *vmaps;
	int n;
	const pipeline_gate *g;
} job;

/* The thread named after the program whose work it does (the threads it
 * starts inherit the name): per-stage CPU in top -H, ps -L and
 * scripts/peakrss, as the processes' route has it per process. */
static void
named(const char *prog)
{
	prctl(PR_SET_NAME, prog, 0, 0, 0);
}

static int
level0(void *arg, tl_err *e)
{
	job *j = arg;

	named("dem2fqm");
	return j->w->level0(j->w->ctx, j->path, e);
}

static int
filter(void *arg, tl_err *e)
{
	job *j = arg;

	named("fqmfilter");
	return j->w->filter(j->w->ctx, e);
}

static int
solve(void *arg, tl_err *e)
{
	job *j = arg;

	named("fqmsolve");
	return j->w->solve(j->w->ctx, "-", e);
}

static int
pack(void *arg, tl_err *e)
{
	job *j = arg;

	named("tilepack");
	return j->w->pack(j->w->ctx, j->path, j->out, j->vmaps, j->n, j->g, e);
}

/* The gate tilepack's work waits at beside the chain: the chain's tasks
 * are the first n of p. */
typedef struct {
	inproc *p;
	int n;
	int trimmed;
} gate;

static int
gate_ended(void *ctx, int ms)
{
	gate *g = ctx;
	int r = inproc_ended(g->p, g->n, ms);

	/* the chain's heaps back to the system before the levels it made
	 * are packed (glibc keeps an arena a thread: tens of MiB otherwise
	 * held) */
	if (r == 0 && !g->trimmed)
		malloc_trim(0), g->trimmed = 1;
	return r;
}

static int
gate_stopped(void *ctx)
{
	return inproc_stopped(((gate *)ctx)->p);
}

/* dem2fqm into level 0's ring; level l's ring read by its solver
 * (reader 0) and, below the top, by the filter making level l+1's
 * (reader 1): the tees of pipeline_quadrics. */
static int
chain(inproc *p, const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, job *jobs, tl_err *e)
{
	rs_ring *up = inproc_ring(p, levels > 1 ? 2 : 1, e), *next;
	int v;

	jobs[0] = (job){ .w = o->work, .path = dem };
	if (up == NULL || inproc_task(p, level0, &jobs[0], NULL, 0, up, -1, e) < 0)
		return -1;
	for (int l = 0; l < levels; l++) {
		job *js = &jobs[1 + 2 * l], *jf = js + 1;
		/* the vertex map as the processes' route has it: fqmsolve's
		 * stdout, the stream, into the scratch file */
		*js = (job){ .w = o->work };
		if ((v = open(vpath[l], O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC,
		    0600)) < 0)
			return tl_failsys(e, "%s: %s", o->prog, vpath[l]);
		if (inproc_task(p, solve, js, up, 0, NULL, v, e) < 0) {
			close(v);
			return -1;
		}
		if (l == levels - 1)
			break;
		*jf = (job){ .w = o->work };
		next = inproc_ring(p, l + 1 < levels - 1 ? 2 : 1, e);
		if (next == NULL ||
		    inproc_task(p, filter, jf, up, 1, next, -1, e) < 0)
			return -1;
		up = next;
	}
	return 0;
}

/* The stages' progress, from their threads, into the one line. */
static pthread_mutex_t meter_lock = PTHREAD_MUTEX_INITIALIZER;

static void
progress(void *m, const char *label, long long done, long long total)
{
	pthread_mutex_lock(&meter_lock);
	pipeline_progress(m, label, done, total);
	pthread_mutex_unlock(&meter_lock);
}

/* tilepack's work as a task of p (g: beside the chain, or NULL). */
static int
pack_task(inproc *p, const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, char **vm, const pipeline_gate *g, job *pj, tl_err *e)
{
	for (int l = 0; l < levels; l++)
		vm[l] = vpath[l];
	*pj = (job){ .w = o->work, .path = dem, .out = o->out, .vmaps = vm,
	    .n = levels, .g = g };
	return inproc_task(p, pack, pj, NULL, 0, NULL, -1, e);
}

int
pipeline_inproc(const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, scratch *s, meter *m, int *status, tl_err *e)
{
	char *vm[MAXLEVELS];
	job jobs[1 + 2 * MAXLEVELS], pj;
	inproc *p;
	gate gt;
	pipeline_gate pg = { &gt, gate_ended, gate_stopped };
	int r = -1, beside = 0;

	*status = 1;
	tl_progress_sink(progress, m);
	/* the DEM converted once, for the chain and tilepack's work */
	if (o->work->open != NULL)
		beside = o->work->open(o->work->ctx, dem);
	/* beside the chain, tilepack's work is not held by a ring: the run
	 * cannot be stopped by a cancel, a signal ends it at once (inproc.h),
	 * and the work itself polls for the chain's failure */
	if ((p = inproc_new(o->prog, e)) != NULL &&
	    chain(p, o, dem, levels, vpath, jobs, e) == 0) {
		gt = (gate){ .p = p, .n = 2 * levels };
		if (!beside || pack_task(p, o, dem, levels, vpath, vm, &pg, &pj,
		    e) == 0)
			r = inproc_run(p, !beside, s, status, e);
	}
	inproc_free(p);
	/* the threads' heaps back to the system (glibc keeps an arena a
	 * thread: tens of MiB otherwise held) */
	malloc_trim(0);
	if (r == 0 && !beside && (p = inproc_new(o->prog, e)) != NULL) {
		r = pack_task(p, o, dem, levels, vpath, vm, NULL, &pj, e) < 0 ?
		    -1 : inproc_run(p, 0, s, status, e);
		inproc_free(p);
	} else if (r == 0 && !beside)
		r = -1;
	if (o->work->close != NULL)
		o->work->close(o->work->ctx);
	tl_progress_sink(NULL, NULL);
	return r;
}
