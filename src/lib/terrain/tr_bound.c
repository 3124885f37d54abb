/* tr_bound.c - an upper bound, per triangle of a quantised tile, of
 * what the measure (tr_measure.c) finds at the samples under it: for a
 * geographic DEM d[0], the drawn surface (the ECEF plane of the
 * decoded vertices P_i = E(p_i), p_i = (lon, lat, h) as they decode, met
 * by the normal through the sample) against the selection's (the same
 * triangle before quantisation, F, linear in lon, lat, h). With S' the
 * decoded heights linear in lon, lat over the decoded triangle,
 * |D - F| <= |S' - F| + |D - S'|:
 *
 * A = |S' - F|: linear over the decoded triangle, so at most its largest
 *     value at a vertex: h'_i - h_i - grad F . (p'_i - p_i) (the height
 *     quantisation and the slope times the u, v shift), exactly.
 * B = |D - S'|: X = E(p), p = sum b_i p_i in the triangle, against the
 *     plane point Y = sum b_i P_i: Y - X = sum b_i R_i, R_i Taylor's
 *     remainder int (1-t) D2E(p + t d_i)[d_i, d_i], d_i = p_i - p. With
 *     up the normal at the sample, nu = up.(X - Y), tau the rest:
 *     D - S' = up.(Y-X) + n.tau / n.up, so |B| <= |nu| + tan(theta) |tau|
 *     (theta: the plane's tilt from up, at most theta0 at vertex 0 plus
 *     the normals' turn over the triangle, c L + P: L, P its longitude
 *     and latitude extents in radians, c <= cmax the cosine there; the
 *     normals, cmax and smax from the corners' ECEF points, no trig).
 *     up(xi).D2E(xi)[d, d] = -(N + h) c^2 dl^2 - (M + h) dp^2 exactly
 *     (the foot's normal curvatures; up.Dup = 0), so
 *     sum b_i |up.R_i| <= 1/2 W sum b_i (cmax^2 dl_i^2 + dp_i^2)
 *     <= 1/2 W rho^2 (W = Rmax + max(h, 0); sum b_i |q_i - q|^2 is at
 *     most the least enclosing circle's radius squared, rho^2, in the
 *     coordinates (cmax lon, lat)), plus the turn of up between xi and
 *     the sample, (c L + P) |D2E|. |D2E[d, d]| <= (K + |h|)(cmax dl^2 +
 *     2 smax |dl dp| + dp^2) + 2 |dh| (cmax |dl| + |dp|) (the foot's
 *     second derivatives N c, M |s|, M (1 + 1e-4); the normal's c, |s|,
 *     1 and first c, 1), at most G with dl, dp, dh the extents, so
 *     |tau| <= |X - Y| <= G / 2.
 *
 * A projected DEM's piece of selection triangle S is compared with F_S,
 * the linear map over the straight image of S whose pieces the tile
 * draws, not with the selection at the sample's grid place: A is taken
 * against F_S (its plane in lon, lat, h), B is the same, and tr_crs.c
 * adds C, F_S against the selection there. Its pieces past the
 * footprint or in the band get no bound: the samples they may draw lie
 * near the grid's sides, measured instead (tr_level.c).
 *
 * The tile's bound is 2 (A + B [+ C]) + 1 um (TR_BOUND_SAFETY): the factor covers the
 * roundings of the measure (relative 1e-13 of its terms) and of this
 * derivation's inputs, and the samples the locator puts a rounding
 * outside their triangle. Where the tilt reaches 80 degrees, or a term
 * is not finite, the bound is infinite: measure. */
#include <math.h>
#include <stdlib.h>

#include "terrain/tr_impl.h"

#define RMAX 6399593.7    /* m: a / sqrt(1 - e^2), the largest N, M */
#define KD2 (RMAX * 1.0001) /* the foot's second derivatives */
#define DEG (M_PI / 180)

/* A point of the part of the triangle that holds samples: longitude,
 * latitude (degrees, decoded) and its barycentric coordinates. */
typedef struct {
	double x, y, b[3];
} cpt;

/* Polygon p (n points) clipped to the side s * (x or y, k) >= s * c;
 * the result into q: its count. */
