/* pack_impl.h - what pack.c (a pyramid in one process), pack_jobs.c (in
 * separate processes: pieces, gather, list), pack_parts.c (pieces in
 * parts of rows) and pack_record.c (the jobs' records, which both of the
 * latter write) share. Private to those four. */
#ifndef TL_PACK_IMPL_H
#define TL_PACK_IMPL_H

#include <pthread.h>

#include "base/outfile.h"
#include "base/progress.h"
#include "raster/raster.h"
#include "pack/pack.h"
#include "pyramid/pyramid.h"

/* The vertex map being read, for the row callback. */
typedef struct {
	rs_reader *r;
	const rs_header *h;
	const char *name;
	int cz, cx, cy; /* channels Z, X, Y (X, Y -1 on 1D levels) */
	float *row;     /* the span asked for, every channel */
	int next;       /* the next row to read */
	dem *d;         /* a known level 0 (pack_args known0): rows the
	                 * DEM's, r NULL; or NULL */
	const pack_gate *gate; /* polled a row at a time, or NULL */
} vmap;

/* Where finished blocks go, and what the index learns from them. */
typedef struct {
	const char *dir;
	const rs_header *attrs; /* the vertex map's fqm:* and geo:* */
	enum rs_compression comp; /* the blocks' (pack_args) */
	int tree;         /* dir is work's tree: see work */
	pyramid_level *L;
} sink;

/* What every level reads. */
typedef struct {
	const pack_args *a;
	dem *d;
	const char *tmp; /* the directory being built */
	/* 1: tmp is a tree this process builds (tl_outdir_begin), whose
	 * blocks are written under their final names; 0: a plan's work
	 * directory, which outlives a killed job and whose files a later
	 * job takes for complete: each is written under a temporary name
	 * and renamed (tl_out_begin_fresh) */
	int tree;
	pyramid_index *ix;
	const geo_ground *m;
	pack_level *out;
	int fifo;           /* a level comes through a FIFO: read once */
	int known0;         /* level 0 from the DEM (pack_args known0) */
	pthread_mutex_t mu; /* the stats in out, the progress */
	tl_progress pr;
	long long done;     /* DEM samples scanned (all pieces, all levels) */
} work;

/* Where a work directory keeps its finished pieces' records, and its
 * parts: each part's local errors (L-B0-B1-Y0.exr), then its record
 * (L-B0-B1-Y0). */
#define PIECES ".pieces"
#define PARTS ".parts"

/* Level l's vertex map opened and checked against the DEM (g). */
int pk_vmap_open(vmap *v, const char *path, int l, const georef *g,
    tl_err *e);
void pk_vmap_close(vmap *v);
/* The index's entry for a level, from its vertex map's header. */
int pk_level_entry(pyramid_level *pl, int l, const vmap *v, tl_err *e);
/* Level l over its open vertex map v, its blocks into k. */
void pk_level_setup(work *w, int l, vmap *v, sink *k, int threads,
    level_args *L);
/* Piece p of level l (p NULL: the whole level, from a FIFO). */
int pk_run_piece(work *w, int l, const level_piece *p, int threads,
    tl_err *e);
/* A piece's stats into level l's. */
void pk_merge_stats(work *w, int l, const level_stats *st);
/* The levels' sizes and blocks into out, from the index. */
void pk_report_levels(const pyramid_index *ix, pack_level *out);
/* Level pl's pieces, as every mode cuts them, allocated; *n of them. */
level_piece *pk_level_cut(const pyramid_level *pl, int *n, tl_err *e);
/* What piece p of level l reads (level_piece_window). */
void pk_window(const work *w, int l, const level_piece *p, level_window *win);

/* pack_record.c: a text record of a job at path, written last and
 * atomically: pk_record_open's stream, then pk_record_close (which
 * commits it, or removes it on a write error). */
FILE *pk_record_open(tl_outfile *o, const char *path, tl_err *e);
int pk_record_close(tl_outfile *o, FILE *f, tl_err *e);

/* pack_parts.c: how many parts piece p of level pl runs in (1: whole),
 * under w->a->part_samples; part k's DEM rows [y0, y1); a part made into
 * w->tmp/.parts; a piece made from its n parts there. */
int pk_nparts(const work *w, int l, const level_piece *p);
void pk_part_rows(int height, int n, int k, int *y0, int *y1);
int pk_run_part(work *w, int l, const level_piece *p, int y0, int y1,
    tl_err *e);
int pk_run_merged(work *w, int l, const level_piece *p, int n, tl_err *e);

#endif
