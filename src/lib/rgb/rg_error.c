/* rg_error.c - the error of the surface MapLibre draws (rg_impl.h): at
 * every valid sample of the DEM itself (read as the warp read it, heights
 * as the tiles hold them, each placed on Web Mercator through PROJ), the
 * vertical distance to each zoom's decoded heights interpolated
 * bilinearly between its pixel centres (terrain_coverage.ts's sampler;
 * across tiles through the backfilled neighbours, so one surface over
 * the zoom's grid, clamped at its edges as a tile with no neighbour is),
 * a zoom per thread of the pool, in a fixed order (the same sums for any
 * count). A zoom keeps the span of its rows one DEM row reaches, decoded
 * from its scratch of codes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rgb/rg_impl.h"
#include "geo/wgs84.h"

typedef struct {
	int z, l;
	float *buf;       /* rows lo .. lo + nr - 1 of the zoom */
	int lo, nr, cap;
	double max, sum;
	long long n;
	int fail;
	tl_err e;
} zerr;

typedef struct {
	rg_job *j;
	zerr *ze;
	int w;
	const double *px, *py; /* deepest zoom's pixel-corner coordinates */
	double ylo, yhi;       /* of the row's valid samples */
	double res;            /* the deepest zoom's pixel, metres */
	double wx0, ww;        /* the grid's first column and the world's
	                        * width: a sample is placed in the world
	                        * from wx0 east (across the antimeridian,
	                        * or given past 180) */
	const float *dz;
	const unsigned char *dv;
} pass;

/* Grid coordinate of global deepest-zoom position p (pixel corners,
 * s = 2^-l): between the zoom's pixel centres c0 and *c1 = c0 + 1 at
 * fraction *t, clamped to the grid's n (MapLibre's border, backfilled
 * from a tile's own edge where no neighbour is). */
static int
cell(double p, double s, long long o, int n, int *c1, double *t)
{
	double u = p * s - 0.5 - (double)o;
	int c0;

	if (!(u > 0))
		u = 0;
	if (u > n - 1)
		u = n - 1;
	c0 = (int)floor(u);
	*t = u - c0;
	*c1 = c0 + 1 < n ? c0 + 1 : c0;
	return c0;
}

/* The zoom's rows lo .. hi in ze->buf, those held kept. */
static int
span(rg_job *j, zerr *ze, int lo, int hi)
{
	rg_zoom *zz = &j->zoom[ze->z];
	size_t w = (size_t)zz->g.w;
	int n = hi - lo + 1, keep0 = -1, keep1 = -2;

	if (n > ze->cap) {
		float *b = malloc((size_t)n * w * sizeof *b);
		if (b == NULL) {
			ze->fail = 1;
			tl_fail(&ze->e, "out of memory");
			return -1;
		}
		if (ze->nr > 0)
			memcpy(b, ze->buf, (size_t)ze->nr * w * sizeof *b);
		free(ze->buf);
		ze->buf = b, ze->cap = n;
	}
	if (ze->nr > 0) {
		keep0 = lo > ze->lo ? lo : ze->lo;
		keep1 = hi < ze->lo + ze->nr - 1 ? hi : ze->lo + ze->nr - 1;
	}
	if (keep0 <= keep1)
		memmove(ze->buf + (size_t)(keep0 - lo) * w,
		    ze->buf + (size_t)(keep0 - ze->lo) * w,
		    (size_t)(keep1 - keep0 + 1) * w * sizeof *ze->buf);
	for (int r = lo; r <= hi; r++) {
		float *b = ze->buf + (size_t)(r - lo) * w;
		if (r >= keep0 && r <= keep1)
			continue;
		/* the row's codes, decoded in place (4 bytes each) */
		if (tl_pread(zz->fd, b, w * sizeof(uint32_t), (long long)r *
		    (long long)w * (long long)sizeof(uint32_t), "scratch",
		    &ze->e) < 0) {
			ze->fail = 1, ze->nr = 0;
			return -1;
		}
		for (size_t i = 0; i < w; i++) {
			uint32_t c;
			memcpy(&c, b + i, sizeof c);
			b[i] = (float)rg_decode(j->a->enc, c & (RG_VALID - 1));
		}
	}
	ze->lo = lo, ze->nr = n;
	return 0;
}

