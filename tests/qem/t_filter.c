/* t_filter - the streaming level filter (filter.h): kernels, the odd
 * reflection past the edges, the ring's push/pull order and sizes, the
 * padding past the DEM, and QEM-filtering of a tilted plane (dx != dy,
 * sizes not 2^k+1) through every level and kernel, in double, each level
 * solved with QEM-1D and QEM-3D (the plane must survive exactly). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "qem/filter.h"
#include "qem/fqm0.h"
#include "qem/solve.h"
#include "tap.h"
#include "urand.h"

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
	geo_ground m;
	filter_state f;
	int pushes = 0, pulls = 0, late = 0, early = 0, r;

	geo_ground_const(&m, 4 * fh, 30, 20, NULL);
	r = filter_init(&f, k, 0, fw, fh, fw, fh, &m, NULL);
	ok(r == 0 && f.cw == geo_level_size(fw, 1) &&
	    f.ch == geo_level_size(fh, 1) && f.nring == (k->radius > 0 ? 2 * k->radius + 1 : 2),
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
	geo_ground_free(&m);
}

/* Kernel none: heights and quadric-free vertices subsample exactly; a
 * coarse vertex past the DEM's last sample is padding (V 0). */
static void
test_padding(void)
{
	enum { W = 6, H = 4 };
	fqm_vertex fine[H][W], coarse[3][4];
	geo_ground m;
	filter_state f;
	int bad = 0, pad = 0;

	memset(fine, 0, sizeof fine);
	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++)
			fine[j][i].z = 10 * j + i, fine[j][i].s = 100 + i + j,
			fine[j][i].v = 1;
	geo_ground_const(&m, 16, 30, 20, NULL);
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
	geo_ground_free(&m);
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
	geo_ground m;
	int n = 4 * (W > H ? W : H);
	fqm_vertex *lev, *next;
	solve_vertex *out;
	double worst = 0;
	int w = W, h = H;

	*worst3d = 0;
	geo_ground_const(&m, n, DX, DY, NULL);
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
	geo_ground_free(&m);
	return worst;
}


/* --- the filter as first written, the reference for its vector form --- */

/* The level filter as it was written first: every tap through
 * quadric_translate and quadric_add, one vertex structure at a time.
 * filter.c must compute its outputs bit for bit. */
typedef struct {
	filter_state f; /* sizes, kernel, metric; its ring unused */
	fqm_vertex *ring;
} ref_state;

static void
ref_add_moved(quadric *q, const quadric *r, double dx, double dy, double dz,
    double w)
{
	quadric t = *r;
	double d[3] = { dx, dy, dz };

	quadric_translate(&t, d);
	quadric_add(q, &t, w);
}

static void
ref_push(ref_state *R, const fqm_vertex *fine)
{
	filter_state *f = &R->f;
	const filter_kernel *k = f->k;
	int j = f->next++, slot = j % f->nring;
	fqm_vertex *out = R->ring + (size_t)slot * f->cw;
	double step = (double)(1L << f->level), sx[GEO_MAX_NODES];
	size_t st = sizeof *fine / sizeof(double);
	double vw;

	f->tag[slot] = j;
	geo_row_sx(f->m, (double)((long)j << f->level), sx);
	for (int c = 0; c < f->cw; c++) {
		fqm_vertex *o = &out[c];
		double s = step * geo_on_row(f->m, sx,
		    (double)((long)c << (f->level + 1)));
		double zh = 0;
		memset(o, 0, sizeof *o);
		for (int a = -k->radius; a <= k->radius; a++)
			zh += k->w[abs(a)] *
			    filter_extend(&fine[0].z, st, f->fw, 2 * c + a);
		o->z = zh;
		o->s = filter_extend(&fine[0].s, st, f->fw, 2 * c);
		vw = 0;
		for (int a = -k->radius; a <= k->radius; a++) {
			int i = 2 * c + a;
			double w = k->w[abs(a)];
			if (i >= f->fw) {
				if (k->radius > 0)
					continue;
				i = f->fw - 1, w = 1;
			}
			if (i < 0)
				continue;
			ref_add_moved(&o->q, &fine[i].q, -(i - 2 * c) * s, 0,
			    zh - fine[i].z, w);
			if (i == 2 * c + a)
				o->v += w * fine[i].v, vw += w;
		}
		o->v = vw > 0 ? o->v / vw : 0;
	}
}

