/* pipeline_stage.c - one stage of the pipeline run alone (the option
 * checks, the level count, the stamp), our own failures' messages, and
 * the one progress line the stages feed (a leaf of the pipeline). */
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "jobs/pipeline_impl.h"

/* The stages' progress into the one line (meter, pipeline_impl.h). */
void
pipeline_progress(void *ctx, const char *label, long long done,
    long long total)
{
	meter *m = ctx;
	double f = total > 0 ? (double)done / (double)total : 0;

	if (strcmp(label, "dem2fqm") == 0 ||
	    strcmp(label, "vgis-job level0") == 0)
		m->quad = f;
	else if (strcmp(label, "tilepack") == 0)
		m->pack = f;
	else
		return;
	f = QUADRIC_SHARE * m->quad + (1 - QUADRIC_SHARE) * m->pack;
	tl_progress_step(&m->bar, (long long)(1000 * f));
}

/* Runs one stage alone: its usage error (exit 2) is returned as -1 with
 * status 2; other failures only when fatal is set. */
int
pipeline_alone(const pipeline_opts *o, words *a, int in, int fatal, char *cap,
    size_t ncap, int *status, tl_err *e)
{
	graph *g = graph_new(o->prog, o->bindir, e);
	int k, r = -1, st = 1;

	if (g == NULL)
		goto done;
	if ((k = graph_exec(g, (char *const *)a->w, in, -1, e)) < 0 ||
	    (cap != NULL && graph_capture(g, k, cap, ncap, e) < 0))
		goto done;
	r = graph_run(g, &st, e);
	if (r < 0 && !fatal && st == 1)
		r = 0; /* not a usage error: the real run will say */
done:
	graph_free(g);
	*status = r < 0 ? st : 0;
	return r;
}

/* Our own failure (not a stage's, which names itself): "prog: what". */
int
pipeline_ours(const pipeline_opts *o, tl_err *e)
{
	char m[sizeof e->msg];

	snprintf(m, sizeof m, "%s", e->msg);
	return tl_fail(e, "%s: %s", o->prog, m);
}
