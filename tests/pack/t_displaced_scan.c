/* t_displaced_scan - the displaced levels' exact-error paths
 * (exact_error.c: the batched path, triangles set up for a batch of rows
 * four lanes at once; and a batch whose rows of positions have offsets
 * all 0, level 0 of QEM-3D, through the integer scan: batch_flat) give
 * every local and base error bit for bit as the reference, tri_row a
 * triangle at a time (TL_EXACT_REF), in their AVX2 copy and their plain
 * one (TL_NO_AVX2): rough terrain with voids and steep slopes, offsets
 * up to 0.45 of a cell everywhere, 0 everywhere (of both signs), or 0
 * but in a band of rows (the batches near it take the batched path, the
 * others the scan), levels 0 to 3 (and 5, offsets 0: the scan's long
 * chords only), one thread and shares on three, the whole level and a
 * piece alone (a window not at column 0). */
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geo/levels.h"
#include "pack/level.h"
#include "tap.h"
#include "tmpdir.h"
#include "urand.h"
#include "tiff.h"

static char tmp[PATH_MAX - 64];

/* The level's heights, offsets up to 0.45 of a cell (jitter: metres) in
 * rows band0 .. band1-1, 0 (jitter 0: -0 or +0) elsewhere. */
typedef struct {
	const float *z;
	int w;
	double jitter;
	int band0, band1;
} rows;

static int
row_fn(void *ctx, int r, int c0, int n, float *z, float *x, float *y,
    tl_err *e)
{
	rows *R = ctx;

	memcpy(z, R->z + (size_t)r * R->w + c0, (size_t)n * sizeof *z);
	for (int i = 0; x != NULL && i < n; i++) {
		double j = r >= R->band0 && r < R->band1 ? R->jitter : 0;
		x[i] = rough_offset(j, c0 + i, r, 7);
		y[i] = rough_offset(j, c0 + i, r, 8);
	}
	return 0;
}

/* The blocks' E (gw x gh, the padded grid) and base errors. */
typedef struct {
	int bx, gw;
	float *e;
	double *base;
	int blocks;
	pthread_mutex_t mu;
} sink;

static int
block_fn(void *ctx, const pyramid_block *b, tl_err *e)
{
	sink *s = ctx;

	pthread_mutex_lock(&s->mu);
	s->blocks++;
	s->base[b->bj * s->bx + b->bi] = b->base;
	for (int r = 0; r < BT_SIZE; r++)
		for (int c = 0; c < BT_SIZE; c++)
			s->e[(size_t)(b->bj * BT_CELLS + r) * s->gw +
			    b->bi * BT_CELLS + c] = b->e[r * BT_SIZE + c];
	pthread_mutex_unlock(&s->mu);
	return 0;
}

/* Level `level` of the DEM at path (heights v, w x h), displaced, on
 * threads; piece >= 0: that piece of one block column alone. The
 * environment picks the path. Sizes of E and base into ne, nb. */
static int
run(const char *path, int level, int w, int h, const float *v, int threads,
    int piece, const int band[2], sink *s, size_t *ne, size_t *nb)
{
	static const dem_opts none;
	level_args L = { 0 };
	geo_ground m = { 0 };
	rows R = { v, w, (double)(1 << level), band[0], band[1] };
	level_stats st;
	tl_err e;
	dem *d;
	int by = pyramid_nblocks(h), r = -1;

	s->bx = pyramid_nblocks(w), s->gw = s->bx * BT_CELLS + 1;
	*ne = (size_t)s->gw * (by * BT_CELLS + 1), *nb = (size_t)s->bx * by;
	s->e = calloc(*ne, sizeof *s->e), s->base = calloc(*nb,
	    sizeof *s->base), s->blocks = 0;
	pthread_mutex_init(&s->mu, NULL);
	if ((d = dem_open(path, &none, &e)) == NULL ||
	    geo_ground_init(&m, dem_georef(d), &e) < 0)
		goto done;
	L.level = level, L.size[0] = w, L.size[1] = h, L.displaced = 1;
	L.m = &m, L.threads = threads, L.row = row_fn, L.row_ctx = &R;
	L.block = block_fn, L.block_ctx = s;
	if (piece < 0)
		r = level_run(&L, d, &st, &e);
	else {
		level_piece p[64];
		int n = level_pieces(&L, 1, p, 64);
		r = piece < n ? level_run_piece(&L, &p[piece], d, &st, &e) : -1;
	}
done:
	if (r < 0)
		printf("# %s\n", e.msg);
	if (d != NULL)
		dem_close(d);
	geo_ground_free(&m);
	pthread_mutex_destroy(&s->mu);
	return r;
}

