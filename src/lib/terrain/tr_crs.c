/* tr_crs.c - the CRS term of a projected DEM's tile bound (tr_bound.c):
 * how far the drawn piece of a selected triangle, straight in
 * longitude and latitude, is from the selection, straight in the grid.
 *
 * S is a selected triangle (a piece of one, cut to the grid: tr_cut.c)
 * with level-0 places G_i and heights h_i, P its plane over the grid;
 * T' the straight triangle of the vertices' images l_i = phi(G_i) in
 * degrees, F_S the heights linear over T' (the tile's pieces of S carry
 * it: tr_clip.c). A_S, the affine map with A_S(l_i) = G_i, makes F_S =
 * P o A_S. A sample at place g, drawn at l = phi(g) under a piece of S,
 * is measured against Z(g), the selection's height there (the plane of
 * the selected triangle holding g, tr_gsel.c). With psi = phi^-1,
 *
 *   |F_S(l) - Z(g)| <= |P(a) - P(g)| + |P(g) - Z(g)|,  a = A_S(l).
 *
 * a - g = A_S(l) - psi(l) = sum b_i R_i (b_i the coordinates of l in T',
 * R_i Taylor's remainder of psi from l to l_i; sum b_i (l_i - l) = 0),
 * so |a - g| <= e = 1/2 M rho^2 for l in T' (M bounds |D2 psi[d, d]|,
 * tr_curve.c; sum b_i |l_i - l|^2 <= rho^2, T''s least enclosing circle
 * squared); for l up to delta outside T' (a decoded corner's place) e
 * gains |D A_S - D psi| delta, bounded from M and T' (turn()). The
 * first term is at most |grad P| e. The second is 0 for g in S; else g lies within e + |D A_S| delta of S
 * (A_S maps T' onto S) and P - Z, 0 on S, grows by at most |grad P| + G
 * per cell from it, G the steepest selected triangle within the reach of
 * S (of the tile's, those within a twentieth of a tile of it, tr_cut.c's
 * keep_grid: the places reached lie within reach |D phi| degrees of S's
 * piece there, which must be under half that; found by buckets of the
 * grid, each holding its triangles' steepest). So
 *
 *   C = |grad P| e + (|grad P| + G) (e + |D A_S| delta).
 *
 * The pieces past the footprint or in the band get no bound: how deep
 * in the grid a sample they draw may lie comes from their corners
 * through PROJ's inverse (tr_crs_claim), and those samples are
 * measured (tr_level.c). */
#include <math.h>
#include <stdlib.h>

#include "terrain/tr_bary.h"
#include "terrain/tr_impl.h"

double
tr_encl(const double l[3])
{
	int k = l[1] > l[0] ? 1 : 0;
	double h;

	k = l[2] > l[k] ? 2 : k;
	if (l[k] >= l[(k + 1) % 3] + l[(k + 2) % 3])
		return l[k] / 4;
	h = 2 * (l[0] * l[1] + l[1] * l[2] + l[2] * l[0]) - (l[0] * l[0] +
	    l[1] * l[1] + l[2] * l[2]);
	return dmax(l[k] / 4, l[0] * l[1] * l[2] / h);
}

/* tr_encl of the triangle x, y. */
static double
enclosing(const double *x, const double *y)
{
	double l[3];

	for (int i = 0; i < 3; i++) {
		int a = (i + 1) % 3, b = (i + 2) % 3;
		l[i] = (x[a] - x[b]) * (x[a] - x[b]) + (y[a] - y[b]) * (y[a] -
		    y[b]);
	}
	return tr_encl(l);
}

