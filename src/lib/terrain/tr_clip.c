/* tr_clip.c - the part of a selection triangle inside a longitude-
 * latitude rectangle (Sutherland-Hodgman, x lines first, then y lines), with
 * every new vertex computed from the ORIGINAL triangle (the edge it lies
 * on, its two ends in a fixed order, or its plane at a corner), never
 * from an earlier clip: the same point of the same selection comes out
 * bit for bit the same in every cell and tile that cuts it, which is
 * what makes neighbours share their edge vertices. */
#include <string.h>

#include "terrain/tr_impl.h"

enum { X0 = 8, X1 = 16, Y0 = 32, Y1 = 64 }; /* bits 1, 2, 4: edges 0-2 */

typedef struct {
	double x, y, h;
	int m; /* the lines it lies on: triangle edges, clip lines */
} pv;

/* Edge k (vertex k to k+1), its ends ordered by (x, y). */
static void
ends(const tr_tri *t, int k, int *a, int *b)
{
	int i = k, j = (k + 1) % 3;

	if (t->x[j] < t->x[i] || (t->x[j] == t->x[i] && t->y[j] < t->y[i]))
		i = j, j = k;
	*a = i, *b = j;
}

/* The triangle's plane at (x, y), its vertices taken in (x, y) order. */
static double
plane(const tr_tri *t, double x, double y)
{
	int o[3] = { 0, 1, 2 };

	for (int i = 0; i < 3; i++)
		for (int j = i + 1; j < 3; j++)
			if (t->x[o[j]] < t->x[o[i]] || (t->x[o[j]] == t->x[o[i]] &&
			    t->y[o[j]] < t->y[o[i]])) {
				int s = o[i];
				o[i] = o[j], o[j] = s;
			}
	double x1 = t->x[o[1]] - t->x[o[0]], y1 = t->y[o[1]] - t->y[o[0]];
	double x2 = t->x[o[2]] - t->x[o[0]], y2 = t->y[o[2]] - t->y[o[0]];
	double h1 = t->h[o[1]] - t->h[o[0]], h2 = t->h[o[2]] - t->h[o[0]];
	double d = x1 * y2 - x2 * y1;

	return t->h[o[0]] + ((x - t->x[o[0]]) * (y2 * h1 - y1 * h2) +
	    (y - t->y[o[0]]) * (x1 * h2 - x2 * h1)) / d;
}

static int
lowbit(int m)
{
	return m & 1 ? 0 : m & 2 ? 1 : 2;
}

/* Where segment p q crosses the line (axis 0: x = v, 1: y = v). */
static pv
cross(const tr_tri *t, const pv *p, const pv *q, int axis, double v, int bit)
{
	int c = p->m & q->m, a, b;
	pv r;

	if (c & 7) {
		int k = lowbit(c & 7);
		ends(t, k, &a, &b);
		double s = axis == 0 ? (v - t->x[a]) / (t->x[b] - t->x[a]) :
		    (v - t->y[a]) / (t->y[b] - t->y[a]);
		r.x = axis == 0 ? v : t->x[a] + s * (t->x[b] - t->x[a]);
		r.y = axis == 1 ? v : t->y[a] + s * (t->y[b] - t->y[a]);
		r.h = t->h[a] + s * (t->h[b] - t->h[a]);
		r.m = (1 << k) | bit;
	} else {
		/* along an x line, cut by a y line: a corner */
		r.x = p->x, r.y = v, r.h = plane(t, r.x, r.y);
		r.m = (c & (X0 | X1)) | bit;
	}
	return r;
}

static int
clip1(const tr_tri *t, const pv *in, int n, pv *out, int axis, double v,
    int ge, int bit)
{
	int k = 0;

	for (int i = 0; i < n; i++) {
		const pv *p = &in[i], *q = &in[(i + 1) % n];
		double pc = axis ? p->y : p->x, qc = axis ? q->y : q->x;
		int pin = ge ? pc >= v : pc <= v, qin = ge ? qc >= v : qc <= v;
		if (pin) {
			out[k] = *p;
			if (pc == v)
				out[k].m |= bit;
			k++;
		}
		if (pin != qin && pc != v && qc != v)
			out[k++] = cross(t, p, q, axis, v, bit);
	}
	return k;
}

