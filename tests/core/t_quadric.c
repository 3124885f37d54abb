/* t_quadric - the quadric algebra, and QEM-filtering of a tilted plane
 * (dx != dy, sizes not 2^k+1) through every level and kernel, in double. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/filter.h"
#include "core/solve.h"
#include "tap.h"

static double
urand(unsigned *s)
{
	*s = *s * 1103515245u + 12345u;
	return ((*s >> 8) & 0xffffff) / (double)0x1000000 * 2 - 1;
}

static void
rand_quadric(quadric *q, unsigned *s)
{
	quadric_zero(q);
	for (int k = 0; k < 4; k++) {
		double n[3] = { urand(s), urand(s), urand(s) + 2 }, l;
		l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int i = 0; i < 3; i++)
			n[i] /= l;
		quadric_add_plane(q, n, 10 * urand(s), 1 + urand(s));
	}
}

static void
test_algebra(void)
{
	unsigned s = 1;
	double worst = 0, worst2 = 0, worst3 = 0;

	/* A plane quadric is the squared, weighted distance to the plane. */
	for (int t = 0; t < 1000; t++) {
		quadric q;
		double n[3] = { 0.6, 0, 0.8 }, v[3] = { urand(&s), urand(&s),
			urand(&s) }, d = urand(&s), w = 3;
		double dist = n[0] * v[0] + n[1] * v[1] + n[2] * v[2] + d;
		quadric_zero(&q);
		quadric_add_plane(&q, n, d, w);
		worst = fmax(worst, fabs(quadric_eval(&q, v) - w * dist * dist));
	}
	ok(worst < 1e-12, "plane quadric = w * distance^2 (max dev %.2g)",
	    worst);

	/* Translation: Q'(v - d) = Q(v) for every v. */
	for (int t = 0; t < 1000; t++) {
		quadric q, r;
		double d[3], v[3], vd[3];
		rand_quadric(&q, &s);
		for (int k = 0; k < 3; k++) {
			d[k] = 100 * urand(&s), v[k] = 100 * urand(&s);
			vd[k] = v[k] - d[k];
		}
		r = q;
		quadric_translate(&r, d);
		worst2 = fmax(worst2, fabs(quadric_eval(&r, vd) - quadric_eval(&q, v)) /
		    (1 + fabs(quadric_eval(&q, v))));
	}
	ok(worst2 < 1e-12, "translation identity Q'(v-d) = Q(v) "
	    "(max rel dev %.2g)", worst2);

	/* Triangle quadric: zero at its corners, area * dist^2 off it. */
	{
		quadric q;
		double p0[3] = { 0, 0, 0 }, p1[3] = { 30, 0, 3 },
		       p2[3] = { 0, 20, -4 }, area, n[3], l, off[3];
		quadric_zero(&q);
		area = quadric_add_triangle(&q, p0, p1, p2, 1);
		/* n = (p1 - p0) x (p2 - p0) */
		n[0] = 0 * (-4) - 3 * 20;
		n[1] = 3 * 0 - 30 * (-4);
		n[2] = 30 * 20 - 0 * 0;
		l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		for (int k = 0; k < 3; k++)
			off[k] = 5 * n[k] / l;
		ok(fabs(area - l / 2) < 1e-9 && fabs(quadric_eval(&q, p1)) < 1e-9 &&
		    fabs(quadric_eval(&q, p2)) < 1e-9 &&
		    fabs(quadric_eval(&q, off) - area * 25) < 1e-6 * area,
		    "triangle quadric: 0 at corners, area*d^2 at distance d");
	}

	/* Eigen-decomposition reconstructs A; the 3D minimiser solves
	 * A v = -b for full rank. */
	for (int t = 0; t < 1000; t++) {
		quadric q;
		double w[3], V[3][3], v[3], g[3], a[3][3];
		rand_quadric(&q, &s);
		quadric_eigen(q.a, w, V);
		a[0][0] = q.a[0], a[0][1] = a[1][0] = q.a[1];
		a[0][2] = a[2][0] = q.a[2], a[1][1] = q.a[3];
		a[1][2] = a[2][1] = q.a[4], a[2][2] = q.a[5];
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++) {
				double r = 0;
				for (int k = 0; k < 3; k++)
					r += V[i][k] * w[k] * V[j][k];
				worst3 = fmax(worst3, fabs(r - a[i][j]));
			}
		quadric_min_3d(&q, 1e-9, v);
		for (int i = 0; i < 3; i++)
			g[i] = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2] +
			    q.b[i];
		worst3 = fmax(worst3, fabs(g[0]) + fabs(g[1]) + fabs(g[2]));
	}
	ok(worst3 < 1e-9, "eigen reconstruction and full-rank minimiser "
	    "(max dev %.2g)", worst3);

	/* Flat terrain: rank 1, the minimiser keeps x = y = 0. */
	{
		quadric q;
		double n[3] = { 0, 0, 1 }, v[3];
		int rank;
		quadric_zero(&q);
		quadric_add_plane(&q, n, -7, 2);
		rank = quadric_min_3d(&q, 1e-3, v);
		ok(rank == 1 && v[0] == 0 && v[1] == 0 && fabs(v[2] - 7) < 1e-12,
		    "flat quadric: rank 1, x = y = 0, z on the plane");
	}
	/* Ridge: rank 2, the vertex stays on its line along the ridge. */
	{
		quadric q;
		double n1[3] = { 0.6, 0, 0.8 }, n2[3] = { -0.6, 0, 0.8 }, v[3];
		int rank;
		quadric_zero(&q);
		/* planes z = -0.75 (x - 2) and z = 0.75 (x - 2): ridge x = 2 */
		quadric_add_plane(&q, n1, -0.6 * 2, 1);
		quadric_add_plane(&q, n2, 0.6 * 2, 1);
		rank = quadric_min_3d(&q, 1e-3, v);
		ok(rank == 2 && fabs(v[0] - 2) < 1e-12 && fabs(v[1]) < 1e-12 &&
		    fabs(v[2]) < 1e-12, "ridge quadric: rank 2, on the crest, "
		    "y free and kept at 0 (v = %g %g %g)", v[0], v[1], v[2]);
	}
}

