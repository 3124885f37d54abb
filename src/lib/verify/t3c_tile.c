/* t3c_tile.c - one decoded glb of the 3D Tiles terrain profile against
 * its tile's rectangle and its TILE_* metadata: the vertices placed on
 * the globe (ECEF to longitude, latitude, height), heights, bounding
 * sphere and horizon occlusion point as for quantized-mesh (qm_tile.c's
 * EllipsoidalOccluder), triangles, the surface closed, CESIUM_tile_edges,
 * normals. Float
 * checks allow the positions' rounding (t3c_tile.noise) and 1 mm, and
 * report the worst vertex once per tile. */
#include "verify/t3c.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geo/wgs84.h"

#define TOL 1e-3

static const double radii[3] = { 6378137.0, 6378137.0, 6356752.3142451793 };

double
t3c_level_error(int z)
{
	return 78271.52 / ldexp(1, z);
}

/* WGS84 ECEF to longitude, latitude (degrees), height; *axis: the
 * distance from the polar axis. */
static void
geodetic(const double p[3], double *lon, double *lat, double *h,
    double *axis)
{
	const double a = 6378137.0, f = 1 / 298.257223563;
	const double e2 = f * (2 - f);
	double r = hypot(p[0], p[1]), phi = atan2(p[2], r * (1 - e2)), s, n;

	for (int k = 0; k < 8; k++) {
		s = sin(phi), n = a / sqrt(1 - e2 * s * s);
		phi = atan2(p[2] + e2 * n * s, r);
	}
	s = sin(phi);
	*h = r * cos(phi) + p[2] * s - a * sqrt(1 - e2 * s * s);
	*lon = atan2(p[1], p[0]) * 180 / M_PI, *lat = phi * 180 / M_PI;
	*axis = r;
}

/* The rounding of vertex i's longitude, in u units (0..QM_MAXQ). */
static double
lon_noise(const t3c_tile *t, double axis, double w)
{
	return t->noise / fmax(axis, 1e-9) * 180 / M_PI / w * QM_MAXQ;
}

static double
snap(double q, double d)
{
	return fabs(q) <= d ? 0 : fabs(q - QM_MAXQ) <= d ? QM_MAXQ : q;
}

int
t3c_place(const t3c_tile *t, int z, int x, int y, double *uv, double *h,
    unsigned char *pole)
{
	double rect[4], w, lon, lat, axis, du, dv;

	qm_rect(z, x, y, rect);
	w = rect[2] - rect[0];
	dv = t->noise / radii[2] * 180 / M_PI / w * QM_MAXQ + 1e-6;
	for (uint32_t i = 0; i < t->n; i++) {
		geodetic(t->p + 3 * (size_t)i, &lon, &lat, &h[i], &axis);
		du = lon_noise(t, axis, w) + 1e-6;
		/* longitude lost in the rounding: 1/1000 of the tile */
		pole[i] = du > 1e-3 * QM_MAXQ;
		lon = remainder(lon - rect[0] - w / 2, 360) + w / 2;
		uv[2 * i] = pole[i] ? 0.5 * QM_MAXQ : snap(lon / w * QM_MAXQ,
		    du);
		uv[2 * i + 1] = snap((lat - rect[1]) / w * QM_MAXQ, dv);
	}
	return 0;
}

static void
check_meta(const t3c_meta *m, int z, int x, int y, qm_report *r)
{
	int bad = !isfinite(m->hmin) || !isfinite(m->hmax) ||
	    m->hmin > m->hmax || !isfinite(m->sphere[3]) || m->sphere[3] < 0;

	/* an occlusion point of NaN (none exists: a root tile) is never
	 * culled, as in the .terrain header; infinities are refused */
	for (int k = 0; k < 3; k++)
		bad |= !isfinite(m->sphere[k]) || isinf(m->hop[k]);
	if (bad)
		qm_issue_add(r, QM_HEADER, z, x, y, "TILE_* metadata not "
		    "finite (the occlusion point may be NaN), or minimum height %g over maximum %g, or radius "
		    "%g", m->hmin, m->hmax, m->sphere[3]);
}

