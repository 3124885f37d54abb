/* qm_tile.c - one decoded quantized-mesh tile against itself: its header
 * against its vertices (heights, bounding sphere, horizon occlusion
 * point as CesiumJS's EllipsoidalOccluder has it), its triangles (in
 * range, counter-clockwise, with area), its edge lists, its extensions.
 * Float checks report the worst vertex once per tile. */
#include "verify/qm.h"

#include "base/json.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geo/wgs84.h"

#define TOL 1e-3 /* metres: what the header may miss a vertex by */

/* CesiumJS's Ellipsoid.WGS84 radii: its scaled space divides by them. */
static const double radii[3] = { 6378137.0, 6378137.0, 6356752.3142451793 };

void
qm_vertex(const qm_tile *t, const double rect[4], uint32_t i,
    double llh[3], double ecef[3])
{
	double u = (double)t->u[i] / QM_MAXQ, v = (double)t->v[i] / QM_MAXQ;
	double h = (double)t->h[i] / QM_MAXQ;

	/* CesiumJS's lerp: (1 - t) a + t b */
	llh[0] = (1 - u) * rect[0] + u * rect[2];
	llh[1] = (1 - v) * rect[1] + v * rect[3];
	llh[2] = (1 - h) * t->hmin + h * (double)t->hmax;
	geo_ecef(llh[0], llh[1], llh[2], ecef);
}

static int
in_range(const qm_tile *t, int z, int x, int y, qm_report *r)
{
	const int32_t *q[3] = { t->u, t->v, t->h };
	static const char *name[3] = { "u", "v", "height" };
	int bad = 0;

	for (int c = 0; c < 3; c++)
		for (uint32_t i = 0; i < t->n; i++)
			if (q[c][i] < 0 || q[c][i] > QM_MAXQ) {
				if (!bad++)
					qm_issue_add(r, QM_DECODE, z, x, y,
					    "vertex %u: %s %d outside 0..32767 "
					    "(zig-zag deltas summed)", i,
					    name[c], q[c][i]);
			}
	return bad;
}

static void
check_heights(const qm_tile *t, int z, int x, int y, qm_report *r)
{
	int lo = 0, hi = 0;

	for (int k = 0; k < 3; k++)
		if (!isfinite(t->center[k]) || !isfinite(t->sphere[k]))
			qm_issue_add(r, QM_HEADER, z, x, y, "centre or "
			    "bounding sphere centre not finite");
	if (!isfinite(t->sphere[3]) || t->sphere[3] < 0)
		qm_issue_add(r, QM_HEADER, z, x, y, "bounding sphere radius "
		    "%g", t->sphere[3]);
	if (!isfinite(t->hmin) || !isfinite(t->hmax) || t->hmin > t->hmax) {
		qm_issue_add(r, QM_HEADER, z, x, y, "minimum height %g, "
		    "maximum %g", t->hmin, t->hmax);
		return;
	}
	if (t->hmin == t->hmax || t->n == 0)
		return;
	for (uint32_t i = 0; i < t->n; i++)
		lo |= t->h[i] == 0, hi |= t->h[i] == QM_MAXQ;
	if (!lo)
		qm_issue_add(r, QM_HEIGHTS, z, x, y, "no vertex at height 0: "
		    "the minimum height %g is below every vertex", t->hmin);
	if (!hi)
		qm_issue_add(r, QM_HEIGHTS, z, x, y, "no vertex at height "
		    "32767: the maximum height %g is above every vertex",
		    t->hmax);
}

double
qm_horizon_magnitude(const double p[3], const double d[3],
    const double rad[3])
{
	double s[3], m2 = 0, m, c = 0, x[3], sa, cb, sb;

	for (int k = 0; k < 3; k++)
		s[k] = p[k] / rad[k], m2 += s[k] * s[k];
	m = sqrt(m2);
	for (int k = 0; k < 3; k++)
		s[k] /= m, c += s[k] * d[k];
	/* below the ellipsoid counts as on it */
	m2 = fmax(1, m2), m = fmax(1, m);
	x[0] = s[1] * d[2] - s[2] * d[1];
	x[1] = s[2] * d[0] - s[0] * d[2];
	x[2] = s[0] * d[1] - s[1] * d[0];
	sa = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
	cb = 1 / m;
	sb = sqrt(m2 - 1) * cb;
	return 1 / (c * cb - sa * sb);
}