/* A tilted plane with dyadic coefficients, so every sample is exact in
 * float32; cells 30 m x 20 m. */
#define DX 30.0
#define DY 20.0
static double
plane(double col, double row)
{
	return 1000.0 + 0.375 * col - 1.25 * row;
}

/* Filters a W x H plane up to the top, solving each level with QEM-1D and
 * QEM-3D; returns the worst vertical deviation over all vertices of all
 * levels, padded ones past the edge included. */
static double
plane_pyramid(const filter_kernel *k, int W, int H, double *worst3d)
{
	geo_metric m;
	int n = 4 * (W > H ? W : H);
	fqm_vertex *lev, *next;
	solve_vertex *out;
	double worst = 0;
	int w = W, h = H;

	*worst3d = 0;
	geo_metric_const(&m, n, DX, DY, NULL);
	lev = calloc((size_t)W * H, sizeof *lev);
	/* level 0 */
	{
		float *z = malloc(2 * W * sizeof *z);
		unsigned char *v = malloc(W);
		double *band[2] = { malloc((W - 1) * FQM_BAND0_DOUBLES *
		    sizeof(double)), malloc((W - 1) * FQM_BAND0_DOUBLES *
		    sizeof(double)) };
		memset(v, 1, W);
		for (int i = 0; i < W; i++)
			z[i] = (float)plane(i, 0);
		for (int j = 0; j < H; j++) {
			float *zc = z + (j & 1) * W, *zn = z + !(j & 1) * W;
			if (j + 1 < H) {
				for (int i = 0; i < W; i++)
					zn[i] = (float)plane(i, j + 1);
				fqm_band0(zc, v, zn, v, W, j, &m, band[j & 1]);
			}
			fqm_row0(j > 0 ? band[!(j & 1)] : NULL,
			    j + 1 < H ? band[j & 1] : NULL, zc, v, W,
			    lev + (size_t)j * W);
		}
		free(z), free(v), free(band[0]), free(band[1]);
		/* Move every frame off the plane (a consistent change of
		 * frame): the quadrics, not the reference heights, must
		 * find the plane. */
		unsigned seed = 7;
		for (size_t i = 0; i < (size_t)W * H; i++) {
			double d[3] = { 0, 0, 5 * urand(&seed) };
			quadric_translate(&lev[i].q, d);
			lev[i].z += d[2];
		}
	}
	for (int l = 0;; l++) {
		for (int mode = SOLVE_QEM1D; mode <= SOLVE_QEM3D; mode++) {
			solve_state s;
			solve_init(&s, mode, l, w, h, &m, NULL);
			out = malloc(w * sizeof *out);
			for (int j = 0; j < h; j++) {
				solve_row(&s, lev + (size_t)j * w, out);
				for (int i = 0; i < w; i++) {
					double ci = (double)i * (1 << l) + out[i].x / DX;
					double cj = (double)j * (1 << l) + out[i].y / DY;
					double dev = fabs(out[i].z - plane(ci, cj));
					if (mode == SOLVE_QEM1D)
						worst = fmax(worst, dev);
					else
						*worst3d = fmax(*worst3d, dev);
				}
			}
			free(out);
			solve_free(&s);
		}
		if (w <= 2 && h <= 2)
			break;
		filter_state f;
		filter_init(&f, k, l, w, h, W, H, &m, NULL);
		next = calloc((size_t)f.cw * f.ch, sizeof *next);
		for (int j = 0, y = 0; y < f.ch; y++) {
			while (!filter_ready(&f))
				filter_push(&f, lev + (size_t)j++ * w);
			filter_pull(&f, next + (size_t)y * f.cw);
		}
		w = f.cw, h = f.ch;
		filter_free(&f);
		free(lev);
		lev = next;
	}
	free(lev);
	geo_metric_free(&m);
	return worst;
}

