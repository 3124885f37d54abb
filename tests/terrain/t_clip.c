/* t_clip.c - a selection triangle's part in a cell (tr_clip.c): one
 * within the cell, its vertices on the cell's sides or not, comes out as
 * itself bit for bit (the clips skipped); one across the cell's sides,
 * its part (every vertex in the cell, the area of the exact intersection,
 * each height on its plane); and two that share an edge, one within and
 * one across or both across, meet along it with no crack: every
 * half-edge no other pairs lies on the cell's sides or on the outline
 * of the two (what tr_rim.c's pieces() takes for covered). */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "tap.h"
#include "terrain/tr_impl.h"

static uint64_t seed = 0x2545f4914f6cdd1dull;

static double
rnd(void) /* 0 .. 1 */
{
	seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
	return (double)(seed >> 11) / 9007199254740992.0;
}

static double
cross(double ax, double ay, double bx, double by, double cx, double cy)
{
	return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

static void
tri(tr_tri *t, const double *x, const double *y, const double *h)
{
	for (int i = 0; i < 3; i++) {
		t->x[i] = x[i], t->y[i] = y[i], t->h[i] = h[i];
		t->lo[0] = i ? fmin(t->lo[0], x[i]) : x[i];
		t->hi[0] = i ? fmax(t->hi[0], x[i]) : x[i];
		t->lo[1] = i ? fmin(t->lo[1], y[i]) : y[i];
		t->hi[1] = i ? fmax(t->hi[1], y[i]) : y[i];
	}
}

static void
reset(tr_mesh *m)
{
	m->nv = m->nt = 0;
	if (m->hash)
		memset(m->hash, 0, (size_t)m->hcap * sizeof *m->hash);
}

/* A coordinate in lo .. hi, now and then on an end. */
static double
coord(double lo, double hi)
{
	double k = rnd();

	return k < 0.15 ? lo : k < 0.3 ? hi : lo + rnd() * (hi - lo);
}

static void
within(void)
{
	double r[4] = { -122.5, 48.25, -122.4375, 48.3125 };
	int bad = 0, n = 0;
	tr_mesh m = { 0 };
	tl_err e;

	for (int i = 0; i < 100000; i++) {
		double x[3], y[3], h[3];
		tr_tri t;
		for (int k = 0; k < 3; k++)
			x[k] = coord(r[0], r[2]), y[k] = coord(r[1], r[3]),
			h[k] = rnd() * 1000;
		if (cross(x[0], y[0], x[1], y[1], x[2], y[2]) == 0)
			continue;
		tri(&t, x, y, h), reset(&m), n++;
		if (tr_clip(&m, &t, r, &e) < 0 || m.nt != 1 || m.nv != 3) {
			bad++;
			continue;
		}
		for (int k = 0; k < 3; k++) {
			int v = m.tri[k];
			if (v != k || m.x[v] != x[k] || m.y[v] != y[k] ||
			    m.h[v] != h[k])
				bad++;
		}
	}
	ok(bad == 0 && n > 90000, "a triangle within the cell (%d, its "
	    "vertices on the sides too): itself, bit for bit (%d bad)", n, bad);
	tr_mesh_free(&m);
}

/* The area of triangle x, y within r, clipped here on its own. */
static double
exact(const double *x, const double *y, const double r[4])
{
	double px[16], py[16], qx[16], qy[16], a = 0;
	int n = 3;

	memcpy(px, x, 3 * sizeof *x), memcpy(py, y, 3 * sizeof *y);
	for (int s = 0; s < 4; s++) {
		int k = 0, ax = s % 2, ge = s < 2;
		double v = r[ax ? (ge ? 1 : 3) : (ge ? 0 : 2)];
		for (int i = 0; i < n; i++) {
			int j = (i + 1) % n;
			double pc = ax ? py[i] : px[i], qc = ax ? py[j] : px[j];
			int pin = ge ? pc >= v : pc <= v, qin = ge ? qc >= v : qc <= v;
			if (pin)
				qx[k] = px[i], qy[k++] = py[i];
			if (pin != qin) {
				double f = (v - pc) / (qc - pc);
				qx[k] = px[i] + f * (px[j] - px[i]);
				qy[k++] = py[i] + f * (py[j] - py[i]);
			}
		}
		n = k;
		memcpy(px, qx, (size_t)n * sizeof *px);
		memcpy(py, qy, (size_t)n * sizeof *py);
	}
	for (int i = 0; i < n; i++)
		a += px[i] * py[(i + 1) % n] - px[(i + 1) % n] * py[i];
	return fabs(a) / 2;
}

static void
across(void)
{
	double r[4] = { 10, 20, 11, 21 };
	int bad = 0, cut = 0;
	tr_mesh m = { 0 };
	tl_err e;

	for (int i = 0; i < 100000; i++) {
		double x[3], y[3], h[3], a = 0, d = 0;
		tr_tri t;
		for (int k = 0; k < 3; k++)
			x[k] = coord(9, 12), y[k] = coord(19, 22), h[k] = rnd() * 100;
		if (cross(x[0], y[0], x[1], y[1], x[2], y[2]) == 0)
			continue;
		tri(&t, x, y, h), reset(&m);
		if (tr_clip(&m, &t, r, &e) < 0) {
			bad++;
			continue;
		}
		cut += m.nv > 3;
		for (int k = 0; k < m.nt; k++) {
			const int *q = m.tri + 3 * k;
			a += fabs(cross(m.x[q[0]], m.y[q[0]], m.x[q[1]], m.y[q[1]],
			    m.x[q[2]], m.y[q[2]])) / 2;
		}
		double s = cross(x[0], y[0], x[1], y[1], x[2], y[2]);
		for (int v = 0; v < m.nv; v++) {
			double b1 = cross(x[0], y[0], m.x[v], m.y[v], x[2], y[2]) /
			    s, b2 = cross(x[0], y[0], x[1], y[1], m.x[v], m.y[v]) / s;
			double p = h[0] + b1 * (h[1] - h[0]) + b2 * (h[2] - h[0]);
			if (!(m.x[v] >= r[0] && m.x[v] <= r[2] && m.y[v] >= r[1] &&
			    m.y[v] <= r[3]))
				bad++;
			d = fmax(d, fabs(m.h[v] - p));
		}
		if (!(fabs(a - exact(x, y, r)) <= 1e-9 && d <= 1e-6))
			bad++;
	}
	ok(bad == 0 && cut > 10000, "a triangle across the cell's sides: its "
	    "part, in the cell, its area, its plane (%d cut, %d bad)", cut, bad);
	tr_mesh_free(&m);
}

static int
inside(const tr_tri *t, const double r[4])
{
	return t->lo[0] >= r[0] && t->hi[0] <= r[2] && t->lo[1] >= r[1] &&
	    t->hi[1] <= r[3];
}

/* Whether p lies on segment a b, within eps. */
static int
on(double px, double py, double ax, double ay, double bx, double by)
{
	double l = hypot(bx - ax, by - ay), eps = 1e-9;

	return fabs(cross(ax, ay, bx, by, px, py)) <= eps * l &&
	    fmin(ax, bx) - eps <= px && px <= fmax(ax, bx) + eps &&
	    fmin(ay, by) - eps <= py && py <= fmax(ay, by) + eps;
}

static void
shared(void)
{
	double r[4] = { 10, 20, 11, 21 };
	int bad = 0, mixed = 0, n = 0;
	tr_mesh m = { 0 };
	tl_err e;

	for (int i = 0; i < 50000; i++) {
		/* a convex quad 0 1 2 3 (on a circle), its diagonal 0 2 */
		double qx[4], qy[4], qh[4], g[4], cx = coord(9.8, 11.2);
		double cy = coord(19.8, 21.2), rad = 0.05 + rnd() * 0.6;
		for (int k = 0; k < 4; k++)
			g[k] = rnd() * 2 * M_PI;
		for (int k = 1; k < 4; k++)
			for (int l = k; l > 0 && g[l] < g[l - 1]; l--) {
				double o = g[l];
				g[l] = g[l - 1], g[l - 1] = o;
			}
		for (int k = 0; k < 4; k++)
			qx[k] = cx + rad * cos(g[k]), qy[k] = cy + rad * sin(g[k]),
			qh[k] = rnd() * 100;
		if (cross(qx[0], qy[0], qx[1], qy[1], qx[2], qy[2]) <= 0 ||
		    cross(qx[0], qy[0], qx[2], qy[2], qx[3], qy[3]) <= 0)
			continue;
		double ax[3] = { qx[0], qx[1], qx[2] }, ay[3] = { qy[0], qy[1],
			qy[2] }, ah[3] = { qh[0], qh[1], qh[2] };
		double bx[3] = { qx[0], qx[2], qx[3] }, by[3] = { qy[0], qy[2],
			qy[3] }, bh[3] = { qh[0], qh[2], qh[3] };
		tr_tri ta, tb;
		tri(&ta, ax, ay, ah), tri(&tb, bx, by, bh), reset(&m), n++;
		mixed += inside(&ta, r) != inside(&tb, r);
		if (tr_clip(&m, &ta, r, &e) < 0 || tr_clip(&m, &tb, r, &e) < 0) {
			bad++;
			continue;
		}
		/* each half-edge: its reverse, or on the outline */
		for (int k = 0; k < 3 * m.nt; k++) {
			int a = m.tri[k], b = m.tri[k / 3 * 3 + (k + 1) % 3], pair = 0;
			for (int l = 0; l < 3 * m.nt && !pair; l++)
				pair = m.tri[l] == b && m.tri[l / 3 * 3 + (l + 1) % 3] == a;
			if (pair)
				continue;
			double mx = (m.x[a] + m.x[b]) / 2, my = (m.y[a] + m.y[b]) / 2;
			int out = mx == r[0] || mx == r[2] || my == r[1] ||
			    my == r[3];
			for (int s = 0; s < 4 && !out; s++)
				out = on(mx, my, qx[s], qy[s], qx[(s + 1) % 4],
				    qy[(s + 1) % 4]);
			bad += !out;
		}
	}
	ok(bad == 0 && n > 10000 && mixed > 1000, "two triangles sharing an "
	    "edge, within or across the cell: no crack between them (%d, %d "
	    "one within the cell and one across, %d bad)", n, mixed, bad);
	tr_mesh_free(&m);
}

int
main(void)
{
	within();
	across();
	shared();
	return tap_done();
}
