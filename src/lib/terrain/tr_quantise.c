/* tr_quantise.c - a tile as the renderer gets it: u, v and height
 * quantised to 0 .. 32767, triangles counter-clockwise, vertices in
 * order of first use for the high-water mark, and decoded back to ECEF
 * (the surface the renderer draws, which tr_measure.c measures). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geo/wgs84.h"
#include "terrain/tr_impl.h"

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

/* Vertices renumbered by first use; unused ones dropped but on the
 * tile's edges. */
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
	/* an edge vertex whose triangles all lost their area to the
	 * quantisation stays, after the others: the neighbour has it */
	for (int i = 0; i < m->nv; i++)
		if (w->order[i] < 0 && (w->u[i] == 0 || w->u[i] == QM_MAX ||
		    w->v[i] == 0 || w->v[i] == QM_MAX))
			w->order[i] = n++;
	for (int i = 0; i < m->nv; i++) {
		int k = w->order[i];
		if (k < 0)
			continue;
		/* k <= i: compacting in place from the front is safe only
		 * through copies */
		w->tmp[3 * k] = w->u[i], w->tmp[3 * k + 1] = w->v[i];
		w->tmp[3 * k + 2] = w->q[i];
		w->pos[3 * k] = m->x[i], w->pos[3 * k + 1] = m->y[i];
		w->pos[3 * k + 2] = m->h[i];
	}
	for (int k = 0; k < n; k++) {
		w->u[k] = (uint16_t)w->tmp[3 * k];
		w->v[k] = (uint16_t)w->tmp[3 * k + 1];
		w->q[k] = (uint16_t)w->tmp[3 * k + 2];
		m->x[k] = w->pos[3 * k], m->y[k] = w->pos[3 * k + 1];
		m->h[k] = w->pos[3 * k + 2];
	}
	m->nv = n;
}

/* A triangle a m b that quantisation made a segment (three vertices in
 * a line, m between): the triangle on the other side of a b would leave
 * m on its side, a T-junction; it is split at m. */
static int
unsplit(tr_work *w, const int d[3], tl_err *e)
{
	tr_mesh *m = &w->m;
	int mid = -1, a, b;

	for (int i = 0; i < 3 && mid < 0; i++) {
		int p = d[i], q = d[(i + 1) % 3], r = d[(i + 2) % 3];
		long t = (long)(w->u[p] - w->u[q]) * (w->u[p] - w->u[r]) +
		    (long)(w->v[p] - w->v[q]) * (w->v[p] - w->v[r]);
		if (t < 0) /* p between q and r */
			mid = p, a = q, b = r;
	}
	if (mid < 0)
		return 0;
	for (int t = 0; t < m->nt; t++) {
		int *k = m->tri + 3 * t;
		for (int i = 0; i < 3; i++) {
			int p = k[i], q = k[(i + 1) % 3], c = k[(i + 2) % 3];
			if (!((p == a && q == b) || (p == b && q == a)))
				continue;
			/* a projected DEM's sliver turned over (tr_rim.c):
			 * only into the triangle that now holds mid */
			int t1[3] = { p, mid, c }, t2[3] = { mid, q, c };
			if (m->rim && (qarea(w, t1) <= 0 || qarea(w, t2) <= 0))
				continue;
			k[0] = p, k[1] = mid, k[2] = c;
			if (tr_mesh_tri(m, mid, q, c, e) < 0)
				return -1;
			return tr_rim_inherit(m, t, e);
		}
	}
	return 0;
}

/* Vertices that quantise to one u, v become one (an edge collapse: the
 * triangles between them lose their area and go, the others keep the
 * mesh closed), the one first in (longitude, latitude) order standing for
 * them, so that two tiles merge their shared edge's vertices alike; the
 * others are marked dead (u = v = 0xFFFF) and their triangles remapped. */
