/* t_filter - the streaming level filter (filter.h): kernels, the odd
 * reflection past the edges, the ring's push/pull order and sizes, the
 * padding past the DEM, and QEM-filtering of a tilted plane (dx != dy,
 * sizes not 2^k+1) through every level and kernel, in double, each level
 * solved with QEM-1D and QEM-3D (the plane must survive exactly). */
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
test_kernels(void)
{
	int bad = 0, n = 0;

	for (const filter_kernel *k = filter_kernels; k->name != NULL; k++) {
		double sum = k->w[0];
		for (int a = 1; a <= k->radius; a++)
			sum += 2 * k->w[a];
		for (int a = 0; a <= k->radius; a++)
			bad += k->w[a] < 0;
		bad += fabs(sum - 1) > 1e-15 || k->radius > FILTER_MAX_RADIUS;
		bad += filter_find(k->name) != k;
		n++;
	}
	ok(n == 4 && bad == 0, "%d kernels, taps >= 0 summing to 1, radius "
	    "<= %d, each found by name", n, FILTER_MAX_RADIUS);
	ok(filter_find("binomial")->radius == 1 &&
	    filter_find("binomial5")->radius == 2 &&
	    filter_find("none")->radius == 0, "radii: binomial 1, "
	    "binomial5 2, none 0");
	ok(filter_find("gauss") == NULL && filter_find("") == NULL,
	    "an unknown kernel name is not found");
}

/* Odd reflection keeps a line a line past both ends, with a stride. */
static void
test_extend(void)
{
	double h[2 * 7];
	int bad = 0;

	for (int i = 0; i < 7; i++)
		h[2 * i] = 3 + 2.5 * i, h[2 * i + 1] = NAN;
	for (int i = -6; i <= 12; i++)
		bad += filter_extend(h, 2, 7, i) != 3 + 2.5 * i;
	ok(bad == 0, "filter_extend: a line continues past both ends "
	    "(stride 2, -6 .. 12 of 7)");
	ok(filter_extend(h, 2, 1, -1) == 3 && filter_extend(h, 2, 1, 1) == 3,
	    "filter_extend: one sample extends as a constant");
	ok(filter_extend(h, 2, 7, 3) == h[6], "filter_extend: inside, the "
	    "sample itself");
}

/* Sizes, ring depth, and the order of pushes and pulls: a coarse row m
 * is ready once fine rows up to 2m + r (or the last) are in. */
static void
test_stream(const char *name, int fw, int fh)
{
	const filter_kernel *k = filter_find(name);
	fqm_vertex *fine = calloc(fw, sizeof *fine), *coarse;
	geo_metric m;
	filter_state f;
	int pushes = 0, pulls = 0, late = 0, early = 0, r;

	geo_metric_const(&m, 4 * fh, 30, 20, NULL);
	r = filter_init(&f, k, 0, fw, fh, fw, fh, &m, NULL);
	ok(r == 0 && f.cw == fqm_level_size(fw, 1) &&
	    f.ch == fqm_level_size(fh, 1) && f.nring == (k->radius > 0 ? 2 * k->radius + 1 : 2),
	    "%s %dx%d: coarse %dx%d, ring of %d rows", name, fw, fh, f.cw,
	    f.ch, f.nring);
	coarse = calloc(f.cw, sizeof *coarse);
	for (int i = 0; i < fw; i++)
		fine[i].v = 1;
	while (pulls < f.ch) {
		int need = 2 * pulls + k->radius < fh - 1 ?
		    2 * pulls + k->radius : fh - 1;
		if (!filter_ready(&f)) {
			early += pushes > need; /* should have been ready */
			filter_push(&f, fine);
			pushes++;
			continue;
		}
		late += pushes != need + 1 && pushes < fh;
		filter_pull(&f, coarse);
		pulls++;
	}
	ok(pushes == fh && pulls == f.ch && !filter_ready(&f) && late == 0 &&
	    early == 0, "%s %dx%d: each coarse row ready as soon as its fine "
	    "rows are in (%d pushes, %d pulls)", name, fw, fh, pushes, pulls);
	filter_free(&f);
	free(fine), free(coarse);
	geo_metric_free(&m);
}

/* Kernel none: heights and quadric-free vertices subsample exactly; a
 * coarse vertex past the DEM's last sample is padding (V 0). */
static void
test_padding(void)
{
	enum { W = 6, H = 4 };
	fqm_vertex fine[H][W], coarse[3][4];
	geo_metric m;
	filter_state f;
	int bad = 0, pad = 0;

	memset(fine, 0, sizeof fine);
	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++)
			fine[j][i].z = 10 * j + i, fine[j][i].s = 100 + i + j,
			fine[j][i].v = 1;
	geo_metric_const(&m, 16, 30, 20, NULL);
	filter_init(&f, filter_find("none"), 0, W, H, W, H, &m, NULL);
	for (int j = 0, y = 0; y < f.ch; y++) {
		while (!filter_ready(&f))
			filter_push(&f, fine[j++]);
		filter_pull(&f, coarse[y]);
	}
	for (int y = 0; y < f.ch; y++)
		for (int c = 0; c < f.cw; c++) {
			int past = 2 * c > W - 1 || 2 * y > H - 1;
			/* the plane, extended past the edge */
			double zi = 10 * (2 * y) + 2 * c;
			pad += past;
			bad += past ? coarse[y][c].v != 0 : coarse[y][c].v != 1;
			bad += fabs(coarse[y][c].z - zi) > 1e-12;
			bad += fabs(coarse[y][c].s - (100 + 2 * c + 2 * y)) >
			    1e-12;
		}
	ok(f.cw == 4 && f.ch == 3 && pad == 6 && bad == 0, "kernel none, "
	    "6x4 to 4x3: Z and S sub-sampled (odd reflection past the "
	    "edge), %d padding vertices with V 0", pad);
	filter_free(&f);
	geo_metric_free(&m);
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

int
main(void)
{
	static const int sizes[][2] = { { 37, 23 }, { 129, 129 }, { 3, 3 },
		{ 100, 5 } };

	test_kernels();
	test_extend();
	test_stream("binomial", 9, 7);
	test_stream("binomial5", 10, 12);
	test_stream("none", 5, 2);
	test_padding();
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
