/* tr_measure.c - a tile as the renderer gets it (u, v, height quantised
 * to 0 .. 32767, triangles counter-clockwise, vertices in order of first
 * use for the high-water mark) and its error: for every level-0 sample
 * of the pyramid in the tile, the distance along the ellipsoid's normal
 * at the sample between the sample and the plane, in ECEF, of the drawn
 * triangle over it, between the DECODED vertices. Nothing is assumed:
 * the selection's error, the flat chords' sag, the quantisation, all
 * are in what is measured. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geo/wgs84.h"
#include "terrain/tr_impl.h"

#define NB 32 /* buckets a side for finding a sample's triangle */

const pyramid_block *
tr_block(tr_work *w, int l, int bi, int bj, tl_err *e)
{
	int s = (bi * 7 + bj * 13 + l * 31) & 31;
	pyramid_block *b = &w->cache[s];

	if (w->cused[s] == 1 && w->ckey[s][0] == l && w->ckey[s][1] == bi &&
	    w->ckey[s][2] == bj)
		return b;
	if (w->cused[s] == 0 && pyramid_block_alloc(b, 0, e) < 0)
		return NULL;
	w->cused[s] = 2; /* allocated, holding nothing */
	if (w->ix->lev[l].displaced)
		return tl_fail(e, "%s: level %d is displaced (QEM-3D): not "
		    "exported", w->dir, l), NULL;
	b->level = l, b->bi = bi, b->bj = bj, b->displaced = 0;
	if (pyramid_block_load(w->dir, w->ix, b, e) < 0)
		return NULL;
	w->cused[s] = 1;
	w->ckey[s][0] = l, w->ckey[s][1] = bi, w->ckey[s][2] = bj;
	return b;
}

static int
grow(tr_work *w, tl_err *e)
{
	size_t n = (size_t)w->m.cv;
	uint16_t *u = realloc(w->u, n * sizeof *u), *v, *q;

	if (u)
		w->u = u;
	v = u ? realloc(w->v, n * sizeof *v) : NULL;
	if (v)
		w->v = v;
	q = v ? realloc(w->q, n * sizeof *q) : NULL;
	if (q)
		w->q = q;
	double *p = q ? realloc(w->pos, 3 * n * sizeof *p) : NULL;
	if (p)
		w->pos = p;
	int *o = p ? realloc(w->order, n * sizeof *o) : NULL;
	if (o)
		w->order = o;
	int *t = o ? realloc(w->tmp, 3 * n * sizeof *t) : NULL;
	if (t == NULL)
		return tl_fail(e, "tile: out of memory");
	w->tmp = t;
	return 0;
}

static long
qarea(const tr_work *w, const int *k)
{
	long ax = w->u[k[1]] - w->u[k[0]], ay = w->v[k[1]] - w->v[k[0]];
	long bx = w->u[k[2]] - w->u[k[0]], by = w->v[k[2]] - w->v[k[0]];

	return ax * by - ay * bx;
}

/* Vertices renumbered by first use; unused ones dropped. */
static void
renumber(tr_work *w)
{
	tr_mesh *m = &w->m;
	int n = 0;

	for (int i = 0; i < m->nv; i++)
		w->order[i] = -1;
	for (int i = 0; i < 3 * m->nt; i++) {
		int k = m->tri[i];
		if (w->order[k] < 0)
			w->order[k] = n++;
		m->tri[i] = w->order[k];
	}
	for (int i = 0; i < m->nv; i++) {
		int k = w->order[i];
		if (k < 0)
			continue;
		/* k <= i: compacting in place from the front is safe only
		 * through copies */
		w->tmp[3 * k] = w->u[i], w->tmp[3 * k + 1] = w->v[i];
		w->tmp[3 * k + 2] = w->q[i];
		w->pos[3 * k] = m->h[i];
	}
	for (int k = 0; k < n; k++) {
		w->u[k] = (uint16_t)w->tmp[3 * k];
		w->v[k] = (uint16_t)w->tmp[3 * k + 1];
		w->q[k] = (uint16_t)w->tmp[3 * k + 2];
		m->h[k] = w->pos[3 * k];
	}
	m->nv = n;
}

