/* tr_measure.c - a tile as the renderer gets it (u, v, height quantised
 * to 0 .. 32767, triangles counter-clockwise, vertices in order of first
 * use for the high-water mark) and its error. At every level-0 sample of
 * the pyramid in the tile, the height of the drawn surface (the plane,
 * in ECEF, of the triangle over it between the DECODED vertices, met by
 * the ellipsoid's normal through the sample) is compared with the
 * selection's surface there (the same triangle before quantisation,
 * linear in longitude, latitude, height): d[0], the largest difference,
 * holds every term but the selection's own error (the flat chords' sag,
 * the quantisation, the CRS mapping), which the pyramid's saturated
 * errors bound for the valid samples; and with the sample's height:
 * d[1], the error itself, filled voids included. */
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
			m->rim[nt] = m->rim[t];
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

/* The triangles by bucket of a grid over the part of the u, v square
 * that holds samples (the tile within the terrain's rectangle), about
 * one triangle a bucket; per triangle the terms of its barycentric
 * coordinates in u, v and in longitude, latitude, computed once (the
 * same operations per sample as computing them there). */
typedef struct {
	int *start, *list, nb;
	double o[2], s[2];  /* bucket of (u, v): ((u, v) - o) * s */
	double *plane;      /* per triangle: normal, offset (4) */
	double *bq;         /* per triangle in u, v: x0 y0 x1 y1 x2 y2 d */
	double *bf;         /* in lon, lat: the same, then h0, h1-h0, h2-h0 */
} locator;

static inline double
dmin(double a, double b)
{
	return b < a ? b : a;
}

static inline double
dmax(double a, double b)
{
	return b > a ? b : a;
}

static int
bucket(const locator *l, double c, int k)
{
	int b = (int)floor((c - l->o[k]) * l->s[k]);

	return b < 0 ? 0 : b >= l->nb ? l->nb - 1 : b;
}

/* Each triangle into the buckets its box meets (counts, then lists). */
static void
fill(tr_work *w, locator *l, int pass)
{
	for (int t = 0; t < w->m.nt; t++) {
		const int *k = w->m.tri + 3 * t;
		double lo[2] = { QM_MAX, QM_MAX }, hi[2] = { 0, 0 };
		for (int j = 0; j < 3; j++) {
			lo[0] = dmin(lo[0], w->u[k[j]]), hi[0] = dmax(hi[0], w->u[k[j]]);
			lo[1] = dmin(lo[1], w->v[k[j]]), hi[1] = dmax(hi[1], w->v[k[j]]);
		}
		if (hi[0] < l->o[0] || hi[1] < l->o[1] ||
		    lo[0] > l->o[0] + l->nb / l->s[0] ||
		    lo[1] > l->o[1] + l->nb / l->s[1])
			continue;
		for (int bj = bucket(l, lo[1], 1); bj <= bucket(l, hi[1], 1); bj++)
			for (int bi = bucket(l, lo[0], 0); bi <= bucket(l, hi[0],
			    0); bi++) {
				if (pass == 0)
					l->start[bj * l->nb + bi + 1]++;
				else
					l->list[l->start[bj * l->nb + bi]++] = t;
			}
	}
}

/* Triangle t's planes: ECEF (decoded), barycentric terms in u, v and in
 * longitude, latitude. */
