/* dem_filled.c - filled DEM files (filled(5)): a DEM's converted,
 * void-filled samples and validity saved once (dem_save_filled), so that
 * jobs each needing a window of the DEM read that window only
 * (dem_open_filled) instead of converting and filling all of it again.
 *
 * The layout, little-endian:
 *   0   "TLFILLED"
 *   8   u32 version (1), width W, height H, rows with voids R
 *   24  u64 void samples
 *   32  u64 fingerprint (dem_fingerprint)
 *   40  u64 offset Z of the heights, offset M of the masks
 *   56  u64 FNV-1a of bytes 0 .. 55 and the row bitmap
 *   64  the row bitmap: bit j % 8 of byte j / 8 set when row j has voids
 *   Z   (64 + the bitmap, rounded up to 4096) H rows of W float32
 *   M   (Z + 4WH) the validity masks of the R rows with voids, in row
 *       order, W bytes each (1 valid, 0 void)
 * and the file ends at M + RW. A window of row j is then one pread for
 * its heights and, when the row has voids, one for its mask.
 *
 * The three fill files: dem_voidfill.c the void-fill algorithm,
 * dem_filled.c the filled DEM file (filled(5)), dem_filled_jobs.c that
 * file made in row jobs (filled(5), PARTS). Each calls only those
 * before it and the reader (dem.c, dem_load.c); the reader calls only
 * dem_fill_up, dem_fill_down and dem_fill_free of the first: no loop
 * runs between them (t_loops.sh).
 * Here: the file. */
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dem/dem_impl.h"
#include "base/byteorder.h"
#include "base/outfile.h"

#define FILLED_MAGIC "TLFILLED"
#define FILLED_VERSION 1
#define FILLED_HEAD 64
#define FILLED_ALIGN 4096

/* Where a filled DEM file keeps its heights and masks; rank[k]: the rows
 * with voids before row 64k (which mask is a row's). */
struct dem_file {
	long long zoff, moff;
	char what[256];      /* the file, for messages */
	uint32_t rank[];
};

typedef struct {
	uint32_t version, w, h, vrows;
	uint64_t voids, print, zoff, moff, sum;
} head;

static int file_span(dem *d, int j, int x0, int n, float *z,
    unsigned char *valid, tl_err *e);

/* --- the header ---------------------------------------------------------- */

/* Z and M follow from the size and the rows with voids. */
static void
layout(head *H)
{
	long long nb = ((long long)H->h + 7) / 8;

	H->zoff = (FILLED_HEAD + nb + FILLED_ALIGN - 1) / FILLED_ALIGN *
	    FILLED_ALIGN;
	H->moff = H->zoff + 4ULL * H->w * H->h;
}

static long long
file_size(const head *H)
{
	return (long long)H->moff + (long long)H->vrows * H->w;
}

static void
head_put(unsigned char *b, const head *H)
{
	memcpy(b, FILLED_MAGIC, 8);
	le_put32(b + 8, H->version);
	le_put32(b + 12, H->w);
	le_put32(b + 16, H->h);
	le_put32(b + 20, H->vrows);
	le_put64(b + 24, H->voids);
	le_put64(b + 32, H->print);
	le_put64(b + 40, H->zoff);
	le_put64(b + 48, H->moff);
	le_put64(b + 56, H->sum);
}

static void
head_get(const unsigned char *b, head *H)
{
	H->version = le_get32(b + 8);
	H->w = le_get32(b + 12);
	H->h = le_get32(b + 16);
	H->vrows = le_get32(b + 20);
	H->voids = le_get64(b + 24);
	H->print = le_get64(b + 32);
	H->zoff = le_get64(b + 40);
	H->moff = le_get64(b + 48);
	H->sum = le_get64(b + 56);
}

/* The checksum of the header's first 56 bytes and the bitmap. */
static uint64_t
head_sum(const unsigned char *b, const unsigned char *rowvoid, int h)
{
	return dem_fnv(dem_fnv(DEM_FNV0, b, 56), rowvoid,
	    ((size_t)h + 7) / 8);
}

/* --- saving -------------------------------------------------------------- */

/* Every row's heights, and the masks of the rows with voids: a row at a
 * time whatever the DEM's size. */
static int
write_rows(dem *d, const head *H, int fd, const char *path, tl_err *e)
{
	int w = d->g.width, r = 0;
	float *z = tl_alloc((size_t)w, sizeof *z, e);
	unsigned char *v = tl_alloc((size_t)w, 1, e);
	long long k = 0;

	if (z == NULL || v == NULL)
		r = -1;
	for (int j = 0; j < d->g.height && r == 0; j++) {
		if ((r = dem_read_row(d, j, z, v, e)) < 0)
			break;
		le_swap32s(z, (size_t)w);
		r = tl_pwrite(fd, z, (size_t)w * sizeof *z, (long long)H->zoff +
		    (long long)j * w * (long long)sizeof *z, path, e);
		if (r == 0 && dem_bit(d->rowvoid, j))
			r = tl_pwrite(fd, v, (size_t)w, (long long)H->moff +
			    k++ * w, path, e);
	}
	free(z);
	free(v);
	return r;
}

