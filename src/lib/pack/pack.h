/* pack.h - a DEM's VGIS pyramid from the vertex maps of its levels, the
 * work of tilepack(1): each map checked against the DEM (its level, the
 * DEM's size and georeferencing), every level cut into pieces of 16
 * block columns (level.h) that threads take in order, level 0 first,
 * each reading the vertex map again (FIFOs: each level whole, all at
 * once), the level count enforced, the directory (vgis(5), pyramid.h)
 * built under a temporary name and renamed when complete. */
#ifndef TL_PACK_H
#define TL_PACK_H

#include <stdio.h>

#include "dem/dem.h"
#include "qem/fqm.h"
#include "pack/level.h"

#define PACK_MAXJOBS LEVEL_MAXTHREADS

/* Vertex maps still being made while pack_run runs (dem2vgis's one
 * process, its chain beside it): ended(ctx, ms) waits up to ms
 * milliseconds for them: 0 complete, 1 not yet, -1 never (the run failed
 * or was stopped: pack_run fails, its message unheard); stopped(ctx),
 * polled a row at a time, 1 once the run has failed or been stopped. */
typedef struct {
	void *ctx;
	int (*ended)(void *ctx, int ms);
	int (*stopped)(void *ctx);
} pack_gate;

typedef struct {
	const char *dem_path; /* the DEM the levels were made from */
	dem_opts dem;         /* how to read it */
	const char *dir;      /* the pyramid to make */
	char *const *levels;  /* vertex maps of levels 0 .. nlevels-1, paths
	                       * or "-" */
	int nlevels;
	int jobs;             /* threads, 1 .. PACK_MAXJOBS: a piece each */
	int force;            /* replace dir even if it is not a pyramid */
	/* pack_piece, pack_list: a piece whose DEM window holds more DEM
	 * samples runs in parts of rows (0: never) */
	long long part_samples;
	const char *prog;     /* names the progress line, or NULL: none */
	enum rs_compression comp; /* the blocks' EXR compression: RS_ZIP
	                           * (0, the default) unless tilepack -z */
	dem *opened;          /* pack_run: dem_path already open with dem
	                       * (dem2vgis converts it once for its chain and
	                       * tilepack's work), used and not closed; or
	                       * NULL: opened here */
	/* pack_run: the vertex maps not yet complete (their gate), or NULL:
	 * they are */
	const pack_gate *gate;
	int gate_jobs;        /* of the jobs threads, those that take pieces
	                       * while the gate is shut (the others wait at
	                       * it: the chain has the cores and the memory
	                       * meanwhile); 0: none */
	/* pack_run: level 0's vertex map is known, the header given: the
	 * DEM's heights (its channel Z, as fqmsolve makes it in every mode),
	 * and zero offsets where it has X and Y (QEM-3D), so that level 0 is
	 * made from the DEM at once, without levels[0] (t_level0_known);
	 * but from levels[0] on a DEM with a sample -0 (the solver's Z + 0
	 * may make it +0). NULL: read levels[0] */
	const rs_header *known0;
} pack_args;

/* What a level came to. */
typedef struct {
	int size[2];   /* vertices */
	int blocks[2];
	int displaced;
	level_stats st;
} pack_level;

/* Makes a->dir, or leaves nothing; out[0 .. a->nlevels-1] is filled
 * when it returns 0. On failure e says why the lowest failing level did,
 * whatever the threads' timing; levels are checked before their count,
 * whose fault says less than theirs. */
int pack_run(const pack_args *a, pack_level *out, tl_err *e);

/* A pyramid in separate processes (a plan): each piece of each level
 * (level l's block columns [b0, b1), as pack_run cuts them) by
 * pack_piece, into a->dir taken as a work directory (made if missing,
 * shared by the pieces): its blocks, then a record of them. Then
 * pack_gather reads every piece's record from the work directory dir,
 * writes the index and makes dir the pyramid a->dir, atomically; out as
 * pack_run's. The result is pack_run's, byte for byte. A killed piece
 * leaves no half-written file (its temporaries are swept by the next
 * run of a piece there) and no record: it is simply run again. */
int pack_piece(const pack_args *a, int l, int b0, int b1, int y0, int y1,
    tl_err *e);
int pack_gather(const pack_args *a, const char *dir, pack_level *out,
    tl_err *e);
/* The pieces, "level:b0:b1" a line, level 0 first (from the DEM's header
 * and the vertex maps' headers: nothing is computed), each after its
 * parts if it has any, "level:b0:b1:y0:y1".
 *
 * A piece whose DEM window holds more than a->part_samples samples is
 * made in parts: pack_piece with y1 > 0 makes the part of DEM rows
 * [y0, y1) (level_run_part): its local errors and a record of its base
 * errors and samples under work/.parts; then pack_piece with y1 0 makes
 * the piece from them (level_run_merged), byte for byte as whole. So no
 * job scans more than part_samples DEM samples (and a row), however
 * coarse its level. A part, like a piece, leaves no half-written file
 * and writes its record last. */
int pack_list(const pack_args *a, FILE *f, tl_err *e);

/* One line per level: "prog: level l: WxH vertices, BXxBY blocks, 1D,
 * max E x m, max base error y m". */
void pack_report(FILE *f, const char *prog, const pack_level *L, int n);

/* The checks pack_run makes, each on its own. */

/* A vertex map (named name) is level l of the DEM of georeferencing g:
 * same level, level-0 size and georeferencing (geo_differs). */
int pack_check_level(const fqm_info *fi, int l, const georef *g,
    const char *name, tl_err *e);
/* nlevels is the count of a w0 x h0 DEM's pyramid (geo_levels). */
int pack_check_count(int nlevels, int w0, int h0, tl_err *e);
/* dir may be replaced: absent, a pyramid (it has an index.json), empty
 * (then removed), or force is set. */
int pack_check_dir(const char *dir, int force, tl_err *e);

#endif