/* A tile whose minimum height is below 0 has its point recomputed by
 * CesiumJS (createVerticesFromQuantizedTerrainMesh) from its vertices on
 * an ellipsoid shrunk by that height, towards the header's centre; the
 * header's point is used only when that fails (a magnitude below 0). */
static int
recomputed(const qm_tile *t, const double rect[4])
{
	double rad[3], d[3], dl = 0, llh[3], p[3];

	if (!(t->hmin < 0) || -t->hmin >= radii[2])
		return 0;
	for (int k = 0; k < 3; k++)
		rad[k] = radii[k] + t->hmin;
	for (int k = 0; k < 3; k++)
		d[k] = t->center[k] / rad[k], dl += d[k] * d[k];
	for (int k = 0; k < 3; k++)
		d[k] /= sqrt(dl);
	for (uint32_t i = 0; i < t->n; i++) {
		qm_vertex(t, rect, i, llh, p);
		if (qm_horizon_magnitude(p, d, rad) < 0)
			return 0;
	}
	return 1;
}

static void
check_geometry(const qm_tile *t, int z, int x, int y, qm_report *r)
{
	double rect[4], llh[3], p[3], d[3], pm, out = 0, low = 0, mnone = 0;
	long io = -1, il = -1, inone = -1;

	qm_rect(z, x, y, rect);
	pm = sqrt(t->occlusion[0] * t->occlusion[0] +
	    t->occlusion[1] * t->occlusion[1] +
	    t->occlusion[2] * t->occlusion[2]);
	for (int k = 0; k < 3; k++)
		d[k] = t->occlusion[k] / pm;
	for (uint32_t i = 0; i < t->n; i++) {
		double dx = 0, m;

		qm_vertex(t, rect, i, llh, p);
		for (int k = 0; k < 3; k++)
			dx += (p[k] - t->sphere[k]) * (p[k] - t->sphere[k]);
		if (sqrt(dx) - t->sphere[3] > out)
			out = sqrt(dx) - t->sphere[3], io = i;
		/* a point not finite (NaN, infinite) is never culled:
		 * CesiumJS's comparisons with it are false */
		if (!isfinite(pm))
			continue;
		m = qm_horizon_magnitude(p, d, radii);
		if (!(m > 0) || !isfinite(m)) {
			if (inone < 0)
				inone = i, mnone = m;
		} else if ((m - pm) * radii[2] > low)
			low = (m - pm) * radii[2], il = i;
	}
	if (out > TOL)
		qm_issue_add(r, QM_SPHERE, z, x, y, "vertex %ld lies %.4g m "
		    "outside the bounding sphere (radius %.6g m)", io, out,
		    t->sphere[3]);
	if ((inone >= 0 || low > TOL) && recomputed(t, rect))
		return;
	if (inone >= 0)
		qm_issue_add(r, QM_OCCLUSION, z, x, y, "vertex %ld: no point "
		    "in the occlusion point's direction hides only what it "
		    "hides (CesiumJS's magnitude %g)", inone, mnone);
	else if (low > TOL)
		qm_issue_add(r, QM_OCCLUSION, z, x, y, "the horizon occlusion "
		    "point is %.4g m below vertex %ld's horizon (scaled "
		    "space, times the polar radius): CesiumJS would cull the "
		    "tile while the vertex shows", low, il);
}

