/* tr_cut.c - a projected DEM's selection on the globe: each triangle of
 * the pyramid's selection cut to the DEM's grid rectangle in grid space
 * (a triangle over the padding past the last sample cut on the line of
 * that sample, every new vertex from the original triangle, as tr_clip.c
 * does, then mapped through PROJ), so that the footprint's edges are
 * chords between mapped boundary places, the same in every tile; and
 * past each side a band a few quanta wide carrying the edge heights
 * across (tr_rim_band), so that the samples on the DEM's edge stay
 * inside the DEM's part of the tile however u and v round. */
#include <math.h>
#include <stdlib.h>

#include "terrain/tr_impl.h"

enum { XW = 8, YH = 16 }; /* on x = W, on y = H; bits 1, 2, 4: edges */

typedef struct {
	double x, y, h; /* level-0 grid place, height */
	int m;          /* the lines it lies on */
	int v;          /* original vertex, or -1 */
} gp;

/* Edge k of t (vertex k to k+1), its ends ordered by (x, y). */
static void
gends(const gp *t, int k, int *a, int *b)
{
	int i = k, j = (k + 1) % 3;

	if (t[j].x < t[i].x || (t[j].x == t[i].x && t[j].y < t[i].y))
		i = j, j = k;
	*a = i, *b = j;
}

/* The plane of t at (x, y), its vertices taken in (x, y) order. */
static double
gplane(const gp *t, double x, double y)
{
	int o[3] = { 0, 1, 2 };

	for (int i = 0; i < 3; i++)
		for (int j = i + 1; j < 3; j++)
			if (t[o[j]].x < t[o[i]].x || (t[o[j]].x == t[o[i]].x &&
			    t[o[j]].y < t[o[i]].y)) {
				int s = o[i];
				o[i] = o[j], o[j] = s;
			}
	const gp *a = &t[o[0]], *b = &t[o[1]], *c = &t[o[2]];
	double x1 = b->x - a->x, y1 = b->y - a->y, x2 = c->x - a->x;
	double y2 = c->y - a->y, h1 = b->h - a->h, h2 = c->h - a->h;

	return a->h + ((x - a->x) * (y2 * h1 - y1 * h2) + (y - a->y) *
	    (x1 * h2 - x2 * h1)) / (x1 * y2 - x2 * y1);
}

/* Where p q crosses the line (axis 0: x = v, 1: y = v), from t. */
static gp
gcross(const gp *t, const gp *p, const gp *q, int axis, double v, int bit)
{
	int c = p->m & q->m & 7, a, b;
	gp r;

	r.v = -1;
	if (c) {
		int k = c & 1 ? 0 : c & 2 ? 1 : 2;
		gends(t, k, &a, &b);
		double s = axis == 0 ? (v - t[a].x) / (t[b].x - t[a].x) :
		    (v - t[a].y) / (t[b].y - t[a].y);
		r.x = axis == 0 ? v : t[a].x + s * (t[b].x - t[a].x);
		r.y = axis == 1 ? v : t[a].y + s * (t[b].y - t[a].y);
		r.h = t[a].h + s * (t[b].h - t[a].h);
		r.m = (1 << k) | bit;
	} else { /* along x = W, cut by y = H: the corner */
		r.x = p->x, r.y = v, r.h = gplane(t, r.x, r.y);
		r.m = XW | bit;
	}
	return r;
}

/* The part of polygon in (n) at or below v on axis. */
static int
gclip(const gp *t, const gp *in, int n, gp *out, int axis, double v, int bit)
{
	int k = 0;

	for (int i = 0; i < n; i++) {
		const gp *p = &in[i], *q = &in[(i + 1) % n];
		double pc = axis ? p->y : p->x, qc = axis ? q->y : q->x;
		if (pc <= v) {
			out[k] = *p;
			if (pc == v)
				out[k].m |= bit;
			k++;
		}
		if ((pc <= v) != (qc <= v) && pc != v && qc != v)
			out[k++] = gcross(t, p, q, axis, v, bit);
	}
	return k;
}