static void
planes(const tr_work *w, locator *l, int t)
{
	const tr_mesh *m = &w->m;
	const int *k = m->tri + 3 * t;
	const double *a = w->pos + 3 * k[0], *b = w->pos + 3 * k[1],
	    *c = w->pos + 3 * k[2];
	double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
	double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
	double *p = l->plane + 4 * t, *q = l->bq + 7 * t, *f = l->bf + 10 * t;

	p[0] = u[1] * v[2] - u[2] * v[1], p[1] = u[2] * v[0] - u[0] * v[2];
	p[2] = u[0] * v[1] - u[1] * v[0];
	p[3] = p[0] * a[0] + p[1] * a[1] + p[2] * a[2];
	q[0] = w->u[k[0]], q[1] = w->v[k[0]];
	q[2] = w->u[k[1]] - q[0], q[3] = w->v[k[1]] - q[1];
	q[4] = w->u[k[2]] - q[0], q[5] = w->v[k[2]] - q[1];
	q[6] = q[2] * q[5] - q[4] * q[3];
	f[0] = m->x[k[0]], f[1] = m->y[k[0]];
	f[2] = m->x[k[1]] - f[0], f[3] = m->y[k[1]] - f[1];
	f[4] = m->x[k[2]] - f[0], f[5] = m->y[k[2]] - f[1];
	f[6] = f[2] * f[5] - f[4] * f[3];
	f[7] = m->h[k[0]], f[8] = m->h[k[1]] - f[7], f[9] = m->h[k[2]] - f[7];
}

static int
locate_init(tr_work *w, locator *l, const double uv[4], tl_err *e)
{
	tr_mesh *m = &w->m;
	int nb = (int)ceil(sqrt((double)m->nt)), n;
	size_t nt = (size_t)(m->nt ? m->nt : 1);

	l->nb = nb < 8 ? 8 : nb > 512 ? 512 : nb, n = l->nb * l->nb;
	for (int k = 0; k < 2; k++) {
		l->o[k] = uv[k] - 1;
		l->s[k] = l->nb / (uv[k + 2] - uv[k] + 2);
	}
	l->start = calloc((size_t)n + 1, sizeof *l->start);
	l->plane = malloc(nt * 21 * sizeof *l->plane);
	if (!l->start || !l->plane)
		return tl_fail(e, "tile: out of memory");
	l->bq = l->plane + 4 * nt, l->bf = l->bq + 7 * nt;
	fill(w, l, 0);
	for (int i = 0; i < n; i++)
		l->start[i + 1] += l->start[i];
	if ((l->list = malloc((size_t)(l->start[n] ? l->start[n] : 1) *
	    sizeof *l->list)) == NULL)
		return tl_fail(e, "tile: out of memory");
	fill(w, l, 1);
	for (int i = n; i > 0; i--)
		l->start[i] = l->start[i - 1];
	l->start[0] = 0;
	for (int t = 0; t < m->nt; t++)
		planes(w, l, t);
	return 0;
}

/* The least barycentric coordinate of (su, sv) in triangle t. */
static inline double
least(const locator *l, int t, double su, double sv)
{
	const double *q = l->bq + 7 * t;
	double px = su - q[0], py = sv - q[1];
	double b1 = (px * q[5] - q[4] * py) / q[6];
	double b2 = (q[2] * py - px * q[3]) / q[6];

	return dmin(1 - b1 - b2, dmin(b1, b2));
}

/* The triangle over (su, sv): the one of its bucket with the largest
 * least barycentric coordinate (inside: >= 0). The previous sample's
 * triangle, hint, when the point is well inside it: no other triangle
 * then comes near (they do not overlap), the bucket's answer is it. */
static int
locate(const locator *l, double su, double sv, int hint)
{
	int b, best = -1;
	double bv = -INFINITY;

	if (hint >= 0 && least(l, hint, su, sv) > 1e-9)
		return hint;
	b = bucket(l, sv, 1) * l->nb + bucket(l, su, 0);
	for (int i = l->start[b]; i < l->start[b + 1]; i++) {
		double mn = least(l, l->list[i], su, sv);
		if (mn > bv)
			bv = mn, best = l->list[i];
	}
	return best;
}

/* The selection's surface at (lon, lat): the plane, in longitude,
 * latitude and height, of mesh triangle q before quantisation (a piece
 * of a selected triangle, in its plane). */
static inline double
flat(const locator *l, int q, double lon, double lat)
{
	const double *f = l->bf + 10 * q;
	double px = lon - f[0], py = lat - f[1];
	double b1 = (px * f[5] - f[4] * py) / f[6];
	double b2 = (f[2] * py - px * f[3]) / f[6];

	return f[7] + b1 * f[8] + b2 * f[9];
}

