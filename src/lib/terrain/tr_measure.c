/* tr_measure.c - a quantised tile's error (tr_quantise.c makes it). At
 * every level-0 sample of the pyramid in the tile, the height of the
 * drawn surface (the plane, in ECEF, of the triangle over it between the
 * DECODED vertices, met by the ellipsoid's normal through the sample) is
 * compared with the selection's surface at the sample's grid place: for
 * a geographic DEM the same triangle before quantisation, linear in
 * longitude, latitude, height (the map from the grid is affine); for a
 * projected one the plane of the selected triangle holding the place in
 * the grid (tr_gsel.c), as the drawn triangle, straight between its
 * vertices' images, is not. d[0], the largest difference, holds every
 * term but the selection's own error (the flat chords' sag, the
 * quantisation, the CRS mapping), which the pyramid's saturated errors
 * bound for the valid samples; and with the sample's height: d[1], the
 * error itself, filled voids included.
 * A kept tile given its triangles' bounds (tr_kept_check) fails on a
 * sample farther from the selection than its triangle's bound. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geo/wgs84.h"
#include "terrain/tr_bary.h"
#include "terrain/tr_impl.h"

/* The triangles by bucket of a grid over the part of the u, v square
 * that holds samples (the tile within the terrain's rectangle), about
 * one triangle a bucket; per triangle the terms of its barycentric
 * coordinates in u, v and in longitude, latitude, computed once (the
 * same operations per sample as computing them there). */
typedef struct {
	int *start, *list, nb;
	double o[2], s[2];  /* bucket of (u, v): ((u, v) - o) * s */
	double *plane;      /* per triangle: normal, offset (4) */
	double *bq;         /* per triangle in u, v: tr_bary.h's terms */
	double *bf;         /* in lon, lat: the same and the heights */
	const double *bound; /* per triangle, tr_bound's: checked, or NULL */
	const tr_gsel *gs;  /* projected: the selection in the grid */
	double W, H;        /* projected: the grid's last place, x and y */
	double band;        /* projected: only the samples within band
	                     * cells of a side measured (INFINITY: all) */
	double claim;       /* checked: those deeper drawn by bounded
	                     * triangles (tr_bound's band) */
} locator;
#define TR_PLANES (4 + 2 * TR_BARY_TERMS + 3) /* doubles a triangle */

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
	double *p = l->plane + 4 * t, *q = l->bq + TR_BARY_TERMS * t;
	double *f = l->bf + (TR_BARY_TERMS + 3) * t;

	p[0] = u[1] * v[2] - u[2] * v[1], p[1] = u[2] * v[0] - u[0] * v[2];
	p[2] = u[0] * v[1] - u[1] * v[0];
	p[3] = p[0] * a[0] + p[1] * a[1] + p[2] * a[2];
	q[0] = w->u[k[0]], q[1] = w->v[k[0]];
	q[2] = w->u[k[1]] - q[0], q[3] = w->v[k[1]] - q[1];
	q[4] = w->u[k[2]] - q[0], q[5] = w->v[k[2]] - q[1];
	q[6] = q[2] * q[5] - q[4] * q[3], q[7] = 1 / q[6];
	f[0] = m->x[k[0]], f[1] = m->y[k[0]];
	f[2] = m->x[k[1]] - f[0], f[3] = m->y[k[1]] - f[1];
	f[4] = m->x[k[2]] - f[0], f[5] = m->y[k[2]] - f[1];
	f[6] = f[2] * f[5] - f[4] * f[3], f[7] = 1 / f[6];
	f[8] = m->h[k[0]], f[9] = m->h[k[1]] - f[8], f[10] = m->h[k[2]] - f[8];
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
	l->plane = malloc(nt * TR_PLANES * sizeof *l->plane);
	if (!l->start || !l->plane)
		return tl_fail(e, "tile: out of memory");
	l->bq = l->plane + 4 * nt, l->bf = l->bq + TR_BARY_TERMS * nt;
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

/* The triangle over (su, sv): the one of its bucket with the largest
 * least barycentric coordinate (inside: >= 0). The previous sample's
 * triangle, hint, when the point is well inside it: no other triangle
 * then comes near (they do not overlap), the bucket's answer is it.
 * (tr_bary.h: the exact coordinates' answers, mostly without their
 * divisions.) */