/* The distance from (px, py) to the triangle x, y (0 inside). */
static double
outside(const double *x, const double *y, double px, double py)
{
	double s = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] -
	    x[0]), d = INFINITY;
	int in = 1;

	for (int i = 0; i < 3 && in; i++) { /* each side's same way */
		int j = (i + 1) % 3;
		double c = (x[j] - x[i]) * (py - y[i]) - (y[j] - y[i]) * (px -
		    x[i]);
		in = c * s >= 0;
	}
	if (in)
		return 0;
	for (int i = 0; i < 3; i++) {
		int j = (i + 1) % 3;
		double ex = x[j] - x[i], ey = y[j] - y[i];
		double qx = px - x[i], qy = py - y[i], l2 = ex * ex + ey * ey;
		double t = l2 > 0 ? dmin(1, dmax(0, (ex * qx + ey * qy) / l2)) : 0;
		qx -= t * ex, qy -= t * ey;
		d = dmin(d, qx * qx + qy * qy);
	}
	return sqrt(d);
}

/* |D A_S| (Frobenius) of selection triangle f; -1 when T' or S is
 * degenerate. */
static double
affine_norm(const tr_tri *f)
{
	double lx1 = f->x[1] - f->x[0], lx2 = f->x[2] - f->x[0];
	double ly1 = f->y[1] - f->y[0], ly2 = f->y[2] - f->y[0];
	double gx1 = f->gx[1] - f->gx[0], gx2 = f->gx[2] - f->gx[0];
	double gy1 = f->gy[1] - f->gy[0], gy2 = f->gy[2] - f->gy[0];
	double det = lx1 * ly2 - lx2 * ly1;
	/* D A = G L^-1, L = (l1 - l0, l2 - l0) by columns */
	double a = (gx1 * ly2 - gx2 * ly1) / det, b = (gx2 * lx1 - gx1 * lx2) /
	    det, c = (gy1 * ly2 - gy2 * ly1) / det, d = (gy2 * lx1 - gy1 *
	    lx2) / det;
	double n = sqrt(a * a + b * b + c * c + d * d);

	return isfinite(n) && n > 0 ? n : -1;
}

/* |grad P| of f in the grid, metres a cell; -1 when degenerate. */
static double
slope(const tr_tri *f)
{
	double x1 = f->gx[1] - f->gx[0], y1 = f->gy[1] - f->gy[0];
	double x2 = f->gx[2] - f->gx[0], y2 = f->gy[2] - f->gy[0];
	double h1 = f->h[1] - f->h[0], h2 = f->h[2] - f->h[0];
	double d = x1 * y2 - x2 * y1;
	double a = (y2 * h1 - y1 * h2) / d, b = (x1 * h2 - x2 * h1) / d;
	double n = sqrt(a * a + b * b);

	return isfinite(n) ? n : -1;
}

/* How far D A_S may differ from D psi within T' (cells a degree):
 * with E = (l1 - l0, l2 - l0), D A_S E = D psi(l0) E + (R1, R2), |R_k|
 * <= M |l_k - l0|^2 / 2, so |D A_S - D psi(l0)| <= |(R1, R2)| |E^-1|
 * (Frobenius norms), and D psi moves by at most M a degree from l0:
 * plus M diam T' (tr_crs adds M delta for a corner delta outside). */
static double
turn(const tr_grid *g, const tr_tri *f)
{
	double ax = f->x[1] - f->x[0], ay = f->y[1] - f->y[0];
	double bx = f->x[2] - f->x[0], by = f->y[2] - f->y[0];
	double a2 = ax * ax + ay * ay, b2 = bx * bx + by * by;
	double c2 = (f->x[2] - f->x[1]) * (f->x[2] - f->x[1]) +
	    (f->y[2] - f->y[1]) * (f->y[2] - f->y[1]);
	double det = fabs(ax * by - ay * bx), M = g->d2psi;
	double t = 0.5 * M * sqrt(a2 * a2 + b2 * b2) * sqrt(a2 + b2) / det +
	    M * sqrt(dmax(a2, dmax(b2, c2)));

	return isfinite(t) ? t : INFINITY;
}