static void
measure_zoom(pass *p, zerr *ze)
{
	const dem_mgrid *zg = &p->j->zoom[ze->z].g;
	double s = ldexp(1, -ze->l), t;
	int a, lo = cell(p->ylo, s, zg->y0, zg->h, &a, &t), hi;

	cell(p->yhi, s, zg->y0, zg->h, &hi, &t);
	if (ze->fail || span(p->j, ze, lo, hi) < 0)
		return;
	for (int i = 0; i < p->w; i++) {
		double tx, ty, h, d;
		int c0, c1, r0, r1;
		const float *ra, *rb;

		if (!p->dv[i])
			continue;
		c0 = cell(p->px[i], s, zg->x0, zg->w, &c1, &tx);
		r0 = cell(p->py[i], s, zg->y0, zg->h, &r1, &ty);
		ra = ze->buf + (size_t)(r0 - lo) * zg->w;
		rb = ze->buf + (size_t)(r1 - lo) * zg->w;
		h = (ra[c0] * (1 - tx) + ra[c1] * tx) * (1 - ty) +
		    (rb[c0] * (1 - tx) + rb[c1] * tx) * ty;
		d = fabs(h - p->dz[i]);
		ze->max = fmax(ze->max, d);
		ze->sum += d * d;
		ze->n++;
	}
}

static void
measure(void *arg, int k, int i0, int i1)
{
	for (int q = i0; q < i1; q++)
		measure_zoom(arg, &((pass *)arg)->ze[q]);
	(void)k;
}

/* Row y's samples placed: p->px, p->py, and the span of the valid. */
static int
place(pass *p, const georef *g, geo_proj *pj, double *x, double *y,
    double *z, int row, double res, tl_err *e)
{
	p->ylo = INFINITY, p->yhi = -INFINITY;
	for (int i = 0; i < p->w; i++) {
		geo_vertex_crs(g, 0, i, row, &x[i], &y[i]);
		z[i] = 0;
	}
	if (geo_proj_lonlat(pj, x, y, z, p->w, e) < 0)
		return -1;
	for (int i = 0; i < p->w; i++) {
		x[i] = rg_merc_x(x[i], res), y[i] = rg_merc_y(y[i], res);
		if (x[i] < p->wx0)
			x[i] += p->ww;
		else if (x[i] >= p->wx0 + p->ww)
			x[i] -= p->ww;
		if (p->dv[i] && isfinite(x[i]) && isfinite(y[i]))
			p->ylo = fmin(p->ylo, y[i]), p->yhi = fmax(p->yhi, y[i]);
		else
			((unsigned char *)p->dv)[i] = 0;
	}
	return 0;
}

static int
rows(rg_job *j, dem *src, pass *p, int nz, tl_err *e)
{
	const georef *g = dem_georef(src);
	double res = p->res;
	double *x = tl_alloc(g->width, sizeof *x, e);
	double *y = tl_alloc(g->width, sizeof *y, e);
	double *z = tl_alloc(g->width, sizeof *z, e);
	geo_proj pj = { 0 };
	int r = x && y && z ? geo_proj_open(&pj, g, e) : -1;

	p->px = x, p->py = y;
	for (int row = 0; r == 0 && row < g->height; row++) {
		if ((r = dem_read_row(src, row, (float *)p->dz,
		    (unsigned char *)p->dv, e)) < 0 ||
		    (r = place(p, g, &pj, x, y, z, row, res, e)) < 0)
			break;
		if (p->ylo > p->yhi)
			continue; /* no valid sample */
		tl_pool_for(j->pool, nz, measure, p);
		for (int q = 0; q < nz; q++)
			if (p->ze[q].fail && r == 0)
				*e = p->ze[q].e, r = -1;
	}
	if (pj.ctx != NULL)
		geo_proj_close(&pj);
	free(x), free(y), free(z);
	return r;
}

int
rg_error(rg_job *j, dem *src, rg_report *rep, tl_err *e)
{
	int nz = rep->maxzoom - rep->minzoom + 1, r = 0;
	int w = dem_georef(src)->width;
	zerr *ze = tl_alloc(nz, sizeof *ze, e);
	float *dz = tl_alloc(w, sizeof *dz, e);
	unsigned char *dv = tl_alloc(w, 1, e);
	const dem_mgrid *g = &j->zoom[rep->maxzoom].g;
	pass p = { j, ze, w, NULL, NULL, 0, 0, dem_mgrid_res(g),
	    (double)g->x0, ldexp(g->dim, g->z), dz, dv };

	if (ze == NULL || dz == NULL || dv == NULL)
		r = -1;
	for (int q = 0; r == 0 && q < nz; q++)
		ze[q].z = rep->maxzoom - q, ze[q].l = q;
	if (r == 0)
		r = rows(j, src, &p, nz, e);
	for (int q = 0; ze != NULL && q < nz; q++) {
		int z = ze[q].z;
		rep->max[z] = ze[q].max, rep->n[z] = ze[q].n;
		rep->rms[z] = ze[q].n ? sqrt(ze[q].sum / ze[q].n) : 0;
		free(ze[q].buf);
	}
	free(ze), free(dz), free(dv);
	return r;
}