static double
ref_ext_rows(const ref_state *R, int c, int i, int field)
{
	const filter_state *f = &R->f;
	int n = f->fh, r;

	if (i >= 0 && i < n) {
		const fqm_vertex *row = R->ring + (size_t)(i % f->nring) * f->cw;
		return field ? row[c].s : row[c].z;
	}
	if (i < 0) {
		r = -i < n ? -i : n - 1;
		return 2 * ref_ext_rows(R, c, 0, field) -
		    ref_ext_rows(R, c, r, field);
	}
	r = 2 * (n - 1) - i;
	if (r < 0)
		r = 0;
	return 2 * ref_ext_rows(R, c, n - 1, field) -
	    ref_ext_rows(R, c, r, field);
}

static void
ref_pull(ref_state *R, fqm_vertex *coarse)
{
	filter_state *f = &R->f;
	const filter_kernel *k = f->k;
	int m = f->out, j0 = 2 * m;
	double vw, y0[GEO_MAX_NODES], y[2 * FILTER_MAX_RADIUS + 1][GEO_MAX_NODES];

	f->out++;
	geo_row_y(f->m, (double)((long)j0 << f->level), y0);
	for (int b = -k->radius; b <= k->radius; b++) {
		int i = j0 + b < f->fh ? j0 + b : f->fh - 1;
		if (i >= 0)
			geo_row_y(f->m, (double)((long)i << f->level),
			    y[b + k->radius]);
	}
	for (int c = 0; c < f->cw; c++) {
		fqm_vertex *o = &coarse[c];
		double I = (double)((long)c << (f->level + 1));
		double zc = 0;
		memset(o, 0, sizeof *o);
		for (int b = -k->radius; b <= k->radius; b++)
			zc += k->w[abs(b)] * ref_ext_rows(R, c, j0 + b, 0);
		o->z = zc;
		o->s = ref_ext_rows(R, c, j0, 1);
		vw = 0;
		for (int b = -k->radius; b <= k->radius; b++) {
			int i = j0 + b;
			double w = k->w[abs(b)];
			const fqm_vertex *h;
			if (i >= f->fh) {
				if (k->radius > 0)
					continue;
				i = f->fh - 1, w = 1;
			}
			if (i < 0)
				continue;
			h = R->ring + (size_t)(i % f->nring) * f->cw + c;
			ref_add_moved(&o->q, &h->q, 0, geo_on_row(f->m, y0, I) -
			    geo_on_row(f->m, y[b + k->radius], I), zc - h->z,
			    w);
			if (i == j0 + b)
				o->v += w * h->v, vw += w;
		}
		o->v = vw > 0 ? o->v / vw : 0;
		if ((long)c << (f->level + 1) > f->w0 - 1 ||
		    (long)m << (f->level + 1) > f->h0 - 1)
			o->v = 0;
	}
}

/* fqmfilter's own path (filter_push_row, filter_pull_row: floats in the
 * FQM's channels) and the vertex one (filter_push, filter_pull) against
 * the reference, on random rows: the outputs must be the same bits. */