int
tr_quantise(tr_work *w, int z, int x, int y, float *minh, float *maxh,
    tl_err *e)
{
	tr_mesh *m = &w->m;
	double r[4], wd = ldexp(180, -z), lo = INFINITY, hi = -INFINITY;
	int nt = 0;

	if (grow(w, e) < 0)
		return -1;
	tr_tile_rect(z, x, y, r);
	for (int i = 0; i < m->nv; i++) {
		double lon = w->g.ax + w->g.bx * m->x[i];
		double lat = w->g.ay + w->g.by * m->y[i];
		double u = rint((lon - r[0]) / wd * QM_MAX);
		double v = rint((lat - r[1]) / wd * QM_MAX);
		w->u[i] = (uint16_t)fmax(0, fmin(QM_MAX, u));
		w->v[i] = (uint16_t)fmax(0, fmin(QM_MAX, v));
		w->q[i] = 0;
	}
	/* counter-clockwise in longitude, latitude; those quantisation
	 * leaves without area dropped */
	for (int t = 0; t < m->nt; t++) {
		int *k = m->tri + 3 * t;
		double ax = m->x[k[1]] - m->x[k[0]], ay = m->y[k[1]] - m->y[k[0]];
		double bx = m->x[k[2]] - m->x[k[0]], by = m->y[k[2]] - m->y[k[0]];
		if ((ax * by - ay * bx) * w->g.bx * w->g.by < 0) {
			int s = k[1];
			k[1] = k[2], k[2] = s;
		}
		if (qarea(w, k) <= 0)
			continue;
		memmove(m->tri + 3 * nt++, k, 3 * sizeof *k);
	}
	m->nt = nt;
	renumber(w);
	/* the header's heights: the used vertices' extremes, as floats
	 * holding them; the extremes decode to them exactly */
	for (int i = 0; i < m->nv; i++)
		lo = fmin(lo, m->h[i]), hi = fmax(hi, m->h[i]);
	*minh = (float)lo, *maxh = (float)hi;
	if (*minh > lo)
		*minh = nextafterf(*minh, -INFINITY);
	if (*maxh < hi)
		*maxh = nextafterf(*maxh, INFINITY);
	for (int i = 0; i < m->nv; i++) {
		double q = *maxh > *minh ? rint((m->h[i] - *minh) /
		    ((double)*maxh - *minh) * QM_MAX) : 0;
		w->q[i] = (uint16_t)fmax(0, fmin(QM_MAX, q));
		if (m->h[i] == hi)
			w->q[i] = QM_MAX; /* not 32766 for a float's rounding */
		if (m->h[i] == lo)
			w->q[i] = 0;
	}
	for (int i = 0; i < m->nv; i++) {
		double tu = w->u[i] / (double)QM_MAX, tv = w->v[i] / (double)QM_MAX;
		double tq = w->q[i] / (double)QM_MAX;
		geo_ecef((1 - tu) * r[0] + tu * r[2], (1 - tv) * r[1] + tv * r[3],
		    (1 - tq) * *minh + tq * *maxh, w->pos + 3 * i);
	}
	return 0;
}

/* Triangles by bucket of the u, v square (CSR in w->tmp-like arrays). */
typedef struct {
	int *start, *list;
	double *plane; /* per triangle: normal, offset (4) */
} locator;

static int
locate_init(tr_work *w, locator *l, tl_err *e)
{
	tr_mesh *m = &w->m;
	long total = 0;

	l->start = calloc(NB * NB + 1, sizeof *l->start);
	l->plane = malloc((size_t)(m->nt ? m->nt : 1) * 4 * sizeof *l->plane);
	if (!l->start || !l->plane)
		return tl_fail(e, "tile: out of memory");
	for (int pass = 0; pass < 2; pass++) {
		for (int t = 0; t < m->nt; t++) {
			const int *k = m->tri + 3 * t;
			int b0 = QM_MAX, b1 = 0, c0 = QM_MAX, c1 = 0;
			for (int j = 0; j < 3; j++) {
				b0 = w->u[k[j]] < b0 ? w->u[k[j]] : b0;
				b1 = w->u[k[j]] > b1 ? w->u[k[j]] : b1;
				c0 = w->v[k[j]] < c0 ? w->v[k[j]] : c0;
				c1 = w->v[k[j]] > c1 ? w->v[k[j]] : c1;
			}
			for (int bj = c0 * NB / (QM_MAX + 1); bj <= c1 * NB /
			    (QM_MAX + 1); bj++)
				for (int bi = b0 * NB / (QM_MAX + 1); bi <= b1 *
				    NB / (QM_MAX + 1); bi++) {
					if (pass == 0)
						l->start[bj * NB + bi + 1]++;
					else
						l->list[l->start[bj * NB + bi]++] = t;
				}
		}
		if (pass == 0) {
			for (int i = 0; i < NB * NB; i++)
				l->start[i + 1] += l->start[i];
			total = l->start[NB * NB];
			if ((l->list = malloc((size_t)(total ? total : 1) *
			    sizeof *l->list)) == NULL)
				return tl_fail(e, "tile: out of memory");
		} else {
			for (int i = NB * NB; i > 0; i--)
				l->start[i] = l->start[i - 1];
			l->start[0] = 0;
		}
	}
	for (int t = 0; t < m->nt; t++) {
		const int *k = m->tri + 3 * t;
		const double *a = w->pos + 3 * k[0], *b = w->pos + 3 * k[1],
		    *c = w->pos + 3 * k[2];
		double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
		double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
		double *n = l->plane + 4 * t;
		n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2];
		n[2] = u[0] * v[1] - u[1] * v[0];
		n[3] = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
	}
	return 0;
}

