/* rg_split.c - dem2rgb's work split between a plan's jobs (rgb.h): the
 * warp job (the DEM on the deepest zoom's grid once, its voids filled,
 * saved as a filled DEM file), a part's band (segment 0 of the chain on a
 * window of that grid, its tiles, the pieces of the zooms' codes and of
 * the next segment's grid it owns), and the gather's join of the pieces
 * into what one process holds after segment 0.
 *
 * Why identical: the filled file gives the rows one process's reader
 * gives (dem.h, dem_open_filled); the chain on a window, the metric and
 * the filters told its offset, gives the whole grid's values at the
 * columns more than RG_HALO(t) from its edges (the filter's reach, as the
 * pyramid's band jobs: pipeline.h, pipeline_halo; plus a column of
 * margin and the centres' neighbour), and every column a part owns is
 * that far from its window's edges or on the grid's own edge. The
 * pieces are the codes and the vertex heights one process computes, and
 * the gather runs the later segments and the error pass as one process
 * does. Which columns are whose: rg_band.c; a part's rows into its
 * tiles and pieces: rg_tiles.c. WORK.grid/: seg0.tif, seg0.filled; K/zZ.code (part K's columns
 * lo .. hi - 1 of zoom Z's codes, row by row), K/next (its columns of the
 * next segment's vertices, float32, NaN: void). */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "rgb/rg_impl.h"
#include "geo/levels.h"

/* The grid of segment 0 and its levels, as rg_run makes them. */
static int
seg0(const rg_args *a, rg_report *rep, double ll[4], dem_mgrid *g, int *nl,
    tl_err *e)
{
	int s;

	if (rg_grid0(a, rep, ll, g, e) < 0)
		return -1;
	s = a->mode == SOLVE_FILTERED ? 0 : g->z - a->minzoom < RG_SEG ?
	    g->z - a->minzoom : RG_SEG;
	*nl = s + 1;
	return 0;
}

