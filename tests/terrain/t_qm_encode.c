/* t_qm_encode.c - the quantized-mesh encoder's pieces (terrain/
 * qm_encode.c) against what the format's readers do, computed here
 * independently: zig-zag decoded as CesiumJS does, high-water-mark codes
 * decoded back to indices, oct-encoded normals decoded as CesiumJS's
 * AttributeCompression.octDecode, and the horizon occlusion point seeing
 * every vertex over the unit sphere in scaled space (tangent: no closer
 * point does). */
#include <math.h>
#include <stdlib.h>

#include "tap.h"
#include "terrain/tr_impl.h"

static void
zigzag(void)
{
	int bad = 0;

	for (int d = -32767; d <= 32767; d++) {
		int z = qm_zigzag(d);
		if (((z >> 1) ^ -(z & 1)) != d || z < 0 || z > 65534)
			bad++;
	}
	ok(bad == 0, "zig-zag of every delta -32767 .. 32767 decodes back");
	ok(qm_zigzag(0) == 0 && qm_zigzag(-1) == 1 && qm_zigzag(1) == 2 &&
	    qm_zigzag(-2) == 3 && qm_zigzag(32767) == 65534 &&
	    qm_zigzag(-32767) == 65533, "zig-zag: 0 -1 1 -2 -> 0 1 2 3");
}

static void
hwm(void)
{
	uint32_t ix[6] = { 0, 1, 2, 1, 3, 2 }, want[6] = { 0, 0, 0, 2, 0, 2 };
	uint32_t hi = 0, code[3000], idx[3000];
	int same = 1, n = 3000, m = 0;

	for (int i = 0; i < 6; i++)
		same &= qm_hwm(ix[i], &hi) == want[i];
	ok(same && hi == 4, "high-water mark of 0 1 2 1 3 2: 0 0 0 2 0 2");
	/* random triangles over vertices numbered by first use */
	srand(7);
	for (int i = 0; i < n; i++) {
		idx[i] = (m == 0 || rand() % 3 == 0) ? (uint32_t)m++ :
		    (uint32_t)(rand() % m);
	}
	hi = 0;
	for (int i = 0; i < n; i++)
		code[i] = qm_hwm(idx[i], &hi);
	/* the reader's decoding (quantized-mesh README) */
	uint32_t highest = 0;
	same = 1;
	for (int i = 0; i < n; i++) {
		uint32_t c = code[i], k = highest - c;
		same &= k == idx[i];
		if (c == 0)
			++highest;
	}
	ok(same && highest == (uint32_t)m, "%d random indices: codes decode "
	    "back", n);
}

/* CesiumJS's AttributeCompression.octDecodeInRange, range 255 */
static void
octdec(const uint8_t b[2], double n[3])
{
	double x = b[0] / 255.0 * 2 - 1, y = b[1] / 255.0 * 2 - 1;
	double z = 1 - (fabs(x) + fabs(y)), l;

	if (z < 0) {
		double ox = x;
		x = (1 - fabs(y)) * (ox >= 0 ? 1 : -1);
		y = (1 - fabs(ox)) * (y >= 0 ? 1 : -1);
	}
	l = sqrt(x * x + y * y + z * z);
	n[0] = x / l, n[1] = y / l, n[2] = z / l;
}

static void
oct(void)
{
	double up[3] = { 0, 0, 1 }, down[3] = { 0, 0, -1 }, ex[3] = { 1, 0, 0 };
	double worst = 0;
	uint8_t b[2];

	qm_oct(up, b);
	ok(b[0] == 128 && b[1] == 128, "oct: +z -> 128 128 (%d %d)", b[0],
	    b[1]);
	qm_oct(down, b);
	ok(b[0] == 255 && b[1] == 255, "oct: -z -> 255 255 (%d %d)", b[0],
	    b[1]);
	qm_oct(ex, b);
	ok(b[0] == 255 && b[1] == 128, "oct: +x -> 255 128 (%d %d)", b[0],
	    b[1]);
	srand(11);
	for (int i = 0; i < 20000; i++) {
		double v[3], d[3], l = 0, c;
		for (int k = 0; k < 3; k++)
			v[k] = rand() / (double)RAND_MAX * 2 - 1, l += v[k] * v[k];
		if (l < 1e-6)
			continue;
		for (int k = 0; k < 3; k++)
			v[k] /= sqrt(l);
		qm_oct(v, b);
		octdec(b, d);
		c = v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
		worst = fmax(worst, acos(fmin(1, c)) * 180 / M_PI);
	}
	ok(worst < 1.0, "oct: 20000 random unit vectors decode within 1 "
	    "degree (worst %.3f)", worst);
}

/* Distance from the origin to segment a b. */
static double
segdist(const double a[3], const double b[3])
{
	double d[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, dd = 0, t = 0;

	for (int k = 0; k < 3; k++)
		dd += d[k] * d[k], t -= a[k] * d[k];
	t = dd > 0 ? fmax(0, fmin(1, t / dd)) : 0;
	double p[3] = { a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2] };
	return sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
}

static void
horizon(void)
{
	const double A = 6378137.0, B = 6356752.314245179;
	double p[3 * 64], s[3 * 64], dir[3] = { 0, 0, 0 }, o[3], lo = INFINITY;
	int n = 0, r;

	/* a patch of a tile near 48N 124W, heights 0 .. 800 m */
	for (int i = 0; i < 8; i++)
		for (int j = 0; j < 8; j++, n++) {
			double lon = (-124 + 0.1 * i) * M_PI / 180;
			double lat = (48 + 0.1 * j) * M_PI / 180, h = 100.0 * i;
			double e2 = 1 - B * B / (A * A), sl = sin(lat);
			double nn = A / sqrt(1 - e2 * sl * sl);
			p[3 * n] = (nn + h) * cos(lat) * cos(lon);
			p[3 * n + 1] = (nn + h) * cos(lat) * sin(lon);
			p[3 * n + 2] = (nn * (1 - e2) + h) * sl;
			for (int k = 0; k < 3; k++)
				dir[k] += p[3 * n + k] / 64;
			s[3 * n] = p[3 * n] / A, s[3 * n + 1] = p[3 * n + 1] / A;
			s[3 * n + 2] = p[3 * n + 2] / B;
		}
	r = qm_horizon(dir, p, n, o);
	for (int i = 0; i < n; i++)
		lo = fmin(lo, segdist(o, s + 3 * i));
	ok(r == 0 && lo >= 1 - 1e-9, "horizon point: every vertex seen over "
	    "the unit sphere (closest approach %.12f)", lo);
	double q[3] = { o[0] * 0.999, o[1] * 0.999, o[2] * 0.999 };
	lo = INFINITY;
	for (int i = 0; i < n; i++)
		lo = fmin(lo, segdist(q, s + 3 * i));
	ok(lo < 1, "horizon point: 0.1%% closer, some vertex is hidden "
	    "(closest approach %.9f)", lo);
	/* a vertex on the other side of the globe: no point exists */
	p[0] = -p[0], p[1] = -p[1], p[2] = -p[2];
	ok(qm_horizon(dir, p, n, o) < 0, "horizon point: none for a vertex "
	    "past 90 degrees");
}

int
main(void)
{
	zigzag();
	hwm();
	oct();
	horizon();
	return tap_done();
}