/* The header and bitmap; H's counts set, its layout and sum made here. */
static int
write_head(int fd, const char *path, head *H, const unsigned char *rowvoid,
    tl_err *e)
{
	unsigned char b[FILLED_HEAD];

	layout(H);
	head_put(b, H);
	H->sum = head_sum(b, rowvoid, (int)H->h);
	head_put(b, H);
	if (tl_pwrite(fd, b, sizeof b, 0, path, e) < 0 ||
	    tl_pwrite(fd, rowvoid, ((size_t)H->h + 7) / 8, FILLED_HEAD, path,
	    e) < 0)
		return -1;
	return 0;
}

static int
write_filled(dem *d, int fd, const char *path, tl_err *e)
{
	head H = { FILLED_VERSION, (uint32_t)d->g.width,
	    (uint32_t)d->g.height, 0, (uint64_t)d->voids, d->print, 0, 0, 0 };

	for (int j = 0; j < d->g.height; j++)
		H.vrows += dem_bit(d->rowvoid, j);
	layout(&H);
	if (write_rows(d, &H, fd, path, e) < 0)
		return -1;
	return write_head(fd, path, &H, d->rowvoid, e);
}

int
dem_filled_head(int fd, const char *path, int w, int h,
    const unsigned char *rowvoid, long long voids, uint64_t print,
    long long *zoff, long long *moff, long long *size, tl_err *e)
{
	head H = { FILLED_VERSION, (uint32_t)w, (uint32_t)h, 0,
	    (uint64_t)voids, print, 0, 0, 0 };

	for (int j = 0; j < h; j++)
		H.vrows += dem_bit(rowvoid, j);
	if (write_head(fd, path, &H, rowvoid, e) < 0)
		return -1;
	*zoff = (long long)H.zoff, *moff = (long long)H.moff;
	*size = file_size(&H);
	return 0;
}

int
dem_save_filled(dem *d, const char *path, tl_err *e)
{
	tl_outfile out;

	if (strcmp(path, "-") == 0)
		return tl_fail(e, "-: a filled DEM file must be a named file");
	if (d->fd < 0 || d->unfilled)
		return tl_fail(e, "%s: cannot save it filled: opened %s",
		    d->what, d->fd < 0 ? "for its header only" :
		    "for a window of columns, unfilled");
	if (tl_out_begin(&out, path, e) < 0)
		return -1;
	if (write_filled(d, out.fd, path, e) < 0) {
		tl_out_abort(&out);
		return -1;
	}
	return tl_out_commit(&out, e);
}

/* --- opening ------------------------------------------------------------- */

/* The header, or why the file is not a filled DEM file. */
static int
read_head(int fd, const char *path, long long size, head *H, tl_err *e)
{
	unsigned char b[FILLED_HEAD];
	long long n = size < FILLED_HEAD ? size : FILLED_HEAD;

	if (n > 0 && tl_pread(fd, b, (size_t)n, 0, path, e) < 0)
		return -1;
	if (n < 8 || memcmp(b, FILLED_MAGIC, 8) != 0)
		return tl_fail(e, "%s: not a filled DEM file (no %s magic; "
		    "dem_save_filled makes them)", path, FILLED_MAGIC);
	if (n < FILLED_HEAD)
		return tl_fail(e, "%s: truncated filled DEM file: %lld bytes, "
		    "its header alone is %d", path, size, FILLED_HEAD);
	head_get(b, H);
	if (H->version != FILLED_VERSION)
		return tl_fail(e, "%s: filled DEM file of version %u, this "
		    "reader knows %d", path, H->version, FILLED_VERSION);
	return 0;
}

/* The size, the layout, the bitmap and the counts agree; rowvoid is the
 * bitmap, read. */
static int
check_head(int fd, const char *path, long long size, const head *H,
    unsigned char *rowvoid, tl_err *e)
{
	long long nb = ((long long)H->h + 7) / 8;
	uint64_t rows = 0;
	unsigned char b[FILLED_HEAD];
	head L = *H;

	layout(&L);
	if (size < FILLED_HEAD + nb)
		return tl_fail(e, "%s: truncated filled DEM file: %lld bytes, "
		    "its header is %lld", path, size, FILLED_HEAD + nb);
	if (tl_pread(fd, rowvoid, (size_t)nb, FILLED_HEAD, path, e) < 0)
		return -1;
	head_put(b, H);
	if (head_sum(b, rowvoid, (int)H->h) != H->sum)
		return tl_fail(e, "%s: damaged filled DEM file: its header's "
		    "checksum does not match", path);
	for (long long j = 0; j < nb * 8; j++)
		rows += (uint64_t)dem_bit(rowvoid, j);
	if (L.zoff != H->zoff || L.moff != H->moff || rows != H->vrows ||
	    H->voids < rows || H->voids > (uint64_t)H->w * H->h)
		return tl_fail(e, "%s: damaged filled DEM file: inconsistent "
		    "header", path);
	if (size != file_size(H))
		return tl_fail(e, "%s: %s filled DEM file: %lld bytes, a %u x "
		    "%u one with %u rows with voids has %lld", path,
		    size < file_size(H) ? "truncated" : "damaged", size, H->w,
		    H->h, H->vrows, file_size(H));
	return 0;
}

