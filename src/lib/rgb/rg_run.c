/* rg_run.c - dem2rgb's work (rgb.h): the DEM warped onto the deepest
 * zoom's pixel centres, the chain run segment by segment (each restarting
 * from the previous one's top level of vertices, aligned anew; -m
 * average: 2 x 2 means instead, rg_box.c), the tiles of every zoom (the
 * centres of each level, rg_centre.c), the error pass, tiles.json, the
 * tree committed at once; or (-o) the tiles handed to a PMTiles writer
 * and the archive renamed into place at the end. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rgb/rg_impl.h"
#include "base/outfile.h"
#include "base/paths.h"
#include "geo/levels.h"
#include "geo/vdatum.h"

/* One segment: zooms zt .. zt - (nl - 1); its top level written, padded,
 * as the next segment's DEM when next is not NULL. */
typedef struct {
	rg_job *j;
	int zt, nl, first, minz;
	dem_mwriter *next;
	rg_box *box;     /* -m average: the zooms from the deepest's rows */
	dem_mgrid ng;
	long long pad[2];
	int rows;        /* rows of the next grid written */
	float *nrow;
} seg;

static int
next_row(seg *s, const double *h, const double *v, int w, tl_err *e)
{
	int k;

	for (; s->rows < s->pad[1]; s->rows++) {
		for (k = 0; k < s->ng.w; k++)
			s->nrow[k] = NAN;
		if (dem_mwriter_row(s->next, s->rows, s->nrow, e) < 0)
			return -1;
	}
	for (k = 0; k < s->ng.w; k++) {
		long i = k - (long)s->pad[0];
		s->nrow[k] = i >= 0 && i < w && v[i] > 0 ? (float)h[i] : NAN;
	}
	return dem_mwriter_row(s->next, s->rows++, s->nrow, e);
}

/* A level's centres are its zoom's rows; the top level's vertices, the
 * next segment's DEM. */
static int
emit(void *ctx, int l, int r, const double *h, const double *v, int w,
    int centre, tl_err *e)
{
	seg *s = ctx;
	int z = s->zt - l;

	if (!centre && s->j->band != NULL)
		return l == s->nl - 1 && s->zt - l > s->minz ?
		    rg_band_next(s->j, r, h, v, e) : 0;
	if (!centre)
		return s->next != NULL && l == s->nl - 1 ?
		    next_row(s, h, v, w, e) : 0;
	if (s->box != NULL)
		return rg_box_row(s->box, z, r, h, v, e);
	if (l >= s->first && z >= s->minz)
		return s->j->band != NULL ?
		    rg_band_row(s->j, l, z, r, h, v, e) :
		    rg_zoom_row(s->j, z, r, h, v, e);
	return 0;
}

/* The rows of the next grid past the last level row: voids. */
static int
next_close(seg *s, tl_err *e)
{
	int r = 0;

	for (int k = 0; k < s->ng.w; k++)
		s->nrow[k] = NAN;
	while (r == 0 && s->rows < s->ng.h)
		r = dem_mwriter_row(s->next, s->rows++, s->nrow, e);
	if (dem_mwriter_close(s->next, r < 0 ? &(tl_err){ 0 } : e) < 0)
		r = -1;
	s->next = NULL;
	return r;
}

/* Segment k on grid g from the DEM file path (opened with o): its zooms
 * made; the next grid in *ng, or ng->z < 0 after the last. A plan's
 * part (j->band): segment 0 on the band's window of the filled grid. */
