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
 * dem_fill_up, dem_fill_down and dem_fill_free of the first: no loop
 * runs between them (t_loops.sh).
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

/* The rows are read and written a chunk of up to R adjacent rows per
 * pread or pwrite, R = DEM_FILLBYTES / (17 w), at least 1: per row of a
 * chunk 4 w bytes raw, 4 w filled, up to 8 w of "below" records, w of
 * mask. The records are those of the void runs down the columns, one a
 * run (and one a chunk), not one a void sample: for a DEM of sea or
 * large voids a few MiB, where a record per sample of each row with
 * voids wrote and read back twice the DEM's size. */
#define DEM_FILLBYTES (4LL << 20)

typedef struct {
	int w, h, R;
	dem_fill_band io;       /* where the rows come from and go */
	int whole;              /* dem_fill: in place, masks by row number */
	long long k;            /* the next mask's number */
	const unsigned char *rowvoid; /* one bit per row: it has voids */
	float *r, *f, *av;      /* raw row, filled row, nearest valid above */
	int32_t *arow, *left;   /* its row (-1 none); nearest valid to the left */
	below *b, *bl;          /* this row's "below" records; running state
	                         * (pass_up), the runs' records (pass_down) */
	unsigned char *mask;
	/* a chunk's rows: raw and filled by row, its below records (and
	 * their count after them) and the masks of its rows with voids one
	 * after another; r, f, mask point in */
	float *rr, *ff;
	below *bb;
	unsigned char *mm;
} fillbuf;

/* The chunk's buffers are mapped (dem_map), the rows' malloc'd. */
static void
fillbuf_free(fillbuf *F)
{
	size_t n = (size_t)F->w * F->R;

	dem_unmap(F->rr, n * sizeof(float));
	dem_unmap(F->ff, n * sizeof(float));
	dem_unmap(F->bb, (n + 1) * sizeof(below));
	dem_unmap(F->mm, n);
	free(F->av), free(F->arow), free(F->left), free(F->bl);
}