static double
area(const double *x, const double *y, int a, int b, int c)
{
	return (x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a]);
}

static int
push(tr_work *w, const tr_tri *q)
{
	if (w->nsel == w->csel) {
		int n = w->csel ? 2 * w->csel : 1024;
		tr_tri *a = realloc(w->sel, (size_t)n * sizeof *a);
		int *o = a ? realloc(w->row, (size_t)n * sizeof *o) : NULL;
		if (a)
			w->sel = a;
		if (o == NULL)
			return -1;
		w->row = o, w->csel = n;
	}
	w->sel[w->nsel++] = *q;
	return 0;
}

/* Triangle (a, b, c) of the longitudes x, latitudes y, heights h,
 * level-0 places gx, gy, into the selection when its box meets r; edge
 * 2 for the band's, else 1 when a vertex lies on or past a side. */
static int
add(tr_work *w, const double *x, const double *y, const double *h,
    const double *gx, const double *gy, int edge, int a, int b, int c,
    const double r[4])
{
	double W = w->g->w0 - 1, H = w->g->h0 - 1;
	tr_tri q;
	int k[3] = { a, b, c };

	q.lo[0] = q.lo[1] = INFINITY, q.hi[0] = q.hi[1] = -INFINITY;
	q.edge = edge;
	for (int i = 0; i < 3; i++) {
		q.x[i] = x[k[i]], q.y[i] = y[k[i]], q.h[i] = h[k[i]];
		q.gx[i] = gx[k[i]], q.gy[i] = gy[k[i]];
		if (!(q.gx[i] > 0 && q.gx[i] < W && q.gy[i] > 0 && q.gy[i] < H))
			q.edge = q.edge ? q.edge : 1;
		q.lo[0] = fmin(q.lo[0], q.x[i]), q.hi[0] = fmax(q.hi[0], q.x[i]);
		q.lo[1] = fmin(q.lo[1], q.y[i]), q.hi[1] = fmax(q.hi[1], q.y[i]);
	}
	if (q.hi[0] < r[0] || q.lo[0] > r[2] || q.hi[1] < r[1] ||
	    q.lo[1] > r[3])
		return 0;
	return push(w, &q);
}

/* The cut polygon (k vertices, lon/lat x y) as a fan from the first
 * apex whose triangles all turn the polygon's way (the map may bend a
 * thin one past a chord), else from vertex 0. */
static int
fan(tr_work *w, const double *x, const double *y, const double *h,
    const double *gx, const double *gy, int k, const double r[4])
{
	double s = 0;
	int a = 0;

	for (int i = 0; i < k; i++)
		s += x[i] * y[(i + 1) % k] - x[(i + 1) % k] * y[i];
	for (int c = 0; c < k; c++) {
		int good = 1;
		for (int i = 1; i + 1 < k && good; i++)
			good = area(x, y, c, (c + i) % k, (c + i + 1) % k) * s > 0;
		if (good) {
			a = c;
			break;
		}
	}
	for (int i = 1; i + 1 < k; i++)
		if (area(x, y, a, (a + i) % k, (a + i + 1) % k) != 0 &&
		    add(w, x, y, h, gx, gy, 0, a, (a + i) % k, (a + i + 1) % k,
		    r) < 0)
			return -1;
	return 0;
}

/* Outward of the DEM's grid side an edge of the cut polygon lies on: its
 * direction (dx, dy), or 0. */
static int
outward(const gp *p, const gp *q, double W, double H, double *dx,
    double *dy)
{
	*dx = *dy = 0;
	if (p->x == 0 && q->x == 0)
		*dx = -1;
	else if (p->x == W && q->x == W)
		*dx = 1;
	else if (p->y == 0 && q->y == 0)
		*dy = -1;
	else if (p->y == H && q->y == H)
		*dy = 1;
	return *dx != 0 || *dy != 0;
}

/* The band past the DEM's sides along the cut polygon c (k vertices,
 * lon/lat x y, heights h): per edge on a side a quad d cells wide, its
 * heights carried across; per DEM corner (met by an edge on x = 0 or
 * x = W) a square. New places through PROJ. */