static void
check_heights(const t3c_tile *t, const t3c_meta *m, const double *h,
    int z, int x, int y, qm_report *r)
{
	double tol = 2 * t->noise + TOL, lo = INFINITY, hi = -INFINITY;
	uint32_t il = 0, ih = 0;

	for (uint32_t i = 0; i < t->n; i++) {
		if (h[i] < lo)
			lo = h[i], il = i;
		if (h[i] > hi)
			hi = h[i], ih = i;
	}
	if (t->n == 0)
		return;
	if (lo < m->hmin - tol || lo > m->hmin + tol)
		qm_issue_add(r, QM_HEIGHTS, z, x, y, "the lowest vertex (%u) "
		    "at %.4f m, TILE_MINIMUM_HEIGHT %.4f m", il, lo, m->hmin);
	if (hi > m->hmax + tol || hi < m->hmax - tol)
		qm_issue_add(r, QM_HEIGHTS, z, x, y, "the highest vertex (%u) "
		    "at %.4f m, TILE_MAXIMUM_HEIGHT %.4f m", ih, hi, m->hmax);
}

/* The horizon magnitude of vertex p as low as its rounding allows (it
 * grows with height, steeply near the ellipsoid: 0.1 m above it at a
 * pole moves it by 10^-4). 1: fine whatever it is, the point being at
 * infinity (10^15 radii: CesiumJS never culls) and p within its
 * rounding of the half-space it sees. */
static int
horizon(const double p[3], double noise, const double d[3], double pm,
    double *mg)
{
	double q[3], len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
	double c = 0, s2 = 0;

	for (int k = 0; k < 3; k++)
		q[k] = p[k] * fmax(0, 1 - noise / fmax(len, 1e-9));
	*mg = qm_horizon_magnitude(q, d, radii);
	for (int k = 0; k < 3; k++)
		c += p[k] / radii[k] * d[k], s2 += p[k] / radii[k] * p[k] /
		    radii[k];
	return pm > 1e15 && c / sqrt(s2) > -(noise / fmax(len, 1e-9) + 1e-12);
}

static void
check_geometry(const t3c_tile *t, const t3c_meta *m, int z, int x, int y,
    qm_report *r)
{
	double d[3], pm, out = 0, low = 0, mnone = 0, tol = t->noise + TOL;
	long io = -1, il = -1, inone = -1;

	pm = sqrt(m->hop[0] * m->hop[0] + m->hop[1] * m->hop[1] +
	    m->hop[2] * m->hop[2]);
	for (int k = 0; k < 3; k++)
		d[k] = m->hop[k] / pm;
	for (uint32_t i = 0; i < t->n; i++) {
		const double *p = t->p + 3 * (size_t)i;
		double dx = 0, mg;

		for (int k = 0; k < 3; k++)
			dx += (p[k] - m->sphere[k]) * (p[k] - m->sphere[k]);
		if (sqrt(dx) - m->sphere[3] > out)
			out = sqrt(dx) - m->sphere[3], io = i;
		if (!isfinite(pm))
			continue;
		if (horizon(p, t->noise, d, pm, &mg))
			continue;
		if (!(mg > 0) || !isfinite(mg)) {
			if (inone < 0)
				inone = i, mnone = mg;
		} else if ((mg - pm) * radii[2] > low)
			low = (mg - pm) * radii[2], il = i;
	}
	if (out > tol)
		qm_issue_add(r, QM_SPHERE, z, x, y, "vertex %ld lies %.4g m "
		    "outside TILE_BOUNDING_SPHERE (radius %.6g m)", io, out,
		    m->sphere[3]);
	if (inone >= 0)
		qm_issue_add(r, QM_OCCLUSION, z, x, y, "vertex %ld: no point "
		    "in TILE_HORIZON_OCCLUSION_POINT's direction hides only "
		    "what it hides (CesiumJS's magnitude %g)", inone, mnone);
	else if (low > tol)
		qm_issue_add(r, QM_OCCLUSION, z, x, y, "TILE_HORIZON_OCCLUSION"
		    "_POINT is %.4g m below vertex %ld's horizon (scaled "
		    "space, times the polar radius): CesiumJS would cull the "
		    "tile while the vertex shows", low, il);
}

/* Seen from above: in (u, v) beyond the rounding, or for a triangle with
 * a vertex at a pole in ECEF against the normal at its centroid. */