static void
check_triangles(const qm_tile *t, int z, int x, int y, qm_report *r)
{
	int bad = 0, cw = 0, flat = 0;

	for (uint32_t k = 0; k < t->ntri; k++) {
		const int64_t *c = t->idx + 3 * (size_t)k;
		int64_t a, b;

		if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= t->n ||
		    c[1] >= t->n || c[2] >= t->n) {
			if (!bad++)
				qm_issue_add(r, QM_INDEX, z, x, y, "triangle "
				    "%u: indices %lld %lld %lld, %u vertices "
				    "(a high-water-mark code above the "
				    "highest so far gives one below 0)", k,
				    (long long)c[0], (long long)c[1],
				    (long long)c[2], t->n);
			continue;
		}
		a = (int64_t)(t->u[c[1]] - t->u[c[0]]) *
		    (t->v[c[2]] - t->v[c[0]]);
		b = (int64_t)(t->v[c[1]] - t->v[c[0]]) *
		    (t->u[c[2]] - t->u[c[0]]);
		if (a == b && !flat++)
			qm_issue_add(r, QM_DEGENERATE, z, x, y, "triangle %u "
			    "(%lld %lld %lld) has no area in (u, v)", k,
			    (long long)c[0], (long long)c[1],
			    (long long)c[2]);
		if (a < b && !cw++)
			qm_issue_add(r, QM_WINDING, z, x, y, "triangle %u "
			    "(%lld %lld %lld) is clockwise seen from outside "
			    "the ellipsoid", k, (long long)c[0],
			    (long long)c[1], (long long)c[2]);
	}
	if (t->ntri == 0 && t->n > 0)
		qm_issue_add(r, QM_DEGENERATE, z, x, y, "no triangle");
}

static void
check_edges(const qm_tile *t, int z, int x, int y, qm_report *r)
{
	static const char *side[4] = { "west", "south", "east", "north" };
	unsigned char *mark = calloc(t->n + 1, 1);

	if (mark == NULL) {
		qm_issue_add(r, QM_EDGES, z, x, y, "out of memory");
		return;
	}
	for (int s = 0; s < 4; s++) {
		int bad = 0;

		memset(mark, 0, t->n);
		for (uint32_t k = 0; k < t->nedge[s]; k++) {
			uint32_t i = t->edge[s][k];

			if (i >= t->n || mark[i]) {
				if (!bad++)
					qm_issue_add(r, QM_EDGES, z, x, y,
					    "%s list: index %u %s", side[s], i,
					    i >= t->n ? "past the vertices" :
					    "twice");
				continue;
			}
			mark[i] = 1;
		}
		for (uint32_t i = 0; i < t->n; i++) {
			int32_t q = s == QM_WEST || s == QM_EAST ? t->u[i] :
			    t->v[i];
			int on = q == (s < 2 ? 0 : QM_MAXQ);

			if (on != mark[i] && !bad++)
				qm_issue_add(r, QM_EDGES, z, x, y, "vertex %u "
				    "(u %d, v %d) %s the %s edge but %s its "
				    "list", i, t->u[i], t->v[i],
				    on ? "on" : "off", side[s],
				    on ? "not in" : "in");
		}
	}
	free(mark);
}

/* The surface drawn is closed (qm_closed.c): places are (u, v, height). */
static void
check_closed(const qm_tile *t, int z, int x, int y, qm_report *r)
{
	double *key = malloc((3 * (size_t)t->n + 1) * sizeof *key);
	double *uv = malloc((2 * (size_t)t->n + 1) * sizeof *uv);
	qm_closure_in in = { .n = t->n, .key = key, .uv = uv,
	    .ncorner = 3 * (size_t)t->ntri, .corner = t->idx };
	qm_closure c;
	uint32_t *o = c.open_edge;

	if (key == NULL || uv == NULL) {
		free(key), free(uv);
		qm_issue_add(r, QM_DECODE, z, x, y, "out of memory");
		return;
	}
	for (uint32_t i = 0; i < t->n; i++) {
		key[3 * i] = uv[2 * i] = t->u[i];
		key[3 * i + 1] = uv[2 * i + 1] = t->v[i];
		key[3 * i + 2] = t->h[i];
	}
	if (qm_closed(&in, &c) < 0)
		qm_issue_add(r, QM_DECODE, z, x, y, "out of memory");
	else if (c.open)
		qm_issue_add(r, QM_HOLE, z, x, y, "%zu edges inside the tile "
		    "belong to one triangle only, a crack; the first from "
		    "vertex %u (u %d, v %d, height %d) to %u (u %d, v %d, "
		    "height %d)", c.open, o[0], t->u[o[0]], t->v[o[0]],
		    t->h[o[0]], o[1], t->u[o[1]], t->v[o[1]], t->h[o[1]]);
	if (c.over)
		qm_issue_add(r, QM_HOLE, z, x, y, "%zu edges shared by "
		    "triangles running the same way or by three or more, an "
		    "overlap; the first from vertex %u to %u", c.over,
		    c.over_edge[0], c.over_edge[1]);
	free(key), free(uv);
}