static __attribute__((noinline)) int
locate_far(const locator *l, double su, double sv)
{
	int b = bucket(l, sv, 1) * l->nb + bucket(l, su, 0);

	return tr_bary_best(l->bq, l->list + l->start[b], l->start[b + 1] -
	    l->start[b], su, sv);
}

static inline int
locate(const locator *l, double su, double sv, int hint)
{
	if (hint >= 0 && tr_bary_above(l->bq + TR_BARY_TERMS * hint, su, sv,
	    1e-9))
		return hint;
	return locate_far(l, su, sv);
}

/* How deep in the grid (its last places W, H) the box x0 .. x1, y0 ..
 * y1 of places lies: cells from the nearest side to its nearest point
 * (a place: x0 = x1, y0 = y1). */
static inline double
depth_in(double W, double H, double x0, double y0, double x1, double y1)
{
	return dmin(dmin(x0, W - x1), dmin(y0, H - y1));
}

/* The drawn surface's height over a sample: the plane of triangle q
 * (decoded, ECEF) met by the normal through the sample's foot f,
 * direction up. */
static inline double
drawn(const locator *l, int q, const double f[3], const double up[3])
{
	const double *n = l->plane + 4 * q;

	return (n[3] - n[0] * f[0] - n[1] * f[1] - n[2] * f[2]) /
	    (n[0] * up[0] + n[1] * up[1] + n[2] * up[2]);
}

/* A geographic DEM's sample's terms into d: the drawn surface over it
 * against the selection's surface there (the plane, in longitude,
 * latitude and height, of the triangle before quantisation: a piece of a
 * selected triangle, in its plane, which is the selection's in the DEM's
 * grid: the map is affine) and against its height z. The
 * selection's height exactly only where the near one (tr_bary.h) leaves
 * it able to raise d[0]: d[0] is the same. */
static inline void
sample(const locator *l, int q, const double f[3], const double up[3],
    double x, double y, double z, double d[2])
{
	const double *fq = l->bf + (TR_BARY_TERMS + 3) * q;
	double hs = drawn(l, q, f, up);
	double v = fabs(hs - z), s;

	d[1] = dmax(d[1], v);
	if (!(fabs(hs - tr_bary_near_flat(fq, x, y, hs, &s)) + s < d[0]))
		d[0] = dmax(d[0], fabs(hs - tr_bary_flat(fq, x, y)));
}

/* A projected DEM's sample: the drawn surface against the selection
 * at the sample's grid place (gx, gy), the plane of the selected
 * triangle gt holding it (tr_gsel.c), or, gt NULL (past the footprint),
 * against the sample's height z itself. The selection's height exactly
 * only where the near one (tr_bary.h) leaves it able to raise d[0]:
 * d[0] is the same. */
static inline int
sample_grid(const locator *l, int q, const double *gt, const double f[3],
    const double up[3], double gx, double gy, double z, double d[2])
{
	double hs = drawn(l, q, f, up);
	double v = fabs(hs - z), s, fg;

	d[1] = dmax(d[1], v);
	if (gt == NULL)
		d[0] = dmax(d[0], v);
	else if (!(fabs(hs - tr_bary_near_flat(gt, gx, gy, hs, &s)) + s <
	    d[0])) {
		if (isnan(fg = tr_bary_flat(gt, gx, gy)))
			return -1; /* (the near one NaN too) */
		d[0] = dmax(d[0], fabs(hs - fg));
	}
	return 0;
}

/* The check of tr_bound (tr_kept_check): sample (f, up) under
 * triangle q within q's bound of the selection, else -1. */
static int
check(const locator *l, int q, const double f[3], const double up[3],
    double x, double y, tl_err *e)
{
	double hs = drawn(l, q, f, up);
	double d = fabs(hs - tr_bary_flat(l->bf + (TR_BARY_TERMS + 3) * q, x,
	    y));

	if (d <= l->bound[q] * (1 + 1e-9) + 1e-7)
		return 0;
	return tl_fail(e, "tile: sample at %.9f, %.9f: %.6f m from the "
	    "selection, over its triangle's bound %.6f m", x, y, d,
	    l->bound[q]);
}