static double
orient(const t3c_tile *t, const double *uv, const unsigned char *pole,
    const uint32_t *c, double eps)
{
	const double *a = uv + 2 * c[0], *b = uv + 2 * c[1];
	const double *d = uv + 2 * c[2];
	double e1[3], e2[3], g[3], N[3], lon, lat, h, ax, foot[3], up[3];

	if (!pole[c[0]] && !pole[c[1]] && !pole[c[2]]) {
		double s = (b[0] - a[0]) * (d[1] - a[1]) -
		    (b[1] - a[1]) * (d[0] - a[0]);
		double per = hypot(b[0] - a[0], b[1] - a[1]) +
		    hypot(d[0] - b[0], d[1] - b[1]) +
		    hypot(a[0] - d[0], a[1] - d[1]);

		return fabs(s) <= 2 * eps * per ? 0 : s;
	}
	for (int k = 0; k < 3; k++) {
		e1[k] = t->p[3 * c[1] + k] - t->p[3 * c[0] + k];
		e2[k] = t->p[3 * c[2] + k] - t->p[3 * c[0] + k];
		g[k] = (t->p[3 * c[0] + k] + t->p[3 * c[1] + k] +
		    t->p[3 * c[2] + k]) / 3;
	}
	N[0] = e1[1] * e2[2] - e1[2] * e2[1];
	N[1] = e1[2] * e2[0] - e1[0] * e2[2];
	N[2] = e1[0] * e2[1] - e1[1] * e2[0];
	/* two corners one point (the pole's): no orientation */
	if (sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]) <= 2 * t->noise *
	    (sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]) +
	    sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2])))
		return 0;
	geodetic(g, &lon, &lat, &h, &ax);
	geo_ellipsoid(lon, lat, foot, up);
	return N[0] * up[0] + N[1] * up[1] + N[2] * up[2];
}

static void
check_triangles(const t3c_tile *t, const double *uv,
    const unsigned char *pole, double eps, int z, int x, int y,
    qm_report *r)
{
	int bad = 0, cw = 0, flat = 0;

	for (uint32_t k = 0; k < t->ntri; k++) {
		const uint32_t *c = t->idx + 3 * (size_t)k;

		if (c[0] >= t->n || c[1] >= t->n || c[2] >= t->n) {
			if (!bad++)
				qm_issue_add(r, QM_INDEX, z, x, y, "triangle "
				    "%u: indices %u %u %u, %u vertices", k,
				    c[0], c[1], c[2], t->n);
			continue;
		}
		if ((c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) &&
		    !flat++)
			qm_issue_add(r, QM_DEGENERATE, z, x, y, "triangle %u "
			    "(%u %u %u) repeats a vertex", k, c[0], c[1],
			    c[2]);
		else if (orient(t, uv, pole, c, eps) < 0 && !cw++)
			qm_issue_add(r, QM_WINDING, z, x, y, "triangle %u "
			    "(%u %u %u) is clockwise seen from above", k, c[0],
			    c[1], c[2]);
	}
	if (t->ntri == 0 && t->n > 0)
		qm_issue_add(r, QM_DEGENERATE, z, x, y, "no triangle");
}

/* Each list: in range, once each, exactly the vertices on its edge
 * (a vertex at a pole, whose longitude is lost, may be on the west and
 * east edges or not), in the order CesiumJS's skirts walk: left south to
 * north, bottom east to west, right north to south, top west to east. */
static void
check_edges(const t3c_tile *t, const double *uv, const unsigned char *pole,
    double eps, int z, int x, int y, qm_report *r)
{
	static const char *side[4] = { "left", "bottom", "right", "top" };
	static const int along[4] = { 1, 0, 1, 0 }, sign[4] = { 1, -1, -1, 1 };
	unsigned char *mark = calloc(t->n + 1, 1);

	if (mark == NULL)
		return;
	for (int s = 0; s < 4; s++) {
		int bad = 0, ew = s == QM_WEST || s == QM_EAST;
		double last = -INFINITY;

		memset(mark, 0, t->n);
		for (uint32_t k = 0; k < t->nedge[s] && !bad; k++) {
			uint32_t i = t->edge[s][k];
			double a;

			if (i >= t->n || mark[i]) {
				bad++;
				qm_issue_add(r, QM_EDGES, z, x, y, "%s list: "
				    "index %u %s", side[s], i, i >= t->n ?
				    "past the vertices" : "twice");
				break;
			}
			mark[i] = 1;
			if (pole[i] && !along[s])
				continue;
			a = sign[s] * uv[2 * i + along[s]];
			if (a < last - 2 * eps && !bad++)
				qm_issue_add(r, QM_EDGES, z, x, y, "%s list: "
				    "vertex %u out of the order the skirts "
				    "walk", side[s], i);
			last = fmax(last, a);
		}
		for (uint32_t i = 0; i < t->n && !bad; i++) {
			double q = uv[2 * i + !ew];
			int on = q == (s < 2 ? 0 : QM_MAXQ);

			if (ew && pole[i])
				continue;
			if (on != mark[i] && !bad++)
				qm_issue_add(r, QM_EDGES, z, x, y, "vertex %u "
				    "(u %.2f, v %.2f) %s the %s edge but %s its "
				    "list", i, uv[2 * i], uv[2 * i + 1],
				    on ? "on" : "off", side[s],
				    on ? "not in" : "in");
		}
	}
	free(mark);
}