int
rg_warp(const rg_args *a, const char *work, tl_err *e)
{
	char dir[4200], path[4300], fill[4300], vd[256];
	rg_report rep = { 0 };
	double ll[4];
	dem_mgrid g;
	dem_opts o;
	dem *d;
	int nl, r;

	/* -m average: nothing but the directory (the plan's mark) */
	snprintf(dir, sizeof dir, "%s.grid", work);
	if (!RG_SPLIT(a))
		return mkdir(dir, 0777) < 0 && errno != EEXIST ?
		    tl_failsys(e, "%s", dir) : 0;
	if (seg0(a, &rep, ll, &g, &nl, e) < 0 ||
	    rg_warp_opts(a, &o, vd, sizeof vd, e) < 0)
		return -1;
	if (mkdir(dir, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", dir);
	snprintf(path, sizeof path, "%s/seg0.tif", dir);
	snprintf(fill, sizeof fill, "%s/seg0.filled", dir);
	if (dem_warp_mercator(a->dem, a->dopt.has_nodata, a->dopt.nodata, &g,
	    a->cubic, a->jobs, path, e) < 0)
		return -1;
#ifdef __GLIBC__
	malloc_trim(0); /* the warper's buffers given back, as rg_run does */
#endif
	if ((d = dem_open(path, &o, e)) == NULL)
		return -1;
	r = dem_save_filled(d, fill, e);
	dem_close(d);
	return r;
}

/* A file of the part's pieces, made anew. */
static int
piece(const char *work, int k, const char *name, tl_err *e)
{
	char p[4300];
	int fd;

	snprintf(p, sizeof p, "%s.grid/%d/%s", work, k, name);
	if ((fd = open(p, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0666)) < 0)
		return tl_failsys(e, "%s", p);
	return fd;
}

/* The part's pieces opened, its window's rows allocated. */
static int
part_open(rg_job *j, const char *work, int next, tl_err *e)
{
	rg_band *b = j->band;
	char p[4300], name[32];
	int w = b->x1 - b->x0;

	snprintf(p, sizeof p, "%s.grid/%d", work, b->k);
	if (mkdir(p, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", p);
	for (int l = 0; l < b->nl; l++) {
		snprintf(name, sizeof name, "z%d.code", b->maxz - l);
		if (b->maxz - l >= j->a->minzoom &&
		    (b->fd[l] = piece(work, b->k, name, e)) < 0)
			return -1;
	}
	if (next && (b->nfd = piece(work, b->k, "next", e)) < 0)
		return -1;
	if ((b->h = tl_alloc(w, sizeof *b->h, e)) == NULL ||
	    (b->v = tl_alloc(w, sizeof *b->v, e)) == NULL ||
	    (b->f = tl_alloc(w, sizeof *b->f, e)) == NULL ||
	    rg_rows_alloc(j, w, e) < 0)
		return -1;
	return 0;
}

static void
band_free(rg_band *b)
{
	for (int l = 0; l < b->nl; l++)
		if (b->fd[l] >= 0)
			close(b->fd[l]);
	if (b->nfd >= 0)
		close(b->nfd);
	free(b->h), free(b->v), free(b->f);
}

int
rg_split_part(const rg_args *a, const char *work, int k, int n,
    rg_report *rep, int win[3], tl_err *e)
{
	char path[4300], fill[4300], vd[256];
	double ll[4];
	dem_mgrid g, ng;
	dem_opts o;
	rg_band b;
	rg_job j = { 0 };
	rg_scratch sc;
	int nl, r = -1;

	memset(rep, 0, sizeof *rep);
	if (seg0(a, rep, ll, &g, &nl, e) < 0 ||
	    rg_warp_opts(a, &o, vd, sizeof vd, e) < 0)
		return -1;
	rg_band_of(&b, &g, rep->maxzoom, nl, k, n);
	win[0] = b.x0, win[1] = b.x1, win[2] = g.w;
	snprintf(path, sizeof path, "%s.grid/seg0.tif", work);
	snprintf(fill, sizeof fill, "%s.grid/seg0.filled", work);
	b.filled = fill;
	rep->segments = 1;
	if (b.x1 == b.x0) /* nothing of this part's */
		return 0;
	if (rg_scratch_begin(&sc, e) < 0)
		return -1;
	j.scratch = sc.sc.path, j.tree = work, j.band = &b;
	j.wrap = ll[2] > 180;
	if (rg_job_init(&j, a, e) == 0 &&
	    part_open(&j, work, g.z - (nl - 1) > a->minzoom, e) == 0)
		r = rg_segment(&j, 0, &g, path, &o, &ng, rep, e);
	rg_job_free(&j);
	band_free(&b);
	rg_scratch_end(&sc);
	return r;
}

/* Part k's piece name (rows of hi - lo values of size sz) into the
 * columns lo .. of the rows of w values of fd. */
static int
join(int fd, int w, int h, const char *work, int k, const char *name,
    int lo, int hi, size_t sz, unsigned char *buf, tl_err *e)
{
	char p[4300];
	int in, r = 0;

	if (hi == lo)
		return 0;
	snprintf(p, sizeof p, "%s.grid/%d/%s", work, k, name);
	if ((in = open(p, O_RDONLY | O_CLOEXEC)) < 0)
		return tl_failsys(e, "%s", p);
	for (int y = 0; r == 0 && y < h; y++)
		if ((r = tl_pread(in, buf, (size_t)(hi - lo) * sz,
		    (long long)y * (hi - lo) * (long long)sz, p, e)) == 0)
			r = tl_pwrite(fd, buf, (size_t)(hi - lo) * sz,
			    ((long long)y * w + lo) * (long long)sz, "scratch",
			    e);
	close(in);
	return r;
}

/* The next segment's grid ng (level t of g, pad before it) from the
 * vertex rows in fd (wt x ht floats) into the DEM file path. */
static int
next_grid(const dem_mgrid *ng, const long long pad[2], int fd, int wt,
    int ht, const char *path, float *row, tl_err *e)
{
	dem_mwriter *m = dem_mwriter_open(path, ng, e);
	int r = m != NULL ? 0 : -1;

	for (int y = 0; r == 0 && y < ng->h; y++) {
		long long s = y - pad[1];
		for (int k = 0; k < ng->w; k++)
			row[k] = NAN;
		if (s >= 0 && s < ht)
			r = tl_pread(fd, row + pad[0], (size_t)wt * sizeof *row,
			    s * wt * (long long)sizeof *row, "scratch", e);
		if (r == 0)
			r = dem_mwriter_row(m, y, row, e);
	}
	if (m != NULL && dem_mwriter_close(m, r < 0 ? &(tl_err){ 0 } : e) < 0)
		r = -1;
	return r;
}

/* Segment 0's zooms' codes and the next grid from the parts' pieces. */
static int
joins(rg_job *j, const char *work, const dem_mgrid *g, int nl, int n,
    dem_mgrid *ng, rg_report *rep, tl_err *e)
{
	const rg_args *a = j->a;
	int t = nl - 1, wt = geo_level_size(g->w, t), ht = geo_level_size(g->h,
	    t), r = 0, fd = -1, s2;
	unsigned char *buf = tl_alloc(g->w > wt ? g->w : wt, 4, e);
	long long pad[2];
	char p[4300];
	rg_band b;

	ng->z = -1;
	for (int l = 0; r == 0 && buf != NULL && l < nl; l++) {
		int z = g->z - l;
		dem_mgrid lg = { z, g->dim, g->x0 >> l, g->y0 >> l,
		    geo_level_size(g->w, l), geo_level_size(g->h, l) };
		if (z < a->minzoom || (r = rg_zoom_open(j, z, &lg, e)) < 0)
			break;
		snprintf(p, sizeof p, "z%d.code", z);
		for (int k = 0; r == 0 && k < n; k++) {
			rg_band_of(&b, g, g->z, nl, k, n);
			r = join(j->zoom[z].fd, lg.w, lg.h, work, k, p,
			    b.lo[l], b.hi[l], 4, buf, e);
		}
		/* the tiles across parts */
		if (r == 0 && (r = rg_zoom_cut(j, z, e)) == 0)
			rep->tiles[z] += j->zoom[z].tiles,
			rep->bytes[z] += j->zoom[z].bytes;
	}
	if (buf == NULL || r < 0 || g->z - t <= a->minzoom) {
		free(buf);
		return buf == NULL ? -1 : r;
	}
	s2 = g->z - t - a->minzoom < RG_SEG ? g->z - t - a->minzoom : RG_SEG;
	rg_grid_next(ng, g, t, s2, pad);
	rep->pad[0] += pad[0], rep->pad[1] += pad[1];
	snprintf(p, sizeof p, "%s/next.raw", j->scratch);
	if ((fd = open(p, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600)) < 0)
		r = tl_failsys(e, "%s", p);
	for (int k = 0; r == 0 && k < n; k++) {
		rg_band_of(&b, g, g->z, nl, k, n);
		r = join(fd, wt, ht, work, k, "next", b.lo[t], b.hi[t], 4,
		    buf, e);
	}
	snprintf(p, sizeof p, "%s/seg1.tif", j->scratch);
	if (r == 0)
		r = next_grid(ng, pad, fd, wt, ht, p, j->row, e);
	if (fd >= 0)
		close(fd);
	free(buf);
	if (r < 0)
		ng->z = -1;
	return r;
}

int
rg_split_gather(const rg_args *a, const char *work, int n, rg_report *rep,
    tl_err *e)
{
	rg_args b = *a;
	char path[4300], fill[4300], vd[256];
	double ll[4];
	dem_mgrid g, ng;
	dem_opts o;
	rg_job j = { 0 };
	rg_scratch sc;
	rg_band gb;
	dem *d;
	int nl, r = -1;

	if (seg0(a, rep, ll, &g, &nl, e) < 0 ||
	    rg_warp_opts(a, &o, vd, sizeof vd, e) < 0)
		return -1;
	/* the datum as segment 0 found it on the warped grid */
	snprintf(path, sizeof path, "%s.grid/seg0.tif", work);
	snprintf(fill, sizeof fill, "%s.grid/seg0.filled", work);
	if ((d = dem_open_filled(path, &o, fill, e)) == NULL)
		return -1;
	snprintf(rep->vdatum, sizeof rep->vdatum, "%s",
	    dem_georef(d)->vdatum[0] || o.vdatum == NULL ?
	    dem_georef(d)->vdatum : o.vdatum);
	dem_close(d);
	rep->segments = 1;
	rg_band_of(&gb, &g, g.z, nl, -1, n); /* the tiles across parts */
	j.band = &gb;
	/* measured as part 0 of a plan: tiles.json is the gather's */
	b.work = work, b.part = 0, b.sink = NULL, b.dump = NULL;
	if (rg_scratch_begin(&sc, e) < 0)
		return -1;
	j.scratch = sc.sc.path, j.tree = work, j.wrap = ll[2] > 180;
	if (rg_job_init(&j, &b, e) == 0 && rg_rows_alloc(&j, g.w, e) == 0) {
		r = joins(&j, work, &g, nl, n, &ng, rep, e);
		j.band = NULL; /* the later segments whole */
		r = rg_finish(&j, r, &ng, &o, ll, rep, e);
	}
	rg_job_free(&j);
	rg_scratch_end(&sc);
	return r;
}
