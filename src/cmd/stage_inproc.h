/* stage_inproc.h - the stages' work as dem2vgis's threads call it
 * (jobs/pipeline.h, pipeline_work): dem2fqm's, fqmfilter's, fqmsolve's
 * and tilepack's functions with the options dem2vgis would give them on
 * their command lines, each failing with its program's own words. */
#ifndef TL_STAGE_INPROC_H
#define TL_STAGE_INPROC_H

#include "jobs/pipeline.h"
#include "stage.h"

/* The DEM converted once, by dem2fqm's work, and kept open for
 * tilepack's (pipeline_work's open and close). */
typedef struct {
	char path[4096];      /* the DEM pipeline_work's open named */
	int named;            /* path holds it */
	int done;             /* d or err is the conversion's answer */
	dem *d;               /* the open DEM, or NULL: err says why */
	tl_err err;
} stage_dem;

typedef struct {
	cli c[4];             /* as dem2fqm, fqmfilter, fqmsolve, tilepack */
	stage_level0 l0;
	stage_filter f;
	stage_solve s;
	pack_args pk;
	int quiet;
	int mode3d;           /* QEM-3D: its chain and pieces are larger */
	stage_dem dem;
	pipeline_work w;
} stage_inproc;

/* Fills p from dem2vgis's cli c and the pipeline's options o (already
 * checked by them); p->w is the work to give o->work. */
int stage_inproc_init(stage_inproc *p, const cli *c,
    const pipeline_opts *o, tl_err *e);

#endif
