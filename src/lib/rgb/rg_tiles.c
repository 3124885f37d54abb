/* rg_tiles.c - a zoom's rows into its tiles: each row's codes kept in a
 * scratch file (the error pass decodes it too), and when a band of dim
 * rows of the tile columns covering the zoom's grid is complete, its
 * tiles cut from that file and encoded on the pool's threads (a row of
 * dim codes held a thread, never the band), written in order; the
 * intended heights dumped for the tests (rg_impl.h); a plan's part's
 * rows (rg_split.c): its columns into its tiles and its pieces. */
#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rgb/rg_impl.h"

static int
floordiv(long long a, int b)
{
	return (int)(a >= 0 ? a / b : -((-a + b - 1) / b));
}

int
rg_zoom_open(rg_job *j, int z, const dem_mgrid *g, tl_err *e)
{
	rg_zoom *zz = &j->zoom[z];
	int dim = j->a->dim;
	char p[4200];

	memset(zz, 0, sizeof *zz);
	zz->g = *g, zz->ty = -1, zz->fd = -1, zz->on = 1;
	zz->tx0 = floordiv(g->x0, dim);
	zz->ntx = floordiv(g->x0 + g->w - 1, dim) - (int)zz->tx0 + 1;
	if (zz->ntx > j->nimg) {
		free(j->img), free(j->imgn);
		j->nimg = zz->ntx;
		if ((j->img = tl_alloc(j->nimg, sizeof *j->img, e)) == NULL ||
		    (j->imgn = tl_alloc(j->nimg, sizeof *j->imgn, e)) == NULL)
			return -1;
	}
	snprintf(p, sizeof p, "%s/z%d.code", j->scratch, z);
	if ((zz->fd = open(p, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC,
	    0600)) < 0)
		return tl_failsys(e, "%s", p);
	if (j->a->dump != NULL) {
		snprintf(p, sizeof p, "%s/%d.tif", j->a->dump, z);
		if ((zz->dz = dem_mwriter_open(p, g, e)) == NULL)
			return -1;
		snprintf(p, sizeof p, "%s/%d.valid.tif", j->a->dump, z);
		if ((zz->dv = dem_mwriter_open(p, g, e)) == NULL)
			return -1;
	}
	if (j->tree == NULL)
		return 0;
	snprintf(p, sizeof p, "%s/%d", j->tree, z);
	if (mkdir(p, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", p);
	return 0;
}

void
rg_zoom_close(rg_zoom *zz)
{
	tl_err e;

	if (zz->fd >= 0)
		close(zz->fd);
	zz->fd = -1;
	dem_mwriter_close(zz->dz, &e);
	dem_mwriter_close(zz->dv, &e);
	zz->dz = zz->dv = NULL;
}

typedef struct {
	rg_job *j;
	rg_zoom *zz;
	int z;
} band;

int
rg_zoom_ntiles(const rg_job *j, const rg_zoom *zz)
{
	long long n = 1LL << zz->g.z;

	return j->wrap && zz->ntx > n ? (int)n : zz->ntx;
}

long long
rg_zoom_column(const rg_job *j, const rg_zoom *zz, int t)
{
	long long x = zz->tx0 + t, n = 1LL << zz->g.z;

	return j->wrap && x >= n ? x - n : x;
}

/* The grid's columns c0 .. c0 + dim - 1 of row gr read into line (those
 * on the grid, k0 .. k1 - 1; false when none is). */
static int
span(const rg_zoom *zz, long long gr, long c0, int dim, uint32_t *line,
    long *k0, long *k1, tl_err *e)
{
	int w = zz->g.w;

	*k0 = c0 < 0 ? 0 : c0, *k1 = c0 + dim < w ? c0 + dim : w;
	if (*k0 >= *k1)
		return 0;
	if (tl_pread(zz->fd, line + (*k0 - c0), (size_t)(*k1 - *k0) *
	    sizeof *line, (gr * w + *k0) * (long long)sizeof *line, "scratch",
	    e) < 0)
		return -1;
	return 1;
}

/* Row y (0 .. dim - 1) of tile t of the band into line: the grid's
 * codes, those of a row or column past the grid its nearest one's, not
 * valid (the band's rows are rlo .. rhi - 1 of the tile row); where the
 * grid runs on past the world's east edge into the same tile (j->wrap),
 * the columns a world east (past the grid's first end, or valid where
 * that end's are not) in their place. */
static int
tile_row(const rg_job *j, const rg_zoom *zz, int t, int y, uint32_t *line,
    tl_err *e)
{
	int dim = j->a->dim;
	int from = y < zz->rlo ? zz->rlo : y >= zz->rhi ? zz->rhi - 1 : y;
	long long gr = zz->ty * dim + from - zz->g.y0;
	/* the tile's first column on the grid, and the span it covers */
	long c0 = (long)(zz->tx0 * dim - zz->g.x0) + (long)t * dim, k0, k1;
	long cw = c0 + (long)((long long)dim << zz->g.z), kw0, kw1;
	uint32_t mask = from == y ? ~0u : ~RG_VALID;
	int r = span(zz, gr, c0, dim, line, &k0, &k1, e), rw = 0;

	assert(r != 0);
	if (r > 0 && j->wrap)
		rw = span(zz, gr, cw, dim, line + dim, &kw0, &kw1, e);
	if (r < 0 || rw < 0)
		return -1;
	for (long i = 0; i < dim; i++) {
		long k = c0 + i, kw = cw + i;
		if (k < k0)
			line[i] = line[k0 - c0] & ~RG_VALID;
		else if (k >= k1)
			line[i] = line[k1 - 1 - c0] & ~RG_VALID;
		if (rw > 0 && kw >= kw0 && kw < kw1 && (k < k0 || k >= k1 ||
		    (line[dim + i] & ~line[i] & RG_VALID)))
			line[i] = line[dim + i];
		line[i] &= mask;
	}
	return 0;
}

/* Tile t of the band into j->img[t] (NULL when it holds no valid
 * pixel). */
static void
encode_tiles(void *arg, int k, int t0, int t1)
{
	band *b = arg;
	rg_job *j = b->j;
	rg_zoom *zz = b->zz;
	int dim = j->a->dim;

	for (int t = t0; t < t1; t++) {
		unsigned char *rgb = j->rgb[k];
		uint32_t any = 0, *line = j->line[k];

		j->img[t] = NULL;
		if (j->tfail[k] || !rg_part_owns(j, zz, t))
			continue;
		for (int r = 0; r < dim; r++) {
			if (tile_row(j, zz, t, r, line, &j->terr[k]) < 0) {
				j->tfail[k] = 1;
				break;
			}
			for (int i = 0; i < dim; i++) {
				uint32_t c = line[i];
				unsigned char *p = rgb + ((size_t)r * dim + i) * 3;
				any |= c;
				p[0] = c >> 16 & 255, p[1] = c >> 8 & 255;
				p[2] = c & 255;
			}
		}
		if (!(any & RG_VALID) || j->tfail[k])
			continue;
		if (rg_image(j->a->fmt, rgb, dim, &j->img[t], &j->imgn[t],
		    &j->terr[k]) < 0)
			j->tfail[k] = 1;
	}
}

static int
write_file(const char *path, const unsigned char *p, size_t n, tl_err *e)
{
	int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
	ssize_t k = 0;

	if (fd < 0)
		return tl_failsys(e, "%s", path);
	while (n > 0 && (k = write(fd, p, n)) > 0)
		p += k, n -= (size_t)k;
	if (k < 0 || close(fd) < 0) {
		int er = errno;
		close(fd);
		errno = er;
		return tl_failsys(e, "%s", path);
	}
	return 0;
}

/* The band's tiles encoded and written. */
static int
flush(rg_job *j, int z, tl_err *e)
{
	rg_zoom *zz = &j->zoom[z];
	band b = { j, zz, z };
	char p[4300];
	int r = 0;

	memset(j->tfail, 0, j->nt * sizeof *j->tfail);
	tl_pool_for(j->pool, rg_zoom_ntiles(j, zz), encode_tiles, &b);
	for (int k = 0; k < j->nt; k++)
		if (j->tfail[k] && r == 0)
			*e = j->terr[k], r = -1;
	for (int t = 0; t < rg_zoom_ntiles(j, zz); t++) {
		long long x = rg_zoom_column(j, zz, t);
		if (j->img[t] == NULL)
			continue;
		if (r == 0 && j->tree != NULL) {
			snprintf(p, sizeof p, "%s/%d/%lld", j->tree, z, x);
			if (mkdir(p, 0777) < 0 && errno != EEXIST)
				r = tl_failsys(e, "%s", p);
		}
		if (r == 0 && j->tree != NULL) {
			snprintf(p, sizeof p, "%s/%d/%lld/%lld.%s", j->tree, z,
			    x, zz->ty, rg_format_ext(j->a->fmt));
			r = write_file(p, j->img[t], j->imgn[t], e);
		}
		if (r == 0)
			zz->tiles++, zz->bytes += (long long)j->imgn[t];
		if (r == 0 && j->a->sink != NULL)
			r = j->a->sink(j->a->sink_ctx, z, x, zz->ty,
			    j->img[t], j->imgn[t], e);
		free(j->img[t]);
		j->img[t] = NULL;
	}
	zz->ty = -1;
	return r;
}

int
rg_zoom_cut(rg_job *j, int z, tl_err *e)
{
	rg_zoom *zz = &j->zoom[z];
	const dem_mgrid *g = &zz->g;
	int dim = j->a->dim, r = 0;

	for (long long ty = floordiv(g->y0, dim); r == 0 &&
	    ty <= floordiv(g->y0 + g->h - 1, dim); ty++) {
		long long y0 = ty * dim > g->y0 ? ty * dim : g->y0;
		long long y1 = (ty + 1) * dim < g->y0 + g->h ? (ty + 1) * dim :
		    g->y0 + g->h;
		zz->ty = ty;
		zz->rlo = (int)(y0 - ty * dim), zz->rhi = (int)(y1 - ty * dim);
		r = flush(j, z, e);
	}
	return r;
}

static int
range_fail(const rg_job *j, int z, int r, int i, double h, tl_err *e)
{
	double lo, hi;

	rg_range(j->a->enc, &lo, &hi);
	return tl_fail(e, "height %.3f m at zoom %d, pixel (%lld, %lld): "
	    "outside the %s encoding's range %.4f .. %.4f m", h, z,
	    j->zoom[z].g.x0 + i, j->zoom[z].g.y0 + r,
	    rg_encoding_name(j->a->enc), lo, hi);
}

int
rg_zoom_row(rg_job *j, int z, int r, const double *h, const double *v,
    tl_err *e)
{
	rg_zoom *zz = &j->zoom[z];
	const dem_mgrid *g = &zz->g;
	int dim = j->a->dim, w = g->w;
	long long y = g->y0 + r;

	assert(zz->on && r < g->h);
	for (int i = 0; i < w; i++) {
		long c = rg_code(j->a->enc, (float)h[i]);

		if (c < 0)
			return range_fail(j, z, r, i, h[i], e);
		j->code[i] = (uint32_t)c | (v[i] > 0 ? RG_VALID : 0);
	}
	if (tl_pwrite(zz->fd, j->code, (size_t)w * sizeof *j->code,
	    (long long)r * w * (long long)sizeof *j->code, "scratch", e) < 0)
		return -1;
	if (zz->dz != NULL) {
		for (int i = 0; i < w; i++)
			j->row[i] = (float)h[i];
		if (dem_mwriter_row(zz->dz, r, j->row, e) < 0)
			return -1;
		for (int i = 0; i < w; i++)
			j->row[i] = v[i] > 0;
		if (dem_mwriter_row(zz->dv, r, j->row, e) < 0)
			return -1;
	}
	if (zz->ty < 0)
		zz->ty = y / dim, zz->rlo = (int)(y - zz->ty * dim);
	zz->rhi = (int)(y - zz->ty * dim) + 1;
	if (zz->rhi < dim && r < g->h - 1)
		return 0;
	return flush(j, z, e);
}

int
rg_band_row(rg_job *j, int l, int z, int r, const double *h,
    const double *v, tl_err *e)
{
	rg_band *b = j->band;
	int o = b->x0 >> l, lo = b->lo[l] - o, hi = b->hi[l] - o;
	int w = j->zoom[z].g.w;

	/* only the owned columns encoded: the others may be wrong (the
	 * window's edges), and no owned tile reads them */
	for (int i = 0; i < w; i++) {
		int in = i >= lo && i < hi;
		b->h[i] = in ? h[i] : 0, b->v[i] = in ? v[i] : 0;
	}
	if (rg_zoom_row(j, z, r, b->h, b->v, e) < 0)
		return -1;
	/* j->code: the row's codes, as rg_zoom_row left them */
	return tl_pwrite(b->fd[l], j->code + lo, (size_t)(hi - lo) *
	    sizeof *j->code, (long long)r * (hi - lo) *
	    (long long)sizeof *j->code, "piece", e);
}

int
rg_band_next(rg_job *j, int r, const double *h, const double *v,
    tl_err *e)
{
	rg_band *b = j->band;
	int t = b->nl - 1, o = b->x0 >> t, n = b->hi[t] - b->lo[t];

	for (int i = 0; i < n; i++) {
		int c = b->lo[t] - o + i;
		b->f[i] = v[c] > 0 ? (float)h[c] : NAN;
	}
	return tl_pwrite(b->nfd, b->f, (size_t)n * sizeof *b->f,
	    (long long)r * n * (long long)sizeof *b->f, "piece", e);
}