static void
test_level(const char *path, int W, int H, int level, int threads,
    int piece, int b0, int b1)
{
	const int band[2] = { b0, b1 };
	int w = geo_level_size(W, level), h = geo_level_size(H, level);
	float *v = malloc((size_t)w * h * sizeof *v);
	sink ref, fast, plain;
	size_t ne, nb;
	int r;

	for (int j = 0; j < h; j++)
		for (int i = 0; i < w; i++)
			v[(size_t)j * w + i] = rough(i, j, 1 + level) +
			    (float)(3 * (i % 50));
	setenv("TL_EXACT_REF", "1", 1);
	r = run(path, level, w, h, v, threads, piece, band, &ref, &ne, &nb);
	unsetenv("TL_EXACT_REF");
	r |= run(path, level, w, h, v, threads, piece, band, &fast, &ne, &nb);
	setenv("TL_NO_AVX2", "1", 1);
	r |= run(path, level, w, h, v, threads, piece, band, &plain, &ne, &nb);
	unsetenv("TL_NO_AVX2");
	ok(r == 0 && ref.blocks > 0 && fast.blocks == ref.blocks &&
	    memcmp(ref.e, fast.e, ne * sizeof *ref.e) == 0 &&
	    memcmp(ref.base, fast.base, nb * sizeof *ref.base) == 0 &&
	    memcmp(ref.e, plain.e, ne * sizeof *ref.e) == 0 &&
	    memcmp(ref.base, plain.base, nb * sizeof *ref.base) == 0,
	    "level %d, %d thread(s), %s, offsets %s: E and base errors are "
	    "the reference's, bit for bit (%d blocks)", level, threads,
	    piece < 0 ? "whole" : "piece 1 alone", b1 == INT_MAX ?
	    "everywhere" : b1 > b0 ? "0 but in a band" : "all 0", ref.blocks);
	free(ref.e), free(ref.base), free(fast.e), free(fast.base);
	free(plain.e), free(plain.base), free(v);
}

int
main(void)
{
	int W = 400, H = 300;
	float *z = malloc((size_t)W * H * sizeof *z);
	char path[PATH_MAX];

	if (tmpdir_make(tmp, sizeof tmp, "tldisp") < 0) {
		ok(0, "set up");
		return tap_done();
	}
	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++)
			z[(size_t)j * W + i] = (i / 7 + j / 5) % 11 == 3 ?
			    NAN : rough(i, j, 0) + (float)(3 * (i % 50));
	snprintf(path, sizeof path, "%s/rough.tif", tmp);
	if (write_tiff(path, W, H, z) < 0)
		ok(0, "the DEM");
	else {
		for (int level = 0; level <= 3; level++) {
			int h = geo_level_size(H, level);
			test_level(path, W, H, level, 1, -1, 0, INT_MAX);
			test_level(path, W, H, level, 3, -1, 0, INT_MAX);
			test_level(path, W, H, level, 1, -1, 0, 0);
			test_level(path, W, H, level, 3, -1, 0, 0);
			test_level(path, W, H, level, 1, -1, h / 2, h / 2 + 3);
			test_level(path, W, H, level, 3, -1, h / 2, h / 2 + 3);
		}
		/* level 5, offsets all 0: the integer scan with every
		 * chord long (a leaf's 33 samples), a centre at a time */
		test_level(path, W, H, 5, 1, -1, 0, 0);
		test_level(path, W, H, 5, 3, -1, 0, 0);
		test_level(path, W, H, 0, 1, 1, 0, INT_MAX);
		test_level(path, W, H, 0, 1, 1, 0, 0);
		test_level(path, W, H, 0, 1, 1, 100, 103);
	}
	free(z);
	tmpdir_done(tmp);
	return tap_done();
}