/* The samples of level-0 block (bi, bj) b, its vertices at lon, lat,
 * in tile t (of rectangle r) under locator l; rim: per triangle, 1 past
 * a projected DEM's footprint (or NULL). */
static int
measure_block(const tr_grid *g, const pyramid_block *b, const double *lon,
    const double *lat, const locator *l, const unsigned char *rim, int bi,
    int bj, const double t[4], const double r[4], double d[2], tl_err *e)
{
	double wd = r[2] - r[0], fl = 1 / 298.257223563, e2 = fl * (2 - fl);
	double cl[BT_SIZE], sl[BT_SIZE], nn[BT_SIZE], co[BT_SIZE], so[BT_SIZE];
	int hint = -1, col[BT_SIZE], ncol = 0, nI = BT_SIZE;
	double d0 = d[0], d1 = d[1];

	if (g->w0 - bi * BT_CELLS < nI)
		nI = g->w0 - bi * BT_CELLS;
	/* a geographic grid: latitude per row, longitude per column, so the
	 * normals' sines and cosines per row and column (as geo_ellipsoid
	 * computes them), and the columns in the tile listed once, the rows
	 * out of it skipped whole: the same samples in the same order as
	 * the test of each */
	for (int k = 0; !g->projected && k < BT_SIZE; k++) {
		double a = lat[k] * (M_PI / 180), o = lon[k] *
		    (M_PI / 180);
		sl[k] = sin(a), cl[k] = cos(a), so[k] = sin(o), co[k] = cos(o);
		nn[k] = 6378137.0 / sqrt(1 - e2 * sl[k] * sl[k]);
		if (k < nI && !(lon[k] < t[0] || lon[k] > t[2]))
			col[ncol++] = k;
	}
	for (int I = 0; g->projected && I < nI; I++)
		col[ncol++] = I;
	for (int J = 0; J < BT_SIZE; J++) {
		if (bj * BT_CELLS + J >= g->h0)
			break;
		if (!g->projected && (lat[J] < t[1] || lat[J] > t[3]))
			continue;
		for (int ci = 0; ci < ncol; ci++) {
			int I = col[ci], k = J * BT_SIZE + I;
			double f[3], up[3], x = tr_vlon(g, lon, J, I);
			double y = tr_vlat(g, lat, J, I);
			if (g->projected && (x < t[0] || x > t[2] || y < t[1] ||
			    y > t[3]))
				continue;
			int q = hint = locate(l, (x - r[0]) / wd * QM_MAX,
			    (y - r[1]) / wd * QM_MAX, hint);
			if (q < 0)
				return tl_fail(e, "tile: sample (%d, %d) under no "
				    "triangle", bi * BT_CELLS + I, bj * BT_CELLS + J);
			const double *n = l->plane + 4 * q;
			if (g->projected)
				geo_ellipsoid(x, y, f, up);
			else {
				f[0] = nn[J] * cl[J] * co[I];
				f[1] = nn[J] * cl[J] * so[I];
				f[2] = nn[J] * (1 - e2) * sl[J];
				up[0] = cl[J] * co[I], up[1] = cl[J] * so[I];
				up[2] = sl[J];
			}
			double hs = (n[3] - n[0] * f[0] - n[1] * f[1] - n[2] * f[2]) /
			    (n[0] * up[0] + n[1] * up[1] + n[2] * up[2]);
			/* past a projected DEM's footprint, the sample itself */
			d0 = dmax(d0, fabs(hs - (rim && rim[q] ?
			    b->z[k] : flat(l, q, x, y))));
			d1 = dmax(d1, fabs(hs - b->z[k]));
		}
	}
	d[0] = d0, d[1] = d1;
	return 0;
}

/* A tile's locator kept for its measure: its rectangle r, the part t of
 * it in the terrain's rectangle, the rim marks of its triangles. */
struct tr_kept {
	double r[4], t[4];
	locator l;
	unsigned char *rim;
	size_t bytes;
};

void
tr_kept_free(tr_kept *k)
{
	if (k == NULL)
		return;
	free(k->l.start), free(k->l.list), free(k->l.plane), free(k->rim);
	free(k);
}

