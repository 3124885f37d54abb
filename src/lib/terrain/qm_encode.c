/* qm_encode.c - a tile's bytes in quantized-mesh-1.0 (quantized-mesh(5)):
 * the header, zig-zag delta coded u, v, height, high-water-mark indices,
 * the four edge lists, extension 1 (oct-encoded normals); gzipped on
 * request. Little-endian whatever the host. No extension 4 (metadata):
 * CesiumJS (1.129) throws on a tile's metadata unless layer.json names
 * metadataAvailability, and then ignores layer.json's available. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/gzip.h"
#include "terrain/tr_impl.h"

#define WGS84_A 6378137.0
#define WGS84_B 6356752.314245179

uint16_t
qm_zigzag(int d)
{
	return (uint16_t)(d >= 0 ? 2 * d : -2 * d - 1);
}

uint32_t
qm_hwm(uint32_t i, uint32_t *highest)
{
	uint32_t code = *highest - i;

	if (code == 0)
		++*highest;
	return code;
}

static double
snorm(double v)
{
	v = v < -1 ? -1 : v > 1 ? 1 : v;
	return floor((v * 0.5 + 0.5) * 255 + 0.5); /* Math.round */
}

void
qm_oct(const double n[3], uint8_t out[2])
{
	double s = fabs(n[0]) + fabs(n[1]) + fabs(n[2]);
	double x = n[0] / s, y = n[1] / s;

	if (n[2] < 0) {
		double ox = x, oy = y;
		x = (1 - fabs(oy)) * (ox < 0 ? -1 : 1);
		y = (1 - fabs(ox)) * (oy < 0 ? -1 : 1);
	}
	out[0] = (uint8_t)snorm(x), out[1] = (uint8_t)snorm(y);
}

/* EllipsoidalOccluder's computeMagnitude: the distance along the scaled
 * direction d (unit) at which the point sees scaled position s over the
 * horizon. */
static double
magnitude(const double s[3], const double d[3])
{
	double m2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2], m = sqrt(m2);
	double u[3] = { s[0] / m, s[1] / m, s[2] / m }, c[3];
	double ca, sa, cb, sb;

	m2 = fmax(1, m2), m = fmax(1, m);
	ca = u[0] * d[0] + u[1] * d[1] + u[2] * d[2];
	c[0] = u[1] * d[2] - u[2] * d[1];
	c[1] = u[2] * d[0] - u[0] * d[2];
	c[2] = u[0] * d[1] - u[1] * d[0];
	sa = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
	cb = 1 / m, sb = sqrt(m2 - 1) * cb;
	return 1 / (ca * cb - sa * sb);
}

int
qm_horizon(const double dir[3], const double *p, int n, double out[3])
{
	double d[3] = { dir[0] / WGS84_A, dir[1] / WGS84_A, dir[2] / WGS84_B };
	double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), best = 0;
	int bad = 0;

	for (int k = 0; k < 3; k++)
		d[k] /= l;
	for (int i = 0; i < n; i++) {
		double s[3] = { p[3 * i] / WGS84_A, p[3 * i + 1] / WGS84_A,
			p[3 * i + 2] / WGS84_B };
		double m = magnitude(s, d);
		if (!(m > 0) || isinf(m))
			bad = 1; /* at or past the horizon cone */
		else if (m > best)
			best = m;
	}
	for (int k = 0; k < 3; k++)
		out[k] = d[k] * best;
	return bad || !(best > 0) ? -1 : 0;
}

/* --- the byte buffer ------------------------------------------------ */

static int
room(tr_work *w, size_t n, tl_err *e)
{
	size_t c = w->cbuf ? w->cbuf : 65536;
	unsigned char *b;

	if (w->nbuf + n <= w->cbuf)
		return 0;
	while (c < w->nbuf + n)
		c *= 2;
	if ((b = realloc(w->buf, c)) == NULL)
		return tl_fail(e, "tile: out of memory");
	w->buf = b, w->cbuf = c;
	return 0;
}

static void
put(tr_work *w, uint64_t v, int bytes)
{
	for (int i = 0; i < bytes; i++)
		w->buf[w->nbuf++] = (unsigned char)(v >> (8 * i));
}

static void
put_f64(tr_work *w, double d)
{
	uint64_t v;

	memcpy(&v, &d, 8);
	put(w, v, 8);
}

static void
put_f32(tr_work *w, float f)
{
	uint32_t v;

	memcpy(&v, &f, 4);
	put(w, v, 4);
}

