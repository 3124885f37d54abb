/* plan_rgb.h - dem2rgb's tiles written as a job graph instead of made
 * (dem2rgb --plan): n parts, each a range of every zoom's tiles into
 * the plan's work tree, then the gather that makes the tree (or the
 * PMTiles archive) appear, byte for byte one process's (rgb.h gives the
 * rule). Each job's command is a step of vgis-job (vgis-job(1)); the
 * same three consumers as a DEM's plan (plan.h): a Makefile
 * (incremental), a script for GNU parallel and one submitting a Slurm
 * job array, every job a make target run through the plan's script
 * job, which checks the DEM's files as the plan recorded them
 * (dem.stamp), holds a lock and makes its done/ file. */
#ifndef TL_PLAN_RGB_H
#define TL_PLAN_RGB_H

#include "base/util.h"

typedef struct {
	const char *prog;
	const char *bindir;           /* vgis-job's directory */
	const char *dem, *out;        /* made absolute in the plan */
	int archive;                  /* out is a PMTiles archive (-o) */
	const char *const *opt;       /* dem2rgb's options, every job */
	int nopt;
	int jobs;                     /* a part's threads; 0: 1 */
	int nparts;
} plan_rgb_opts;

/* Writes the plan into the directory dir, made atomically (refused if it
 * exists); its dem.stamp records the DEM's files. */
int plan_rgb_write(const plan_rgb_opts *o, const char *dir, tl_err *e);

#endif
