/* t_fqm0 - level 0 of the FQM streamed from a DEM (fqm0.h): its rows are
 * bit for bit the composition of fqm_band0 and fqm_row0 over the DEM's
 * rows read independently, every level-0 quadric passes through its
 * vertex (b = 0, c = 0), a void corner kills its triangles, and rows out
 * of order are a programming error (assert). */
#include "core/fqm0.h"
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
compose(dem *d, const geo_metric *m, fqm_vertex *want)
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
	geo_metric m;
	fqm0_state s;
	tl_err e = { "" };
	int r = 0, bc = 0, voidq = 1;
	double sx, sy;

	if (d == NULL || geo_metric_init(&m, dem_georef(d), &e) < 0) {
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
	geo_metric_free(&m);
	dem_close(d);
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
		geo_metric m;
		fqm0_state s;
		freopen("/dev/null", "w", stderr);
		if (d == NULL || geo_metric_init(&m, dem_georef(d), NULL) < 0 ||
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
	unlink(path);
	rmdir(dir);
	return tap_done();
}
