/* stage.h - the work of the quadric stages, one function each, shared by
 * the programs a person runs (dem2fqm, fqmfilter, fqmsolve) and by the
 * steps a plan runs (vgis-job level0, filter, solve), which add a window
 * (-w), a filled DEM (-F) or a cut of columns (-C) to the same work, so
 * that a plan's band job computes exactly what the whole filter does.
 * Each fills e and returns -1 on failure; warnings go to stderr through
 * the cli (cli_warn). */
#ifndef TL_STAGE_H
#define TL_STAGE_H

#include "cli.h"
#include "qem/filter.h"
#include "qem/solve.h"
#include "pack/pack.h"

#define STAGE_MAXGUARD 8

/* dem2fqm: a DEM's level-0 FQM, or its header (-I). */
typedef struct {
	const char *in, *out;  /* the DEM, "-" for stdin; the FQM */
	int info;              /* -I: 1 the header, 2 (-II) the voids too */
	const char *filled;    /* vgis-job level0 -F: the samples from this
	                        * filled DEM (filled(5)), or NULL */
	int win[2], has_win;   /* vgis-job level0 -w: columns a .. b-1 */
	/* dem2vgis's threads: the DEM, opened once for the chain and
	 * tilepack's work, from open(open_ctx) (NULL and e: its failure),
	 * neither opened nor closed here; or open NULL */
	dem *(*open)(void *open_ctx, tl_err *e);
	void *open_ctx;
} stage_level0;

int stage_dem2fqm(const cli *c, const stage_level0 *o, tl_err *e);

/* The outputs kept off the files the DEM dem_path is read from (dem_paths)
 * and off the filled DEM filled_in read with it (or NULL), before any
 * work (paths.h): outs[0 .. n-1]. */
int stage_guard(const char *dem_path, const char *filled_in,
    const char *const *outs, int n, tl_err *e);

/* fqmfilter: one level of QEM filtering. */
typedef struct {
	const filter_kernel *kernel;
	int cut[2], has_cut;   /* vgis-job filter -C: output columns a..b-1 */
	const char *in, *out;
} stage_filter;

int stage_fqmfilter(const cli *c, const stage_filter *o, tl_err *e);

/* fqmsolve: a level's vertex map. */
typedef struct {
	enum solve_mode mode;
	double rel;            /* -r */
	int verbose;           /* -v */
	int jobs;              /* -j */
	int cut[2], has_cut;   /* vgis-job solve -C: columns a .. b-1 */
	const char *in, *out;
} stage_solve;

int stage_fqmsolve(const cli *c, const stage_solve *o, tl_err *e);

/* tilepack's pieces (tilepack -p, vgis-job piece, part): "level:b0:b1"
 * or "level:b0:b1:y0:y1" into p[0 .. 4] (y0 = y1 = 0 for a piece):
 * 0, or -1 if it is neither (0 <= b0 < b1, 0 <= y0 < y1). */
int stage_piece_parse(const char *s, int p[5]);

/* tilepack's output a->dir kept off every input before any work
 * (paths.h): the DEM's files, the vertex maps (a band list's bands too),
 * the gather's work directory (or NULL). */
int stage_pack_guard(const pack_args *a, const char *gather, tl_err *e);

#endif