int
rg_segment(rg_job *j, int k, const dem_mgrid *g, const char *path,
    const dem_opts *o, dem_mgrid *ng, rg_report *rep, tl_err *e)
{
	rg_band *b = j->band;
	int minz = j->a->minzoom, box = j->a->mode == SOLVE_FILTERED;
	int s1 = box ? 0 : g->z - minz < RG_SEG ? g->z - minz : RG_SEG;
	int zlo = box ? minz : g->z - s1;
	rg_box bx = { 0 };
	seg s = { j, g->z, s1 + 1, k > 0, minz, NULL, box ? &bx : NULL,
	    { 0 }, { 0 }, 0, NULL };
	char p[4200];
	dem *d;
	int r = -1;

	ng->z = -1;
	if ((d = b != NULL ? dem_open_filled(path, o, b->filled, e) :
	    dem_open(path, o, e)) == NULL) {
		/* the message names the scratch file: name the DEM */
		char why[sizeof e->msg];
		const char *m = strstr(e->msg, ".tif: ");
		snprintf(why, sizeof why, "%s", m != NULL ? m + 6 : e->msg);
		return tl_fail(e, "%s (on the zoom-%d grid): %s", j->a->dem,
		    g->z, why);
	}
	/* the warped grid declares no datum: the source's (or -D) unless
	 * converted (-H) */
	if (k == 0)
		snprintf(rep->vdatum, sizeof rep->vdatum, "%s",
		    dem_georef(d)->vdatum[0] || o->vdatum == NULL ?
		    dem_georef(d)->vdatum : o->vdatum);
	for (int l = s.first; !box && l < s.nl; l++) {
		dem_mgrid lg = { g->z - l, g->dim, g->x0 >> l, g->y0 >> l,
		    geo_level_size(g->w, l), geo_level_size(g->h, l) };
		if (b != NULL) /* the window's columns */
			lg.x0 = (g->x0 + b->x0) >> l,
			lg.w = geo_level_size(b->x1 - b->x0, l);
		if (rg_zoom_open(j, g->z - l, &lg, e) < 0)
			goto done;
	}
	if (box && rg_box_open(&bx, j, g, minz, e) < 0)
		goto done;
	if (zlo > minz) {
		int s2 = g->z - s1 - minz < RG_SEG ? g->z - s1 - minz : RG_SEG;
		rg_grid_next(&s.ng, g, s1, s2, s.pad);
		rep->pad[0] += s.pad[0], rep->pad[1] += s.pad[1];
		snprintf(p, sizeof p, "%s/seg%d.tif", j->scratch, k + 1);
		if (b == NULL && ((s.nrow = tl_alloc(s.ng.w, sizeof *s.nrow,
		    e)) == NULL || (s.next = dem_mwriter_open(p, &s.ng,
		    e)) == NULL))
			goto done;
	}
	r = rg_chain(d, b != NULL ? b->x0 : 0, b != NULL ? b->x1 - b->x0 :
	    dem_georef(d)->width, s.nl, rep->maxzoom - g->z, j->a->mode, emit,
	    &s, e);
	if (s.next != NULL && next_close(&s, r < 0 ? &(tl_err){ 0 } : e) < 0)
		r = -1;
	if (r == 0 && s.ng.w > 0)
		*ng = s.ng;
done:
	if (s.next != NULL)
		dem_mwriter_close(s.next, &(tl_err){ 0 });
	free(s.nrow);
	rg_box_free(&bx);
	for (int z = g->z - s.first; z >= zlo; z--) {
		rep->tiles[z] = j->zoom[z].tiles;
		rep->bytes[z] = j->zoom[z].bytes;
	}
	dem_close(d);
	return r;
}

/* An existing archive is replaced only when it is a PMTiles file. */
static int
check_archive(const char *out, const struct stat *st, tl_err *e)
{
	char magic[7];
	int fd = -1;

	if (S_ISREG(st->st_mode))
		fd = open(out, O_RDONLY | O_CLOEXEC);
	if (fd < 0 || read(fd, magic, sizeof magic) != sizeof magic ||
	    memcmp(magic, "PMTiles", sizeof magic) != 0) {
		if (fd >= 0)
			close(fd);
		return tl_fail(e, "%s: exists and is not a PMTiles archive: "
		    "not replaced", out);
	}
	close(fd);
	return 0;
}

/* An existing OUT is replaced only when it is a raster-dem tree (-o: a
 * PMTiles archive). */
int
rg_check_out(const rg_args *a, tl_err *e)
{
	char p[4200];
	struct stat st;
	tl_paths s = { 0 };
	int r;

	r = dem_paths(&s, a->dem, e);
	if (r == 0)
		r = tl_paths_check(&s, a->out, e);
	tl_paths_free(&s);
	if (r < 0)
		return -1;
	if (stat(a->out, &st) < 0)
		return errno == ENOENT ? 0 : tl_failsys(e, "%s", a->out);
	if (a->pmtiles)
		return check_archive(a->out, &st, e);
	snprintf(p, sizeof p, "%s/tiles.json", a->out);
	if (!S_ISDIR(st.st_mode) || stat(p, &st) < 0)
		return tl_fail(e, "%s: exists and is not a raster-dem tree "
		    "(no tiles.json): not replaced", a->out);
	return 0;
}

/* The options the warped DEM is opened with: the source's vertical
 * datum (the warp drops it), heights orthometric unless -H says. */