/* A gsel triangle's (tr_gsel.c's terms) gradient squared. */
static double
gslope2(const double *t)
{
	double gx = (t[5] * t[9] - t[3] * t[10]) / t[6];
	double gy = (t[2] * t[10] - t[4] * t[9]) / t[6];

	return gx * gx + gy * gy;
}

static int
sbucket(const tr_steep *st, double c, int k)
{
	return tr_bucket(c, st->o[k], st->s[k], st->nb);
}

int
tr_steep_init(tr_steep *st, const tr_work *w)
{
	enum { GT = TR_BARY_TERMS + 3 };
	double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };

	st->nb = 16, st->all = 0;
	if ((st->mx = calloc((size_t)st->nb * st->nb, sizeof *st->mx)) == NULL)
		return -1;
	for (int i = 0; i < w->ngsel; i++)
		for (int k = 0; k < 2; k++) {
			double a, b;
			tr_gsel_box(w->gsel + GT * (size_t)i, k, &a, &b);
			lo[k] = dmin(lo[k], a), hi[k] = dmax(hi[k], b);
		}
	for (int k = 0; k < 2; k++)
		st->o[k] = lo[k], st->s[k] = st->nb / (hi[k] - lo[k] + 1);
	for (int i = 0; i < w->ngsel; i++) {
		const double *t = w->gsel + GT * (size_t)i;
		double g2 = gslope2(t), x0, x1, y0, y1;
		/* a degenerate triangle: NaN, no sample in it; infinite: none
		 * bounded */
		if (isnan(g2))
			continue;
		st->all = dmax(st->all, g2);
		tr_gsel_box(t, 0, &x0, &x1), tr_gsel_box(t, 1, &y0, &y1);
		for (int j = sbucket(st, y0, 1); j <= sbucket(st, y1, 1); j++)
			for (int b = sbucket(st, x0, 0); b <= sbucket(st, x1, 0); b++)
				st->mx[j * st->nb + b] = dmax(st->mx[j * st->nb + b], g2);
	}
	for (int i = 0; i < st->nb * st->nb; i++)
		st->mx[i] = sqrt(st->mx[i]) * (1 + 1e-15);
	st->all = sqrt(st->all) * (1 + 1e-15);
	if (!isfinite(st->all))
		st->all = INFINITY;
	return 0;
}

void
tr_steep_free(tr_steep *st)
{
	free(st->mx);
	st->mx = NULL;
}

/* The steepest of the tile's selected triangles within d cells of f's
 * box in the grid. */
static double
steep_near(const tr_steep *st, const tr_tri *f, double d)
{
	double x0 = dmin(f->gx[0], dmin(f->gx[1], f->gx[2])) - d;
	double x1 = dmax(f->gx[0], dmax(f->gx[1], f->gx[2])) + d;
	double y0 = dmin(f->gy[0], dmin(f->gy[1], f->gy[2])) - d;
	double y1 = dmax(f->gy[0], dmax(f->gy[1], f->gy[2])) + d;
	double most = 0;

	if (!isfinite(st->all))
		return INFINITY;
	for (int j = sbucket(st, y0, 1); j <= sbucket(st, y1, 1); j++)
		for (int b = sbucket(st, x0, 0); b <= sbucket(st, x1, 0); b++)
			most = dmax(most, st->mx[j * st->nb + b]);
	return most;
}

void
tr_crs_prep(const tr_grid *g, const tr_steep *st, const tr_tri *f,
    double pre[TR_CRS_PRE])
{
	double e = 0.5 * g->d2psi * enclosing(f->x, f->y);

	pre[0] = affine_norm(f), pre[1] = slope(f);
	pre[2] = isfinite(e) ? e : INFINITY;
	pre[5] = turn(g, f);
	/* the neighbours within the reach of pieces a cell off S at most
	 * (past it, the tile's steepest) */
	pre[4] = pre[2] + 1;
	pre[3] = steep_near(st, f, pre[4]);
}