static int
fillbuf_alloc(fillbuf *F, int w, int h, int rows, tl_err *e)
{
	size_t n = (size_t)w;
	long long R = DEM_FILLBYTES / (17LL * w);

	memset(F, 0, sizeof *F);
	F->w = w, F->h = h;
	F->R = R < 1 ? 1 : R > rows ? rows : (int)R;
	F->rr = dem_map(n * F->R * sizeof(float), e);
	F->ff = F->rr ? dem_map(n * F->R * sizeof(float), e) : NULL;
	F->av = tl_alloc(n, sizeof(float), e);
	F->arow = tl_alloc(n, sizeof(int32_t), e);
	F->left = tl_alloc(n, sizeof(int32_t), e);
	F->bb = F->ff ? dem_map((n * F->R + 1) * sizeof(below), e) : NULL;
	F->bl = tl_alloc(n, sizeof(below), e);
	F->mm = F->bb ? dem_map(n * F->R, e) : NULL;
	if (!F->rr || !F->ff || !F->av || !F->arow || !F->left || !F->bb ||
	    !F->bl || !F->mm) {
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

/* The rows with voids of lo .. hi-1, size bytes each, read (wr 0) or
 * written (wr 1) in one call per run of adjacent ones: row j at
 * off + (j - base) size in fd, in buf one after another (compact) or
 * at (j - lo) size. */
static int
void_runs(const fillbuf *F, int wr, int fd, void *buf, size_t size,
    int compact, int lo, int hi, long long off, int base, const char *what,
    tl_err *e)
{
	char *p = buf;

	for (int j = lo, t; j < hi; j = t) {
		for (t = j; t < hi && dem_bit(F->rowvoid, t); t++)
			;
		if (t == j) {
			t++;
			continue;
		}
		if (!compact)
			p = (char *)buf + (size_t)(j - lo) * size;
		if ((wr ? tl_pwrite(fd, p, (size_t)(t - j) * size, off +
		    (long long)(j - base) * size, what, e) : tl_pread(fd, p,
		    (size_t)(t - j) * size, off + (long long)(j - base) * size,
		    what, e)) < 0)
			return -1;
		p += (size_t)(t - j) * size;
	}
	return 0;
}

/* Rows lo .. hi-1 read raw into the chunk. */
static int
read_chunk(fillbuf *F, int lo, int hi, tl_err *e)
{
	return tl_pread(F->io.in, F->rr, (size_t)(hi - lo) * F->w *
	    sizeof(float), F->io.zin + zoff(F, lo), F->io.win, e);
}

/* The chunks both passes take: R rows each from y0, the last shorter;
 * chunk k's first row. */
static int
chunk_lo(const fillbuf *F, long long k)
{
	return (int)(F->io.y0 + k * F->R);
}

static long long
chunks(const fillbuf *F)
{
	return (F->io.y1 - F->io.y0 + (long long)F->R - 1) / F->R;
}

/* Whether void sample i of row j starts a "below" record: row j is the
 * first of its chunk, or the sample above it is valid. Down a column,
 * the voids from one record's sample to the next valid sample all have
 * the same nearest valid sample below, so it is stored once. prev: row
 * j - 1 (unused when j is the chunk's first). */
static int
starts(const float *prev, int j, int lo, int i)
{
	return j == lo || !isnan(prev[i]);
}

/* Pass 1, bottom-up: per chunk, the records of its rows with voids, in
 * row order, column order within a row, then their count (a record
 * whose row is it), appended to bfd; *end: the bytes written. */
static int
pass_up(fillbuf *F, int bfd, long long *end, tl_err *e)
{
	size_t cap = (size_t)F->w * F->R;

	*end = 0;
	for (long long k = chunks(F) - 1; k >= 0; k--) {
		int lo = chunk_lo(F, k), hi = chunk_lo(F, k + 1);
		size_t top = cap;
		hi = hi < F->io.y1 ? hi : F->io.y1;
		if (read_chunk(F, lo, hi, e) < 0)
			return -1;
		/* rows and columns backwards, the records from the end */
		for (int j = hi - 1; j >= lo; j--) {
			const float *prev = j > lo ? F->rr +
			    (size_t)(j - 1 - lo) * F->w : NULL;
			int v = dem_bit(F->rowvoid, j);
			F->r = F->rr + (size_t)(j - lo) * F->w;
			for (int i = F->w - 1; i >= 0; i--)
				if (!isnan(F->r[i]))
					F->bl[i].v = F->r[i], F->bl[i].row = j;
				else if (v && starts(prev, j, lo, i))
					F->bb[--top] = F->bl[i];
		}
		F->bb[cap] = (below){ 0, (int32_t)(cap - top) };
		if (tl_pwrite(bfd, F->bb + top, (cap - top + 1) * sizeof(below),
		    *end, "scratch file", e) < 0)
			return -1;
		*end += (long long)(cap - top + 1) * sizeof(below);
	}
	return 0;
}

/* The records of the next chunk top-down, the last pass_up wrote before
 * *end, into F->bb. */
static int
records(fillbuf *F, int bfd, long long *end, tl_err *e)
{
	below n;

	if (tl_pread(bfd, &n, sizeof n, *end - (long long)sizeof n,
	    "scratch file", e) < 0)
		return -1;
	*end -= (long long)(n.row + 1) * sizeof(below);
	return tl_pread(bfd, F->bb, (size_t)n.row * sizeof(below), *end,
	    "scratch file", e);
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

/* Rows lo .. hi-1, filled in the chunk, and the masks of those with
 * voids: in place in dem.c's scratch file (the rows with voids only),
 * the masks by row number; in a filled DEM file every row,
 * little-endian (swapped by pass_down), the masks by rank from k. */
static int
put_chunk(fillbuf *F, int lo, int hi, long long k, tl_err *e)
{
	size_t row = F->w * sizeof(float);

	if (F->whole)
		return void_runs(F, 1, F->io.out, F->ff, row, 0, lo, hi,
		    F->io.zout, 0, F->io.wout, e) < 0 ||
		    void_runs(F, 1, F->io.out, F->mm, (size_t)F->w, 1, lo, hi,
		    F->io.moff, 0, F->io.wout, e) < 0 ? -1 : 0;
	if (tl_pwrite(F->io.out, F->ff, (size_t)(hi - lo) * row, F->io.zout +
	    zoff(F, lo), F->io.wout, e) < 0)
		return -1;
	return F->k > k ? tl_pwrite(F->io.out, F->mm, (size_t)(F->k - k) *
	    F->w, F->io.moff + k * F->w, F->io.wout, e) : 0;
}

/* Pass 2, top-down: fill each row with voids, write it and its validity
 * mask; rows without voids are copied unless filled in place. F->bl,
 * pass_up's done, holds per column the record of the void run at hand. */
static int
pass_down(fillbuf *F, int bfd, long long end, int (*done)(void *, int),
    void *ctx, tl_err *e)
{
	for (long long q = 0; q < chunks(F); q++) {
		long long k = F->k;
		int lo = chunk_lo(F, q), hi = chunk_lo(F, q + 1), c = 0;
		size_t t = 0;
		hi = hi < F->io.y1 ? hi : F->io.y1;
		if (read_chunk(F, lo, hi, e) < 0 ||
		    records(F, bfd, &end, e) < 0)
			return -1;
		for (int j = lo; j < hi; j++) {
			const float *prev = j > lo ? F->rr +
			    (size_t)(j - 1 - lo) * F->w : NULL;
			F->r = F->rr + (size_t)(j - lo) * F->w;
			F->f = F->ff + (size_t)(j - lo) * F->w;
			if (dem_bit(F->rowvoid, j)) {
				for (int i = 0; i < F->w; i++)
					if (isnan(F->r[i]) &&
					    starts(prev, j, lo, i))
						F->bl[i] = F->bb[t++];
				F->b = F->bl;
				F->mask = F->mm + (size_t)c++ * F->w;
				fill_row(F, j);
				F->k++;
			} else if (!F->whole) {
				memcpy(F->f, F->r, F->w * sizeof(float));
			}
			if (!F->whole)
				le_swap32s(F->f, (size_t)F->w);
			for (int i = 0; i < F->w; i++)
				if (!isnan(F->r[i]))
					F->av[i] = F->r[i], F->arow[i] = j;
		}
		if (put_chunk(F, lo, hi, k, e) < 0)
			return -1;
		if (done != NULL && done(ctx, hi) < 0)
			return tl_fail(e, "void fill: stopped");
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
 * file, once a vertical run of voids, top-down carries the nearest above
 * in memory. Memory O(width), disk O(width * height); deterministic. */
struct dem_filling {
	fillbuf F;
	int bfd;
	long long end;   /* pass_up's records: their bytes */
};

/* The fill's first pass: its buffers, its scratch file, pass_up. */
static dem_filling *
fill_up(const dem_fill_band *b, int whole, const unsigned char *rowvoid,
    int w, int h, tl_err *e)
{
	dem_filling *f = tl_alloc(1, sizeof *f, e);

	if (f == NULL)
		return NULL;
	f->bfd = -1;
	if (fillbuf_alloc(&f->F, w, h, b->y1 - b->y0, e) < 0) {
		free(f);
		return NULL;
	}
	f->F.io = *b, f->F.whole = whole, f->F.k = b->rank;
	f->F.rowvoid = rowvoid;
	/* the nearest valid samples beyond the rows, for a band */
	for (int i = 0; i < w; i++) {
		if (b->above != NULL && b->above[i].row >= 0)
			f->F.av[i] = b->above[i].v, f->F.arow[i] =
			    b->above[i].row;
		if (b->below != NULL)
			f->F.bl[i] = b->below[i];
	}
	if ((f->bfd = tl_scratch(e)) < 0 ||
	    pass_up(&f->F, f->bfd, &f->end, e) < 0) {
		dem_fill_free(f);
		return NULL;
	}
	return f;
}

int
dem_fill_down(dem_filling *f, int (*done)(void *, int), void *ctx,
    tl_err *e)
{
	return pass_down(&f->F, f->bfd, f->end, done, ctx, e);
}

void
dem_fill_free(dem_filling *f)
{
	if (f == NULL)
		return;
	if (f->bfd >= 0)
		close(f->bfd);
	fillbuf_free(&f->F);
	free(f);
}

static int
fill(const dem_fill_band *b, int whole, const unsigned char *rowvoid,
    int w, int h, tl_err *e)
{
	dem_filling *f = fill_up(b, whole, rowvoid, w, h, e);
	int r;

	if (f == NULL)
		return -1;
	r = dem_fill_down(f, NULL, NULL, e);
	dem_fill_free(f);
	return r;
}

dem_filling *
dem_fill_up(int fd, const unsigned char *rowvoid, int w, int h, tl_err *e)
{
	dem_fill_band b = { fd, fd, 0, 0,
	    (long long)h * w * (long long)sizeof(float), 0, 0, h, NULL, NULL,
	    "scratch file", "scratch file" };

	return fill_up(&b, 1, rowvoid, w, h, e);
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
