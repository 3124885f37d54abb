/* pack_jobs.c - a pyramid in separate processes: a piece (or a part)
 * into a work directory, the gather, the list of jobs (pack.h). */
#include "pack/pack_impl.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/outfile.h"

static int
mkdir_ok(const char *path, tl_err *e)
{
	return mkdir(path, 0777) == 0 || errno == EEXIST ? 0 :
	    tl_failsys(e, "%s", path);
}

/* Level l's index entry from its vertex map, checked against the DEM. */
static int
level_read(work *w, int l, tl_err *e)
{
	vmap v;
	int r = pk_vmap_open(&v, w->a->levels[l], l, dem_georef(w->d), e);

	if (r == 0)
		r = pk_level_entry(&w->ix->lev[l], l, &v, e);
	pk_vmap_close(&v);
	return r;
}

/* 1 when (b0, b1) is one of level pl's pieces, -1 out of memory. */
static int
is_piece(const pyramid_level *pl, int b0, int b1, int *n, tl_err *e)
{
	level_piece *p = pk_level_cut(pl, n, e);
	int r = 0;

	if (p == NULL)
		return -1;
	for (int k = 0; k < *n; k++)
		r |= p[k].b0 == b0 && p[k].b1 == b1;
	free(p);
	return r;
}

static void
record_path(char *buf, size_t n, const char *dir, int l, int b0, int b1)
{
	snprintf(buf, n, "%s/" PIECES "/%d-%d-%d", dir, l, b0, b1);
}

/* The piece's record, written last: its blocks' index entries and its
 * stats, exact (%.17g). */
static int
record_write(const work *w, int l, int b0, int b1, tl_err *e)
{
	const pyramid_level *pl = &w->ix->lev[l];
	const level_stats *st = &w->out[l].st;
	char path[4096];
	tl_outfile o;
	FILE *f;

	record_path(path, sizeof path, w->tmp, l, b0, b1);
	if ((f = pk_record_open(&o, path, e)) == NULL)
		return -1;
	fprintf(f, "piece %d %d %d\nstats %.17g %.17g %lld\n", l, b0, b1,
	    st->max_e, st->max_base, st->samples);
	for (int bj = 0; bj < pl->blocks[1]; bj++)
		for (int bi = b0; bi < b1; bi++) {
			size_t i = (size_t)bj * pl->blocks[0] + bi;
			fprintf(f, "%d %d %.17g %.17g %.17g %.17g\n", bi, bj,
			    pl->zmin[i], pl->zmax[i], pl->base[i], pl->emax[i]);
		}
	return pk_record_close(&o, f, e);
}

/* Reads piece p of level l's record from the work directory dir into
 * the index and stats. */
static int
record_read(work *w, int l, const level_piece *p, void *ctx, tl_err *e)
{
	pyramid_level *pl = &w->ix->lev[l];
	const char *dir = ctx;
	int b0 = p->b0, b1 = p->b1;
	level_stats st = { 0 };
	char path[4096];
	int rl, r0, r1, n = 0;
	FILE *f;

	record_path(path, sizeof path, dir, l, b0, b1);
	if ((f = fopen(path, "r")) == NULL)
		return errno == ENOENT ? tl_fail(e, "%s: level %d, block "
		    "columns %d..%d: piece not made", dir, l, b0, b1 - 1) :
		    tl_failsys(e, "%s", path);
	if (fscanf(f, "piece %d %d %d stats %lf %lf %lld", &rl, &r0, &r1,
	    &st.max_e, &st.max_base, &st.samples) != 6 || rl != l ||
	    r0 != b0 || r1 != b1)
		goto bad;
	for (;;) {
		double z0, z1, b, em;
		int bi, bj, k = fscanf(f, "%d %d %lf %lf %lf %lf", &bi, &bj, &z0,
		    &z1, &b, &em);
		if (k == EOF)
			break;
		if (k != 6 || bi < b0 || bi >= b1 || bj < 0 ||
		    bj >= pl->blocks[1])
			goto bad;
		size_t i = (size_t)bj * pl->blocks[0] + bi;
		pl->zmin[i] = z0, pl->zmax[i] = z1, pl->base[i] = b;
		pl->emax[i] = em;
		n++;
	}
	if (n != (b1 - b0) * pl->blocks[1])
		goto bad;
	fclose(f);
	pk_merge_stats(w, l, &st);
	return 0;
bad:
	fclose(f);
	return tl_fail(e, "%s: not a record of piece %d:%d:%d", path, l, b0,
	    b1);
}