double
tr_crs(const tr_grid *g, const tr_tri *f, const double pre[TR_CRS_PRE],
    const double xd[3], const double yd[3], double gmax, double margin,
    double *reach)
{
	double da = pre[0], gp = pre[1], delta = 0, e, c, G;

	*reach = INFINITY;
	if (da < 0 || gp < 0)
		return INFINITY;
	for (int j = 0; j < 3; j++)
		delta = dmax(delta, outside(f->x, f->y, xd[j], yd[j]));
	e = pre[2] + (pre[5] + g->d2psi * delta) * delta;
	*reach = e + da * delta;
	/* G holds the triangles within margin of the tile, and the places
	 * this may reach lie within reach cells of S: less than half the
	 * margin, or no bound */
	if (!(2 * *reach * g->d1phi < margin))
		return INFINITY;
	G = *reach <= pre[4] ? pre[3] : gmax;
	c = gp * e + (gp + G) * *reach;
	return isfinite(c) ? c : INFINITY;
}

/* The deepest level-0 place, in cells from the grid's nearest side,
 * that the decoded triangle (lon, lat) x, y may draw: with g_j =
 * psi(x_j, y_j) (PROJ's inverse) and A its affine interpolant over the
 * triangle, psi is within e = M rho^2 / 2 of A; each side's distance is
 * linear, so over the triangle A's is at most its largest at a corner,
 * and the depth (the least of the four) at most the least of those;
 * INFINITY where PROJ has no inverse there. */
static double
deepest(tr_work *w, const double *x, const double *y)
{
	const tr_grid *g = w->g;
	double X[3], Y[3], Z[3] = { 0, 0, 0 }, W = g->w0 - 1, H = g->h0 - 1;
	double far[4] = { -INFINITY, -INFINITY, -INFINITY, -INFINITY };

	for (int j = 0; j < 3; j++)
		X[j] = x[j], Y[j] = y[j];
	if (geo_proj_crs(&w->proj, X, Y, Z, 3) < 0)
		return INFINITY;
	for (int j = 0; j < 3; j++) {
		double I = (X[j] - g->ax) / g->bx, J = (Y[j] - g->ay) / g->by;
		far[0] = dmax(far[0], I), far[1] = dmax(far[1], W - I);
		far[2] = dmax(far[2], J), far[3] = dmax(far[3], H - J);
	}
	double d = dmin(dmin(far[0], far[1]), dmin(far[2], far[3])) +
	    0.5 * g->d2psi * enclosing(x, y);

	return isfinite(d) ? d : INFINITY;
}

double
tr_crs_claim(tr_work *w, const double r[4])
{
	const tr_mesh *m = &w->m;
	double most = -1;

	for (int t = 0; t < m->nt; t++) {
		int s = m->src[t];
		const int *k = m->tri + 3 * t;
		double x[3], y[3];
		if (!m->rim[t] && !(s >= 0 && w->sel[s].edge == 2))
			continue;
		for (int j = 0; j < 3; j++) {
			double tu = w->u[k[j]] / (double)QM_MAX;
			double tv = w->v[k[j]] / (double)QM_MAX;
			x[j] = (1 - tu) * r[0] + tu * r[2];
			y[j] = (1 - tv) * r[1] + tv * r[3];
		}
		/* one wholly past the terrain's rectangle draws no sample the
		 * measure takes (tr_keep: the tile's part in it), and may lie
		 * where the CRS has no place */
		const double *o = w->g->r;
		if (dmax(x[0], dmax(x[1], x[2])) < o[0] ||
		    dmin(x[0], dmin(x[1], x[2])) > o[2] ||
		    dmax(y[0], dmax(y[1], y[2])) < o[1] ||
		    dmin(y[0], dmin(y[1], y[2])) > o[3])
			continue;
		most = dmax(most, deepest(w, x, y));
		if (most == INFINITY)
			break;
	}
	return most;
}