/* Oct-encoded normals (CesiumJS's AttributeCompression.octDecode) must
 * point up, out of the ground. */
static void
check_normals(const qm_tile *t, int z, int x, int y, qm_report *r)
{
	double rect[4], llh[3], p[3], foot[3], up[3];

	qm_rect(z, x, y, rect);
	for (uint32_t i = 0; i < t->n; i++) {
		double nx = t->normals[2 * i] / 255.0 * 2 - 1;
		double ny = t->normals[2 * i + 1] / 255.0 * 2 - 1;
		double nz = 1 - fabs(nx) - fabs(ny), dot;

		if (nz < 0) {
			double ox = nx;

			nx = (1 - fabs(ny)) * (ox < 0 ? -1 : 1);
			ny = (1 - fabs(ox)) * (ny < 0 ? -1 : 1);
		}
		qm_vertex(t, rect, i, llh, p);
		geo_ellipsoid(llh[0], llh[1], foot, up);
		dot = (nx * up[0] + ny * up[1] + nz * up[2]) /
		    sqrt(nx * nx + ny * ny + nz * nz);
		/* a height field's normals point up; 2 deg for the 8-bit
		 * octahedral quantisation */
		if (dot < -sin(2 * M_PI / 180)) {
			qm_issue_add(r, QM_EXTENSION, z, x, y, "vertex %u's "
			    "normal points %.1f deg from up, into the "
			    "ground", i, acos(fmax(-1, dot)) * 180 / M_PI);
			return;
		}
	}
}

static void
check_extensions(const qm_tile *t, int z, int x, int y, int normals,
    qm_report *r)
{
	if (t->normals_len >= 0 && t->normals_len != 2 * (long)t->n)
		qm_issue_add(r, QM_EXTENSION, z, x, y, "oct normals (1): %ld "
		    "bytes for %u vertices", t->normals_len, t->n);
	else if (t->normals_len >= 0)
		check_normals(t, z, x, y, r);
	else if (normals)
		qm_issue_add(r, QM_EXTENSION, z, x, y, "layer.json lists "
		    "octvertexnormals; the tile has no extension 1");
	if (t->watermask_len >= 0 && t->watermask_len != 1 &&
	    t->watermask_len != 256 * 256)
		qm_issue_add(r, QM_EXTENSION, z, x, y, "water mask (2): %ld "
		    "bytes, not 1 or 65536", t->watermask_len);
	if (t->metadata_len >= 0 && t->metadata == NULL)
		qm_issue_add(r, QM_EXTENSION, z, x, y, "metadata (4): %ld "
		    "bytes do not hold a length and the JSON it counts",
		    t->metadata_len);
	else if (t->metadata != NULL) {
		json_error_t je;
		json_t *j = json_loads(t->metadata, 0, &je);

		if (!json_is_object(j))
			qm_issue_add(r, QM_EXTENSION, z, x, y, "metadata (4):"
			    " not a JSON object: %s", je.text);
		json_decref(j);
	}
}

int
qm_tile_sane(const qm_tile *t)
{
	if (!isfinite(t->hmin) || !isfinite(t->hmax))
		return 0;
	for (uint32_t i = 0; i < t->n; i++)
		if (t->u[i] < 0 || t->u[i] > QM_MAXQ || t->v[i] < 0 ||
		    t->v[i] > QM_MAXQ || t->h[i] < 0 || t->h[i] > QM_MAXQ)
			return 0;
	return 1;
}

void
qm_tile_check(const qm_tile *t, int z, int x, int y, int normals,
    qm_report *r)
{
	check_heights(t, z, x, y, r);
	if (in_range(t, z, x, y, r))
		return; /* positions past the tile: nothing else is sound */
	check_geometry(t, z, x, y, r);
	check_triangles(t, z, x, y, r);
	check_edges(t, z, x, y, r);
	check_closed(t, z, x, y, r);
	check_extensions(t, z, x, y, normals, r);
}