size_t
tr_kept_bytes(const tr_kept *k)
{
	return k->bytes;
}

int
tr_keep(tr_work *w, int z, int x, int y, tr_kept **out, tl_err *e)
{
	tr_kept *k;
	double *r, *t;
	size_t nt = (size_t)w->m.nt;

	*out = NULL;
	if ((k = calloc(1, sizeof *k)) == NULL)
		return tl_fail(e, "tile: out of memory");
	r = k->r, t = k->t;
	tr_tile_rect(z, x, y, r);
	t[0] = fmax(r[0], w->g->r[0]), t[2] = fmin(r[2], w->g->r[2]);
	t[1] = fmax(r[1], w->g->r[1]), t[3] = fmin(r[3], w->g->r[3]);
	if (!(t[0] <= t[2] && t[1] <= t[3])) {
		free(k);
		return 0; /* no sample */
	}
	double uv[4] = { (t[0] - r[0]) / (r[2] - r[0]) * QM_MAX,
		(t[1] - r[1]) / (r[3] - r[1]) * QM_MAX,
		(t[2] - r[0]) / (r[2] - r[0]) * QM_MAX,
		(t[3] - r[1]) / (r[3] - r[1]) * QM_MAX };
	if (locate_init(w, &k->l, uv, e) < 0 || (w->m.rim &&
	    (k->rim = malloc(nt ? nt : 1)) == NULL)) {
		tr_kept_free(k);
		return tl_fail(e, "tile: out of memory");
	}
	if (k->rim)
		memcpy(k->rim, w->m.rim, nt);
	k->bytes = sizeof *k + ((size_t)k->l.nb * k->l.nb + 1 +
	    (size_t)k->l.start[k->l.nb * k->l.nb]) * sizeof(int) +
	    (nt ? nt : 1) * 21 * sizeof(double) + (k->rim ? nt : 0);
	*out = k;
	return 0;
}

int
tr_kept_meets(const tr_grid *g, const tr_kept *k, int kb)
{
	const double *o = g->box[0] + 4 * (size_t)kb, *t = k->t;

	return !(o[2] < t[0] || o[0] > t[2] || o[3] < t[1] || o[1] > t[3]);
}

int
tr_kept_block(const tr_grid *g, const tr_kept *k, int kb, int bi, int bj,
    const pyramid_block *b, const double *lon, const double *lat,
    double d[2], tl_err *e)
{
	if (!tr_kept_meets(g, k, kb))
		return 0;
	return measure_block(g, b, lon, lat, &k->l, k->rim, bi, bj, k->t,
	    k->r, d, e);
}

/* Every level-0 sample in kept tile kp, through the thread's cache. */
int
tr_kept_walk(tr_work *w, const tr_kept *kp, double d[2], tl_err *e)
{
	const pyramid_level *L0 = &w->ix->lev[0];

	/* last to first: the blocks the selection read last (level 0 at
	 * the deep levels) are still in the cache */
	for (int k = L0->blocks[0] * L0->blocks[1] - 1; k >= 0; k--) {
		int bi = k % L0->blocks[0], bj = k / L0->blocks[0];
		const double *lon, *lat;
		const pyramid_block *b;
		if (tr_kept_meets(w->g, kp, k) && ((b = tr_block(w, 0, bi, bj,
		    &lon, &lat, e)) == NULL || tr_kept_block(w->g, kp, k, bi, bj,
		    b, lon, lat, d, e) < 0))
			return -1;
	}
	return 0;
}

/* Every level-0 sample in the tile and in the terrain's rectangle. */
int
tr_measure(tr_work *w, int z, int x, int y, double d[2], tl_err *e)
{
	tr_kept *kp;
	int ret;

	d[0] = d[1] = 0;
	if (tr_keep(w, z, x, y, &kp, e) < 0)
		return -1;
	ret = kp ? tr_kept_walk(w, kp, d, e) : 0; /* NULL: no sample */
	tr_kept_free(kp);
	return ret;
}