static int
clip_side(const cpt *p, int n, int k, double s, double c, cpt *q)
{
	int m = 0;

	for (int i = 0; i < n; i++) {
		const cpt *a = &p[i], *b = &p[(i + 1) % n];
		double va = s * ((k ? a->y : a->x) - c);
		double vb = s * ((k ? b->y : b->x) - c);
		if (va >= 0)
			q[m++] = *a;
		if ((va < 0) != (vb < 0)) {
			double t = va / (va - vb);
			cpt *r = &q[m++];
			r->x = a->x + t * (b->x - a->x);
			r->y = a->y + t * (b->y - a->y);
			for (int j = 0; j < 3; j++)
				r->b[j] = a->b[j] + t * (b->b[j] - a->b[j]);
		}
	}
	return m;
}

/* For the quadratic form of diagonal q (d coordinates of the vertices
 * v[3][d]), the largest over polygon c (n points) of
 * sum b_i |v_i - p|^2: f(p) = R^2 - |p - centre|^2, concave, so at the
 * circumcentre when the polygon holds it, else on an edge, where
 * f((1-t) A + t B) = (1-t) f(A) + t f(B) + t (1-t) |A - B|^2. */
static double
spread(const double v[3][3], int d, const double q[3], const cpt *c, int n,
    const double o[4], const double *xd, const double *yd)
{
	double f[8], pt[8][3], best = 0, l[3], w[3], sw;

	for (int i = 0; i < n; i++) {
		f[i] = 0;
		for (int k = 0; k < d; k++)
			pt[i][k] = c[i].b[0] * v[0][k] + c[i].b[1] * v[1][k] +
			    c[i].b[2] * v[2][k];
		for (int j = 0; j < 3; j++)
			for (int k = 0; k < d; k++)
				f[i] += c[i].b[j] * q[k] * (v[j][k] - pt[i][k]) *
				    (v[j][k] - pt[i][k]);
		best = fmax(best, f[i]);
	}
	for (int i = 0; i < n; i++) {
		int j = (i + 1) % n;
		double dd = 0, t;
		for (int k = 0; k < d; k++)
			dd += q[k] * (pt[i][k] - pt[j][k]) * (pt[i][k] - pt[j][k]);
		if (!(dd > 0))
			continue;
		t = fmin(1, fmax(0, 0.5 + (f[j] - f[i]) / (2 * dd)));
		best = fmax(best, (1 - t) * f[i] + t * f[j] + t * (1 - t) * dd);
	}
	/* the circumcentre: barycentric l_i (l_j + l_k - l_i), l_i the
	 * side opposite i squared */
	for (int i = 0; i < 3; i++) {
		int a = (i + 1) % 3, b = (i + 2) % 3;
		l[i] = 0;
		for (int k = 0; k < d; k++)
			l[i] += q[k] * (v[a][k] - v[b][k]) * (v[a][k] - v[b][k]);
	}
	sw = 0;
	for (int i = 0; i < 3; i++)
		w[i] = l[i] * (l[(i + 1) % 3] + l[(i + 2) % 3] - l[i]), sw += w[i];
	if (!(sw > 0) || w[0] < 0 || w[1] < 0 || w[2] < 0)
		return best;
	double cx = (w[0] * xd[0] + w[1] * xd[1] + w[2] * xd[2]) / sw;
	double cy = (w[0] * yd[0] + w[1] * yd[1] + w[2] * yd[2]) / sw;
	if (cx < o[0] || cx > o[2] || cy < o[1] || cy > o[3])
		return best;
	/* R^2 = (abc / 4 area)^2 = l0 l1 l2 / sum w (sum w = 16 area^2) */
	return fmax(best, l[0] * l[1] * l[2] / sw);
}

/* spread() over the whole triangle: tr_encl in the metric q. */
static double
spread_all(const double v[3][3], int d, const double q[3])
{
	double l[3];

	for (int i = 0; i < 3; i++) {
		int a = (i + 1) % 3, b = (i + 2) % 3;
		l[i] = 0;
		for (int k = 0; k < d; k++)
			l[i] += q[k] * (v[a][k] - v[b][k]) * (v[a][k] - v[b][k]);
	}
	return tr_encl(l);
}

/* A triangle's corners as the measure has them and as they decode. */
typedef struct {
	double xd[3], yd[3], hd[3];     /* decoded: degrees, metres */
	double val[3];                  /* S' - F there */
	double lo[3], hi[3];            /* the box of xd, yd, hd */
} corners;

