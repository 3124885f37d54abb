/* filter.c - kernels and the separable, streaming quadric filter. */
#include "core/filter.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

const filter_kernel filter_kernels[] = {
	{ "binomial", 1, { 2 / 4., 1 / 4. } },
	{ "none", 0, { 1 } },
	{ "box", 1, { 1 / 3., 1 / 3. } },
	{ "binomial5", 2, { 6 / 16., 4 / 16., 1 / 16. } },
	{ NULL, 0, { 0 } },
};

const filter_kernel *
filter_find(const char *name)
{
	for (const filter_kernel *k = filter_kernels; k->name != NULL; k++)
		if (strcmp(k->name, name) == 0)
			return k;
	return NULL;
}

double
filter_extend(const double *h, size_t stride, int n, int i)
{
	int r;

	if (i >= 0 && i < n)
		return h[(size_t)i * stride];
	if (i < 0) {
		r = -i < n ? -i : n - 1;
		return 2 * h[0] - h[(size_t)r * stride];
	}
	r = 2 * (n - 1) - i;
	if (r < 0)
		r = 0;
	return 2 * h[(size_t)(n - 1) * stride] - h[(size_t)r * stride];
}

/* q += w * r seen from the point (dx, dy, dz) of r's frame. */
static void
add_moved(quadric *q, const quadric *r, double dx, double dy, double dz,
    double w)
{
	quadric t = *r;
	double d[3] = { dx, dy, dz };

	quadric_translate(&t, d);
	quadric_add(q, &t, w);
}

int
filter_init(filter_state *f, const filter_kernel *k, int level, int fw, int fh,
    int w0, int h0, const geo_metric *m, tl_err *e)
{
	assert(k->radius >= 0 && k->radius <= FILTER_MAX_RADIUS);
	memset(f, 0, sizeof *f);
	f->w0 = w0, f->h0 = h0;
	f->k = k;
	f->level = level;
	f->fw = fw, f->fh = fh;
	f->cw = (fw - 1 + 1) / 2 + 1; /* ceil((fw-1)/2) + 1 */
	f->ch = (fh - 1 + 1) / 2 + 1;
	f->m = m;
	/* 2r+1 rows, and at least 2: a padded row's odd reflection
	 * (2h[n-1] - h[n-2]) needs the two last rows even without a kernel */
	f->nring = k->radius > 0 ? 2 * k->radius + 1 : 2;
	f->ring = tl_alloc((size_t)f->nring * f->cw, sizeof *f->ring, e);
	f->tag = tl_alloc(f->nring, sizeof *f->tag, e);
	if (f->ring == NULL || f->tag == NULL) {
		filter_free(f);
		return -1;
	}
	for (int s = 0; s < f->nring; s++)
		f->tag[s] = -1;
	return 0;
}

void
filter_free(filter_state *f)
{
	free(f->ring), free(f->tag);
	f->ring = NULL;
	f->tag = NULL;
}

int
filter_ready(const filter_state *f)
{
	int need = 2 * f->out + f->k->radius;

	if (need > f->fh - 1)
		need = f->fh - 1;
	return f->out < f->ch && f->next > need;
}

/* Horizontal pass over fine row j: into the frame of fine column 2k,
 * at the horizontally filtered reference height. */
void
filter_push(filter_state *f, const fqm_vertex *fine)
{
	const filter_kernel *k = f->k;
	int j = f->next++, slot = j % f->nring;
	fqm_vertex *out = f->ring + (size_t)slot * f->cw;
	double step = (double)(1L << f->level), sx[GEO_MAX_NODES];
	size_t st = sizeof *fine / sizeof(double);
	double vw;

	assert(j < f->fh); /* fine rows 0 .. fh-1, in order */
	f->tag[slot] = j;
	geo_row_sx(f->m, (double)((long)j << f->level), sx);
	for (int c = 0; c < f->cw; c++) {
		fqm_vertex *o = &out[c];
		/* metres between fine columns along this row, at the coarse
		 * vertex whose frame the taps move into (georef.h) */
		double s = step * geo_on_row(f->m, sx,
		    (double)((long)c << (f->level + 1)));
		double zh = 0;
		memset(o, 0, sizeof *o);
		for (int a = -k->radius; a <= k->radius; a++)
			zh += k->w[abs(a)] *
			    filter_extend(&fine[0].z, st, f->fw, 2 * c + a);
		o->z = zh;
		o->s = filter_extend(&fine[0].s, st, f->fw, 2 * c);
		vw = 0;
		for (int a = -k->radius; a <= k->radius; a++) {
			int i = 2 * c + a;
			double w = k->w[abs(a)];
			if (i >= f->fw) {
				/* past the edge: no planes there; a padded
				 * vertex no tap reaches (kernel none) takes
				 * its neighbour's, extrapolating its planes */
				if (k->radius > 0)
					continue;
				i = f->fw - 1, w = 1;
			}
			if (i < 0)
				continue;
			add_moved(&o->q, &fine[i].q, -(i - 2 * c) * s, 0,
			    zh - fine[i].z, w);
			if (i == 2 * c + a)
				o->v += w * fine[i].v, vw += w;
		}
		o->v = vw > 0 ? o->v / vw : 0;
	}
}

