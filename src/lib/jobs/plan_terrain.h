/* plan_terrain.h - a pyramid-to-terrain export written as a job graph
 * instead of run (vgis2terrain --plan): per range of a level's tiles a
 * job of round 1, then, once the level's round 1 is done, one of round 2,
 * then the gather that makes the terrain appear (terrain.h gives the
 * rule, byte for byte one process's output). Each job's command is a
 * step of vgis-job (vgis-job(1)); the same three consumers as a DEM's
 * plan (plan.h): a Makefile (incremental), a script for GNU parallel
 * and one submitting Slurm job arrays, every job a make target run
 * through the plan's script job, which checks the pyramid as the plan
 * recorded it (pyramid.stamp), holds a lock and makes its done/ file. */
#ifndef TL_PLAN_TERRAIN_H
#define TL_PLAN_TERRAIN_H

#include "base/util.h"

typedef struct {
	const char *prog;
	const char *bindir;           /* absolute: vgis-job's directory */
	const char *pyr, *out;        /* absolute paths */
	const char *const *opt;       /* the export's options, every job */
	int nopt;
	int jobs;                     /* a range job's threads; 0: 1 */
	const int (*range)[3];        /* z, i0, i1 */
	int nrange;
} plan_terrain_opts;

/* Writes the plan into the directory dir, made atomically (refused if it
 * exists); its pyramid.stamp records the pyramid's index. */
int plan_terrain_write(const plan_terrain_opts *o, const char *dir,
    tl_err *e);

#endif
