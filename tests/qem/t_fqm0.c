/* t_fqm0 - level 0 of the FQM streamed from a DEM (fqm0.h): its rows are
 * bit for bit the composition of fqm_band0 and fqm_row0 over the DEM's
 * rows read independently, every level-0 quadric passes through its
 * vertex (b = 0, c = 0), a void corner kills its triangles, and rows out
 * of order are a programming error (assert). */
#include "qem/fqm0.h"
#include "tap.h"

#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

enum { W = 7, H = 5 };

static char dir[PATH_MAX / 2], path[PATH_MAX];

/* An Esri ASCII grid, 30 m cells, one void at column 0 of row 1. */
static void
write_dem(void)
{
	FILE *f;

	snprintf(path, sizeof path, "%s/small.asc", dir);
	f = fopen(path, "w");
	fprintf(f, "ncols %d\nnrows %d\nxllcorner 500000\nyllcorner 4000000\n"
	    "cellsize 30\nNODATA_value -9999\n", W, H);
	for (int j = 0; j < H; j++) {
		for (int i = 0; i < W; i++)
			fprintf(f, "%d ", i == 0 && j == 1 ? -9999 :
			    (i * 7 + j * 13) % 11 * 3 + 100);
		fputc('\n', f);
	}
	fclose(f);
}

/* The expected rows: every DEM row read first, then the bands. */
static void
compose(dem *d, const geo_ground *m, fqm_vertex *want)
{
	static float z[H][W];
	static unsigned char v[H][W];
	static double band[H][(W - 1) * FQM_BAND0_DOUBLES];

	for (int j = 0; j < H; j++)
		dem_read_row(d, j, z[j], v[j], NULL);
	for (int j = 0; j + 1 < H; j++)
		fqm_band0(z[j], v[j], z[j + 1], v[j + 1], W, j, m, band[j]);
	for (int j = 0; j < H; j++)
		fqm_row0(j > 0 ? band[j - 1] : NULL, j + 1 < H ? band[j] : NULL,
		    z[j], v[j], W, want + (size_t)j * W);
}

static void
test_rows(const dem_opts *o, const char *what)
{
	static fqm_vertex got[H * W], want[H * W];
	dem *d = dem_open(path, o, NULL);
	geo_ground m;
	fqm0_state s;
	tl_err e = { "" };
	int r = 0, bc = 0, voidq = 1;
	double sx, sy;

	if (d == NULL || geo_ground_init(&m, dem_georef(d), &e) < 0) {
		ok(0, "%s: the DEM and its metric (%s)", what, e.msg);
		return;
	}
	geo_scale(&m, 0, 0, &sx, &sy);
	r = fqm0_init(&s, d, &m, &e);
	for (int j = 0; r == 0 && j < H; j++)
		r = fqm0_row(&s, j, got + (size_t)j * W, &e);
	fqm0_free(&s);
	compose(d, &m, want);
	ok(r == 0 && memcmp(got, want, sizeof got) == 0, "%s (%gx%g m "
	    "cells): fqm0 rows are the fqm_band0 / fqm_row0 composition, bit "
	    "for bit", what, sx, sy);
	for (int k = 0; k < H * W; k++) {
		const quadric *q = &got[k].q;
		bc += q->b[0] != 0 || q->b[1] != 0 || q->b[2] != 0 || q->c != 0;
	}
	for (int a = 0; a < 6; a++)
		voidq &= got[W].q.a[a] == 0;
	ok(bc == 0 && got[0].q.a[QUADRIC_A33] > 0, "%s: every level-0 "
	    "quadric passes through its vertex (b = 0, c = 0)", what);
	ok(voidq && got[W].v == 0 && isfinite(got[W].z) && got[W + 1].v == 1 &&
	    got[W + 1].q.a[QUADRIC_A33] > 0, "%s: the void vertex: V 0, a "
	    "filled height %g, no triangle (its quadric 0)", what, got[W].z);
	ok(got[2 * W + 3].z == got[2 * W + 3].s &&
	    got[2 * W + 3].z == (3 * 7 + 2 * 13) % 11 * 3 + 100,
	    "%s: Z and S are the DEM's height", what);
	geo_ground_free(&m);
	dem_close(d);
}

/* fqm_step0 (and _encode) against fqm_band0 / fqm_row0 (and fqm_encode),
 * bit for bit, on grids built to reach every path: widths odd and even
 * (a lone last cell), voids sparse and dense (pairs all real, empty,
 * mixed), flats (zero normals, -0 products), zero-width rows (degenerate
 * triangles), per-row and lattice metrics. */