/* QEM-3D on quadrics pulling each vertex up to a cell away in a random
 * direction: every cell of the result is convex with its triangles at
 * least `shrink` of their grid area, boundary vertices on their boundary,
 * offsets within half a cell. Checked by brute force on the whole level. */
static void
test_folds(int level, int W, int H, double reach)
{
	geo_metric m;
	int n = (W > H ? W : H) << (level + 1);
	fqm_vertex *in = calloc(W, sizeof *in);
	solve_vertex *lev = calloc((size_t)W * H, sizeof *lev);
	solve_state s;
	unsigned seed = 99;
	long bad = 0, moved = 0, outside = 0;
	double sx, sy;

	geo_metric_const(&m, n, DX, DY, NULL);
	sx = DX * (1 << level), sy = DY * (1 << level);
	solve_init(&s, SOLVE_QEM3D, level, W, H, &m, NULL);
	for (int j = 0; j < H; j++) {
		for (int i = 0; i < W; i++) {
			/* three planes through a random point: full rank */
			double p[3] = { reach * sx * urand(&seed),
				reach * sy * urand(&seed), 3 * urand(&seed) };
			double ns[3][3] = { { 0.3, 0, 1 }, { -0.2, 0.4, 1 },
				{ 0, -0.5, 1 } };
			quadric_zero(&in[i].q);
			for (int k = 0; k < 3; k++) {
				double *nn = ns[k], l = sqrt(nn[0] * nn[0] +
				    nn[1] * nn[1] + 1);
				double u[3] = { nn[0] / l, nn[1] / l, 1 / l };
				quadric_add_plane(&in[i].q, u, -(u[0] * p[0] +
				    u[1] * p[1] + u[2] * p[2]), 1);
			}
			in[i].z = 100, in[i].v = 1;
		}
		solve_row(&s, in, lev + (size_t)j * W);
	}
	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++) {
			solve_vertex *v = &lev[(size_t)j * W + i];
			moved += v->x != 0 || v->y != 0;
			if (fabs(v->x) > sx / 2 || fabs(v->y) > sy / 2 ||
			    ((i == 0 || i == W - 1) && v->x != 0) ||
			    ((j == 0 || j == H - 1) && v->y != 0))
				outside++;
			/* the two-cell triangles of a scale-1 edge vertex */
			int kind = (i & 1) && !(j & 1) ? 0 : !(i & 1) && (j & 1) ?
			    1 : -1;
			static const int et[2][2][3][2] = {
				{ { { -1, 0 }, { 1, 0 }, { 0, -1 } },
				  { { -1, 0 }, { 1, 0 }, { 0, 1 } } },
				{ { { 0, -1 }, { 0, 1 }, { -1, 0 } },
				  { { 0, -1 }, { 0, 1 }, { 1, 0 } } },
			};
			for (int t = 0; kind >= 0 && t < 2; t++) {
				double g3[3][2], p3[3][2], ga, pa;
				int inside = 1;
				for (int k = 0; k < 3; k++) {
					int ii = i + et[kind][t][k][0];
					int jj = j + et[kind][t][k][1];
					if (ii < 0 || jj < 0 || ii >= W || jj >= H)
						inside = 0;
					else {
						solve_vertex *u = &lev[(size_t)jj * W + ii];
						g3[k][0] = ii * sx, g3[k][1] = jj * sy;
						p3[k][0] = g3[k][0] + u->x;
						p3[k][1] = g3[k][1] + u->y;
					}
				}
				if (!inside)
					continue;
				ga = (g3[1][0] - g3[0][0]) * (g3[2][1] - g3[0][1]) -
				    (g3[1][1] - g3[0][1]) * (g3[2][0] - g3[0][0]);
				pa = (p3[1][0] - p3[0][0]) * (p3[2][1] - p3[0][1]) -
				    (p3[1][1] - p3[0][1]) * (p3[2][0] - p3[0][0]);
				bad += ga > 0 ? pa < s.shrink * ga : pa > s.shrink * ga;
			}
			if (i + 1 == W || j + 1 == H)
				continue;
			double g[4][2] = { { 0, 0 }, { sx, 0 }, { sx, sy },
				{ 0, sy } }, p[4][2];
			solve_vertex *c[4] = { v, v + 1, v + 1 + W, v + W };
			for (int k = 0; k < 4; k++)
				p[k][0] = g[k][0] + c[k]->x,
				p[k][1] = g[k][1] + c[k]->y;
			bad += !solve_cell_ok(p, g, s.shrink);
		}
	ok(bad == 0 && outside == 0 && moved > W * H / 2,
	    "QEM-3D %dx%d level %d, targets up to %.1f cell away: %ld "
	    "folded cell or two-cell triangles, %ld offsets out of bounds, "
	    "%ld of %d vertices "
	    "moved, fold fix reduced %lld (zeroed %lld)", W, H, level, reach,
	    bad, outside, moved, W * H, s.reduced, s.zeroed);
	solve_free(&s);
	free(in), free(lev);
	geo_metric_free(&m);
}

int
main(void)
{
	static const int sizes[][2] = { { 37, 23 }, { 129, 129 }, { 3, 3 },
		{ 100, 5 } };

	test_algebra();
	test_folds(0, 60, 40, 0.3);
	test_folds(2, 60, 40, 1.0);
	test_folds(3, 129, 129, 3.0);
	for (const filter_kernel *k = filter_kernels; k->name; k++)
		for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
			double w3, w1 = plane_pyramid(k, sizes[s][0], sizes[s][1],
			    &w3);
			ok(w1 < 1e-9, "tilted plane %dx%d, kernel %s: QEM-1D "
			    "exact at every level and boundary (max %.2g m)",
			    sizes[s][0], sizes[s][1], k->name, w1);
			ok(w3 < 1e-9, "tilted plane %dx%d, kernel %s: QEM-3D "
			    "stays on the plane (max %.2g m)", sizes[s][0],
			    sizes[s][1], k->name, w3);
		}
	return tap_done();
}
