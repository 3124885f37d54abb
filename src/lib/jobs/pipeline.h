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
 * "dem2fqm -I" reports. With o->work, a run's stages are threads of
 * this process instead (inproc.h): the pipes and tees are rings of
 * rows, and the same vertex maps, in the same scratch files, go to
 * tilepack's work, which runs beside the chain (level 0's vertex map,
 * known, taken from the DEM at once), byte for byte the same pyramid.
 * Several DEMs are one mosaic: the stages get a list of them
 * (dem2fqm(1)) written in the scratch directory. The steps
 * of a plan that are no filter of a person's (the guard of the outputs,
 * the DEM's stamp, a band's window and columns) are vgis-job's
 * (vgis-job(1)), installed beside them. */
#ifndef TL_PIPELINE_H
#define TL_PIPELINE_H

#include "qem/filter.h"
#include "base/util.h"

#define PIPELINE_MAXOPTS 32

/* What tilepack's work is given when it runs beside the chain that
 * makes its vertex maps (the one-process route): ended(ctx, ms) says
 * whether the chain has ended, waiting up to ms milliseconds: 0 its
 * vertex maps are complete, 1 not yet, -1 never (a stage failed, or the
 * run was stopped); stopped(ctx): 1 once the run has failed or been
 * stopped (a poll: its work is then in vain). */
typedef struct {
	void *ctx;
	int (*ended)(void *ctx, int ms);
	int (*stopped)(void *ctx);
} pipeline_gate;

/* The stages' work as functions, for the one-process route (inproc.h):
 * each runs in a thread of its own whose "-" is a ring of rows, and on
 * failure fills e with the message its program would print ("prog:
 * why"). level0: dem2fqm DEM -; filter: fqmfilter - -; solve: fqmsolve
 * - out; pack: tilepack DEM OUT vmaps, after the chain (g NULL) or
 * beside it (g its gate: level 0, whose vertex map is known, from the
 * DEM at once, the others once the chain has ended; a failure of the
 * chain's is the run's, pack's then unheard). open (or NULL) names the
 * DEM before the chain and converts it: level0 takes that conversion
 * (or its failure) instead of making its own, and pack uses it too (the
 * same DEM, the same options); it returns 1 when the DEM is converted
 * (pack may run beside the chain), 0 when not (a failure, which level0
 * reports; a name too long). close, after pack or a failure, closes
 * it. count (or NULL) is vgis-job guard DEM OUTS then dem2fqm -I DEM for
 * a DEM file (not stdin) without their processes, each failure in its
 * program's words ("vgis-job guard: ...", "dem2fqm: ..."): the DEM's
 * level count and size. */
typedef struct {
	void *ctx;
	int (*count)(void *ctx, const char *dem, const char *const *outs,
	    int nout, int *levels, int *w, int *h, tl_err *e);
	int (*open)(void *ctx, const char *dem);
	void (*close)(void *ctx);
	int (*level0)(void *ctx, const char *dem, tl_err *e);
	int (*filter)(void *ctx, tl_err *e);
	int (*solve)(void *ctx, const char *out, tl_err *e);
	int (*pack)(void *ctx, const char *dem, const char *out,
	    char *const *vmaps, int n, const pipeline_gate *g, tl_err *e);
} pipeline_work;

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
	/* -M as a part of a plan split into column bands (plan.h; vgis-job
	 * chain's options): */
	int band[2];           /* --band a,b: level-0 columns a .. b-1 only,
	                        * read with pipeline_halo(band_levels) more
	                        * on either side; b 0: no band */
	int band_levels;       /* --band-levels T: the vertex maps of levels
	                        * 0 .. T-1, and level T's FQM as f.fqm */
	const char *fill;      /* --fill: the filled DEM (vgis-job fill) */
	const char *from;      /* --from: the chain from this FQM (a band
	                        * list of the bands' f.fqm) instead of the
	                        * DEM: vertex maps of its level and above */
	int bandplan;          /* --plan: band width in level-0 columns (0:
	                        * the plan's own choice, -1: no bands) */
	int fillplan;          /* --plan: the fill's row bands, in rows (0:
	                        * the plan's own choice, -1: one job) */
	long long partplan;    /* --plan: tilepack -b, DEM samples a job
	                        * scans at most (-1: tilepack's default) */
	const pipeline_work *work; /* a run (no -M, no plan): the stages as
	                        * threads of this process, or NULL: as
	                        * processes */
} pipeline_opts;

/* The level-0 columns a band reads past its own on either side so that
 * levels 0 .. t come out as the whole DEM's: a window's edge vertex lacks
 * the cells beyond it (1 column wrong), and a filter of radius r turns z
 * wrong fine columns into ceil((z + r) / 2) coarse ones, so at most
 * max(1, r) columns of every level are wrong, max(1, r) x 2^t at level
 * 0 for level t (r <= FILTER_MAX_RADIUS). One level-t column more of
 * margin; a multiple of 2^t, so that a window starts on every level's
 * grid. t_plan_bands shows a halo of 2^t failing for binomial5. */
#define pipeline_halo(t) ((long)(FILTER_MAX_RADIUS + 1) << (t))

/* Runs it. 0, or -1 with e holding the failing stage's own message and
 * *status the exit status to give (2 usage, 1 failure, 128+n signal). */
int pipeline_run(const pipeline_opts *o, int *status, tl_err *e);

#endif
