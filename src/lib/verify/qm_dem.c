/* qm_dem.c - the surface CesiumJS draws from the tiles (flat triangles
 * between the decoded vertices in ECEF) against every valid sample of
 * the DEM: per sample and level, the tile(s) whose closed rectangle
 * holds it, the triangle whose (u, v) holds it, and the vertical
 * distance, along the ellipsoid's normal at the sample, from the sample
 * to that triangle's plane. The DEM is read once, north to south, a row
 * at a time; per level a hash of the tiles near that row is kept, a tile
 * dropped once the rows have passed south of it. */
#include "verify/qm.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geo/wgs84.h"

#define EDGE 1e-7   /* of a tile's width: a sample this near an edge is
                     * in both tiles */
#define BARY 1e-9   /* triangles are closed */

typedef struct {
	qm_key key;
	long slot;        /* its index in the set's keys */
	int ok;           /* placed: its format's reader could load it */
	double rect[4];
	qm_mesh m;
	int g;            /* g x g cells over (u, v) */
	uint32_t *cell;   /* g g + 1 starts into list */
	uint32_t *list;
} qt;

typedef struct {
	qt **t;
	long cap, n;
} cache;

typedef struct {
	const qm_set *s;
	qm_mesh_load load;
	void *ctx;
	qm_report *r;
	cache c[QM_MAXZ + 1];
	double *maxerr;   /* per tile of the set */
	long long *samples;
	int (*at)[2];     /* the sample of maxerr */
} run;

static void
qt_free(qt *t)
{
	if (t == NULL)
		return;
	qm_mesh_free(&t->m);
	free(t->cell), free(t->list);
	free(t);
}

static int
cellof(double q, int g)
{
	int c = (int)(q / (QM_MAXQ + 1.0) * g);

	return c < 0 ? 0 : c >= g ? g - 1 : c;
}

/* Triangles listed under every cell their (u, v) box meets; one with a
 * vertex at a pole (whose u is the whole pole's row) under every cell
 * of its rows. */
static int
grid(qt *t)
{
	const qm_mesh *M = &t->m;
	uint32_t *fill;
	int g;

	t->g = g = (int)fmin(256, fmax(1, sqrt(M->ntri / 2.0)));
	t->cell = calloc((size_t)g * g + 1, sizeof *t->cell);
	fill = calloc((size_t)g * g + 1, sizeof *fill);
	if (t->cell == NULL || fill == NULL) {
		free(fill);
		return -1;
	}
	for (int pass = 0; pass < 2; pass++) {
		for (uint32_t k = 0; k < M->ntri; k++) {
			const uint32_t *c = M->tri + 3 * (size_t)k;
			double u0 = QM_MAXQ, u1 = 0, v0 = QM_MAXQ, v1 = 0;

			for (int m = 0; m < 3; m++) {
				double u = M->uv[2 * c[m]], v = M->uv[2 * c[m] + 1];

				if (M->pole != NULL && M->pole[c[m]])
					u0 = 0, u1 = QM_MAXQ, u = 0.5 * QM_MAXQ;
				u0 = u < u0 ? u : u0, u1 = u > u1 ? u : u1;
				v0 = v < v0 ? v : v0, v1 = v > v1 ? v : v1;
			}
			for (int b = cellof(v0, g); b <= cellof(v1, g); b++)
				for (int a = cellof(u0, g); a <= cellof(u1, g);
				    a++) {
					size_t q = (size_t)b * g + a;

					if (pass == 0)
						t->cell[q + 1]++;
					else
						t->list[fill[q]++] = k;
				}
		}
		if (pass == 0) {
			for (size_t q = 0; q < (size_t)g * g; q++)
				t->cell[q + 1] += t->cell[q];
			memcpy(fill, t->cell, (size_t)g * g * sizeof *fill);
			t->list = malloc(((size_t)t->cell[(size_t)g * g] + 1) *
			    sizeof *t->list);
			if (t->list == NULL) {
				free(fill);
				return -1;
			}
		}
	}
	free(fill);
	return 0;
}

void
qm_mesh_free(qm_mesh *m)
{
	free(m->p), free(m->uv), free(m->pole), free(m->tri);
	memset(m, 0, sizeof *m);
}

/* The tile's drawn geometry from its format's reader; ok 0 when it
 * cannot be placed (its own checks say why: its samples are skipped).
 * NULL: no memory. */
