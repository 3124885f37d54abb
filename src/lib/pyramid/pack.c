/* pack.c - a DEM's pyramid from its levels' vertex maps (see pack.h). */
#include "pyramid/pack.h"

#include <assert.h>
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/outfile.h"
#include "pyramid/pyramid.h"

int
pack_check_level(const fqm_info *fi, int l, const georef *g,
    const char *name, tl_err *e)
{
	const char *what;

	if (fi->level != l)
		return tl_fail(e, "%s: is level %d, expected level %d (levels "
		    "go in order from 0)", name, fi->level, l);
	if (fi->size0[0] != g->width || fi->size0[1] != g->height)
		return tl_fail(e, "%s: made from a %dx%d DEM, the DEM is %dx%d",
		    name, fi->size0[0], fi->size0[1], g->width, g->height);
	if ((what = geo_differs(&fi->geo, g)) != NULL)
		return tl_fail(e, "%s: georeferencing (%s) differs from the "
		    "DEM's: made with other DEM options?", name, what);
	return 0;
}

/* Levels 0 .. the first that fits one block, no fewer, no more: the
 * rule viewers and the checker hold a pyramid to. */
int
pack_check_count(int nlevels, int w0, int h0, tl_err *e)
{
	int want = fqm_levels(w0, h0);

	if (nlevels == want)
		return 0;
	return tl_fail(e, "%d levels given, a %dx%d DEM's pyramid has %d "
	    "(0 .. the first that fits one %dx%d block)", nlevels, w0, h0,
	    want, FQM_BLOCK, FQM_BLOCK);
}

