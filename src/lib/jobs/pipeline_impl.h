/* pipeline_impl.h - the pipeline's insides, shared by pipeline*.c: the
 * limits, an argv under construction, the progress meter, and what each
 * file gives the others. Calls go one way: pipeline.c (the front door) to
 * pipeline_input.c, pipeline_chain.c and pipeline_plan.c, and all of them
 * to pipeline_stage.c (a leaf). */
#ifndef TL_PIPELINE_IMPL_H
#define TL_PIPELINE_IMPL_H

#include <assert.h>
#include <stddef.h>

#include "base/progress.h"
#include "base/scratch.h"
#include "jobs/graph.h"
#include "jobs/pipeline.h"

#define MAXLEVELS 32 /* levels of a DEM of 2^31 x 2^31 samples: 25 */
#define MAXWORDS (PIPELINE_MAXOPTS + MAXLEVELS + 16)
#define PATHMAX 4200

typedef char vpath_t[PATHMAX];

/* The whole pipeline's one progress line, from what the stages report:
 * the quadric chain runs at dem2fqm's pace, then tilepack's pieces of
 * every level. The weights are the two phases' shares of the time
 * (scripts/bench-pyramid). */
#define QUADRIC_SHARE 0.35

typedef struct {
	tl_progress bar;
	double quad, pack; /* fractions done */
} meter;

/* An argv under construction; the words are not copied (graph_exec
 * copies the whole argv). */
typedef struct {
	const char *w[MAXWORDS + 1];
	int n;
} words;

static inline void
say(words *a, const char *w)
{
	assert(a->n < MAXWORDS);
	a->w[a->n++] = w;
	a->w[a->n] = NULL;
}

static inline void
say_demopts(words *a, const pipeline_opts *o)
{
	for (int i = 0; i < o->ndemopt; i++)
		say(a, o->demopt[i]);
}

/* pipeline_stage.c: running one stage alone (its usage error, exit 2, is
 * -1 with status 2; other failures only when fatal is set); our own
 * failure as "prog: what"; the meter fed by the stages' progress. */
int pipeline_alone(const pipeline_opts *, words *, int in, int fatal,
    char *cap, size_t ncap, int *status, tl_err *);
int pipeline_ours(const pipeline_opts *, tl_err *);
void pipeline_progress(void *meter, const char *label, long long done,
    long long total);

/* pipeline_input.c: the DEM as the stages read it: stdin spooled into
 * the scratch, a mosaic's list of DEMs, its level count and size. */
int pipeline_spool_stdin(const pipeline_opts *, const scratch *,
    char *path, size_t n, tl_err *);
int pipeline_write_list(const pipeline_opts *, const char *dir,
    char *path, size_t n, tl_err *);
int pipeline_level_count(const pipeline_opts *, const char *dem,
    int *levels, int *width, int *height, int *status, tl_err *);

/* pipeline_chain.c: the stages' graphs: the quadric chain (levels first
 * .. levels-1), tilepack, and -M (the chain alone, into o->out). */
int pipeline_quadrics(const pipeline_opts *, const char *dem, int first,
    int levels, int w, vpath_t *vpath, const char *fpath, meter *,
    int *status, tl_err *);
int pipeline_pack(const pipeline_opts *, const char *dem, int levels,
    vpath_t *vpath, meter *, int *status, tl_err *);
int pipeline_vmaps_only(const pipeline_opts *, const char *dem,
    int levels, int w, vpath_t *vpath, meter *, int *status, tl_err *);

/* pipeline_inproc.c: the chain and tilepack as threads (o->work). */
int pipeline_inproc(const pipeline_opts *, const char *dem, int levels,
    vpath_t *vpath, scratch *, meter *, int *status, tl_err *);

/* pipeline_plan.c: --plan, the job graph written instead of a run. */
int pipeline_plan(const pipeline_opts *, const char *dem, const scratch *,
    int levels, int w, int h, int *status, tl_err *);

#endif