/* The same for a projected DEM's sample at grid place (gx, gy), depth
 * cells from the nearest side, against the selection's height there
 * (zs, or NaN past the footprint): a piece that has no bound (NaN: past
 * the footprint, the band) draws only samples within l->claim of a
 * side; an infinite one checks nothing. */
static int
check_grid(const locator *l, int q, const double f[3], const double up[3],
    double gx, double gy, double depth, double zs, tl_err *e)
{
	double d = fabs(drawn(l, q, f, up) - zs);

	if (l->bound[q] == INFINITY)
		return 0;
	if (isnan(l->bound[q])) {
		if (depth <= l->claim)
			return 0;
		return tl_fail(e, "tile: sample (%.0f, %.0f), %.1f cells from "
		    "the grid's sides, drawn by a triangle past the footprint or "
		    "in the band, over the %.3f cells claimed", gx, gy, depth,
		    l->claim);
	}
	if (d <= l->bound[q] * (1 + 1e-9) + 1e-7)
		return 0;
	return tl_fail(e, "tile: sample (%.0f, %.0f): %.6f m from the "
	    "selection, over its triangle's bound %.6f m", gx, gy, d,
	    l->bound[q]);
}

/* A geographic block's columns and rows: the normals' sines and cosines
 * (as geo_ellipsoid computes them) and the places in the tile's u, v
 * (as each sample computes them), per column and per row. */
typedef struct {
	double cl[BT_SIZE], sl[BT_SIZE], nn[BT_SIZE], co[BT_SIZE];
	double so[BT_SIZE], su[BT_SIZE], sv[BT_SIZE];
} trig;

static void
trig_init(trig *c, const double *lon, const double *lat, const double r[4])
{
	double wd = r[2] - r[0], fl = 1 / 298.257223563, e2 = fl * (2 - fl);

	for (int k = 0; k < BT_SIZE; k++) {
		double a = lat[k] * (M_PI / 180), o = lon[k] *
		    (M_PI / 180);
		c->sl[k] = sin(a), c->cl[k] = cos(a);
		c->so[k] = sin(o), c->co[k] = cos(o);
		c->nn[k] = 6378137.0 / sqrt(1 - e2 * c->sl[k] * c->sl[k]);
		c->su[k] = (lon[k] - r[0]) / wd * QM_MAX;
		c->sv[k] = (lat[k] - r[1]) / wd * QM_MAX;
	}
}

void
tr_block_feet(const tr_grid *g, const double *lon, const double *lat,
    int bi, int bj, double *fu)
{
	for (int J = 0; J < BT_SIZE && bj * BT_CELLS + J < g->h0; J++)
		for (int I = 0; I < BT_SIZE && bi * BT_CELLS + I < g->w0; I++) {
			int k = J * BT_SIZE + I;
			geo_ellipsoid(lon[k], lat[k], fu + 6 * k, fu + 6 * k + 3);
		}
}

/* A projected DEM's sample k = (I, J) of level-0 block (bi, bj) b (its
 * vertices at lon, lat; fu its feet or NULL, those not yet computed
 * where fok is 0, fok NULL: all) in tile part t of rectangle
 * r under locator l into dd, the hints of the last found; -1 when no
 * triangle holds it. */