/* What -p, -g and -l share: the DEM's header, the index's levels from
 * the vertex maps' headers. */
static int
work_open(work *w, pyramid_index *ix, geo_ground *m, const pack_args *a,
    pack_level *out, tl_err *e)
{
	memset(w, 0, sizeof *w);
	w->a = a, w->ix = ix, w->m = m, w->out = out;
	w->mu = (pthread_mutex_t)PTHREAD_MUTEX_INITIALIZER;
	memset(out, 0, (size_t)a->nlevels * sizeof *out);
	if ((w->d = dem_open_info(a->dem_path, &a->dem, e)) == NULL)
		return -1;
	ix->version = VGIS_VERSION;
	ix->geo = *dem_georef(w->d);
	ix->size0[0] = ix->geo.width, ix->size0[1] = ix->geo.height;
	ix->nlevels = a->nlevels;
	if ((ix->lev = tl_alloc(a->nlevels, sizeof *ix->lev, e)) == NULL ||
	    geo_ground_init(m, &ix->geo, e) < 0)
		return -1;
	for (int l = 0; l < a->nlevels; l++)
		if (level_read(w, l, e) < 0)
			return -1;
	return pack_check_count(ix->nlevels, ix->size0[0], ix->size0[1], e);
}

static void
work_close(work *w, pyramid_index *ix, geo_ground *m)
{
	dem_close(w->d);
	geo_ground_free(m);
	pyramid_index_free(ix);
}

/* The DEM of a piece in a process of its own: only the columns its
 * window scans, so that a job's disk and time do not grow with the
 * DEM's width (the header, opened by work_open, is replaced). */
static int
open_window(work *w, int l, const level_piece *p, tl_err *e)
{
	level_window win;
	dem *d;

	pk_window(w, l, p, &win);
	if ((d = dem_open_cols(w->a->dem_path, &w->a->dem, (int)win.d0,
	    (int)win.d1, e)) == NULL)
		return -1;
	dem_close(w->d);
	w->d = d;
	return 0;
}

/* The work directory's subdirectory name, made if missing, what killed
 * runs left there swept. */
static int
work_subdir(const char *dir, const char *name, tl_err *e)
{
	char path[4096];

	snprintf(path, sizeof path, "%s/%s", dir, name);
	if (mkdir_ok(path, e) < 0)
		return -1;
	tl_out_sweep_dir(path);
	return 0;
}

/* fn on every piece of every level, level 0 first, until one fails. */
static int
each_piece(work *w, int (*fn)(work *, int, const level_piece *, void *,
    tl_err *), void *ctx, tl_err *e)
{
	for (int l = 0; l < w->a->nlevels; l++) {
		level_piece *p;
		int n, r = 0;
		if ((p = pk_level_cut(&w->ix->lev[l], &n, e)) == NULL)
			return -1;
		for (int k = 0; r == 0 && k < n; k++)
			r = fn(w, l, &p[k], ctx, e);
		free(p);
		if (r < 0)
			return -1;
	}
	return 0;
}

/* Which job (l, b0, b1) with rows (y0, y1) is (y1 0: the piece): one
 * of pack_list's, checked. Returns the piece's parts, 1 when whole. */
static int
job_check(work *w, int l, const level_piece *p, int y0, int y1, tl_err *e)
{
	int k, n, np;

	if ((k = is_piece(&w->ix->lev[l], p->b0, p->b1, &n, e)) <= 0)
		return k == 0 ? tl_fail(e, "piece %d:%d:%d: not one of level "
		    "%d's %d pieces", l, p->b0, p->b1, l, n) : -1;
	np = pk_nparts(w, l, p);
	if (y1 == 0)
		return np;
	for (k = 0; np > 1 && k < np; k++) {
		int a, b;
		pk_part_rows(w->ix->geo.height, np, k, &a, &b);
		if (a == y0 && b == y1)
			return np;
	}
	return tl_fail(e, "part %d:%d:%d:%d:%d: not one of the piece's %d "
	    "parts%s", l, p->b0, p->b1, y0, y1, np, np == 1 ?
	    " (it is made whole: -b sets how many samples a part holds)" : "");
}

