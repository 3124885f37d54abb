/* pipeline_inproc.c - a run's stages as threads of this process
 * (pipeline.h, o->work; inproc.h): the quadric chain with rings for its
 * pipes and tees, each level's vertex map the stream into the scratch
 * file the processes' route writes, then tilepack's work over them,
 * the DEM converted once for both (pipeline_work's open). */
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
	return j->w->pack(j->w->ctx, j->path, j->out, j->vmaps, j->n, e);
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

int
pipeline_inproc(const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, scratch *s, meter *m, int *status, tl_err *e)
{
	char *vm[MAXLEVELS];
	job jobs[1 + 2 * MAXLEVELS], pj;
	inproc *p;
	int r = -1;

	*status = 1;
	tl_progress_sink(progress, m);
	/* the DEM converted once, for the chain and tilepack's work */
	if (o->work->open != NULL)
		o->work->open(o->work->ctx, dem);
	if ((p = inproc_new(o->prog, e)) != NULL &&
	    chain(p, o, dem, levels, vpath, jobs, e) == 0)
		r = inproc_run(p, 1, s, status, e);
	inproc_free(p);
	/* the chain's threads' heaps back to the system before tilepack's
	 * (glibc keeps an arena a thread: tens of MiB otherwise held) */
	malloc_trim(0);
	if (r == 0 && (p = inproc_new(o->prog, e)) != NULL) {
		for (int l = 0; l < levels; l++)
			vm[l] = vpath[l];
		pj = (job){ .w = o->work, .path = dem, .out = o->out,
		    .vmaps = vm, .n = levels };
		r = inproc_task(p, pack, &pj, NULL, 0, NULL, -1, e) < 0 ? -1 :
		    inproc_run(p, 0, s, status, e);
		inproc_free(p);
	} else if (r == 0)
		r = -1;
	if (o->work->close != NULL)
		o->work->close(o->work->ctx);
	tl_progress_sink(NULL, NULL);
	return r;
}