/* The plane through (x_i, y_i, h_i), i < 3: its gradient g; -1 where
 * there is none. */
static int
grad(const double *x, const double *y, const double *h, double g[2])
{
	double x1 = x[1] - x[0], y1 = y[1] - y[0];
	double x2 = x[2] - x[0], y2 = y[2] - y[0];
	double h1 = h[1] - h[0], h2 = h[2] - h[0];
	double f6 = x1 * y2 - x2 * y1;

	g[0] = (y2 * h1 - y1 * h2) / f6, g[1] = (x1 * h2 - x2 * h1) / f6;
	return isfinite(g[0]) && isfinite(g[1]) ? 0 : -1;
}

/* Triangle k's corners into c, val against F, the triangle's own plane
 * in longitude, latitude (f NULL) or selection triangle f's (a projected
 * DEM: the piece's S, tr_crs); -1 where that has no gradient. */
static int
corners_of(const tr_work *w, const int *k, const tr_tri *f,
    const double r[4], double lo, double hi, corners *c)
{
	const tr_mesh *m = &w->m;
	double X[3], Y[3], Z[3], g[2];

	for (int j = 0; j < 3; j++)
		X[j] = f ? f->x[j] : m->x[k[j]], Y[j] = f ? f->y[j] : m->y[k[j]],
		Z[j] = f ? f->h[j] : m->h[k[j]];
	/* F's gradient, per degree */
	if (grad(X, Y, Z, g) < 0)
		return -1;
	double gx = g[0], gy = g[1];
	for (int j = 0; j < 3; j++) {
		double tu = w->u[k[j]] / (double)QM_MAX;
		double tv = w->v[k[j]] / (double)QM_MAX;
		double tq = w->q[k[j]] / (double)QM_MAX;
		double p[3] = { (1 - tu) * r[0] + tu * r[2],
			(1 - tv) * r[1] + tv * r[3], (1 - tq) * lo + tq * hi };
		c->xd[j] = p[0], c->yd[j] = p[1], c->hd[j] = p[2];
		c->val[j] = f ? p[2] - Z[0] - gx * (p[0] - X[0]) - gy * (p[1] -
		    Y[0]) : p[2] - m->h[k[j]] - gx * (p[0] - m->x[k[j]]) -
		    gy * (p[1] - m->y[k[j]]);
		for (int i = 0; i < 3; i++) {
			c->lo[i] = j ? dmin(c->lo[i], p[i]) : p[i];
			c->hi[i] = j ? dmax(c->hi[i], p[i]) : p[i];
		}
	}
	return 0;
}

/* The normals at the decoded corners, from their ECEF points alone:
 * (X, Y, Z / (1 - e^2)) is (N + h) up + h up_z e^2 / (1 - e^2) z, within
 * 1.1e-9 |h| radians of up (*da that and the roundings). cmax, smax:
 * the largest cosine and |sine| of latitude over the triangle (at a
 * corner, or 1 for the cosine when it spans the equator); up0, vertex
 * 0's. */
static void
normals(const double *pos, const int *k, double habs, int equator,
    double *cmax, double *smax, double up0[3], double *da)
{
	double e2 = (1 / 298.257223563) * (2 - 1 / 298.257223563);

	*da = 1.1e-9 * habs + 1e-12, *cmax = 0, *smax = 0;
	for (int j = 0; j < 3; j++) {
		const double *p = pos + 3 * k[j];
		double g[3] = { p[0], p[1], p[2] / (1 - e2) };
		double n = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
		double c = sqrt(g[0] * g[0] + g[1] * g[1]) / n;
		*cmax = dmax(*cmax, c), *smax = dmax(*smax, fabs(g[2]) / n);
		if (j == 0)
			up0[0] = g[0] / n, up0[1] = g[1] / n, up0[2] = g[2] / n;
	}
	*cmax = equator ? 1 : dmin(1, *cmax + *da);
	*smax = dmin(1, *smax + *da);
}

/* The tangent of the largest tilt over the triangle of its plane
 * (decoded ECEF) from the normal: tan(theta0 + a), theta0 at vertex 0
 * (normal up0), a the normals' turn; INFINITY from 89.9 degrees. */