static int
band(tr_work *w, const gp *c, const double *x, const double *y,
    const double *h, int k, double d, const double r[4])
{
	double W = w->g->w0 - 1, H = w->g->h0 - 1, px[48], py[48], ph[48];
	double mx[48], my[48], gx[48], gy[48], gm[96];
	int n = 0, m = 0, at[48];
	tl_err e;

	for (int i = 0; i < k; i++) {
		const gp *p = &c[i], *q = &c[(i + 1) % k];
		int j = (i + 1) % k;
		double dx, dy;
		if (!outward(p, q, W, H, &dx, &dy))
			continue;
		/* p, q known; q', p' new */
		gx[n] = p->x, gy[n] = p->y;
		px[n] = x[i], py[n] = y[i], ph[n] = h[i], at[n++] = -1;
		gx[n] = q->x, gy[n] = q->y;
		px[n] = x[j], py[n] = y[j], ph[n] = h[j], at[n++] = -1;
		mx[m] = q->x + d * dx, my[m] = q->y + d * dy;
		ph[n] = q->h, at[n++] = m++;
		mx[m] = p->x + d * dx, my[m] = p->y + d * dy;
		ph[n] = p->h, at[n++] = m++;
		for (int s = 0; s < 2 && dx != 0; s++) {
			const gp *o = s ? q : p;
			double oy = o->y == 0 ? -d : d;
			if (o->y != 0 && o->y != H)
				continue;
			gx[n] = o->x, gy[n] = o->y;
			px[n] = x[s ? j : i], py[n] = y[s ? j : i];
			ph[n] = o->h, at[n++] = -1;
			mx[m] = o->x + d * dx, my[m] = o->y;
			ph[n] = o->h, at[n++] = m++;
			mx[m] = o->x + d * dx, my[m] = o->y + oy;
			ph[n] = o->h, at[n++] = m++;
			mx[m] = o->x, my[m] = o->y + oy;
			ph[n] = o->h, at[n++] = m++;
		}
	}
	if (n == 0)
		return 0;
	for (int i = 0; i < m; i++)
		gm[2 * i] = mx[i], gm[2 * i + 1] = my[i];
	if (tr_lonlat(w->g, &w->proj, &w->ix->geo, mx, my, m, &e) < 0)
		return -1;
	for (int i = 0; i < n; i++)
		if (at[i] >= 0) /* mx, my converted in place: theirs kept */
			gx[i] = gm[2 * at[i]], gy[i] = gm[2 * at[i] + 1],
			px[i] = mx[at[i]], py[i] = my[at[i]];
	for (int i = 0; i < n; i += 4)
		if (add(w, px, py, ph, gx, gy, 2, i, i + 1, i + 2, r) < 0 ||
		    add(w, px, py, ph, gx, gy, 2, i, i + 2, i + 3, r) < 0)
			return -1;
	return 0;
}

/* The selected triangle o for the measure (tr_gsel.c) when its part
 * over the DEM (x, y: k places) lies near the tile's part r of level z:
 * within a twentieth of a tile, far more than a grid line's image bends
 * from its chord over one triangle, so every sample drawn in the tile
 * finds the triangle holding its grid place. */
static int
keep_grid(tr_work *w, int z, const gp *o, const double *x, const double *y,
    int k, const double r[4])
{
	double lo[2] = { x[0], y[0] }, hi[2] = { x[0], y[0] };
	double m = ldexp(180, -z) / 20, gx[3], gy[3], gh[3];

	for (int i = 1; i < k; i++) {
		lo[0] = fmin(lo[0], x[i]), hi[0] = fmax(hi[0], x[i]);
		lo[1] = fmin(lo[1], y[i]), hi[1] = fmax(hi[1], y[i]);
	}
	if (hi[0] < r[0] - m || lo[0] > r[2] + m || hi[1] < r[1] - m ||
	    lo[1] > r[3] + m)
		return 0;
	for (int i = 0; i < 3; i++)
		gx[i] = o[i].x, gy[i] = o[i].y, gh[i] = o[i].h;
	return tr_gsel_add(w, gx, gy, gh);
}