static inline int
measure_proj(const pyramid_block *b, const double *lon, const double *lat,
    double *fu, unsigned char *fok, const locator *l,
    const unsigned char *rim, int bi, int bj, int I, int J,
    const double t[4], const double r[4], int *hint, int *ghint,
    double dd[2], tl_err *e)
{
	double wd = r[2] - r[0], f[3], up[3];
	int k = J * BT_SIZE + I, q;
	double gx = bi * BT_CELLS + I, gy = bj * BT_CELLS + J;
	double depth = depth_in(l->W, l->H, gx, gy, gx, gy);

	if (depth > l->band)
		return 0;
	double x = lon[k], y = lat[k];
	if (x < t[0] || x > t[2] || y < t[1] || y > t[3])
		return 0;
	q = locate(l, (x - r[0]) / wd * QM_MAX, (y - r[1]) / wd * QM_MAX,
	    *hint);
	if (fu != NULL) {
		if (fok != NULL && !fok[k]) /* as tr_block_feet's */
			geo_ellipsoid(x, y, fu + 6 * k, fu + 6 * k + 3), fok[k] = 1;
		memcpy(f, fu + 6 * k, sizeof f),
		memcpy(up, fu + 6 * k + 3, sizeof up);
	} else
		geo_ellipsoid(x, y, f, up);
	if ((*hint = q) < 0)
		return tl_fail(e, "tile: sample (%d, %d) under no triangle",
		    bi * BT_CELLS + I, bj * BT_CELLS + J);
	int out = rim && rim[q];
	const double *gt = out ? NULL : tr_gsel_find(l->gs, gx, gy, ghint);
	if ((!out && gt == NULL) || sample_grid(l, q, gt, f, up, gx, gy,
	    b->z[k], dd) < 0)
		return tl_fail(e, "tile: sample (%d, %d) in no selected "
		    "triangle", bi * BT_CELLS + I, bj * BT_CELLS + J);
	if (l->bound && check_grid(l, q, f, up, gx, gy, depth, gt ?
	    tr_bary_flat(gt, gx, gy) : NAN, e) < 0)
		return -1;
	return 0;
}

/* A projected block's samples in tile part t, square by square of
 * bx (tr_far.c: the boxes of its 4-cell squares), those whose box
 * misses t skipped whole: their samples all fail measure_proj's test.
 * Each sample in one square (its rows and columns from the square's
 * first to before the next's, the block's last in the last); a tile's
 * distances are maxima, the same in any order. */
static int
measure_squares(const tr_grid *g, const pyramid_block *b,
    const double *lon, const double *lat, double *fu, unsigned char *fok,
    const double *bx, const locator *l, const unsigned char *rim, int bi,
    int bj, const double t[4], const double r[4], double dd[2], tl_err *e)
{
	int n = BT_CELLS / TR_FAR_K0, hint = -1, ghint = -1;
	int nI = g->w0 - bi * BT_CELLS, nJ = g->h0 - bj * BT_CELLS;

	nI = nI < BT_SIZE ? nI : BT_SIZE, nJ = nJ < BT_SIZE ? nJ : BT_SIZE;
	for (int sj = 0; sj < n && sj * TR_FAR_K0 < nJ; sj++)
		for (int si = 0; si < n && si * TR_FAR_K0 < nI; si++) {
			const double *o = bx + 4 * (sj * n + si);
			if (o[2] < t[0] || o[0] > t[2] || o[3] < t[1] ||
			    o[1] > t[3])
				continue;
			int J1 = sj == n - 1 ? BT_SIZE : (sj + 1) * TR_FAR_K0;
			int I1 = si == n - 1 ? BT_SIZE : (si + 1) * TR_FAR_K0;
			J1 = J1 < nJ ? J1 : nJ, I1 = I1 < nI ? I1 : nI;
			for (int J = sj * TR_FAR_K0; J < J1; J++)
				for (int I = si * TR_FAR_K0; I < I1; I++)
					if (measure_proj(b, lon, lat, fu, fok, l, rim, bi,
					    bj, I, J, t, r, &hint, &ghint, dd, e) < 0)
						return -1;
		}
	return 0;
}

/* The samples of level-0 block (bi, bj) b, its vertices at lon, lat,
 * in tile t (of rectangle r) under locator l; rim: per triangle, 1 past
 * a projected DEM's footprint (or NULL); fu, a projected block's feet
 * and normals (tr_block_feet) or NULL, fok as measure_proj's; bx, a
 * projected block's boxes (tr_far_boxes) or NULL. */