int
rg_warp_opts(const rg_args *a, dem_opts *o, char *vd, size_t n, tl_err *e)
{
	dem_opts io = a->dopt;
	dem *d;

	io.heights = NULL;
	if ((d = dem_open_info(a->dem, &io, e)) == NULL)
		return -1;
	snprintf(vd, n, "%s", dem_georef(d)->vdatum);
	dem_close(d);
	*o = a->dopt;
	o->has_nodata = 0; /* the warp's voids are NaN */
	if (o->vdatum == NULL && vd[0] != '\0')
		o->vdatum = vd;
	if (o->heights == NULL && o->vdatum != NULL &&
	    vdatum_is_ellipsoid(o->vdatum))
		o->heights = "EPSG:5773"; /* MapLibre's heights: above MSL */
	return 0;
}

int
rg_job_init(rg_job *j, const rg_args *a, tl_err *e)
{
	j->a = a;
	if ((j->pool = tl_pool_new(a->jobs, e)) == NULL)
		return -1;
	j->nt = tl_pool_threads(j->pool);
	if ((j->rgb = tl_alloc(j->nt, sizeof *j->rgb, e)) == NULL ||
	    (j->terr = tl_alloc(j->nt, sizeof *j->terr, e)) == NULL ||
	    (j->tfail = tl_alloc(j->nt, sizeof *j->tfail, e)) == NULL ||
	    (j->line = tl_alloc(j->nt, sizeof *j->line, e)) == NULL)
		return -1;
	for (int k = 0; k < j->nt; k++)
		if ((j->rgb[k] = tl_alloc((size_t)a->dim * a->dim, 3, e)) ==
		    NULL || (j->line[k] = tl_alloc(2 * a->dim, sizeof **j->line,
		    e)) == NULL)
			return -1;
	return 0;
}

void
rg_job_free(rg_job *j)
{
	for (int z = 0; z <= RG_MAXZOOM; z++)
		if (j->zoom[z].on)
			rg_zoom_close(&j->zoom[z]);
	for (int k = 0; j->rgb != NULL && k < j->nt; k++)
		free(j->rgb[k]);
	for (int k = 0; j->line != NULL && k < j->nt; k++)
		free(j->line[k]);
	free(j->rgb), free(j->line), free(j->terr), free(j->tfail);
	free(j->img), free(j->imgn), free(j->row), free(j->code);
	if (j->pool)
		tl_pool_free(j->pool);
}

/* The segments, the error pass, tiles.json, all in the tree j->tree
 * (NULL: the tiles to the sink only, no tiles.json). */
static int
build(rg_job *j, const dem_mgrid *g0, const double ll[4], rg_report *rep,
    tl_err *e)
{
	const rg_args *a = j->a;
	char path[4200], vd[256];
	dem_opts o;
	dem_mgrid g = *g0, ng;
	int r;

	snprintf(path, sizeof path, "%s/seg0.tif", j->scratch);
	if (rg_warp_opts(a, &o, vd, sizeof vd, e) < 0 ||
	    rg_rows_alloc(j, g.w, e) < 0 ||
	    dem_warp_mercator(a->dem, a->dopt.has_nodata, a->dopt.nodata,
	    &g, a->cubic, a->jobs, path, e) < 0)
		return -1;
#ifdef __GLIBC__
	/* the warper's buffers, freed in its threads' arenas, given back
	 * rather than held resident through the chain */
	malloc_trim(0);
#endif
	r = rg_segment(j, 0, &g, path, &o, &ng, rep, e);
	rep->segments = 1;
	return rg_finish(j, r, &ng, &o, ll, rep, e);
}

/* A row of the widest grid: a later segment's is at most w / 32 + 2
 * wide plus under 32 of alignment. */
int
rg_rows_alloc(rg_job *j, int w, tl_err *e)
{
	int rw = w > 64 ? w : 64;

	if ((j->row = tl_alloc(rw, sizeof *j->row, e)) == NULL ||
	    (j->code = tl_alloc(rw, sizeof *j->code, e)) == NULL)
		return -1;
	return 0;
}

/* After segment 0 (r its result, ng the next grid, o the options it
 * was opened with): the later segments, the error pass, tiles.json. */