static int
identity_case(const filter_kernel *k, int fw, int fh, int level,
    const geo_ground *m, unsigned seed)
{
	/* the channels in their sorted order, as a header has them */
	const fqm_layout L = { { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 }, 12, 10, 11 };
	int w0 = level > 0 ? ((fw - 2) << level) + 2 : fw;
	int h0 = level > 0 ? ((fh - 2) << level) + 2 : fh, bad = 0;
	filter_state f, g;
	ref_state R;
	float *row = malloc((size_t)fw * 13 * sizeof *row), *out, *want;
	fqm_vertex *fine = malloc((size_t)fw * sizeof *fine), *cr, *cv;

	if (filter_init(&f, k, level, fw, fh, w0, h0, m, NULL) < 0 ||
	    filter_init(&g, k, level, fw, fh, w0, h0, m, NULL) < 0 ||
	    filter_init(&R.f, k, level, fw, fh, w0, h0, m, NULL) < 0)
		return 1;
	R.ring = calloc((size_t)R.f.nring * R.f.cw, sizeof *R.ring);
	out = malloc((size_t)f.cw * 13 * sizeof *out);
	want = malloc((size_t)f.cw * 13 * sizeof *want);
	cr = malloc((size_t)f.cw * sizeof *cr);
	cv = malloc((size_t)f.cw * sizeof *cv);
	for (int y = 0; y < f.ch; y++) {
		while (!filter_ready(&f)) {
			for (int i = 0; i < fw * 13; i++)
				row[i] = any_float(&seed);
			for (int i = 0; i < fw; i++) /* V: 0, 1 or between */
				row[11 * fw + i] = fabsf(row[11 * fw + i]) > 1 ?
				    1 : fabsf(row[11 * fw + i]);
			fqm_decode(&L, row, fw, fine);
			filter_push_row(&f, &L, row);
			filter_push(&g, fine);
			ref_push(&R, fine);
		}
		filter_pull_row(&f, &L, out);
		filter_pull(&g, cv);
		ref_pull(&R, cr);
		fqm_encode(&L, cr, f.cw, want);
		bad += memcmp(out, want, (size_t)f.cw * 13 * sizeof *out) != 0;
		bad += memcmp(cv, cr, (size_t)f.cw * sizeof *cr) != 0;
	}
	filter_free(&f), filter_free(&g), filter_free(&R.f);
	free(R.ring), free(row), free(fine), free(out), free(want), free(cr);
	free(cv);
	return bad;
}

static void
test_identity(void)
{
	static const int sizes[][2] = { { 2, 5 }, { 3, 3 }, { 5, 2 },
		{ 4, 6 }, { 8, 9 }, { 9, 8 }, { 37, 23 }, { 64, 7 } };
	geo_ground m[2];
	georef g;
	int bad = 0, n = 0;
	unsigned seed = 11;

	/* a per-row metric whose rows differ (as a geographic DEM's do) */
	geo_ground_const(&m[0], 1024, 30, 20, NULL);
	for (int j = 0; j < 1024; j++) {
		m[0].dx[j] = 30 - 0.01 * j + 1e-3 * urand(&seed);
		m[0].y[j] = j > 0 ? m[0].y[j - 1] + 20 + 1e-3 * j : 0;
	}
	/* a projected lattice: UTM 11N, 30 m cells */
	memset(&g, 0, sizeof g);
	g.model = GEO_PROJECTED, g.epsg = 32611;
	strcpy(g.crs, "EPSG:32611");
	g.origin[0] = 400000, g.origin[1] = 3800000;
	g.step[0] = 30, g.step[1] = -30, g.unit = 1, g.point = 1;
	g.width = g.height = 1024;
	if (geo_ground_init(&m[1], &g, NULL) < 0) {
		ok(0, "UTM metric for the identity test");
		geo_ground_free(&m[0]);
		return;
	}
	for (int mi = 0; mi < 2; mi++)
		for (const filter_kernel *k = filter_kernels; k->name; k++)
			for (size_t s = 0; s < sizeof sizes / sizeof sizes[0];
			    s++)
				for (int level = 0; level <= 3; level += 3) {
					bad += identity_case(k, sizes[s][0],
					    sizes[s][1], level, &m[mi],
					    seed++) != 0;
					n++;
				}
	ok(bad == 0, "filter_push_row / filter_pull_row and filter_push / "
	    "filter_pull give the bits of the filter as first written "
	    "(quadric_translate per tap): %d cases of %d, every kernel, "
	    "per-row and lattice metrics, levels 0 and 3, random rows with "
	    "zeros of both signs, tiny and huge values", n - bad, n);
	geo_ground_free(&m[0]), geo_ground_free(&m[1]);
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
	test_identity();
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