/* Twice the signed area of vertices a b c of m. */
static double
area2(const tr_mesh *m, int a, int b, int c)
{
	return (m->x[b] - m->x[a]) * (m->y[c] - m->y[a]) -
	    (m->y[b] - m->y[a]) * (m->x[c] - m->x[a]);
}

/* The convex polygon id[0..k-1] in triangles that use every one of its
 * vertices (none left on another triangle's side: a T-junction): a fan
 * from a corner whose neighbours are corners too (no vertex lies on the
 * lines of its sides), else from a vertex added at the centroid, on
 * the triangle's plane. */
static int
fan(tr_mesh *m, const tr_tri *t, const int *id, int k, tl_err *e)
{
	int flat[16], a = -1, c;
	double cx = 0, cy = 0;

	for (int i = 0; i < k; i++)
		flat[i] = area2(m, id[(i + k - 1) % k], id[i], id[(i + 1) % k]) ==
		    0;
	for (int i = 0; i < k && a < 0; i++)
		if (!flat[i] && !flat[(i + k - 1) % k] && !flat[(i + 1) % k])
			a = i;
	if (a >= 0) {
		for (int i = 1; i + 1 < k; i++)
			if (area2(m, id[a], id[(a + i) % k], id[(a + i + 1) % k]) !=
			    0 && tr_mesh_tri(m, id[a], id[(a + i) % k],
			    id[(a + i + 1) % k], e) < 0)
				return -1;
		return 0;
	}
	for (int i = 0; i < k; i++)
		cx += m->x[id[i]] / k, cy += m->y[id[i]] / k;
	if ((c = tr_mesh_vertex(m, cx, cy, plane(t, cx, cy), e)) < 0)
		return -1;
	for (int i = 0; i < k; i++)
		if (area2(m, c, id[i], id[(i + 1) % k]) != 0 &&
		    tr_mesh_tri(m, c, id[i], id[(i + 1) % k], e) < 0)
			return -1;
	return 0;
}

/* Whether every vertex of t lies in r (its sides included): the clips
 * would keep the triangle as it is, no vertex made. Most do, a cell
 * being wider than the selection's triangles. */
static int
within(const tr_tri *t, const double r[4])
{
	for (int i = 0; i < 3; i++)
		if (!(t->x[i] >= r[0] && t->x[i] <= r[2] && t->y[i] >= r[1] &&
		    t->y[i] <= r[3]))
			return 0;
	return 1;
}

int
tr_clip(tr_mesh *m, const tr_tri *t, const double r[4], tl_err *e)
{
	pv a[16], b[16];
	int n = 3, id[16], k = 0;

	for (int i = 0; i < 3; i++) {
		a[i].x = t->x[i], a[i].y = t->y[i], a[i].h = t->h[i];
		a[i].m = 1 << i | 1 << ((i + 2) % 3);
	}
	if (!within(t, r)) {
		n = clip1(t, a, n, b, 0, r[0], 1, X0);
		n = clip1(t, b, n, a, 0, r[2], 0, X1);
		n = clip1(t, a, n, b, 1, r[1], 1, Y0);
		n = clip1(t, b, n, a, 1, r[3], 0, Y1);
	}
	for (int i = 0; i < n; i++) {
		const pv *p = &a[i], *q = &a[(i + 1) % n];
		if (p->x == q->x && p->y == q->y)
			continue;
		if ((id[k] = tr_mesh_vertex(m, p->x, p->y, p->h, e)) < 0)
			return -1;
		k++;
	}
	return k < 3 ? 0 : fan(m, t, id, k, e);
}