int
rg_finish(rg_job *j, int r, const dem_mgrid *ng0, const dem_opts *o0,
    const double ll[4], rg_report *rep, tl_err *e)
{
	const rg_args *a = j->a;
	char path[4200];
	dem_opts o = *o0, so;
	dem_mgrid g, ng = *ng0;
	dem *ref = NULL;

	/* the error's reference: the DEM itself, read as the warp read it,
	 * its heights converted as the tiles' are */
	so = o, so.has_nodata = a->dopt.has_nodata, so.nodata = a->dopt.nodata;
	/* the later segments' heights are converted already */
	o.heights = NULL, o.vdatum = rep->vdatum[0] ? rep->vdatum : NULL;
	for (int k = 1; r == 0 && ng.z >= 0; k++) {
		g = ng;
		snprintf(path, sizeof path, "%s/seg%d.tif", j->scratch, k);
		r = rg_segment(j, k, &g, path, &o, &ng, rep, e);
		rep->segments++;
	}
	/* a plan's job: part 0 alone measures, the gather writes
	 * tiles.json (rg_plan.c) */
	if (a->work != NULL && a->part != 0)
		return r;
	if (r == 0 && (ref = dem_open(a->dem, &so, e)) == NULL)
		r = -1;
	if (r == 0)
		r = rg_error(j, ref, rep, e);
	if (ref != NULL)
		dem_close(ref);
	if (r == 0 && j->tree != NULL && a->work == NULL)
		r = rg_tilejson(j, rep, ll, e);
	return r;
}

/* -o: each tile to the archive, then to the caller's sink. */
typedef struct {
	pm_writer *w;
	const rg_args *a;
} pm_sink;

static int
to_archive(void *ctx, int z, long long x, long long y,
    const unsigned char *p, size_t n, tl_err *e)
{
	pm_sink *s = ctx;

	if (pm_add(s->w, z, (unsigned)x, (unsigned)y, p, n, e) < 0)
		return -1;
	return s->a->sink != NULL ?
	    s->a->sink(s->a->sink_ctx, z, x, y, p, n, e) : 0;
}

/* The tiles as one archive, a->out (built like the tree, j->tree
 * NULL). */
static int
archive(rg_job *j, const dem_mgrid *g, const double ll[4], rg_report *rep,
    tl_err *e)
{
	const rg_args *a = j->a;
	rg_args b = *a;
	pm_sink s = { NULL, a };

	if ((s.w = pm_open(a->out, e)) == NULL)
		return -1;
	b.sink = to_archive, b.sink_ctx = &s;
	j->a = &b;
	if (build(j, g, ll, rep, e) < 0) {
		pm_abort(s.w);
		j->a = a;
		return -1;
	}
	j->a = a;
	return rg_pmtiles_close(s.w, j, rep, ll, e);
}

int
rg_grid0(const rg_args *a, rg_report *rep, double ll[4], dem_mgrid *g,
    tl_err *e)
{
	double cell;
	int s;

	if (dem_extent_wgs84(a->dem, ll, &cell, e) < 0)
		return -1;
	rep->maxzoom = a->maxzoom >= 0 ? a->maxzoom :
	    rg_maxzoom((ll[1] + ll[3]) / 2, cell, a->dim);
	rep->minzoom = a->minzoom;
	if (rep->minzoom > rep->maxzoom)
		return tl_fail(e, "-Z %d: above the maxzoom %d", a->minzoom,
		    rep->maxzoom);
	s = rep->maxzoom - rep->minzoom < RG_SEG ?
	    rep->maxzoom - rep->minzoom : RG_SEG;
	rg_grid_of(g, rep->maxzoom, a->dim, ll, s, rep->pad);
	return 0;
}

int
rg_run(const rg_args *a, rg_report *rep, tl_err *e)
{
	rg_job j = { 0 };
	tl_outfile od = { 0 };
	rg_scratch sc;
	double ll[4];
	dem_mgrid g;
	int r = -1;

	memset(rep, 0, sizeof *rep);
	if ((a->work == NULL && rg_check_out(a, e) < 0) ||
	    rg_grid0(a, rep, ll, &g, e) < 0)
		return -1;
	if (a->dump != NULL && mkdir(a->dump, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", a->dump);
	if (rg_scratch_begin(&sc, e) < 0)
		return -1;
	j.scratch = sc.sc.path, j.wrap = ll[2] > 180;
	if (a->work != NULL) { /* a plan's job, into the shared work tree */
		j.tree = a->work;
		if (rg_job_init(&j, a, e) == 0)
			r = build(&j, &g, ll, rep, e);
	} else if (a->pmtiles) {
		if (rg_job_init(&j, a, e) == 0)
			r = archive(&j, &g, ll, rep, e);
	} else if (rg_job_init(&j, a, e) == 0 &&
	    tl_outdir_begin(&od, a->out, e) == 0) {
		j.tree = od.tmp;
		r = build(&j, &g, ll, rep, e);
		if (r == 0)
			r = tl_outdir_commit(&od, e);
		if (r < 0)
			tl_outdir_abort(&od);
	}
	rg_job_free(&j);
	rg_scratch_end(&sc);
	return r;
}