static int
step0_case(const geo_ground *m, int w, int h, unsigned seed, int voidpct,
    int levels)
{
	float *z = malloc(sizeof *z * (size_t)w * h);
	unsigned char *v = malloc((size_t)w * h);
	double *band = malloc(sizeof *band * (size_t)(w - 1) * FQM_BAND0_DOUBLES *
	    (h - 1));
	double *part = malloc(sizeof *part * 6 * (size_t)w);
	fqm_vertex *want = malloc(sizeof *want * w), *got = malloc(sizeof *got * w);
	float *rw = malloc(sizeof *rw * 13 * (size_t)w);
	float *rg = malloc(sizeof *rg * 13 * (size_t)w);
	fqm_layout L = { { 12, 3, 7, 0, 9, 5, 1, 11, 2, 6 }, 10, 4, 8 };
	int bad = 0;

	for (int k = 0; k < w * h; k++) {
		seed = seed * 1103515245 + 12345;
		z[k] = (float)((seed >> 8) % (unsigned)levels) * 0.75f - 3;
		seed = seed * 1103515245 + 12345;
		v[k] = (int)((seed >> 8) % 100) >= voidpct;
	}
	for (int j = 0; j + 1 < h; j++)
		fqm_band0(z + (size_t)j * w, v + (size_t)j * w,
		    z + (size_t)(j + 1) * w, v + (size_t)(j + 1) * w, w, j, m,
		    band + (size_t)j * (w - 1) * FQM_BAND0_DOUBLES);
	for (int pass = 0; pass < 2; pass++) {
		memset(part, 0, sizeof *part * 6 * (size_t)w);
		for (int j = 0; j < h; j++) {
			const float *z0 = z + (size_t)j * w;
			const unsigned char *v0 = v + (size_t)j * w;
			const float *z1 = j + 1 < h ? z0 + w : NULL;
			const unsigned char *v1 = j + 1 < h ? v0 + w : NULL;
			fqm_row0(j > 0 ? band + (size_t)(j - 1) * (w - 1) *
			    FQM_BAND0_DOUBLES : NULL, j + 1 < h ? band +
			    (size_t)j * (w - 1) * FQM_BAND0_DOUBLES : NULL, z0,
			    v0, w, want);
			if (pass == 0) {
				fqm_step0(z0, v0, z1, v1, w, j, m, part, got);
				bad += memcmp(got, want, sizeof *got * w) != 0;
			} else {
				fqm_encode(&L, want, w, rw);
				fqm_step0_encode(z0, v0, z1, v1, w, j, m, part,
				    &L, rg);
				bad += memcmp(rw, rg, sizeof *rg * 13 * w) != 0;
			}
		}
	}
	free(z), free(v), free(band), free(part), free(want), free(got);
	free(rw), free(rg);
	return bad;
}

static void
test_step0(void)
{
	static const int widths[] = { 3, 4, 5, 6, 9, 40, 67 };
	static const int voids[] = { 0, 5, 40, 80, 100 };
	geo_ground m[3];
	georef g;
	tl_err e = { "" };
	int bad = 0, cases = 0, ok3;

	ok3 = geo_ground_const(&m[0], 9, 30, 20, &e) == 0 &&
	    geo_ground_const(&m[1], 9, 30, 20, &e) == 0;
	/* zero-width cells: flat ones are degenerate triangles */
	if (ok3)
		m[1].dx[2] = m[1].dx[3] = m[1].dx[7] = 0;
	memset(&g, 0, sizeof g);
	g.model = GEO_PROJECTED;
	g.epsg = 32611;
	strcpy(g.crs, "EPSG:32611");
	g.origin[0] = 384000.5, g.origin[1] = 3795000.25;
	g.step[0] = 10, g.step[1] = -10;
	g.unit = 1;
	g.width = 67, g.height = 9;
	ok3 = ok3 && geo_ground_init(&m[2], &g, &e) == 0 && !m[2].per_row;
	if (!ok(ok3, "metrics for fqm_step0 (%s)", e.msg))
		return;
	for (int k = 0; k < 3; k++)
		for (size_t wi = 0; wi < sizeof widths / sizeof *widths; wi++)
			for (size_t vi = 0; vi < sizeof voids / sizeof *voids;
			    vi++)
				for (int levels = 2; levels <= 1000;
				    levels *= 31) {
					bad += step0_case(&m[k], widths[wi], 9,
					    (unsigned)(wi * 131 + vi * 7 + levels),
					    voids[vi], levels) != 0;
					cases++;
				}
	ok(bad == 0, "fqm_step0 and fqm_step0_encode: fqm_row0 of fqm_band0 "
	    "and its fqm_encode bit for bit (%d of %d grids differ: widths 3 "
	    "to 67, 0 to 100%% voids, flats, zero-width rows, per-row and "
	    "UTM metrics)", bad, cases);
	for (int k = 0; k < 3; k++)
		geo_ground_free(&m[k]);
}

/* fqm0_row asserts that rows come in order. */
static void
test_order(void)
{
#ifndef NDEBUG
	int st;
	pid_t pid;

	fflush(stdout);
	if ((pid = fork()) == 0) {
		dem *d = dem_open(path, NULL, NULL);
		fqm_vertex out[W];
		geo_ground m;
		fqm0_state s;
		freopen("/dev/null", "w", stderr);
		if (d == NULL || geo_ground_init(&m, dem_georef(d), NULL) < 0 ||
		    fqm0_init(&s, d, &m, NULL) < 0)
			_exit(3);
		fqm0_row(&s, 0, out, NULL);
		fqm0_row(&s, 2, out, NULL); /* row 1 skipped */
		_exit(0);
	}
	waitpid(pid, &st, 0);
	ok(WIFSIGNALED(st) && WTERMSIG(st) == SIGABRT, "fqm0_row: a row out "
	    "of order fails its assertion");
#endif
}

int
main(void)
{
	const char *t = getenv("TMPDIR");
	dem_opts o = { 0 };

	snprintf(dir, sizeof dir, "%s/t_fqm0.XXXXXX", t && *t ? t : "/tmp");
	if (mkdtemp(dir) == NULL) {
		perror(dir);
		return 1;
	}
	write_dem();
	test_rows(NULL, "7x5 grid");
	o.cell[0] = 30, o.cell[1] = 20;
	test_rows(&o, "7x5 grid, -s 30,20");
	test_order();
	test_step0();
	unlink(path);
	rmdir(dir);
	return tap_done();
}
