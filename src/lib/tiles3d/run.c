/* run.c - vgis2tiles' work: the pyramid's blocks streamed through a pool
 * of threads, one block each at a time, into a tileset built under a
 * temporary name (tiles3d.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/outfile.h"
#include "base/paths.h"
#include "base/pool.h"
#include "base/progress.h"
#include "tiles3d/t3_impl.h"

typedef struct {
	const t3_args *a;
	const pyramid_index *ix;
	t3_set *s;
	t3_work *w;      /* one per thread */
	tl_err *err;     /* one per thread */
	int *failed;     /* one per thread */
	const char *tmp; /* the tree being built */
	int base;        /* first tile of the batch */
} job;

static void
run_range(void *arg, int k, int i0, int i1)
{
	job *j = arg;
	char path[4096];

	for (int i = i0; i < i1 && !j->failed[k]; i++) {
		t3_tile *t = &j->s->tile[j->base + i];
		snprintf(path, sizeof path, "%s/%d/%d_%d.glb", j->tmp, t->level,
		    t->bj, t->bi);
		if (t3_tile_write(&j->w[k], j->a->dir, j->ix, t, path,
		    &j->err[k]) < 0)
			j->failed[k] = 1;
	}
}

/* Every tile, in batches of a few per thread, the progress between. */
static int
stream(job *j, tl_pool *pool, int nthreads, tl_err *e)
{
	int n = j->s->first[j->ix->nlevels], batch = 4 * nthreads;
	tl_progress pr;

	tl_progress_start(&pr, j->a->prog ? j->a->prog : "", n);
	if (j->a->prog == NULL || j->a->quiet)
		pr.on = 0;
	for (j->base = 0; j->base < n; j->base += batch) {
		int m = n - j->base < batch ? n - j->base : batch;
		tl_pool_for(pool, m, run_range, j);
		for (int k = 0; k < nthreads; k++)
			if (j->failed[k]) {
				*e = j->err[k];
				return -1;
			}
		tl_progress_step(&pr, j->base + m);
	}
	tl_progress_end(&pr);
	return 0;
}

/* An existing OUTDIR is replaced only when it is a tileset. */
static int
check_out(const char *out, tl_err *e)
{
	char p[4096];
	struct stat st;

	if (stat(out, &st) < 0)
		return errno == ENOENT ? 0 : tl_failsys(e, "%s", out);
	snprintf(p, sizeof p, "%s/tileset.json", out);
	if (!S_ISDIR(st.st_mode) || stat(p, &st) < 0)
		return tl_fail(e, "%s: exists and is not a tileset: not "
		    "replaced", out);
	return 0;
}

static int
level_dirs(const char *tmp, int n, tl_err *e)
{
	char p[4096];

	for (int l = 0; l < n; l++) {
		snprintf(p, sizeof p, "%s/%d", tmp, l);
		if (mkdir(p, 0777) < 0)
			return tl_failsys(e, "%s", p);
	}
	return 0;
}

static void
report(const t3_set *s, const t3_work *w, int nthreads, t3_report *rep)
{
	rep->tiles = s->first[s->ix->nlevels];
	rep->root_error = s->tile[rep->tiles - 1].error;
	for (int k = 0; k < nthreads; k++) {
		rep->verts += w[k].nverts, rep->tris += w[k].ntris;
		rep->bytes += w[k].nbytes;
		if (w[k].curve > rep->max_curve)
			rep->max_curve = w[k].curve;
	}
}

/* The tiles through the pool into the temporary tree, then the tileset. */
static int
export(job *j, int nthreads, t3_report *rep, tl_err *e)
{
	tl_outfile od = { 0 };
	tl_pool *pool = NULL;
	int r = -1;

	if (check_out(j->a->out, e) < 0 || tl_outdir_begin(&od, j->a->out,
	    e) < 0)
		return -1;
	j->tmp = od.tmp;
	if (level_dirs(od.tmp, j->ix->nlevels, e) < 0 ||
	    (pool = tl_pool_new(nthreads, e)) == NULL ||
	    stream(j, pool, nthreads, e) < 0 ||
	    t3_tileset_write(j->s, &j->w[0].proj, od.tmp, &rep->raised, e) < 0)
		goto done;
	report(j->s, j->w, nthreads, rep);
	r = tl_outdir_commit(&od, e);
done:
	if (r < 0)
		tl_outdir_abort(&od);
	if (pool)
		tl_pool_free(pool);
	return r;
}

int
t3_run(const t3_args *a, t3_report *rep, tl_err *e)
{
	pyramid_index ix = { 0 };
	t3_set s = { 0 };
	geo_ground m = { 0 };
	job j = { .a = a, .ix = &ix, .s = &s };
	int nt = a->jobs < 1 ? 1 : a->jobs > T3_MAXJOBS ? T3_MAXJOBS : a->jobs;
	int r = -1, ready = 0;

	memset(rep, 0, sizeof *rep);
	/* OUTDIR kept off the pyramid before any work (paths.h) */
	if (tl_path_check(a->out, a->dir, "pyramid", TL_PATH_TREE, e) < 0 ||
	    pyramid_index_read(a->dir, &ix, e) < 0)
		return -1;
	if (pyramid_levels_probe(a->dir, &ix, e) < 0) {
		pyramid_index_free(&ix);
		return -1;
	}
	j.w = tl_alloc(nt, sizeof *j.w, e);
	j.err = tl_alloc(nt, sizeof *j.err, e);
	j.failed = tl_alloc(nt, sizeof *j.failed, e);
	if (!j.w || !j.err || !j.failed || t3_check_datum(a, &ix, e) < 0 ||
	    geo_ground_init(&m, &ix.geo, e) < 0)
		goto done;
	for (; ready < nt; ready++)
		if (t3_work_init(&j.w[ready], &ix.geo, &m, e) < 0)
			goto done;
	if (t3_plan(&s, &ix, a->tau0, &j.w[0].proj, e) < 0)
		goto done;
	r = export(&j, nt, rep, e);
done:
	for (int k = 0; k < ready; k++)
		t3_work_free(&j.w[k]);
	free(j.w), free(j.err), free(j.failed);
	t3_set_free(&s);
	geo_ground_free(&m);
	pyramid_index_free(&ix);
	return r;
}