static double
tan_tilt(const double *pos, const int *k, const double up0[3], double a)
{
	const double *p = pos + 3 * k[0], *q = pos + 3 * k[1],
	    *r = pos + 3 * k[2];
	double u[3] = { q[0] - p[0], q[1] - p[1], q[2] - p[2] };
	double v[3] = { r[0] - p[0], r[1] - p[1], r[2] - p[2] };
	double n[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
		u[0] * v[1] - u[1] * v[0] };
	double x[3] = { n[1] * up0[2] - n[2] * up0[1], n[2] * up0[0] -
		n[0] * up0[2], n[0] * up0[1] - n[1] * up0[0] };
	double co = fabs(n[0] * up0[0] + n[1] * up0[1] + n[2] * up0[2]);
	double t0 = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) / co;
	/* tan a <= a / (1 - a^2 / 2) (sin a <= a, cos a >= 1 - a^2/2) */
	double ta = a / (1 - a * a / 2);

	if (!(t0 < 573 && a < 1 && t0 * ta < 0.99))
		return INFINITY;
	return (t0 + ta) / (1 - t0 * ta);
}

/* Triangle t's bound; r the tile's rectangle, lo, hi its header
 * heights; o, the rectangle that holds the samples: only the part of
 * the triangle in it counts (0 where none); f, a projected DEM's
 * selection triangle it is a piece of (its F), else NULL; *ep (f only)
 * the CRS term's reach in cells (tr_crs). */
static double
tri_bound(const tr_work *w, int t, const tr_tri *f, const double *pre,
    double gmax, const double r[4], const double o[4], double lo,
    double hi, double *ep)
{
	const int *k = w->m.tri + 3 * t;
	double A = 0, cmax, smax, up0[3] = { 0, 0, 1 }, da, v[3][3], sn, st;
	double C = 0;
	corners c;
	cpt p[2][8];
	int n = 3, in;

	if (corners_of(w, k, f, r, lo, hi, &c) < 0)
		return INFINITY;
	if (f && (C = tr_crs(w->g, f, pre, c.xd, c.yd, gmax, (r[2] - r[0]) /
	    20, ep)) == INFINITY)
		return INFINITY;
	if (c.hi[0] < o[0] || c.lo[0] > o[2] || c.hi[1] < o[1] ||
	    c.lo[1] > o[3])
		return 0;
	in = c.lo[0] >= o[0] && c.hi[0] <= o[2] && c.lo[1] >= o[1] &&
	    c.hi[1] <= o[3];
	for (int j = 0; j < 3; j++)
		p[0][j] = (cpt){ c.xd[j], c.yd[j], { j == 0, j == 1, j == 2 } };
	if (!in) {
		n = clip_side(p[0], n, 0, 1, o[0], p[1]);
		n = clip_side(p[1], n, 0, -1, o[2], p[0]);
		n = clip_side(p[0], n, 1, 1, o[1], p[1]);
		n = clip_side(p[1], n, 1, -1, o[3], p[0]);
		if (n == 0)
			return 0;
	}
	for (int i = 0; i < n; i++)
		A = dmax(A, fabs(p[0][i].b[0] * c.val[0] + p[0][i].b[1] *
		    c.val[1] + p[0][i].b[2] * c.val[2]));
	double habs = dmax(fabs(c.lo[2]), fabs(c.hi[2]));
	normals(w->pos, k, habs, c.lo[1] <= 0 && c.hi[1] >= 0, &cmax, &smax,
	    up0, &da);
	double L = (c.hi[0] - c.lo[0]) * DEG, P = (c.hi[1] - c.lo[1]) * DEG;
	double turn = cmax * L + P, kh = KD2 + habs, W = RMAX + dmax(c.hi[2], 0);
	double ext = sqrt(cmax * cmax * L * L + P * P);
	double eps = fmin(1, fmax(0.01, (c.hi[2] - c.lo[2]) / (kh * ext)));
	double qn[3] = { W * cmax * cmax, W, 0 }, qt[3] = {
		kh * (cmax + smax * cmax + eps * cmax * cmax),
		kh * (1 + smax / cmax + eps), 2 / (eps * kh) };
	for (int j = 0; j < 3; j++)
		v[j][0] = c.xd[j] * DEG, v[j][1] = c.yd[j] * DEG, v[j][2] = c.hd[j];
	sn = in ? spread_all(v, 2, qn) : spread(v, 2, qn, p[0], n, o, c.xd,
	    c.yd);
	st = in ? spread_all(v, 3, qt) : spread(v, 3, qt, p[0], n, o, c.xd,
	    c.yd);
	double d = A + 0.5 * sn + 0.5 * turn * st + tan_tilt(w->pos, k, up0,
	    turn + da) * 0.5 * st + C;

	return isfinite(d) ? d : INFINITY;
}