int
pack_piece(const pack_args *a, int l, int b0, int b1, int y0, int y1,
    tl_err *e)
{
	pack_level *out = tl_alloc(a->nlevels, sizeof *out, e);
	level_piece p = { b0, b1 };
	pyramid_index ix = { 0 };
	geo_ground m = { 0 };
	work w = { 0 };
	int r = -1, np;
	char sub[16];

	if (out == NULL)
		return -1;
	if (l < 0 || l >= a->nlevels) {
		tl_fail(e, "piece %d:%d:%d: no level %d (levels 0..%d)", l, b0,
		    b1, l, a->nlevels - 1);
		goto done;
	}
	if (work_open(&w, &ix, &m, a, out, e) < 0 ||
	    (np = job_check(&w, l, &p, y0, y1, e)) < 0)
		goto done;
	w.tmp = a->dir;
	if (mkdir_ok(a->dir, e) < 0)
		goto done;
	if (y1 > 0) { /* a part: its errors, then its record */
		r = work_subdir(a->dir, PARTS, e) < 0 ? -1 :
		    pk_run_part(&w, l, &p, y0, y1, e);
		goto done;
	}
	snprintf(sub, sizeof sub, "%d", l);
	if (work_subdir(a->dir, sub, e) < 0 ||
	    work_subdir(a->dir, PIECES, e) < 0)
		goto done;
	/* whole: only the columns its window scans, so that a job's disk
	 * and time do not grow with the DEM's width */
	if (np > 1 ? pk_run_merged(&w, l, &p, np, e) == 0 :
	    open_window(&w, l, &p, e) == 0 &&
	    pk_run_piece(&w, l, &p, a->jobs, e) == 0)
		r = record_write(&w, l, b0, b1, e);
done:
	if (w.a != NULL)
		work_close(&w, &ix, &m);
	free(out);
	return r;
}

int
pack_gather(const pack_args *a, const char *dir, pack_level *out, tl_err *e)
{
	pyramid_index ix = { 0 };
	geo_ground m = { 0 };
	char path[4096];
	work w = { 0 };
	int r = -1;

	if (pack_check_dir(a->dir, a->force, e) < 0 ||
	    work_open(&w, &ix, &m, a, out, e) < 0 ||
	    each_piece(&w, record_read, (void *)dir, e) < 0)
		goto done;
	snprintf(path, sizeof path, "%s/" PIECES, dir);
	tl_rmtree(path);
	snprintf(path, sizeof path, "%s/" PARTS, dir);
	tl_rmtree(path);
	if (pyramid_index_write(dir, &ix, e) < 0 ||
	    tl_dir_install(dir, a->dir, e) < 0)
		goto done;
	pk_report_levels(&ix, out);
	r = 0;
done:
	if (w.a != NULL)
		work_close(&w, &ix, &m);
	return r;
}

/* A piece's line for -l, after its parts' lines. */
static int
list_piece(work *w, int l, const level_piece *p, void *f, tl_err *e)
{
	int np = pk_nparts(w, l, p);

	for (int i = 0; np > 1 && i < np; i++) {
		int y0, y1;
		pk_part_rows(w->ix->geo.height, np, i, &y0, &y1);
		fprintf(f, "%d:%d:%d:%d:%d\n", l, p->b0, p->b1, y0, y1);
	}
	fprintf(f, "%d:%d:%d\n", l, p->b0, p->b1);
	return 0;
}

int
pack_list(const pack_args *a, FILE *f, tl_err *e)
{
	pack_level *out = tl_alloc(a->nlevels, sizeof *out, e);
	pyramid_index ix = { 0 };
	geo_ground m = { 0 };
	work w = { 0 };
	int r = -1;

	if (out == NULL || work_open(&w, &ix, &m, a, out, e) < 0 ||
	    each_piece(&w, list_piece, f, e) < 0)
		goto done;
	r = fflush(f) == 0 ? 0 : tl_failsys(e, "stdout");
done:
	if (w.a != NULL)
		work_close(&w, &ix, &m);
	free(out);
	return r;
}