/* The file's header against the DEM's, and the rank table. */
static int
match(dem *d, const char *path, const head *H, tl_err *e)
{
	int nr = (d->g.height + 63) / 64;
	struct dem_file *f;
	uint32_t k = 0;

	if (H->w != (uint32_t)d->g.width || H->h != (uint32_t)d->g.height ||
	    H->print != d->print)
		return tl_fail(e, "%s: made from another DEM or other options "
		    "(%u x %u, fingerprint %016llx; %s with these options: "
		    "%d x %d, %016llx)", path, H->w, H->h,
		    (unsigned long long)H->print, d->what, d->g.width,
		    d->g.height, (unsigned long long)d->print);
	if ((f = tl_alloc(1, sizeof *f + (size_t)nr * sizeof f->rank[0],
	    e)) == NULL)
		return -1;
	f->zoff = (long long)H->zoff, f->moff = (long long)H->moff;
	snprintf(f->what, sizeof f->what, "%s", path);
	for (int j = 0; j < d->g.height; j++) {
		if (j % 64 == 0)
			f->rank[j / 64] = k;
		k += dem_bit(d->rowvoid, j);
	}
	d->file = f;
	d->span = file_span;
	d->voids = (long long)H->voids;
	return 0;
}

/* Makes the header-only dem d read its samples from the file path. */
static int
attach(dem *d, const char *path, tl_err *e)
{
	struct stat st;
	head H;

	/* O_NONBLOCK: a FIFO is refused, not waited on */
	if ((d->fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0)
		return tl_failsys(e, "%s: cannot open", path);
	if (fstat(d->fd, &st) != 0)
		return tl_failsys(e, "%s: stat", path);
	if (!S_ISREG(st.st_mode))
		return tl_fail(e, "%s: not a filled DEM file (not a regular "
		    "file)", path);
	if (read_head(d->fd, path, (long long)st.st_size, &H, e) < 0)
		return -1;
	if (H.w < 1 || H.h < 1 || H.w > DEM_MAXDIM || H.h > DEM_MAXDIM)
		return tl_fail(e, "%s: damaged filled DEM file: size %u x %u",
		    path, H.w, H.h);
	if ((d->rowvoid = tl_alloc(H.h / 8 + 1, 1, e)) == NULL ||
	    check_head(d->fd, path, (long long)st.st_size, &H, d->rowvoid,
	    e) < 0)
		return -1;
	return match(d, path, &H, e);
}

dem *
dem_open_filled(const char *dem_path, const dem_opts *o, const char *filled,
    tl_err *e)
{
	dem *d;

	if (strcmp(dem_path, "-") == 0) {
		tl_fail(e, "-: a DEM on stdin cannot be opened again for its "
		    "filled DEM file: name the DEM's file");
		return NULL;
	}
	if (strcmp(filled, "-") == 0) {
		tl_fail(e, "-: a filled DEM file must be a named file");
		return NULL;
	}
	if ((d = dem_open_info(dem_path, o, e)) == NULL)
		return NULL;
	if (attach(d, filled, e) < 0) {
		dem_close(d);
		return NULL;
	}
	return d;
}

/* Row j's rank among the rows with voids: its mask's number. */
static long long
rank(const dem *d, int j)
{
	const unsigned char *b = d->rowvoid;
	long long r = d->file->rank[j >> 6];

	for (int k = (j >> 6) << 3; k < j >> 3; k++)
		r += __builtin_popcount(b[k]);
	return r + __builtin_popcount(b[j >> 3] & ((1u << (j & 7)) - 1));
}

/* The dem's span method (struct dem) on a filled DEM file: row j,
 * columns x0 .. x0+n-1, checked by dem_read_span. */
static int
file_span(dem *d, int j, int x0, int n, float *z, unsigned char *valid,
    tl_err *e)
{
	const struct dem_file *f = d->file;
	long long w = d->g.width;

	if (tl_pread(d->fd, z, (size_t)n * sizeof *z, f->zoff + (j * w + x0) *
	    (long long)sizeof *z, f->what, e) < 0)
		return -1;
	le_swap32s(z, (size_t)n);
	if (valid == NULL)
		return 0;
	if (!dem_bit(d->rowvoid, j)) {
		memset(valid, 1, (size_t)n);
		return 0;
	}
	return tl_pread(d->fd, valid, (size_t)n, f->moff + rank(d, j) * w + x0,
	    f->what, e);
}