/* The header: centre, heights, sphere, horizon occlusion point. */
static void
header(tr_work *w, float minh, float maxh)
{
	int n = w->m.nv;
	double lo[3] = { INFINITY, INFINITY, INFINITY }, c[3], r = 0, hp[3];

	for (int i = 0; i < n; i++)
		for (int k = 0; k < 3; k++)
			lo[k] = fmin(lo[k], w->pos[3 * i + k]);
	for (int k = 0; k < 3; k++) {
		double hi = -INFINITY;
		for (int i = 0; i < n; i++)
			hi = fmax(hi, w->pos[3 * i + k]);
		c[k] = 0.5 * (lo[k] + hi);
	}
	for (int i = 0; i < n; i++) {
		const double *p = w->pos + 3 * i;
		double d = sqrt((p[0] - c[0]) * (p[0] - c[0]) +
		    (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2]));
		r = fmax(r, d);
	}
	r = r * (1 + 1e-9) + 1e-3; /* every vertex inside, rounding too */
	/* where no point sees every vertex over the horizon (a root tile,
	 * half the globe: CesiumJS's computation has no result), NaN:
	 * CesiumJS then never culls the tile by the horizon */
	if (qm_horizon(c, w->pos, n, hp) < 0)
		hp[0] = hp[1] = hp[2] = NAN;
	for (int k = 0; k < 3; k++)
		put_f64(w, c[k]);
	put_f32(w, minh), put_f32(w, maxh);
	for (int k = 0; k < 3; k++)
		put_f64(w, c[k]);
	put_f64(w, r);
	for (int k = 0; k < 3; k++)
		put_f64(w, hp[k]);
}

static void
deltas(tr_work *w, const uint16_t *a)
{
	int prev = 0;

	for (int i = 0; i < w->m.nv; i++) {
		put(w, qm_zigzag(a[i] - prev), 2);
		prev = a[i];
	}
}

/* The edge list of the vertices whose coordinate a[] is val. */
static void
edge(tr_work *w, const uint16_t *a, int val, int wide)
{
	uint32_t n = 0;

	for (int i = 0; i < w->m.nv; i++)
		n += a[i] == val;
	put(w, n, 4);
	for (int i = 0; i < w->m.nv; i++)
		if (a[i] == val)
			put(w, (uint32_t)i, wide ? 4 : 2);
}

/* Smooth normals: the sum of the adjacent triangles' area vectors. */
static void
normals(tr_work *w)
{
	double *nr = tr_area_normals(&w->m, w->pos);
	uint8_t oct[2];

	for (int i = 0; i < w->m.nv; i++) {
		double *n = nr ? nr + 3 * i : NULL, l = 0, up[3];
		const double *p = w->pos + 3 * i;
		if (n)
			l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		if (!(l > 0)) { /* no triangle (or no memory): radial */
			l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
			up[0] = p[0] / l, up[1] = p[1] / l, up[2] = p[2] / l;
		} else
			up[0] = n[0] / l, up[1] = n[1] / l, up[2] = n[2] / l;
		qm_oct(up, oct);
		put(w, oct[0], 1), put(w, oct[1], 1);
	}
	free(nr);
}

static int
deflate_buf(tr_work *w, tl_err *e)
{
	unsigned char *out;
	size_t n;
	tl_err z;

	if (tl_gzip(w->buf, w->nbuf, &out, &n, &z) < 0)
		return tl_fail(e, "tile: %s", z.msg);
	free(w->buf);
	w->buf = out, w->cbuf = n, w->nbuf = n;
	return 0;
}

int
qm_encode(tr_work *w, float minh, float maxh, int gzip, tl_err *e)
{
	int nv = w->m.nv, wide = nv > 65536;
	uint32_t hi = 0;

	w->nbuf = 0;
	if (room(w, 88 + 4 + 6 * (size_t)nv + 4 + 4 + 4 * 3 *
	    (size_t)w->m.nt + 16 + 4 * 4 * (size_t)nv + 5 + 2 * (size_t)nv,
	    e) < 0)
		return -1;
	header(w, minh, maxh);
	put(w, (uint32_t)nv, 4);
	deltas(w, w->u), deltas(w, w->v), deltas(w, w->q);
	if (wide && w->nbuf % 4)
		put(w, 0, 4 - w->nbuf % 4);
	put(w, (uint32_t)w->m.nt, 4);
	for (int i = 0; i < 3 * w->m.nt; i++)
		put(w, qm_hwm((uint32_t)w->m.tri[i], &hi), wide ? 4 : 2);
	edge(w, w->u, 0, wide), edge(w, w->v, 0, wide);
	edge(w, w->u, QM_MAX, wide), edge(w, w->v, QM_MAX, wide);
	put(w, 1, 1), put(w, 2 * (uint32_t)nv, 4);
	normals(w);
	return gzip ? deflate_buf(w, e) : 0;
}
