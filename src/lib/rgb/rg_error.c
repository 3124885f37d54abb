/* rg_error.c - the error of the surface MapLibre draws (rg_impl.h): at
 * every valid sample of the DEM on the deepest zoom's grid, the vertical
 * distance to each zoom's decoded heights interpolated bilinearly
 * between its vertices (Terrain.getDEMElevation's surface), a zoom per
 * thread of the pool, in a fixed order (the same sums for any count). */
#include <math.h>
#include <stdlib.h>

#include "rgb/rg_impl.h"

typedef struct {
	int z, l, cached[2];
	float *row[2];
	double max, sum;
	long long n;
	int fail;
	tl_err e;
} zerr;

typedef struct {
	rg_job *j;
	zerr *ze;
	const dem_mgrid *g;
	const float *dz;
	const unsigned char *dv;
	int y;
} pass;

/* Row k of zoom ze's scratch, cached by parity. */
static const float *
zrow(rg_job *j, zerr *ze, int k)
{
	rg_zoom *zz = &j->zoom[ze->z];
	int s = k & 1;

	if (ze->cached[s] != k) {
		if (tl_pread(zz->fd, ze->row[s], (size_t)zz->g.w * sizeof(float),
		    (long long)k * zz->g.w * (long long)sizeof(float),
		    "scratch", &ze->e) < 0) {
			ze->fail = 1;
			return NULL;
		}
		ze->cached[s] = k;
	}
	return ze->row[s];
}

static void
measure(void *arg, int k, int i0, int i1)
{
	pass *p = arg;

	for (int q = i0; q < i1; q++) {
		zerr *ze = &p->ze[q];
		const dem_mgrid *zg = &p->j->zoom[ze->z].g;
		double s = ldexp(1, -ze->l);
		double gy = (p->g->y0 + p->y) * s - zg->y0, ty;
		int r0 = (int)floor(gy), r1;
		const float *a, *b;

		if (ze->fail)
			continue;
		r1 = r0 + 1 < zg->h ? r0 + 1 : r0;
		ty = gy - r0;
		if ((a = zrow(p->j, ze, r0)) == NULL ||
		    (b = zrow(p->j, ze, r1)) == NULL)
			continue;
		for (int i = 0; i < p->g->w; i++) {
			double gx, tx, h, d;
			int c0, c1;

			if (!p->dv[i])
				continue;
			gx = (p->g->x0 + i) * s - zg->x0;
			c0 = (int)floor(gx);
			c1 = c0 + 1 < zg->w ? c0 + 1 : c0;
			tx = gx - c0;
			h = (a[c0] * (1 - tx) + a[c1] * tx) * (1 - ty) +
			    (b[c0] * (1 - tx) + b[c1] * tx) * ty;
			d = fabs(h - p->dz[i]);
			ze->max = fmax(ze->max, d);
			ze->sum += d * d;
			ze->n++;
		}
	}
	(void)k;
}

int
rg_error(rg_job *j, dem *ref, const dem_mgrid *g, rg_report *rep,
    tl_err *e)
{
	int nz = rep->maxzoom - rep->minzoom + 1, r = 0;
	zerr *ze = tl_alloc(nz, sizeof *ze, e);
	float *dz = tl_alloc(g->w, sizeof *dz, e);
	unsigned char *dv = tl_alloc(g->w, 1, e);
	pass p = { j, ze, g, dz, dv, 0 };

	if (ze == NULL || dz == NULL || dv == NULL)
		r = -1;
	for (int q = 0; r == 0 && q < nz; q++) {
		int z = rep->maxzoom - q, w = j->zoom[z].g.w;
		ze[q].z = z, ze[q].l = q;
		ze[q].cached[0] = ze[q].cached[1] = -1;
		if ((ze[q].row[0] = tl_alloc(w, sizeof(float), e)) == NULL ||
		    (ze[q].row[1] = tl_alloc(w, sizeof(float), e)) == NULL)
			r = -1;
	}
	for (int y = 0; r == 0 && y < g->h; y++) {
		if ((r = dem_read_row(ref, y, dz, dv, e)) < 0)
			break;
		p.y = y;
		tl_pool_for(j->pool, nz, measure, &p);
		for (int q = 0; q < nz; q++)
			if (ze[q].fail && r == 0)
				*e = ze[q].e, r = -1;
	}
	for (int q = 0; ze != NULL && q < nz; q++) {
		int z = ze[q].z;
		rep->max[z] = ze[q].max, rep->n[z] = ze[q].n;
		rep->rms[z] = ze[q].n ? sqrt(ze[q].sum / ze[q].n) : 0;
		free(ze[q].row[0]), free(ze[q].row[1]);
	}
	free(ze), free(dz), free(dv);
	return r;
}