static qt *
qt_load(const run *R, qm_key k, long slot)
{
	qt *t = calloc(1, sizeof *t);
	int st;

	if (t == NULL)
		return NULL;
	t->key = k, t->slot = slot;
	qm_rect(QM_KZ(k), QM_KX(k), QM_KY(k), t->rect);
	if ((st = R->load(R->ctx, k, &t->m)) < 0 ||
	    (st == 0 && grid(t) < 0)) {
		qt_free(t);
		return NULL;
	}
	t->ok = st == 0;
	return t;
}

/* quantized-mesh's reader: the tile's vertices as CesiumJS places them,
 * its triangles in range. */
static int
qm_load(void *ctx, qm_key k, qm_mesh *M)
{
	char path[4096];
	double rect[4], llh[3];
	qm_tile m;
	tl_err e;
	int st = 1;

	memset(M, 0, sizeof *M);
	qm_rect(QM_KZ(k), QM_KX(k), QM_KY(k), rect);
	snprintf(path, sizeof path, "%s/%d/%d/%d.terrain", (const char *)ctx,
	    QM_KZ(k), QM_KX(k), QM_KY(k));
	if (qm_read(path, &m, &e) < 0 || !qm_tile_sane(&m))
		goto done;
	st = -1;
	M->p = malloc(((size_t)m.n * 3 + 1) * sizeof *M->p);
	M->uv = malloc(((size_t)m.n * 2 + 1) * sizeof *M->uv);
	M->tri = malloc(((size_t)m.ntri * 3 + 1) * sizeof *M->tri);
	if (M->p == NULL || M->uv == NULL || M->tri == NULL)
		goto done;
	M->n = m.n;
	for (uint32_t i = 0; i < m.n; i++) {
		qm_vertex(&m, rect, i, llh, M->p + 3 * (size_t)i);
		M->uv[2 * i] = m.u[i], M->uv[2 * i + 1] = m.v[i];
	}
	for (uint32_t k2 = 0; k2 < m.ntri; k2++) {
		const int64_t *c = m.idx + 3 * (size_t)k2;

		if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= m.n ||
		    c[1] >= m.n || c[2] >= m.n)
			continue;
		for (int q = 0; q < 3; q++)
			M->tri[3 * (size_t)M->ntri + q] = (uint32_t)c[q];
		M->ntri++;
	}
	st = 0;
done:
	qm_free(&m);
	if (st < 0)
		qm_mesh_free(M);
	return st;
}

static size_t
hash(qm_key k, long cap)
{
	k ^= k >> 31, k *= 0x9e3779b97f4a7c15ULL, k ^= k >> 29;
	return (size_t)(k & (qm_key)(cap - 1));
}

static int
put(cache *c, qt *t)
{
	if (2 * (c->n + 1) > c->cap) {
		cache b = { NULL, c->cap ? 2 * c->cap : 64, 0 };

		if ((b.t = calloc((size_t)b.cap, sizeof *b.t)) == NULL)
			return -1;
		for (long i = 0; i < c->cap; i++)
			if (c->t[i] != NULL)
				put(&b, c->t[i]);
		free(c->t);
		*c = b;
	}
	for (size_t h = hash(t->key, c->cap);; h = (h + 1) & (c->cap - 1))
		if (c->t[h] == NULL) {
			c->t[h] = t, c->n++;
			return 0;
		}
}