/* The triangle over (su, sv): the one of its bucket with the largest
 * least barycentric coordinate (inside: >= 0). */
static int
locate(const tr_work *w, const locator *l, double su, double sv)
{
	int bi = (int)(su * NB / (QM_MAX + 1)), bj = (int)(sv * NB /
	    (QM_MAX + 1)), best = -1;
	double bv = -INFINITY;

	bi = bi < 0 ? 0 : bi >= NB ? NB - 1 : bi;
	bj = bj < 0 ? 0 : bj >= NB ? NB - 1 : bj;
	for (int i = l->start[bj * NB + bi]; i < l->start[bj * NB + bi + 1];
	    i++) {
		const int *k = w->m.tri + 3 * l->list[i];
		double x0 = w->u[k[0]], y0 = w->v[k[0]];
		double x1 = w->u[k[1]] - x0, y1 = w->v[k[1]] - y0;
		double x2 = w->u[k[2]] - x0, y2 = w->v[k[2]] - y0;
		double d = x1 * y2 - x2 * y1, px = su - x0, py = sv - y0;
		double b1 = (px * y2 - x2 * py) / d, b2 = (x1 * py - px * y1) / d;
		double mn = fmin(1 - b1 - b2, fmin(b1, b2));
		if (mn > bv)
			bv = mn, best = l->list[i];
	}
	return best;
}

static int
measure_block(tr_work *w, const locator *l, int bi, int bj, const int s[4],
    const double r[4], double *err, tl_err *e)
{
	const pyramid_block *b = tr_block(w, 0, bi, bj, e);
	double wd = r[2] - r[0];

	if (b == NULL)
		return -1;
	for (int J = s[1]; J <= s[3]; J++) {
		if (J < bj * BT_CELLS || J > bj * BT_CELLS + BT_CELLS)
			continue;
		double lat = w->g.ay + w->g.by * J;
		for (int I = s[0]; I <= s[2]; I++) {
			if (I < bi * BT_CELLS || I > bi * BT_CELLS + BT_CELLS)
				continue;
			double lon = w->g.ax + w->g.bx * I, f[3], up[3];
			int t = locate(w, l, (lon - r[0]) / wd * QM_MAX,
			    (lat - r[1]) / wd * QM_MAX);
			if (t < 0)
				return tl_fail(e, "tile: sample (%d, %d) under no "
				    "triangle", I, J);
			const double *n = l->plane + 4 * t;
			geo_ellipsoid(lon, lat, f, up);
			double hs = (n[3] - n[0] * f[0] - n[1] * f[1] - n[2] * f[2]) /
			    (n[0] * up[0] + n[1] * up[1] + n[2] * up[2]);
			double z = b->z[(J - bj * BT_CELLS) * BT_SIZE + I -
			    bi * BT_CELLS];
			*err = fmax(*err, fabs(hs - z));
		}
	}
	return 0;
}

int
tr_measure(tr_work *w, int z, int x, int y, double *err, tl_err *e)
{
	locator l = { 0 };
	double r[4], g[4];
	int s[4], ret = -1;

	*err = 0;
	tr_tile_rect(z, x, y, r);
	g[0] = (r[0] - w->g.ax) / w->g.bx, g[2] = (r[2] - w->g.ax) / w->g.bx;
	g[1] = (r[1] - w->g.ay) / w->g.by, g[3] = (r[3] - w->g.ay) / w->g.by;
	s[0] = (int)ceil(fmax(0, fmin(g[0], g[2])));
	s[2] = (int)floor(fmin(w->g.w0 - 1, fmax(g[0], g[2])));
	s[1] = (int)ceil(fmax(0, fmin(g[1], g[3])));
	s[3] = (int)floor(fmin(w->g.h0 - 1, fmax(g[1], g[3])));
	if (s[0] > s[2] || s[1] > s[3])
		return 0; /* no sample */
	if (locate_init(w, &l, e) < 0)
		goto done;
	for (int bj = s[1] / BT_CELLS; bj <= s[3] / BT_CELLS; bj++)
		for (int bi = s[0] / BT_CELLS; bi <= s[2] / BT_CELLS; bi++) {
			int bj2 = bj >= w->ix->lev[0].blocks[1] ? bj - 1 : bj;
			int bi2 = bi >= w->ix->lev[0].blocks[0] ? bi - 1 : bi;
			if (measure_block(w, &l, bi2, bj2, s, r, err, e) < 0)
				goto done;
		}
	ret = 0;
done:
	free(l.start), free(l.list), free(l.plane);
	return ret;
}