double
tr_bound(tr_work *w, int z, int x, int y, float minh, float maxh,
    double lim, double *b, double *band)
{
	double r[4], o[4], most = 0, pad, *pre = NULL;
	const tr_grid *g = w->g;
	tr_steep st = { .mx = NULL };

	*band = -1;
	if ((g->projected && !(g->d2psi < INFINITY)) || (!g->projected &&
	    w->m.rim)) {
		for (int t = 0; b && t < w->m.nt; t++)
			b[t] = INFINITY;
		return INFINITY;
	}
	if (g->projected && (tr_steep_init(&st, w) < 0 || !(st.all <
	    INFINITY) || (pre = malloc(TR_CRS_PRE * (size_t)(w->nsel ?
	    w->nsel : 1) * sizeof *pre)) == NULL)) {
		tr_steep_free(&st);
		for (int t = 0; b && t < w->m.nt; t++)
			b[t] = INFINITY;
		return INFINITY;
	}
	for (int i = 0; pre && i < w->nsel; i++)
		pre[TR_CRS_PRE * i] = NAN; /* not yet */
	tr_tile_rect(z, x, y, r);
	/* the samples' rectangle (tr_keep's), widened by 1e-9 of the tile
	 * for the roundings of the samples' u, v (1e-15 of it) */
	pad = (r[2] - r[0]) * 1e-9;
	o[0] = fmax(r[0], w->g->r[0]) - pad, o[2] = fmin(r[2], w->g->r[2]) + pad;
	o[1] = fmax(r[1], w->g->r[1]) - pad, o[3] = fmin(r[3], w->g->r[3]) + pad;
	lim = (lim - 1e-6) / TR_BOUND_SAFETY;
	for (int t = 0; t < w->m.nt; t++) {
		const tr_tri *f = NULL;
		double d, ep = 0;
		double *fp = NULL;
		if (g->projected) {
			int s = w->m.src[t];
			double *q = pre + TR_CRS_PRE * (s < 0 ? 0 : s);
			if (s >= 0 && isnan(q[0]))
				tr_crs_prep(g, &st, &w->sel[s], q);
			if (s < 0 || w->sel[s].edge == 2) {
				/* past the footprint, or the band: its
				 * samples lie in the measured band */
				if (b)
					b[t] = NAN;
				continue;
			}
			f = &w->sel[s], fp = q;
		}
		d = tri_bound(w, t, f, fp, st.all, r, o, minh, maxh, &ep);
		if (b)
			b[t] = d;
		else if (!(d <= lim)) {
			free(pre), tr_steep_free(&st);
			return INFINITY; /* measure it */
		}
		most = dmax(most, d);
	}
	free(pre), tr_steep_free(&st);
	/* the samples a rim or band triangle may draw (a cell more for the
	 * roundings and the map's bounds) */
	if (g->projected && (*band = tr_crs_claim(w, r)) >= 0)
		*band += 1;
	return TR_BOUND_SAFETY * most + 1e-6;
}

/* Places k of 0 .. n-1 with lo <= o + s k <= hi: about, for the share
 * of samples measured. */
static long long
places(double o, double s, int n, double lo, double hi)
{
	double a = (lo - o) / s, b = (hi - o) / s;
	long long k0, k1;

	if (s < 0)
		a = (hi - o) / s, b = (lo - o) / s;
	k0 = (long long)ceil(a), k1 = (long long)floor(b);
	k0 = k0 < 0 ? 0 : k0, k1 = k1 > n - 1 ? n - 1 : k1;
	return k1 >= k0 ? k1 - k0 + 1 : 0;
}

long long
tr_tile_samples(const tr_grid *g, int z, int x, int y)
{
	double r[4];

	if (g->projected)
		return 1;
	tr_tile_rect(z, x, y, r);
	return places(g->ax, g->bx, g->w0, r[0], r[2]) *
	    places(g->ay, g->by, g->h0, r[1], r[3]);
}
