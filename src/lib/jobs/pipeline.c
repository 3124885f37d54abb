/* pipeline.c - DEM to pyramid as supervised stages (pipeline.h): the
 * front door, which guards the outputs, checks the options, and runs the
 * input, the chain and tilepack, or writes the plan (pipeline_impl.h). */
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/paths.h"
#include "jobs/inproc.h"
#include "jobs/pipeline_impl.h"

/* The options passed on, tried before any work: each stage on no input. */
static int
precheck(const pipeline_opts *o, int *status, tl_err *e)
{
	words a = { 0 };

	say(&a, "fqmsolve"), say(&a, "-m"), say(&a, o->mode);
	if (o->cut != NULL)
		say(&a, "-r"), say(&a, o->cut);
	say(&a, "-"), say(&a, "-");
	if (pipeline_alone(o, &a, -1, 0, NULL, 0, status, e) < 0)
		return -1;
	a.n = 0;
	say(&a, "fqmfilter"), say(&a, "-k"), say(&a, o->kernel);
	say(&a, "-"), say(&a, "-");
	return pipeline_alone(o, &a, -1, 0, NULL, 0, status, e);
}

/* The DEM as the stages read it, then the run, -M or the plan. */
static int
stages(const pipeline_opts *o, scratch *s, vpath_t *vpath,
    int *status, tl_err *e)
{
	char spool[PATHMAX];
	const char *dem = o->dem;
	meter m = { 0 };
	int levels, w, h, r;

	*status = 1;
	if (o->ndem > 1) {
		if (pipeline_write_list(o, s->path, spool, sizeof spool, e) < 0)
			return pipeline_ours(o, e);
		dem = spool;
	} else if (strcmp(dem, "-") == 0) {
		if (pipeline_spool_stdin(o, s, spool, sizeof spool, e) < 0)
			return pipeline_ours(o, e);
		dem = spool;
	} else if (access(dem, F_OK) < 0)
		return tl_failsys(e, "%s: %s", o->prog, dem);
	if (pipeline_level_count(o, dem, &levels, &w, &h, status, e) < 0)
		return -1;
	if (o->plan != NULL)
		return pipeline_plan(o, dem, s, levels, w, h, status, e);
	if (o->vmaps)
		return pipeline_vmaps_only(o, dem, levels, w, vpath, &m, status,
		    e);
	for (int l = 0; l < levels; l++)
		snprintf(vpath[l], sizeof vpath[l], "%s/v%d.fqm", s->path, l);
	tl_progress_start(&m.bar, o->prog, 1000);
	if (o->work != NULL)
		r = pipeline_inproc(o, dem, levels, vpath, s, &m, status, e);
	else if ((r = pipeline_quadrics(o, dem, 0, levels, w, vpath, NULL,
	    &m, status, e)) == 0)
		r = pipeline_pack(o, dem, levels, vpath, &m, status, e);
	if (r == 0)
		tl_progress_end(&m.bar);
	else if (m.bar.on && m.bar.last >= 0)
		fputs("\r\033[K", stderr); /* the message goes where it was */
	return r;
}

/* The outputs (OUT, the plan) kept off the inputs given here and off
 * each other, before any work (paths.h); level_count has the reader
 * check what the DEM is read from. */
static int
guard(const pipeline_opts *o, tl_err *e)
{
	const char *plan = o->plan;
	char *const *dem = o->ndem > 1 ? o->dems : (char *const *)&o->dem;
	tl_paths s = { 0 };
	int r = 0;

	for (int k = 0; r == 0 && k < (o->ndem > 1 ? o->ndem : 1); k++)
		r = tl_paths_add(&s, dem[k], 0, e, "the input DEM %s", dem[k]);
	if (r == 0 && o->fill != NULL)
		r = tl_paths_add(&s, o->fill, 0, e, "the input filled DEM %s",
		    o->fill);
	if (r == 0 && o->from != NULL)
		r = tl_paths_add_raster(&s, o->from, "FQM", e);
	if (r == 0)
		r = tl_paths_check(&s, o->out, e);
	if (r == 0 && plan != NULL && (r = tl_paths_check(&s, plan, e)) == 0)
		r = tl_paths_add(&s, o->out, TL_PATH_OUT, e, "the output "
		    "directory %s", o->out);
	if (r == 0 && plan != NULL)
		r = tl_paths_check(&s, plan, e);
	tl_paths_free(&s);
	return r < 0 ? pipeline_ours(o, e) : 0;
}

/* A relative name beginning with '-' would be an option to the stages
 * it is given to: "./" before it. */
static const char *
undashed(const char *p, char *buf, size_t n)
{
	if (p[0] != '-' || p[1] == '\0' || (size_t)snprintf(buf, n, "./%s",
	    p) >= n)
		return p;
	return buf;
}

/* The run: options checked, the scratch, the stages. */
static int
run(const pipeline_opts *o, int *status, tl_err *e)
{
	vpath_t *vpath;
	scratch s;
	int r;

	*status = 1;
	if (guard(o, e) < 0 || precheck(o, status, e) < 0)
		return -1;
	*status = 1;
	if ((vpath = tl_alloc(MAXLEVELS, sizeof *vpath, e)) == NULL)
		return pipeline_ours(o, e);
	if (scratch_begin(&s, o->prog, e) < 0) {
		free(vpath);
		return pipeline_ours(o, e);
	}
	r = stages(o, &s, vpath, status, e);
	scratch_end(&s);
	free(vpath);
	if (graph_signal() && r == 0) {
		*status = 128 + graph_signal();
		r = tl_fail(e, "%s: stopped by signal %d", o->prog,
		    graph_signal());
	}
	return r;
}

int
pipeline_run(const pipeline_opts *opts, int *status, tl_err *e)
{
	char dem[PATHMAX], out[PATHMAX];
	pipeline_opts q = *opts;
	const pipeline_opts *o = &q;
	sigset_t old;
	int r, sig;

	q.dem = undashed(opts->dem, dem, sizeof dem);
	q.out = undashed(opts->out, out, sizeof out);
	if (o->plan != NULL || o->vmaps)
		q.work = NULL; /* those keep the processes' route */
	/* one process: the stop signals are taken where the threads are
	 * watched (inproc.h), until the scratch is gone */
	if (o->work != NULL)
		inproc_block(&old);
	r = run(o, status, e);
	if (o->work != NULL) {
		if ((sig = inproc_pending()) != 0 && r == 0) {
			*status = 128 + sig;
			r = tl_fail(e, "%s: stopped by signal %d", o->prog, sig);
		}
		pthread_sigmask(SIG_SETMASK, &old, NULL);
	}
	return r;
}