int
pack_check_dir(const char *dir, int force, tl_err *e)
{
	char path[4096];
	struct stat st;

	if (stat(dir, &st) != 0)
		return errno == ENOENT ? 0 : tl_failsys(e, "%s", dir);
	if (!S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: exists and is not a directory", dir);
	snprintf(path, sizeof path, "%s/" VGIS_INDEX, dir);
	if (!force && access(path, F_OK) != 0 && rmdir(dir) != 0)
		return tl_fail(e, "%s: exists and is not a pyramid (no "
		    "index.json); use -f to replace it", dir);
	return 0;
}

/* --- one level ---------------------------------------------------------- */

/* The vertex map being read, for the row callback. */
typedef struct {
	rs_reader *r;
	const rs_header *h;
	const char *name;
	int cz, cx, cy; /* channels Z, X, Y (X, Y -1 on 1D levels) */
	float *row;
} vmap;

static int
read_row(void *ctx, int r, float *z, float *x, float *y, tl_err *e)
{
	vmap *v = ctx;
	size_t w = (size_t)v->h->width;

	/* a NaN that a format without checksums let through stops here */
	if (rs_read_row(v->r, v->row, e) < 0 ||
	    fqm_check_row(v->row, (int)w, v->h->nch, r, v->name, e) < 0)
		return -1;
	memcpy(z, v->row + (size_t)v->cz * w, w * sizeof *z);
	if (x != NULL) {
		memcpy(x, v->row + (size_t)v->cx * w, w * sizeof *x);
		memcpy(y, v->row + (size_t)v->cy * w, w * sizeof *y);
	}
	return 0;
}

/* Opens level l's vertex map and checks it against the DEM. */
static int
vmap_open(vmap *v, const char *path, int l, const georef *g, tl_err *e)
{
	const char *name = tl_name(path, 0);
	fqm_info fi;

	memset(v, 0, sizeof *v);
	v->name = name;
	if ((v->r = rs_open(path, e)) == NULL)
		return -1;
	v->h = rs_header_of(v->r);
	if (fqm_info_of(v->h, "vertices", &fi, name, e) < 0 ||
	    pack_check_level(&fi, l, g, name, e) < 0 ||
	    (v->cz = rs_need_channel(v->h, "Z", name, e)) < 0)
		return -1;
	v->cx = rs_channel(v->h, "X"), v->cy = rs_channel(v->h, "Y");
	if ((v->cx < 0) != (v->cy < 0))
		return tl_fail(e, "%s: has only one of channels X and Y", name);
	v->row = tl_alloc((size_t)v->h->width * v->h->nch, sizeof *v->row, e);
	return v->row != NULL ? 0 : -1;
}

static void
vmap_close(vmap *v)
{
	rs_close(v->r);
	free(v->row);
}

/* Where finished blocks go, and what the index learns from them. */
typedef struct {
	const char *dir;
	const rs_header *attrs; /* the vertex map's fqm:* and geo:* */
	pyramid_level *L;
} sink;

static int
write_block(void *ctx, const pyramid_block *b, tl_err *e)
{
	sink *k = ctx;
	char path[4096];
	size_t i = (size_t)b->bj * k->L->blocks[0] + b->bi;

	assert(b->bi < k->L->blocks[0] && b->bj < k->L->blocks[1]);
	pyramid_block_path(path, sizeof path, k->dir, b->level, b->bi, b->bj);
	k->L->zmin[i] = b->zmin, k->L->zmax[i] = b->zmax;
	k->L->base[i] = b->base, k->L->emax[i] = b->emax;
	return pyramid_block_write(path, b, k->attrs, e);
}

/* What every level reads. */
typedef struct {
	const pack_args *a;
	dem *d;
	const char *tmp; /* the directory being built */
	pyramid_index *ix;
	const geo_metric *m;
	pack_level *out;
	int threads;     /* per level */
} work;

/* The index's entry for a level, from its vertex map's header. */
static int
level_entry(pyramid_level *pl, int l, const vmap *v, tl_err *e)
{
	const char *s;

	if (pyramid_level_init(pl, l, v->h->width, v->h->height, e) < 0)
		return -1;
	pl->displaced = v->cx >= 0;
	snprintf(pl->mode, sizeof pl->mode, "%s",
	    (s = rs_get_string(v->h, FQM_ATTR_MODE)) ? s : "");
	snprintf(pl->kernel, sizeof pl->kernel, "%s",
	    (s = rs_get_string(v->h, FQM_ATTR_KERNEL)) ? s : "");
	return 0;
}

/* Level l: its vertex map checked and read, its blocks computed and
 * written into the directory being built, its index entry filled. */
static int
pack_level_run(work *w, int l, tl_err *e)
{
	pyramid_level *pl = &w->ix->lev[l];
	char label[64], path[4096];
	tiles_level L = { 0 };
	vmap v;
	sink k;
	int r = -1;

	assert(l >= 0 && l < w->a->nlevels);
	if (vmap_open(&v, w->a->levels[l], l, dem_georef(w->d), e) < 0 ||
	    level_entry(pl, l, &v, e) < 0)
		goto done;
	snprintf(path, sizeof path, "%s/%d", w->tmp, l);
	if (mkdir(path, 0777) != 0) {
		tl_failsys(e, "%s", path);
		goto done;
	}
	k.dir = w->tmp, k.attrs = v.h, k.L = pl;
	L.level = l;
	L.size[0] = v.h->width, L.size[1] = v.h->height;
	L.displaced = pl->displaced;
	L.m = w->m;
	L.row = read_row, L.row_ctx = &v;
	L.block = write_block, L.block_ctx = &k;
	L.threads = w->threads;
	if (w->a->prog != NULL) {
		snprintf(label, sizeof label, "%s: level %d", w->a->prog, l);
		L.label = label;
	}
	r = tiles_run(&L, w->d, &w->out[l].st, e);
done:
	vmap_close(&v);
	return r;
}

/* Whether some level comes through a FIFO (or stdin): a pipeline
 * feeding several must have them all read at once. */
static int
fifo_inputs(const pack_args *a)
{
	struct stat st;

	for (int l = 0; l < a->nlevels; l++)
		if (strcmp(a->levels[l], "-") == 0 ||
		    (stat(a->levels[l], &st) == 0 && S_ISFIFO(st.st_mode)))
			return 1;
	return 0;
}

typedef struct {
	work *w;
	int l, r;
	tl_err e;
} level_job;

static void *
level_thread(void *arg)
{
	level_job *j = arg;

	j->r = pack_level_run(j->w, j->l, &j->e);
	return NULL;
}

/* Every level on its own thread at once (FIFO inputs); the failure
 * reported is the lowest level's, whatever the threads' timing. */
static int
run_levels_at_once(work *w, tl_err *e)
{
	int n = w->a->nlevels, started = 0, r = 0;
	level_job *j = tl_alloc(n, sizeof *j, e);
	pthread_t *t = tl_alloc(n, sizeof *t, e);

	if (j == NULL || t == NULL) {
		free(j), free(t);
		return -1;
	}
	w->threads = 1;
	for (; started < n; started++) {
		j[started] = (level_job){ .w = w, .l = started };
		if (pthread_create(&t[started], NULL, level_thread,
		    &j[started]) != 0)
			break;
	}
	if (started < n)
		r = tl_fail(e, "%s: %d levels read at once: no thread for "
		    "level %d", w->a->prog ? w->a->prog : "tilepack", n,
		    started);
	for (int l = 0; l < started; l++)
		pthread_join(t[l], NULL);
	for (int l = 0; r == 0 && l < started; l++)
		if (j[l].r < 0) {
			*e = j[l].e;
			r = -1;
		}
	free(j), free(t);
	return r;
}

/* The levels one after another, level 0 (the largest) first, each on
 * every thread: one level's rings in memory at a time, and the failure
 * reported is the lowest level's. */
static int
run_levels(work *w, tl_err *e)
{
	if (fifo_inputs(w->a))
		return run_levels_at_once(w, e);
	w->threads = w->a->jobs;
	for (int l = 0; l < w->a->nlevels; l++)
		if (pack_level_run(w, l, e) < 0)
			return -1;
	return 0;
}

static void
report_levels(const pyramid_index *ix, pack_level *out)
{
	for (int l = 0; l < ix->nlevels; l++) {
		const pyramid_level *pl = &ix->lev[l];
		out[l].size[0] = pl->size[0], out[l].size[1] = pl->size[1];
		out[l].blocks[0] = pl->blocks[0];
		out[l].blocks[1] = pl->blocks[1];
		out[l].displaced = pl->displaced;
	}
}

int
pack_run(const pack_args *a, pack_level *out, tl_err *e)
{
	pyramid_index ix = { 0 };
	geo_metric m = { 0 };
	tl_outfile dir = { 0 };
	work w = { 0 };
	dem *d;
	int r = -1;

	assert(a->nlevels >= 1 && a->jobs >= 1);
	if (pack_check_dir(a->dir, a->force, e) < 0 ||
	    (d = dem_open(a->dem_path, &a->dem, e)) == NULL)
		return -1;
	memset(out, 0, (size_t)a->nlevels * sizeof *out);
	ix.version = VGIS_VERSION;
	ix.geo = *dem_georef(d);
	ix.size0[0] = ix.geo.width, ix.size0[1] = ix.geo.height;
	ix.nlevels = a->nlevels;
	w.a = a, w.d = d, w.ix = &ix, w.m = &m, w.out = out;
	if ((ix.lev = tl_alloc(a->nlevels, sizeof *ix.lev, e)) == NULL ||
	    geo_metric_init(&m, &ix.geo, e) < 0 ||
	    tl_outdir_begin(&dir, a->dir, e) < 0)
		goto done;
	w.tmp = dir.tmp;
	/* the count after the levels, whose own faults say more */
	if (run_levels(&w, e) < 0 ||
	    pack_check_count(ix.nlevels, ix.size0[0], ix.size0[1], e) < 0 ||
	    pyramid_index_write(dir.tmp, &ix, e) < 0)
		goto done;
	report_levels(&ix, out);
	r = tl_outdir_commit(&dir, e);
done:
	if (r < 0)
		tl_outdir_abort(&dir);
	dem_close(d);
	geo_metric_free(&m);
	pyramid_index_free(&ix);
	return r;
}

void
pack_report(FILE *f, const char *prog, const pack_level *L, int n)
{
	for (int l = 0; l < n; l++)
		fprintf(f, "%s: level %d: %dx%d vertices, %dx%d blocks, %s, "
		    "max E %.3f m, max base error %.3f m\n", prog, l,
		    L[l].size[0], L[l].size[1], L[l].blocks[0],
		    L[l].blocks[1], L[l].displaced ? "3D" : "1D",
		    L[l].st.max_e, L[l].st.max_base);
}