/* As quantized-mesh's (qm_closed.c), places the vertices' ECEF floats.
 * Edges from a vertex at a pole are left out: there a row of vertices
 * is one point, up to their rounding. */
static void
check_closed(const t3c_tile *t, const double *uv, const unsigned char *pole,
    int z, int x, int y, qm_report *r)
{
	qm_closure_in in = { .n = t->n, .key = t->p, .uv = uv,
	    .ncorner = 3 * (size_t)t->ntri, .corner32 = t->idx, .skip = pole };
	qm_closure c;

	if (qm_closed(&in, &c) < 0) {
		qm_issue_add(r, QM_DECODE, z, x, y, "out of memory");
		return;
	}
	if (c.open)
		qm_issue_add(r, QM_HOLE, z, x, y, "%zu edges inside the tile "
		    "belong to one triangle only, a crack; the first from "
		    "vertex %u to %u", c.open, c.open_edge[0], c.open_edge[1]);
	if (c.over)
		qm_issue_add(r, QM_HOLE, z, x, y, "%zu edges shared by "
		    "triangles running the same way or by three or more, an "
		    "overlap; the first from vertex %u to %u", c.over,
		    c.over_edge[0], c.over_edge[1]);
}

static void
check_normals(const t3c_tile *t, int z, int x, int y, qm_report *r)
{
	for (uint32_t i = 0; i < t->n; i++) {
		const float *n = t->nrm + 3 * (size_t)i;
		double lon, lat, h, ax, foot[3], up[3], len, dot;

		len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] +
		    (double)n[2] * n[2]);
		geodetic(t->p + 3 * (size_t)i, &lon, &lat, &h, &ax);
		geo_ellipsoid(lon, lat, foot, up);
		dot = (n[0] * up[0] + n[1] * up[1] + n[2] * up[2]) / len;
		if (!(fabs(len - 1) <= 1e-3)) {
			qm_issue_add(r, QM_EXTENSION, z, x, y, "NORMAL of "
			    "vertex %u: length %g, not 1", i, len);
			return;
		}
		/* as for quantized-mesh: 2 deg */
		if (dot < -sin(2 * M_PI / 180)) {
			qm_issue_add(r, QM_EXTENSION, z, x, y, "NORMAL of "
			    "vertex %u points %.1f deg from up, into the "
			    "ground", i, acos(fmax(-1, dot)) * 180 / M_PI);
			return;
		}
	}
}

void
t3c_tile_check(const t3c_tile *t, const t3c_meta *m, int z, int x, int y,
    qm_report *r)
{
	double *uv = malloc((2 * (size_t)t->n + 1) * sizeof *uv);
	double *h = malloc(((size_t)t->n + 1) * sizeof *h), eps = 0;
	unsigned char *pole = malloc((size_t)t->n + 1);
	uint32_t out = 0, first = 0;

	if (uv == NULL || h == NULL || pole == NULL) {
		qm_issue_add(r, QM_DECODE, z, x, y, "out of memory");
		goto done;
	}
	t3c_place(t, z, x, y, uv, h, pole);
	for (uint32_t i = 0; i < t->n; i++)
		if (uv[2 * i] < 0 || uv[2 * i] > QM_MAXQ ||
		    uv[2 * i + 1] < 0 || uv[2 * i + 1] > QM_MAXQ)
			first = out++ ? first : i;
	if (out)
		qm_issue_add(r, QM_DECODE, z, x, y, "%u vertices outside the "
		    "tile's rectangle; the first, %u, at u %.2f v %.2f (of "
		    "0..32767)", out, first, uv[2 * first], uv[2 * first + 1]);
	/* the rounding in (u, v), a pole's aside: of the plane tests */
	for (uint32_t i = 0; i < t->n; i++) {
		double rect[4];

		qm_rect(z, x, y, rect);
		if (!pole[i])
			eps = fmax(eps, lon_noise(t, hypot(t->p[3 * i],
			    t->p[3 * i + 1]), rect[2] - rect[0]) + 1e-6);
	}
	check_meta(m, z, x, y, r);
	check_heights(t, m, h, z, x, y, r);
	check_geometry(t, m, z, x, y, r);
	check_triangles(t, uv, pole, eps, z, x, y, r);
	check_edges(t, uv, pole, eps, z, x, y, r);
	check_closed(t, uv, pole, z, x, y, r);
	check_normals(t, z, x, y, r);
done:
	free(uv), free(h), free(pole);
}
