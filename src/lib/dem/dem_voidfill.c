/* dem_voidfill.c - void filling for geometry, on the DEM reader's scratch
 * file (float32 rows, NaN for a void), in two streaming passes; or on a
 * band of rows given the nearest valid samples beyond it (dem_fill_rows,
 * for filled DEM files made in bands: dem_filled_jobs.c), with the same
 * code, so that both give the same bits.
 *
 * The three fill files: dem_voidfill.c the void-fill algorithm,
 * dem_filled.c the filled DEM file (filled(5)), dem_filled_jobs.c that
 * file made in row jobs (filled(5), PARTS). Each calls only those
 * before it and the reader (dem.c, dem_load.c); the reader calls only
 * dem_fill of the first: no loop runs between them (t_loops.sh).
 * Here: the algorithm. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dem/dem_impl.h"
#include "base/byteorder.h"

/* Nearest valid sample below, per column, for one row with voids. */
typedef dem_near below;

typedef struct {
	int w, h;
	dem_fill_band io;       /* where the rows come from and go */
	int whole;              /* dem_fill: in place, masks by row number */
	long long k;            /* the next mask's number */
	const unsigned char *rowvoid; /* one bit per row: it has voids */
	float *r, *f, *av;      /* raw row, filled row, nearest valid above */
	int32_t *arow, *left;   /* its row (-1 none); nearest valid to the left */
	below *b, *bl;          /* this row's "below" records; running state */
	unsigned char *mask;
} fillbuf;

static void
fillbuf_free(fillbuf *F)
{
	free(F->r), free(F->f), free(F->av), free(F->arow), free(F->left);
	free(F->b), free(F->bl), free(F->mask);
}

static int
fillbuf_alloc(fillbuf *F, int w, int h, tl_err *e)
{
	size_t n = (size_t)w;

	memset(F, 0, sizeof *F);
	F->w = w, F->h = h;
	F->r = tl_alloc(n, sizeof(float), e);
	F->f = tl_alloc(n, sizeof(float), e);
	F->av = tl_alloc(n, sizeof(float), e);
	F->arow = tl_alloc(n, sizeof(int32_t), e);
	F->left = tl_alloc(n, sizeof(int32_t), e);
	F->b = tl_alloc(n, sizeof(below), e);
	F->bl = tl_alloc(n, sizeof(below), e);
	F->mask = tl_alloc(n, 1, e);
	if (!F->r || !F->f || !F->av || !F->arow || !F->left || !F->b ||
	    !F->bl || !F->mask) {
		fillbuf_free(F);
		return -1;
	}
	for (int i = 0; i < w; i++)
		F->arow[i] = F->bl[i].row = -1;
	return 0;
}

/* Row j's offset from a file's first row. */
static long long
zoff(const fillbuf *F, int j)
{
	return (long long)j * F->w * (long long)sizeof(float);
}

/* Row j's "below" records in the scratch file bfd. */
static long long
boff(const fillbuf *F, int j)
{
	return (long long)(j - F->io.y0) * F->w * (long long)sizeof(below);
}

/* Pass 1, bottom-up: for every row with voids, store per column the
 * nearest valid sample below it (sparse: rows without voids stay holes). */
static int
pass_up(fillbuf *F, int bfd, tl_err *e)
{
	for (int j = F->io.y1 - 1; j >= F->io.y0; j--) {
		if (tl_pread(F->io.in, F->r, F->w * sizeof(float), F->io.zin +
		    zoff(F, j), F->io.win, e) < 0)
			return -1;
		if (dem_bit(F->rowvoid, j) && tl_pwrite(bfd, F->bl, F->w *
		    sizeof(below), boff(F, j), "scratch file", e) < 0)
			return -1;
		for (int i = 0; i < F->w; i++)
			if (!isnan(F->r[i]))
				F->bl[i].v = F->r[i], F->bl[i].row = j;
	}
	return 0;
}

/* Adds v at distance dist to an inverse-distance weighted sum. */
static void
idw(double *s, double *ws, double v, double dist)
{
	*s += v / dist;
	*ws += 1 / dist;
}

/* Samples whose row and column hold no valid sample at all: weighted by
 * the nearest samples left and right that the first stage filled. */
static void
fill_row_only(fillbuf *F)
{
	int last = -1, next = -1, w = F->w;

	for (int i = 0; i < w; i++) {
		F->left[i] = last;
		if (!isnan(F->f[i]))
			last = i;
	}
	for (int i = w - 1; i >= 0; i--) {
		double s = 0, ws = 0;
		if (!isnan(F->f[i])) {
			next = i;
			continue;
		}
		if (F->left[i] >= 0)
			idw(&s, &ws, F->f[F->left[i]], i - F->left[i]);
		if (next >= 0)
			idw(&s, &ws, F->f[next], next - i);
		F->f[i] = (float)(s / ws); /* ws > 0: see fill() */
	}
}