static int
measure_block(const tr_grid *g, const pyramid_block *b, const double *lon,
    const double *lat, double *fu, unsigned char *fok, const double *bx,
    const locator *l, const unsigned char *rim, int bi, int bj,
    const double t[4], const double r[4], double d[2], tl_err *e)
{
	double fl = 1 / 298.257223563, e2 = fl * (2 - fl);
	int hint = -1, ghint = -1, col[BT_SIZE], ncol = 0, nI = BT_SIZE;
	double dd[2] = { d[0], d[1] };
	trig c;

	if (g->projected && bx != NULL) {
		if (measure_squares(g, b, lon, lat, fu, fok, bx, l, rim, bi, bj,
		    t, r, dd, e) < 0)
			return -1;
		d[0] = dd[0], d[1] = dd[1];
		return 0;
	}
	if (g->w0 - bi * BT_CELLS < nI)
		nI = g->w0 - bi * BT_CELLS;
	/* a geographic grid: latitude per row, longitude per column, so
	 * the columns in the tile listed once, the rows out of it skipped
	 * whole: the same samples in the same order as the test of each */
	if (!g->projected)
		trig_init(&c, lon, lat, r);
	for (int k = 0; k < nI; k++)
		if (g->projected || !(lon[k] < t[0] || lon[k] > t[2]))
			col[ncol++] = k;
	for (int J = 0; J < BT_SIZE; J++) {
		if (bj * BT_CELLS + J >= g->h0)
			break;
		if (!g->projected && (lat[J] < t[1] || lat[J] > t[3]))
			continue;
		for (int ci = 0; ci < ncol; ci++) {
			int I = col[ci], k = J * BT_SIZE + I, q;
			double f[3], up[3], x = tr_vlon(g, lon, J, I);
			double y = tr_vlat(g, lat, J, I);
			if (g->projected) {
				if (measure_proj(b, lon, lat, fu, fok, l, rim, bi, bj,
				    I, J, t, r, &hint, &ghint, dd, e) < 0)
					return -1;
				continue;
			}
			q = locate(l, c.su[I], c.sv[J], hint);
			f[0] = c.nn[J] * c.cl[J] * c.co[I];
			f[1] = c.nn[J] * c.cl[J] * c.so[I];
			f[2] = c.nn[J] * (1 - e2) * c.sl[J];
			up[0] = c.cl[J] * c.co[I], up[1] = c.cl[J] * c.so[I];
			up[2] = c.sl[J];
			if ((hint = q) < 0)
				return tl_fail(e, "tile: sample (%d, %d) under no "
				    "triangle", bi * BT_CELLS + I, bj * BT_CELLS + J);
			sample(l, q, f, up, x, y, b->z[k], dd);
			if (l->bound && check(l, q, f, up, x, y, e) < 0)
				return -1;
		}
	}
	d[0] = dd[0], d[1] = dd[1];
	return 0;
}

/* A tile's locator kept for its measure: its rectangle r, the part t of
 * it in the terrain's rectangle, the rim marks of its triangles. */
struct tr_kept {
	double r[4], t[4];
	locator l;
	unsigned char *rim;
	double *bound;
	tr_gsel gs;
	size_t bytes;
	int nb0;        /* level 0's blocks a row */
};

void
tr_kept_free(tr_kept *k)
{
	if (k == NULL)
		return;
	free(k->l.start), free(k->l.list), free(k->l.plane), free(k->rim);
	free(k->bound), tr_gsel_free(&k->gs), free(k);
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
	k->l.W = w->g->w0 - 1, k->l.H = w->g->h0 - 1;
	k->nb0 = w->ix->lev[0].blocks[0];
	k->l.band = INFINITY, k->l.claim = INFINITY;
	if (w->g->projected) {
		if (tr_gsel_init(&k->gs, w) < 0) {
			tr_kept_free(k);
			return tl_fail(e, "tile: out of memory");
		}
		k->l.gs = &k->gs;
	}
	k->bytes = k->gs.bytes + sizeof *k + ((size_t)k->l.nb * k->l.nb + 1 +
	    (size_t)k->l.start[k->l.nb * k->l.nb]) * sizeof(int) +
	    (nt ? nt : 1) * TR_PLANES * sizeof(double) + (k->rim ? nt : 0);
	*out = k;
	return 0;
}

int
tr_kept_check(tr_kept *k, const double *b, int nt, double claim,
    tl_err *e)
{
	k->l.claim = claim < 0 ? 0 : claim;
	if ((k->bound = malloc((size_t)(nt ? nt : 1) * sizeof *b)) == NULL)
		return tl_fail(e, "tile: out of memory");
	for (int t = 0; t < nt; t++)
		k->bound[t] = b[t];
	k->l.bound = k->bound;
	return 0;
}

