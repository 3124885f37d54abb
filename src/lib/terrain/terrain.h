/* terrain.h - a VGIS pyramid as quantized-mesh-1.0 terrain tiles on the
 * global geographic quadtree (vgis2terrain(1), quantized-mesh(5)):
 * OUTDIR/layer.json and OUTDIR/{z}/{x}/{y}.terrain, EPSG:4326, TMS rows
 * from the south, two root tiles at level 0. Every tile written is within
 * E_L = 77067.34 m / 2^L (CesiumJS's error for level L) of every valid
 * level-0 sample that it covers, on the surface the renderer draws (flat
 * triangles between the decoded vertices, in ECEF, along the ellipsoid's
 * normal): the pyramid's saturated errors bound its selection, and the
 * distance between the drawn surface and the selection is measured at
 * every sample; a level that cannot be held is refined, never written
 * over its error. Geographic and projected DEMs
 * (PROJ), heights ellipsoidal. The same export as a plan's jobs
 * (vgis2terrain --plan): ranges of a level's tiles, then the gather,
 * byte for byte the files of tr_run. */
#ifndef TL_TERRAIN_H
#define TL_TERRAIN_H

#include "base/util.h"

#define TR_E0 77067.34 /* metres: CesiumJS's level-0 error, 2 roots, 65 */
#define TR_MAXJOBS 64

typedef struct {
	const char *dir;       /* the pyramid */
	const char *out;       /* the tileset directory to make */
	const char *parent;    /* --parent-url, or NULL */
	const char *attrib;    /* --attribution, or NULL */
	int jobs;              /* threads */
	int gzip;              /* -z: tiles gzipped */
	int format;            /* 0: quantized-mesh, 1: 3D Tiles (t3t.h) */
	const char *prog;      /* for warnings; NULL: none */
	int quiet;
} tr_args;

#define TR_MAXZ 24

/* What was written, per level, for the report. */
typedef struct {
	int maxzoom;
	long long tiles[TR_MAXZ + 1], tris[TR_MAXZ + 1], bytes[TR_MAXZ + 1];
	double err[TR_MAXZ + 1];   /* the bound, metres: max(tau, base) +
	                            * the drawn surface's largest distance
	                            * from the selection at a sample */
	double direct[TR_MAXZ + 1]; /* the largest distance from a sample,
	                             * measured (filled voids too), over the
	                             * tiles measured */
	double measured[TR_MAXZ + 1]; /* their share of the samples, or -1
	                               * unknown (a plan's gather) */
	int plevel[TR_MAXZ + 1];   /* pyramid level used */
	double tau[TR_MAXZ + 1];   /* its tolerance */
	int tries[TR_MAXZ + 1];    /* attempts (1: the first choice held) */
} tr_report;

int tr_run(const tr_args *a, tr_report *rep, tl_err *e);

/* --- the export as a plan's jobs (tr_plan.c) ----------------------- */

/* Tiles i0 .. i1-1 of level z, numbered row by row from the level's
 * south-west tile. */
typedef struct {
	int z, i0, i1;
} tr_range;

/* The plan's ranges of a->dir into *r (malloc'd), *n of them: each level
 * cut into equal ranges, as many as its DEM samples (each level covers
 * all of them) hold `samples`, at most one a tile. a->out is checked
 * against the pyramid as tr_run does. */
int tr_plan_ranges(const tr_args *a, long long samples, tr_range **r,
    int *n, tl_err *e);
/* A job: range r made into the directory work (a->out: work), with its
 * record. Round 1 tries 0, 1, ... until the range holds; round 2 (once
 * every round 1 of the level is done) starts from the largest try of
 * the level's round-1 records, and does nothing when its range is
 * already there. */
int tr_plan_part(const tr_args *a, const char *work, const tr_range *r,
    int round, tl_err *e);
/* The gather: every range's record in work; a level whose ranges are at
 * different tries has those behind made again from the largest, until
 * all agree (then at the try tr_run takes); layer.json or the 3D Tiles
 * subtrees written, and work renamed to a->out. */
int tr_plan_gather(const tr_args *a, const char *work, tr_report *rep,
    tl_err *e);

#endif
