/* dem_fill.c - void filling for geometry, on the DEM reader's scratch
 * file (float32 rows, NaN for a void), in two streaming passes. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/dem_impl.h"

static int
bit(const unsigned char *b, long long i)
{
	return b[i >> 3] >> (i & 7) & 1;
}

/* Nearest valid sample below, per column, for one row with voids. */
typedef struct {
	float v;
	int32_t row; /* -1: none */
} below;

typedef struct {
	int w, h, fd;               /* fd: the scratch file of dem.c */
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

static long long
zoff(const fillbuf *F, int j)
{
	return (long long)j * F->w * (long long)sizeof(float);
}

/* Pass 1, bottom-up: for every row with voids, store per column the
 * nearest valid sample below it (sparse: rows without voids stay holes). */
static int
pass_up(fillbuf *F, int bfd, tl_err *e)
{
	for (int j = F->h - 1; j >= 0; j--) {
		if (tl_pread(F->fd, F->r, F->w * sizeof(float), zoff(F, j),
		    "scratch file", e) < 0)
			return -1;
		if (bit(F->rowvoid, j) && tl_pwrite(bfd, F->bl, F->w *
		    sizeof(below), (long long)j * F->w * (long long)sizeof(below),
		    "scratch file", e) < 0)
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

/* Pass 2, top-down: fill each row with voids, overwrite it in place and
 * store its validity mask after the rows. */
static int
pass_down(fillbuf *F, int bfd, tl_err *e)
{
	long long moff = (long long)F->h * F->w * (long long)sizeof(float);

	for (int j = 0; j < F->h; j++) {
		if (tl_pread(F->fd, F->r, F->w * sizeof(float), zoff(F, j),
		    "scratch file", e) < 0)
			return -1;
		if (bit(F->rowvoid, j)) {
			if (tl_pread(bfd, F->b, F->w * sizeof(below),
			    (long long)j * F->w * (long long)sizeof(below),
			    "scratch file", e) < 0)
				return -1;
			fill_row(F, j);
			if (tl_pwrite(F->fd, F->f, F->w * sizeof(float),
			    zoff(F, j), "scratch file", e) < 0 ||
			    tl_pwrite(F->fd, F->mask, (size_t)F->w,
			    moff + (long long)j * F->w, "scratch file", e) < 0)
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
int
dem_fill(int fd, const unsigned char *rowvoid, int w, int h, tl_err *e)
{
	fillbuf F;
	int bfd, r;

	if (fillbuf_alloc(&F, w, h, e) < 0)
		return -1;
	F.fd = fd, F.rowvoid = rowvoid;
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