int
tr_kept_meets(const tr_grid *g, const tr_kept *k, int kb)
{
	const double *o = g->box[0] + 4 * (size_t)kb, *t = k->t;
	double x0 = kb % k->nb0 * BT_CELLS, y0 = kb / k->nb0 * BT_CELLS;
	double x1 = x0 + BT_CELLS, y1 = y0 + BT_CELLS;

	/* a side's band alone measured: a block deeper holds none */
	if (depth_in(k->l.W, k->l.H, x0, y0, x1, y1) > k->l.band)
		return 0;
	return !(o[2] < t[0] || o[0] > t[2] || o[3] < t[1] || o[1] > t[3]);
}

void
tr_kept_band(tr_kept *k, double band)
{
	k->l.band = band;
}

int
tr_kept_meeting(const tr_grid *g, const struct tr_keptz *l, int n, int kb,
    double *band)
{
	int any = 0;

	*band = -1;
	for (int i = 0; i < n; i++)
		if (tr_kept_meets(g, l[i].k, kb))
			any++, *band = dmax(*band, l[i].k->l.band);
	return any;
}

const pyramid_block *
tr_block_band(tr_work *w, int bi, int bj, double band, const double **lon,
    const double **lat, tl_err *e)
{
	const pyramid_block *b;
	double W = w->g->w0 - 1, H = w->g->h0 - 1;
	int *v, n = 0;

	if (!w->g->projected || !(band < INFINITY))
		return tr_block_all(w, 0, bi, bj, lon, lat, e);
	if ((b = tr_block(w, 0, bi, bj, lon, lat, e)) == NULL)
		return NULL;
	if ((v = malloc(PYRAMID_N * sizeof *v)) == NULL)
		return tl_fail(e, "tile: out of memory"), NULL;
	/* the samples measure_proj measures */
	for (int J = 0; J < BT_SIZE; J++)
		for (int I = 0; I < BT_SIZE; I++) {
			double gx = bi * BT_CELLS + I, gy = bj * BT_CELLS + J;
			if (depth_in(W, H, gx, gy, gx, gy) <= band)
				v[n++] = J * BT_SIZE + I;
		}
	if (tr_ll_need(w, b, v, n, e) < 0)
		b = NULL;
	free(v);
	return b;
}

int
tr_kept_block(const tr_grid *g, const tr_kept *k, int kb, int bi, int bj,
    const pyramid_block *b, const double *lon, const double *lat,
    double *fu, unsigned char *fok, const double *bx, double d[2],
    tl_err *e)
{
	if (!tr_kept_meets(g, k, kb))
		return 0;
	return measure_block(g, b, lon, lat, fu, fok, bx, &k->l, k->rim, bi,
	    bj, k->t, k->r, d, e);
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
		if (!tr_kept_meets(w->g, kp, k))
			continue;
		if ((b = tr_block_band(w, bi, bj, kp->l.band, &lon, &lat, e)) ==
		    NULL ||
		    tr_kept_block(w->g, kp, k, bi, bj, b, lon, lat, NULL, NULL,
		    w->g->projected ? tr_far_boxes(w, b, lon, lat) : NULL, d,
		    e) < 0)
			return -1;
	}
	return 0;
}

/* Every level-0 sample in the tile and in the terrain's rectangle
 * (a projected DEM's within band cells of a side). */
int
tr_measure_band(tr_work *w, int z, int x, int y, double band, double d[2],
    tl_err *e)
{
	tr_kept *kp;
	int ret;

	d[0] = d[1] = 0;
	if (tr_keep(w, z, x, y, &kp, e) < 0)
		return -1;
	if (kp)
		tr_kept_band(kp, band);
	ret = kp ? tr_kept_walk(w, kp, d, e) : 0; /* NULL: no sample */
	tr_kept_free(kp);
	return ret;
}

int
tr_measure(tr_work *w, int z, int x, int y, double d[2], tl_err *e)
{
	return tr_measure_band(w, z, x, y, INFINITY, d, e);
}
