/* plan.h - a DEM-to-pyramid build written as a job graph instead of run
 * (dem2vgis --plan): the quadric chain as one job writing every level's
 * vertex map (or as jobs over column bands, below), then tilepack's
 * pieces, one job each, then the gather that makes the pyramid appear.
 * Every job's command is a step of vgis-job (vgis-job(1)), the one
 * program of the plans' inner steps. The same graph
 * three ways: a Makefile (make -C PLANDIR -j N: incremental, so a killed
 * or failed run goes on where it stopped), a script for GNU parallel
 * (stage by stage; PARALLEL may name --sshloginfile for machines that
 * share the file system) and a script submitting Slurm jobs (an array for
 * the pieces, chained by dependencies). Every job is a make target, so
 * all three skip what is done; it runs through the plan's script job,
 * which checks the DEM's files as the plan recorded them (dem.stamp,
 * stamp.h), holds a lock of its own (runners at once run it once) and
 * makes its done/ file; a run of the whole plan first drops the done/
 * files whose outputs are gone. Names and options reach the jobs
 * exactly, quoted for make, sh, GNU parallel and sbatch; a newline,
 * which no Makefile carries, is refused (plan_check). */
#ifndef TL_PLAN_H
#define TL_PLAN_H

#include "base/util.h"

typedef struct {
	const char *prog;
	const char *bindir;            /* absolute: the stages' directory */
	const char *dem, *out;         /* absolute paths */
	const char *const *dems;       /* ndem > 0: a mosaic of these, written
	                                * as the plan's list dems.txt, dem
	                                * unused */
	int ndem;
	const char *const *chainopt;   /* vgis-job chain's options */
	int nchainopt;
	const char *const *demopt;     /* how to read the DEM (the pieces) */
	int ndemopt;
	int levels;
	int force;                     /* -f at the gather */
	/* the chain in column bands (0 bands: one job): a job filling the
	 * DEM's voids once (vgis-job fill), then one per band of bandw level-0
	 * columns (the last to width) for levels 0 .. band_levels-1, then
	 * the chain from level band_levels on, from the bands' FQMs */
	int nbands, bandw, band_levels, width;
	/* the fill itself in nfill row bands of fillrows rows (0: one job):
	 * vgis-job fill's parts (filled(5)): pass 1 per band, the join, pass 2
	 * per band, the commit */
	int nfill, fillrows, height;
	/* -b: pieces in parts of at most this many DEM samples (-1:
	 * tilepack's own bound) */
	long long part_samples;
	/* what identifies the DEM's files (vgis-job stamp, stamp.h): copied
	 * into the plan as dem.stamp, which every job checks first */
	const char *stamp;
} plan_opts;

/* Whether the plan can carry every path and option of o into dir: a
 * newline cannot go into a Makefile's recipe (every other byte is
 * quoted for make, sh, GNU parallel and sbatch). plan_write checks it
 * too; a caller with work to do first checks it before. */
int plan_check(const plan_opts *o, const char *dir, tl_err *e);

/* Writes the plan into the directory dir, made atomically (an existing
 * one is replaced only with force). */
int plan_write(const plan_opts *o, const char *dir, tl_err *e);

#endif