/* The ring row holding fine row i (it is always there: see filter_ready). */
static const fqm_vertex *
held(const filter_state *f, int i)
{
	int slot = i % f->nring;

	assert(i >= 0 && i < f->fh && f->tag[slot] == i);
	return f->tag[slot] == i ? f->ring + (size_t)slot * f->cw : NULL;
}

/* Reference-height column c of the held rows, odd-reflected past the
 * first and last fine row. */
static double
ext_rows(const filter_state *f, int c, int i, int field)
{
	const fqm_vertex *row;
	int n = f->fh, r;

	if (i >= 0 && i < n) {
		row = held(f, i);
		return field ? row[c].s : row[c].z;
	}
	if (i < 0) {
		r = -i < n ? -i : n - 1;
		return 2 * ext_rows(f, c, 0, field) - ext_rows(f, c, r, field);
	}
	r = 2 * (n - 1) - i;
	if (r < 0)
		r = 0;
	return 2 * ext_rows(f, c, n - 1, field) - ext_rows(f, c, r, field);
}

/* Vertical pass: coarse row m from fine rows 2m-r .. 2m+r. */
void
filter_pull(filter_state *f, fqm_vertex *coarse)
{
	const filter_kernel *k = f->k;
	int m = f->out, j0 = 2 * m;
	double vw, y0[GEO_MAX_NODES], y[2 * FILTER_MAX_RADIUS + 1][GEO_MAX_NODES];

	/* every fine row the taps reach is in the ring */
	assert(filter_ready(f));
	f->out++;
	/* geo_y of the coarse row and of each tap's fine row (rows are
	 * measured along the coarse vertex's column) */
	geo_row_y(f->m, (double)((long)j0 << f->level), y0);
	for (int b = -k->radius; b <= k->radius; b++) {
		int i = j0 + b < f->fh ? j0 + b : f->fh - 1;
		if (i >= 0)
			geo_row_y(f->m, (double)((long)i << f->level),
			    y[b + k->radius]);
	}
	for (int c = 0; c < f->cw; c++) {
		fqm_vertex *o = &coarse[c];
		double I = (double)((long)c << (f->level + 1));
		double zc = 0;
		memset(o, 0, sizeof *o);
		for (int b = -k->radius; b <= k->radius; b++)
			zc += k->w[abs(b)] * ext_rows(f, c, j0 + b, 0);
		o->z = zc;
		o->s = ext_rows(f, c, j0, 1);
		vw = 0;
		for (int b = -k->radius; b <= k->radius; b++) {
			int i = j0 + b;
			double w = k->w[abs(b)];
			const fqm_vertex *h;
			if (i >= f->fh) { /* as in filter_push */
				if (k->radius > 0)
					continue;
				i = f->fh - 1, w = 1;
			}
			if (i < 0)
				continue;
			h = &held(f, i)[c];
			add_moved(&o->q, &h->q, 0, geo_on_row(f->m, y0, I) -
			    geo_on_row(f->m, y[b + k->radius], I), zc - h->z,
			    w);
			if (i == j0 + b)
				o->v += w * h->v, vw += w;
		}
		o->v = vw > 0 ? o->v / vw : 0;
		/* past the DEM's last sample: padding, marked invalid */
		if ((long)c << (f->level + 1) > f->w0 - 1 ||
		    (long)m << (f->level + 1) > f->h0 - 1)
			o->v = 0;
	}
}