/* Whether triangle o (its vertices at lon, lat [idx]) adds nothing:
 * inside the DEM's grid (no cut, no band, so the cut polygon is o) and
 * its box beyond keep_grid's margin of r, so that neither keep_grid nor
 * fan (whose triangle has that box, and r lies within the margin) adds
 * it. Most of a block's triangles lie far from a deep level's tile. */
static int
far(const tr_grid *g, int z, const gp *o, const double *lon,
    const double *lat, const int idx[3], const double r[4])
{
	double W = g->w0 - 1, H = g->h0 - 1, m = ldexp(180, -z) / 20;
	double lo[2] = { lon[idx[0]], lat[idx[0]] }, hi[2] = { lo[0], lo[1] };

	for (int i = 0; i < 3; i++)
		if (!(o[i].x > 0 && o[i].x < W && o[i].y > 0 && o[i].y < H))
			return 0;
	for (int i = 1; i < 3; i++) {
		lo[0] = fmin(lo[0], lon[idx[i]]), hi[0] = fmax(hi[0], lon[idx[i]]);
		lo[1] = fmin(lo[1], lat[idx[i]]), hi[1] = fmax(hi[1], lat[idx[i]]);
	}
	return hi[0] < r[0] - m || lo[0] > r[2] + m || hi[1] < r[1] - m ||
	    lo[1] > r[3] + m;
}

int
tr_rim_sel(tr_work *w, const tr_choice *ch, const pyramid_block *b,
    const double *lon, const double *lat, const int t[3][2],
    const double r[4])
{
	const tr_grid *g = w->g;
	double W = g->w0 - 1, H = g->h0 - 1, x[8], y[8], h[8], gx[8], gy[8];
	gp o[3], a[8], c[8];
	int n = 3, k = 0, idx[3], p = ch->p;
	tl_err e;

	for (int i = 0; i < 3; i++) {
		int cc = t[i][0] - b->bi * BT_CELLS, rr = t[i][1] - b->bj * BT_CELLS;
		idx[i] = rr * BT_SIZE + cc;
		o[i].x = (double)t[i][0] * (1 << p), o[i].y = (double)t[i][1] *
		    (1 << p);
		o[i].h = b->z[idx[i]], o[i].v = i;
		o[i].m = 1 << i | 1 << ((i + 2) % 3);
		a[i] = o[i];
	}
	if (tr_ll_need(w, b, idx, 3, &e) < 0)
		return -1;
	if (far(g, ch->z, o, lon, lat, idx, r))
		return 0;
	n = gclip(o, a, n, c, 0, W, XW);
	n = gclip(o, c, n, a, 1, H, YH);
	for (int i = 0; i < n; i++) {
		if (k > 0 && a[i].x == c[k - 1].x && a[i].y == c[k - 1].y)
			continue;
		c[k++] = a[i];
	}
	if (k > 1 && c[0].x == c[k - 1].x && c[0].y == c[k - 1].y)
		k--;
	if (k < 3)
		return 0;
	/* the new places through PROJ, the original ones as cached */
	int nn = 0;
	double px[8], py[8];
	for (int i = 0; i < k; i++)
		if (c[i].v < 0)
			px[nn] = c[i].x, py[nn++] = c[i].y;
	if (nn > 0 && tr_lonlat(g, &w->proj, &w->ix->geo, px, py, nn, &e) < 0)
		return -1;
	nn = 0;
	for (int i = 0; i < k; i++) {
		h[i] = c[i].h, gx[i] = c[i].x, gy[i] = c[i].y;
		if (c[i].v >= 0)
			x[i] = lon[idx[c[i].v]], y[i] = lat[idx[c[i].v]];
		else
			x[i] = px[nn], y[i] = py[nn++];
	}
	if (keep_grid(w, ch->z, o, x, y, k, r) < 0 || fan(w, x, y, h, gx, gy, k, r) < 0)
		return -1;
	return band(w, c, x, y, h, k, tr_rim_band(g, ch->z), r);
}
