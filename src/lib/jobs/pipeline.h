/* pipeline.h - a DEM to its VGIS pyramid as supervised stages (graph.h),
 * what dem2vgis(1) runs:
 *
 *   dem2fqm DEM - | tee | fqmfilter | tee | ... | fqmfilter
 *                   fqmsolve > v0      fqmsolve > v1  ...  fqmsolve > vL
 *   tilepack DEM OUT v0 ... vL
 *
 * The quadric maps travel through pipes only; each level's vertex map is
 * a stream file in a scratch directory (scratch.h); tilepack builds OUT
 * atomically. Levels go up to the first that fits one block, as
 * "dem2fqm -I" reports. Several DEMs are one mosaic: the stages get a
 * list of them (dem2fqm(1)) written in the scratch directory. */
#ifndef TL_PIPELINE_H
#define TL_PIPELINE_H

#include "core/util.h"

#define PIPELINE_MAXOPTS 32

typedef struct {
	const char *prog;      /* for messages and the scratch name */
	const char *bindir;    /* where the stages are, or NULL: PATH */
	const char *dem, *out; /* DEM path or "-" (stdin), output directory */
	char *const *dems;     /* ndem > 1: the DEMs of a mosaic (dem is
	                        * the first), never "-" */
	int ndem;
	const char *name;      /* -n: the DEM's file name, or NULL */
	const char *demopt[PIPELINE_MAXOPTS]; /* DEM options for dem2fqm and
	                                       * tilepack, as argv words */
	int ndemopt;
	const char *mode;      /* fqmsolve -m */
	const char *kernel;    /* fqmfilter -k */
	const char *cut;       /* fqmsolve -r, or NULL */
	const char *jobs;      /* tilepack -j, or NULL */
	int force, quiet;      /* tilepack -f, -q */
	int vmaps;             /* -M: out gets the vertex maps v0.fqm ...
	                        * (a plan's chain job), no pyramid */
	const char *plan;      /* --plan: the job graph into this directory
	                        * instead of a run (plan.h) */
} pipeline_opts;

/* Runs it. 0, or -1 with e holding the failing stage's own message and
 * *status the exit status to give (2 usage, 1 failure, 128+n signal). */
int pipeline_run(const pipeline_opts *o, int *status, tl_err *e);

#endif