static void
merge(tr_work *w)
{
	tr_mesh *m = &w->m;
	unsigned cap = 1;
	int *tab = w->tmp;

	while (2 * cap <= 3 * (unsigned)m->cv)
		cap *= 2;
	for (unsigned i = 0; i < cap; i++)
		tab[i] = -1;
	for (int i = 0; i < m->nv; i++) {
		unsigned k = ((unsigned)w->u[i] * 32771u + w->v[i]) * 2654435761u &
		    (cap - 1);
		for (;; k = (k + 1) & (cap - 1)) {
			int j = tab[k];
			if (j < 0) {
				tab[k] = i;
				break;
			}
			if (w->u[j] != w->u[i] || w->v[j] != w->v[i])
				continue;
			if (m->x[i] < m->x[j] || (m->x[i] == m->x[j] &&
			    m->y[i] < m->y[j]))
				tab[k] = i;
			break;
		}
	}
	for (int i = 0; i < m->nv; i++) {
		unsigned k = ((unsigned)w->u[i] * 32771u + w->v[i]) * 2654435761u &
		    (cap - 1);
		while (w->u[tab[k]] != w->u[i] || w->v[tab[k]] != w->v[i])
			k = (k + 1) & (cap - 1);
		w->order[i] = tab[k];
	}
	for (int i = 0; i < 3 * m->nt; i++)
		m->tri[i] = w->order[m->tri[i]];
	for (int i = 0; i < m->nv; i++)
		if (w->order[i] != i)
			w->u[i] = w->v[i] = 0xFFFF;
}

int
tr_quantise(tr_work *w, int z, int x, int y, float *minh, float *maxh,
    tl_err *e)
{
	tr_mesh *m = &w->m;
	double r[4], wd = ldexp(180, -z), lo = INFINITY, hi = -INFINITY;
	int nt = 0, drop[256][3], ndrop = 0;

	if (grow(w, e) < 0)
		return -1;
	tr_tile_rect(z, x, y, r);
	for (int i = 0; i < m->nv; i++) {
		double u = rint((m->x[i] - r[0]) / wd * QM_MAX);
		double v = rint((m->y[i] - r[1]) / wd * QM_MAX);
		/* on the tile's edge exactly, or off it: a vertex near the
		 * edge does not join the edge lists, which are the vertices
		 * the neighbour shares */
		u = m->x[i] == r[0] ? 0 : m->x[i] == r[2] ? QM_MAX :
		    fmax(1, fmin(QM_MAX - 1, u));
		v = m->y[i] == r[1] ? 0 : m->y[i] == r[3] ? QM_MAX :
		    fmax(1, fmin(QM_MAX - 1, v));
		w->u[i] = (uint16_t)u, w->v[i] = (uint16_t)v;
		w->q[i] = 0;
	}
	merge(w);
	/* counter-clockwise in longitude, latitude; those quantisation
	 * leaves without area dropped */
	for (int t = 0; t < m->nt; t++) {
		int *k = m->tri + 3 * t;
		double ax = m->x[k[1]] - m->x[k[0]], ay = m->y[k[1]] - m->y[k[0]];
		double bx = m->x[k[2]] - m->x[k[0]], by = m->y[k[2]] - m->y[k[0]];
		if (ax * by - ay * bx < 0) {
			int s = k[1];
			k[1] = k[2], k[2] = s;
		}
		if (qarea(w, k) <= 0) {
			if ((qarea(w, k) == 0 || m->rim) && k[0] != k[1] &&
			    k[1] != k[2] &&
			    k[0] != k[2] && ndrop < (int)(sizeof drop /
			    sizeof drop[0]))
				memcpy(drop[ndrop++], k, sizeof drop[0]);
			continue;
		}
		if (m->rim)
			m->rim[nt] = m->rim[t], m->src[nt] = m->src[t];
		memmove(m->tri + 3 * nt++, k, 3 * sizeof *k);
	}
	m->nt = nt;
	for (int i = 0; i < ndrop; i++)
		if (unsplit(w, drop[i], e) < 0)
			return -1;
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