/* One row with voids: F->r raw, F->b its below records, row j. */
static void
fill_row(fillbuf *F, int j)
{
	int last = -1, next = -1, w = F->w, orphans = 0;

	for (int i = 0; i < w; i++) {
		F->left[i] = last;
		if (!isnan(F->r[i]))
			last = i;
	}
	for (int i = w - 1; i >= 0; i--) {
		double s = 0, ws = 0;
		F->mask[i] = !isnan(F->r[i]);
		if (F->mask[i]) {
			F->f[i] = F->r[i];
			next = i;
			continue;
		}
		if (F->left[i] >= 0)
			idw(&s, &ws, F->r[F->left[i]], i - F->left[i]);
		if (next >= 0)
			idw(&s, &ws, F->r[next], next - i);
		if (F->arow[i] >= 0)
			idw(&s, &ws, F->av[i], j - F->arow[i]);
		if (F->b[i].row >= 0)
			idw(&s, &ws, F->b[i].v, F->b[i].row - j);
		F->f[i] = ws > 0 ? (float)(s / ws) : NAN;
		orphans += ws == 0;
	}
	if (orphans > 0)
		fill_row_only(F);
}

/* Row j, filled in F->f, and its mask: in place in dem.c's scratch
 * file, its mask by row number; in a filled DEM file little-endian, its
 * mask by rank. */
static int
put_row(fillbuf *F, int j, int voids, tl_err *e)
{
	long long m = F->whole ? j : F->k;

	F->k += voids;
	if (!F->whole)
		le_swap32s(F->f, (size_t)F->w);
	if (tl_pwrite(F->io.out, F->f, F->w * sizeof(float), F->io.zout +
	    zoff(F, j), F->io.wout, e) < 0)
		return -1;
	return voids ? tl_pwrite(F->io.out, F->mask, (size_t)F->w,
	    F->io.moff + m * F->w, F->io.wout, e) : 0;
}

/* Pass 2, top-down: fill each row with voids, write it and its validity
 * mask; rows without voids are copied unless filled in place. */
static int
pass_down(fillbuf *F, int bfd, tl_err *e)
{
	for (int j = F->io.y0; j < F->io.y1; j++) {
		if (tl_pread(F->io.in, F->r, F->w * sizeof(float), F->io.zin +
		    zoff(F, j), F->io.win, e) < 0)
			return -1;
		if (dem_bit(F->rowvoid, j)) {
			if (tl_pread(bfd, F->b, F->w * sizeof(below), boff(F, j),
			    "scratch file", e) < 0)
				return -1;
			fill_row(F, j);
			if (put_row(F, j, 1, e) < 0)
				return -1;
		} else if (!F->whole) {
			memcpy(F->f, F->r, F->w * sizeof(float));
			if (put_row(F, j, 0, e) < 0)
				return -1;
		}
		for (int i = 0; i < F->w; i++)
			if (!isnan(F->r[i]))
				F->av[i] = F->r[i], F->arow[i] = j;
	}
	return 0;
}

/* Void filling, for geometry only (dem_read_row's mask keeps voids out of
 * error measures). Each void sample gets the inverse-distance weighted
 * mean (weights 1/d, d in samples) of up to four valid samples: the
 * nearest to its left and to its right in its row, and the nearest above
 * and below in its column, at any distance. A void whose row and column
 * hold no valid sample at all (possible only when its whole row is void)
 * then gets the same weighted mean of the nearest filled samples left and
 * right in its row; one exists, since some column has a valid sample.
 * Every result is a convex combination of valid heights. Two streaming
 * passes: bottom-up records the nearest valid sample below in a scratch
 * file, top-down carries the nearest above in memory. Memory O(width),
 * disk O(width * height); deterministic. */
static int
fill(const dem_fill_band *b, int whole, const unsigned char *rowvoid,
    int w, int h, tl_err *e)
{
	fillbuf F;
	int bfd, r;

	if (fillbuf_alloc(&F, w, h, e) < 0)
		return -1;
	F.io = *b, F.whole = whole, F.k = b->rank, F.rowvoid = rowvoid;
	/* the nearest valid samples beyond the rows, for a band */
	for (int i = 0; i < w; i++) {
		if (b->above != NULL && b->above[i].row >= 0)
			F.av[i] = b->above[i].v, F.arow[i] = b->above[i].row;
		if (b->below != NULL)
			F.bl[i] = b->below[i];
	}
	if ((bfd = tl_scratch(e)) < 0) {
		fillbuf_free(&F);
		return -1;
	}
	r = pass_up(&F, bfd, e);
	if (r == 0)
		r = pass_down(&F, bfd, e);
	close(bfd);
	fillbuf_free(&F);
	return r;
}

int
dem_fill(int fd, const unsigned char *rowvoid, int w, int h, tl_err *e)
{
	dem_fill_band b = { fd, fd, 0, 0,
	    (long long)h * w * (long long)sizeof(float), 0, 0, h, NULL, NULL,
	    "scratch file", "scratch file" };

	return fill(&b, 1, rowvoid, w, h, e);
}

/* A band of rows, filled as dem_fill fills them in the whole DEM: the
 * whole is the band 0 .. h-1 with nothing beyond it. */
int
dem_fill_rows(const dem_fill_band *b, const unsigned char *rowvoid, int w,
    int h, tl_err *e)
{
	if (b->y0 < 0 || b->y0 >= b->y1 || b->y1 > h)
		return tl_fail(e, "rows %d .. %d: outside 0 .. %d", b->y0,
		    b->y1 - 1, h - 1);
	return fill(b, 0, rowvoid, w, h, e);
}