/* The set's index of tile k, -1 when there is no such file. */
static long
slot_of(const qm_set *s, qm_key k)
{
	long lo = 0, hi = s->n;

	while (lo < hi) {
		long mid = lo + (hi - lo) / 2;

		if (s->key[mid] < k)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo < s->n && s->key[lo] == k ? lo : -1;
}

/* Tile k from the cache, loaded when absent. *none: no such file.
 * NULL with !*none: out of memory. */
static qt *
get(run *R, qm_key k, int *none)
{
	cache *c = &R->c[QM_KZ(k)];
	long slot;
	qt *t;

	*none = 0;
	if (c->cap > 0)
		for (size_t h = hash(k, c->cap); c->t[h] != NULL;
		    h = (h + 1) & (c->cap - 1))
			if (c->t[h]->key == k)
				return c->t[h];
	if ((slot = slot_of(R->s, k)) < 0) {
		*none = 1;
		return NULL;
	}
	if ((t = qt_load(R, k, slot)) == NULL || put(c, t) < 0) {
		qt_free(t);
		return NULL;
	}
	return t;
}

/* Tiles wholly north of latitude lat: the rows to come are south. */
static int
evict(cache *c, double lat)
{
	long keep = 0, drop = 0;
	qt **all;

	for (long i = 0; i < c->cap; i++)
		drop += c->t[i] != NULL && c->t[i]->rect[1] > lat;
	if (drop == 0)
		return 0;
	if ((all = malloc((size_t)c->n * sizeof *all)) == NULL)
		return -1;
	for (long i = 0; i < c->cap; i++)
		if (c->t[i] != NULL && c->t[i]->rect[1] > lat)
			qt_free(c->t[i]);
		else if (c->t[i] != NULL)
			all[keep++] = c->t[i];
	memset(c->t, 0, (size_t)c->cap * sizeof *c->t);
	c->n = 0;
	for (long i = 0; i < keep; i++)
		put(c, all[i]); /* fits: the table is as large as before */
	free(all);
	return 0;
}

/* The sample's vertical through a triangle with a vertex at a pole: the
 * point at height hs inside the ECEF triangle (the pole's u is
 * unknown, its (u, v) triangle meaningless). */
static int
inside3(const double *A, const double *B, const double *C, const double N[3],
    const double foot[3], const double up[3], double hs)
{
	const double *V[3] = { A, B, C };
	double X[3], nn = N[0] * N[0] + N[1] * N[1] + N[2] * N[2];

	for (int k = 0; k < 3; k++)
		X[k] = foot[k] + hs * up[k];
	for (int m = 0; m < 3; m++) {
		const double *P = V[(m + 1) % 3], *Q = V[(m + 2) % 3];
		double p[3], q[3], x[3];

		for (int k = 0; k < 3; k++)
			p[k] = P[k] - X[k], q[k] = Q[k] - X[k];
		x[0] = p[1] * q[2] - p[2] * q[1];
		x[1] = p[2] * q[0] - p[0] * q[2];
		x[2] = p[0] * q[1] - p[1] * q[0];
		if ((x[0] * N[0] + x[1] * N[1] + x[2] * N[2]) / nn < -BARY)
			return 0;
	}
	return 1;
}

/* Height of the drawn surface at the sample, along its normal: the plane
 * of the triangle whose (u, v) holds (su, sv). 0: none holds it. */
static int
surface(const qt *t, double su, double sv, const double foot[3],
    const double up[3], double *hs)
{
	const qm_mesh *M = &t->m;
	size_t q = (size_t)cellof(sv, t->g) * t->g + cellof(su, t->g);

	for (uint32_t m = t->cell[q]; m < t->cell[q + 1]; m++) {
		const uint32_t *c = M->tri + 3 * (size_t)t->list[m];
		const double *a = M->uv + 2 * c[0], *b = M->uv + 2 * c[1];
		const double *d = M->uv + 2 * c[2];
		const double *A = M->p + 3 * (size_t)c[0];
		const double *B = M->p + 3 * (size_t)c[1];
		const double *C = M->p + 3 * (size_t)c[2];
		double area = (b[0] - a[0]) * (d[1] - a[1]) -
		    (b[1] - a[1]) * (d[0] - a[0]);
		double l0, l1, e1[3], e2[3], N[3], den, num = 0;
		int pole = M->pole != NULL &&
		    (M->pole[c[0]] || M->pole[c[1]] || M->pole[c[2]]);

		if (area == 0 && !pole)
			continue;
		l0 = ((b[0] - su) * (d[1] - sv) - (b[1] - sv) * (d[0] - su)) /
		    area;
		l1 = ((d[0] - su) * (a[1] - sv) - (d[1] - sv) * (a[0] - su)) /
		    area;
		if (!pole && (l0 < -BARY || l1 < -BARY || 1 - l0 - l1 < -BARY))
			continue;
		for (int k = 0; k < 3; k++)
			e1[k] = B[k] - A[k], e2[k] = C[k] - A[k];
		N[0] = e1[1] * e2[2] - e1[2] * e2[1];
		N[1] = e1[2] * e2[0] - e1[0] * e2[2];
		N[2] = e1[0] * e2[1] - e1[1] * e2[0];
		den = N[0] * up[0] + N[1] * up[1] + N[2] * up[2];
		if (den == 0)
			continue; /* flat in ECEF (a pole's row): no height */
		for (int k = 0; k < 3; k++)
			num += (A[k] - foot[k]) * N[k];
		*hs = num / den;
		if (pole && !inside3(A, B, C, N, foot, up, *hs))
			continue;
		return 1;
	}
	return 0;
}

/* One sample at one level: every tile of the level whose closed
 * rectangle holds it. -1: out of memory. */
static int
sample(run *R, int z, double lon, double lat, double h, int i, int j)
{
	double dz = 180 / ldexp(1, z), tx = (lon + 180) / dz;
	double ty = (lat + 90) / dz, foot[3], up[3];
	long x0 = (long)floor(tx), y0 = (long)floor(ty), nx = 2L << z;
	long ny = 1L << z;
	int seen = 0, none;

	geo_ellipsoid(lon, lat, foot, up);
	for (long x = x0 - 1; x <= x0 + 1; x++)
		for (long y = y0 - 1; y <= y0 + 1; y++) {
			double su = (tx - x) * QM_MAXQ, sv = (ty - y) * QM_MAXQ;
			double hs;
			qt *t;

			if (x < 0 || x >= nx || y < 0 || y >= ny ||
			    tx < x - EDGE || tx > x + 1 + EDGE ||
			    ty < y - EDGE || ty > y + 1 + EDGE)
				continue;
			if ((t = get(R, QM_KEY(z, x, y), &none)) == NULL) {
				if (!none)
					return -1;
				continue;
			}
			seen = 1;
			if (!t->ok)
				continue;
			su = fmin(QM_MAXQ, fmax(0, su));
			sv = fmin(QM_MAXQ, fmax(0, sv));
			if (!surface(t, su, sv, foot, up, &hs)) {
				qm_issue_add(R->r, QM_COVERAGE, z, (int)x,
				    (int)y, "DEM sample (%d, %d) at %.9g, "
				    "%.9g lies in no triangle", i, j, lon, lat);
				continue;
			}
			R->samples[t->slot]++;
			if (fabs(h - hs) > R->maxerr[t->slot]) {
				R->maxerr[t->slot] = fabs(h - hs);
				R->at[t->slot][0] = i, R->at[t->slot][1] = j;
			}
		}
	if (!seen)
		qm_issue_add(R->r, QM_COVERAGE, z, (int)fmin(x0, nx - 1),
		    (int)fmin(y0, ny - 1), "DEM sample (%d, %d) at %.9g, %.9g: "
		    "no tile of level %d holds it", i, j, lon, lat, z);
	return 0;
}

/* Per tile its largest distance into the report: error / E_z per level,
 * a violation over E_z + 1 mm. */
static void
finish(run *R)
{
	const qm_set *s = R->s;

	for (long k = 0; k < s->n; k++) {
		int z = QM_KZ(s->key[k]), x = QM_KX(s->key[k]);
		int y = QM_KY(s->key[k]);
		qm_level *L = &R->r->lev[z];
		double el = R->r->level_error(z), *p;

		if (R->samples[k] == 0)
			continue;
		L->samples += R->samples[k];
		if (L->nratio == L->capratio) {
			long cap = L->capratio ? 2 * L->capratio : 64;

			if ((p = realloc(L->ratio, (size_t)cap * sizeof *p)) ==
			    NULL)
				continue;
			L->ratio = p, L->capratio = cap;
		}
		L->ratio[L->nratio++] = R->maxerr[k] / el;
		if (R->maxerr[k] >= L->worst) {
			L->worst = R->maxerr[k];
			L->worst_tile[0] = x, L->worst_tile[1] = y;
		}
		if (R->maxerr[k] > el + 1e-3)
			qm_issue_add(R->r, QM_ERROR, z, x, y, "%.4f m from DEM "
			    "sample (%d, %d), over E_%d = %.4f m (+1 mm)",
			    R->maxerr[k], R->at[k][0], R->at[k][1], z, el);
	}
}

/* Row j's valid samples as longitude, latitude, ellipsoidal height. */
static int
row_lonlat(dem *d, const georef *g, geo_proj *p, int j, float *zr,
    unsigned char *valid, double *x, double *y, double *h, int *col,
    int *n, tl_err *e)
{
	*n = 0;
	if (dem_read_row(d, j, zr, valid, e) < 0)
		return -1;
	for (int i = 0; i < g->width; i++) {
		if (!valid[i])
			continue;
		geo_vertex_crs(g, 0, i, j, &x[*n], &y[*n]);
		h[*n] = zr[i], col[*n] = i, (*n)++;
	}
	return p == NULL || *n == 0 ? 0 : geo_proj_lonlat(p, x, y, h, *n, e);
}

static int
rows(run *R, dem *d, geo_proj *p, int maxz, tl_err *e)
{
	const georef *g = dem_georef(d);
	size_t w = (size_t)g->width;
	float *zr = malloc(w * sizeof *zr);
	unsigned char *valid = malloc(w);
	double *x = malloc(w * sizeof *x), *y = malloc(w * sizeof *y);
	double *h = malloc(w * sizeof *h);
	int *col = malloc(w * sizeof *col), n, r = -1;

	if (zr == NULL || valid == NULL || x == NULL || y == NULL ||
	    h == NULL || col == NULL) {
		tl_fail(e, "out of memory for a DEM row");
		goto done;
	}
	for (int j = 0; j < g->height; j++) {
		double top = -90;

		if (row_lonlat(d, g, p, j, zr, valid, x, y, h, col, &n, e) < 0)
			goto done;
		for (int z = 0; z <= maxz; z++) {
			for (int k = 0; k < n; k++)
				if (sample(R, z, x[k], y[k], h[k], col[k],
				    j) < 0) {
					tl_fail(e, "out of memory for tiles");
					goto done;
				}
		}
		for (int k = 0; k < n; k++)
			top = fmax(top, y[k]);
		for (int z = 0; z <= maxz; z++)
			if (n > 0 && evict(&R->c[z], top + 1e-6) < 0) {
				tl_fail(e, "out of memory");
				goto done;
			}
	}
	r = 0;
done:
	free(zr), free(valid), free(x), free(y), free(h), free(col);
	return r;
}

int
qm_dem_measure(const qm_set *s, qm_mesh_load load, void *ctx,
    const char *dem_path, const dem_opts *o, qm_report *r, tl_err *e)
{
	run R;
	dem *d;
	geo_proj p, *pp = NULL;
	const georef *g;
	int maxz = s->n ? QM_KZ(s->key[s->n - 1]) : -1, st = -1;

	memset(&R, 0, sizeof R);
	R.s = s, R.r = r, R.load = load, R.ctx = ctx;
	if ((d = dem_open(dem_path, o, e)) == NULL)
		return -1;
	g = dem_georef(d);
	if (g->model == GEO_NONE) {
		dem_close(d);
		return tl_fail(e, "%s: no CRS: it cannot be placed on the "
		    "globe", dem_path);
	}
	/* WGS 84's own longitude, latitude: no transformation */
	if (!(g->model == GEO_GEOGRAPHIC && g->epsg == 4326)) {
		if (geo_proj_open(&p, g, e) < 0) {
			dem_close(d);
			return -1;
		}
		pp = &p;
	}
	R.maxerr = calloc((size_t)s->n + 1, sizeof *R.maxerr);
	R.samples = calloc((size_t)s->n + 1, sizeof *R.samples);
	R.at = calloc((size_t)s->n + 1, sizeof *R.at);
	if (R.maxerr == NULL || R.samples == NULL || R.at == NULL)
		tl_fail(e, "out of memory for %ld tiles", s->n);
	else if (rows(&R, d, pp, maxz, e) == 0) {
		finish(&R);
		st = 0;
	}
	for (int z = 0; z <= QM_MAXZ; z++) {
		for (long i = 0; i < R.c[z].cap; i++)
			qt_free(R.c[z].t[i]);
		free(R.c[z].t);
	}
	free(R.maxerr), free(R.samples), free(R.at);
	if (pp != NULL)
		geo_proj_close(pp);
	dem_close(d);
	return st;
}

int
qm_dem_check(const char *dir, const qm_set *s, const char *dem_path,
    const dem_opts *o, qm_report *r, tl_err *e)
{
	return qm_dem_measure(s, qm_load, (void *)dir, dem_path, o, r, e);
}
