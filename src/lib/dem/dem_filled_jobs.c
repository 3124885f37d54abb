/* dem_filled_jobs.c - a filled DEM file (filled(5)) made in row bands by
 * several jobs, byte for byte the file dem_save_filled writes.
 *
 * A void's left and right neighbours, and the fallback of a void whose
 * row and column hold no valid sample, are in its own row: only the
 * column direction crosses bands, and for it a band needs per column
 * the nearest valid sample above its first row and below its last one.
 * So, beside FILLED:
 *   pass 1, per band   converts its rows, unfilled, into FILLED.raw and
 *                      writes FILLED.s.Y0: per column its first and
 *                      last valid samples, its rows' void flags
 *   join, once         sweeps the states down and up into FILLED.e.Y0
 *                      per band (the nearest valid samples above and
 *                      below it, where its masks start) and writes
 *                      FILLED.tmp's header and row bitmap
 *   pass 2, per band   fills its rows from FILLED.raw into FILLED.tmp,
 *                      then writes FILLED.d.Y0 (done)
 *   commit, once       renames FILLED.tmp to FILLED, removes the rest.
 * The parts are little-endian: jobs may run on different hosts.
 *
 * The three fill files: dem_voidfill.c the void-fill algorithm,
 * dem_filled.c the filled DEM file (filled(5)), dem_filled_jobs.c that
 * file made in row jobs (filled(5), PARTS). Each calls only those
 * before it and the reader (dem.c, dem_load.c); the reader calls only
 * dem_fill_up, dem_fill_down and dem_fill_free of the first: no loop
 * runs between them (t_loops.sh).
 * Here: the jobs. One concern in one file, over 600 lines: the parts'
 * protocol (their names, formats and the four steps that write and read
 * them), which no step can change without the others. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dem/dem_impl.h"
#include "base/byteorder.h"
#include "base/outfile.h"

#define PART_HEAD 64
#define STATE_MAGIC "TLFILLS1"
#define EDGE_MAGIC "TLFILLE1"
#define DONE_MAGIC "TLFILLD1"

/* A band's state (pass 1: n are its voids, v1 and v2 its first and last
 * valid samples per column) or its edges (join: n is its rank, the rows
 * with voids above it; v1 and v2 the nearest valid samples above and
 * below it; zoff, moff FILLED.tmp's layout). flags: a byte per row, 1
 * when it has voids. */
typedef struct {
	int w, h, y0, y1;
	uint64_t n, print, zoff, moff;
	dem_near *v1, *v2;
	unsigned char *flags;
} part;

typedef struct {
	char raw[4096], tmp[4096];
} names;

static void
part_free(part *p)
{
	free(p->v1), free(p->v2), free(p->flags);
}

static int
part_alloc(part *p, int w, int h, int y0, int y1, tl_err *e)
{
	memset(p, 0, sizeof *p);
	p->w = w, p->h = h, p->y0 = y0, p->y1 = y1;
	p->v1 = tl_alloc((size_t)w, sizeof *p->v1, e);
	p->v2 = tl_alloc((size_t)w, sizeof *p->v2, e);
	p->flags = tl_alloc((size_t)(y1 - y0), 1, e);
	if (p->v1 == NULL || p->v2 == NULL || p->flags == NULL) {
		part_free(p);
		return -1;
	}
	for (int i = 0; i < w; i++)
		p->v1[i].row = p->v2[i].row = -1;
	return 0;
}

static size_t
part_size(const part *p)
{
	return PART_HEAD + 16 * (size_t)p->w + (size_t)(p->y1 - p->y0);
}

static int
name_of(char *buf, const char *filled, const char *kind, int y0, tl_err *e)
{
	int n = y0 < 0 ? snprintf(buf, 4096, "%s.%s", filled, kind) :
	    snprintf(buf, 4096, "%s.%s.%d", filled, kind, y0);

	return n < 4096 ? 0 : tl_fail(e, "%s: name too long", filled);
}

static int
names_of(names *N, const char *filled, tl_err *e)
{
	if (strcmp(filled, "-") == 0)
		return tl_fail(e, "-: a filled DEM file must be a named file");
	if (name_of(N->raw, filled, "raw", -1, e) < 0 ||
	    name_of(N->tmp, filled, "tmp", -1, e) < 0)
		return -1;
	return 0;
}

static void
near_put(unsigned char *b, const dem_near *n)
{
	uint32_t u;

	memcpy(&u, &n->v, sizeof u);
	le_put32(b, (uint32_t)n->row);
	le_put32(b + 4, u);
}

static void
near_get(const unsigned char *b, dem_near *n)
{
	uint32_t u = le_get32(b + 4);

	n->row = (int32_t)le_get32(b);
	memcpy(&n->v, &u, sizeof u);
}

/* Written atomically: a part exists whole or not at all. */
static int
part_write(const part *p, const char *magic, const char *path, tl_err *e)
{
	size_t n = part_size(p);
	unsigned char *b = tl_alloc(n, 1, e), *q;
	tl_outfile out;
	int r = -1;

	if (b == NULL)
		return -1;
	memcpy(b, magic, 8);
	le_put32(b + 8, (uint32_t)p->w), le_put32(b + 12, (uint32_t)p->h);
	le_put32(b + 16, (uint32_t)p->y0), le_put32(b + 20, (uint32_t)p->y1);
	le_put64(b + 24, p->n), le_put64(b + 32, p->print);
	le_put64(b + 40, p->zoff), le_put64(b + 48, p->moff);
	q = b + PART_HEAD;
	for (int i = 0; i < p->w; i++, q += 8)
		near_put(q, &p->v1[i]);
	for (int i = 0; i < p->w; i++, q += 8)
		near_put(q, &p->v2[i]);
	memcpy(q, p->flags, (size_t)(p->y1 - p->y0));
	if (tl_out_begin(&out, path, e) == 0) {
		if (tl_pwrite(out.fd, b, n, 0, path, e) < 0)
			tl_out_abort(&out);
		else
			r = tl_out_commit(&out, e);
	}
	free(b);
	return r;
}

/* The whole file at path, of exactly n bytes, or why not. */
static unsigned char *
slurp(const char *path, size_t n, tl_err *e)
{
	unsigned char *b = NULL;
	struct stat st;
	int fd;

	/* O_NONBLOCK: a FIFO in a plan's place is refused, not waited on */
	if ((fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0) {
		if (errno == ENOENT)
			tl_fail(e, "%s: missing (its part has not run)", path);
		else
			tl_failsys(e, "%s: cannot open", path);
		return NULL;
	}
	if (fstat(fd, &st) != 0)
		tl_failsys(e, "%s: stat", path);
	else if (!S_ISREG(st.st_mode))
		tl_fail(e, "%s: not a regular file: remove it and run its part "
		    "again", path);
	else if ((long long)st.st_size != (long long)n)
		tl_fail(e, "%s: %lld bytes, not the %zu of this band's part "
		    "(another band height or DEM?)", path,
		    (long long)st.st_size, n);
	else if ((b = tl_alloc(n, 1, e)) != NULL &&
	    tl_pread(fd, b, n, 0, path, e) < 0) {
		free(b);
		b = NULL;
	}
	close(fd);
	return b;
}

/* Reads into p, allocated by the caller for its band: the part must be
 * of that band and of the same DEM (fingerprint) and options. */
static int
part_read(part *p, const char *magic, const char *path, tl_err *e)
{
	unsigned char *b = slurp(path, part_size(p), e), *q;
	int r = -1;

	if (b == NULL)
		return -1;
	if (memcmp(b, magic, 8) != 0)
		tl_fail(e, "%s: not a %s of a filled DEM file", path,
		    magic[6] == 'S' ? "pass 1 state" : "join's edge part");
	else if (le_get32(b + 8) != (uint32_t)p->w ||
	    le_get32(b + 12) != (uint32_t)p->h ||
	    le_get32(b + 16) != (uint32_t)p->y0 ||
	    le_get32(b + 20) != (uint32_t)p->y1 ||
	    le_get64(b + 32) != p->print)
		tl_fail(e, "%s: made for other rows, another DEM or other "
		    "options (rows %u .. %u of %u x %u)", path, le_get32(b + 16),
		    le_get32(b + 20) - 1, le_get32(b + 8), le_get32(b + 12));
	else
		r = 0;
	if (r == 0) {
		p->n = le_get64(b + 24);
		p->zoff = le_get64(b + 40), p->moff = le_get64(b + 48);
		q = b + PART_HEAD;
		for (int i = 0; i < p->w; i++, q += 8)
			near_get(q, &p->v1[i]);
		for (int i = 0; i < p->w; i++, q += 8)
			near_get(q, &p->v2[i]);
		memcpy(p->flags, q, (size_t)(p->y1 - p->y0));
	}
	free(b);
	return r;
}

/* --- pass 1 -------------------------------------------------------------- */

/* Per column the first valid sample of the band, top-down, and the
 * last, bottom-up: each scan stops once every column has one (a row or
 * two but where whole columns are void). */
static int
scan_band(dem *d, part *p, float *z, tl_err *e)
{
	int left = p->w;

	for (int j = p->y0; j < p->y1 && left > 0; j++) {
		if (dem_read_row(d, j, z, NULL, e) < 0)
			return -1;
		for (int i = 0; i < p->w; i++)
			if (p->v1[i].row < 0 && !isnan(z[i]))
				p->v1[i].v = z[i], p->v1[i].row = j, left--;
	}
	left = p->w;
	for (int j = p->y1 - 1; j >= p->y0 && left > 0; j--) {
		if (dem_read_row(d, j, z, NULL, e) < 0)
			return -1;
		for (int i = 0; i < p->w; i++)
			if (p->v2[i].row < 0 && !isnan(z[i]))
				p->v2[i].v = z[i], p->v2[i].row = j, left--;
	}
	return 0;
}

/* The shared raw file holds every row: bands write only theirs, and may
 * make it in any order, so it is extended, never truncated. */
static int
size_raw(int fd, const char *path, long long n, tl_err *e)
{
	struct stat st;

	if (fstat(fd, &st) != 0)
		return tl_failsys(e, "%s: stat", path);
	if ((long long)st.st_size < n && ftruncate(fd, (off_t)n) != 0)
		return tl_failsys(e, "%s: cannot extend to %lld bytes", path, n);
	return 0;
}

static int
state_of(dem *d, int y0, int y1, const char *spath, tl_err *e)
{
	part p;
	float *z;
	int r = -1;

	if (part_alloc(&p, d->g.width, d->g.height, y0, y1, e) < 0)
		return -1;
	p.n = (uint64_t)d->voids, p.print = d->print;
	for (int j = y0; j < y1; j++)
		p.flags[j - y0] = (unsigned char)dem_bit(d->rowvoid, j);
	if ((z = tl_alloc((size_t)p.w, sizeof *z, e)) != NULL &&
	    scan_band(d, &p, z, e) == 0)
		r = part_write(&p, STATE_MAGIC, spath, e);
	free(z);
	part_free(&p);
	return r;
}

int
dem_fill_pass1(const char *dem_path, const dem_opts *o, const char *filled,
    int y0, int y1, tl_err *e)
{
	char spath[4096];
	names N;
	dem *d;
	int fd, r;

	if (names_of(&N, filled, e) < 0 ||
	    name_of(spath, filled, "s", y0, e) < 0)
		return -1;
	/* O_CREAT without O_EXCL: the bands share it */
	if ((fd = open(N.raw, O_RDWR | O_CREAT | O_CLOEXEC, 0666)) < 0)
		return tl_failsys(e, "%s: cannot open", N.raw);
	d = dem_open_rows(dem_path, o, y0, y1, fd, e);
	close(fd);
	if (d == NULL)
		return -1;
	r = size_raw(d->fd, N.raw, 4LL * d->g.width * d->g.height, e);
	if (r == 0)
		r = state_of(d, y0, y1, spath, e);
	dem_close(d);
	return r;
}

/* --- join ---------------------------------------------------------------- */

typedef struct {
	const char *filled;
	int w, h, band_rows, nb;
	uint64_t print;
	unsigned char *rowvoid;
	long long voids;
	dem_near *run;        /* the sweep's running nearest samples */
	dem_near *below;      /* a band's, read back */
	int bfd;              /* per band its "below" vector, bottom-up */
} join;

static int
band_part(const join *J, part *p, int k, const char *kind, char *path,
    tl_err *e)
{
	int y0 = k * J->band_rows, y1 = y0 + J->band_rows < J->h ?
	    y0 + J->band_rows : J->h;

	if (name_of(path, J->filled, kind, y0, e) < 0 ||
	    part_alloc(p, J->w, J->h, y0, y1, e) < 0)
		return -1;
	p->print = J->print;
	return 0;
}

/* Bottom-up: each band's nearest valid samples below it, and the row
 * bitmap and void count of the whole. */
static int
sweep_up(join *J, tl_err *e)
{
	size_t n = (size_t)J->w * sizeof(dem_near);
	char path[4096];
	part p;

	for (int k = J->nb - 1; k >= 0; k--) {
		if (band_part(J, &p, k, "s", path, e) < 0)
			return -1;
		if (part_read(&p, STATE_MAGIC, path, e) < 0 ||
		    tl_pwrite(J->bfd, J->run, n, (long long)k * n,
		    "scratch file", e) < 0) {
			part_free(&p);
			return -1;
		}
		for (int i = 0; i < J->w; i++)
			if (p.v1[i].row >= 0)
				J->run[i] = p.v1[i];
		for (int j = p.y0; j < p.y1; j++)
			if (p.flags[j - p.y0])
				dem_setbit(J->rowvoid, j);
		J->voids += (long long)p.n;
		part_free(&p);
	}
	return 0;
}

/* Top-down: each band's edges, with the nearest valid samples above it
 * and its first mask's rank. */
static int
sweep_down(join *J, long long zoff, long long moff, tl_err *e)
{
	size_t n = (size_t)J->w * sizeof(dem_near);
	char path[4096], epath[4096];
	uint64_t rank = 0;
	part p;
	int r = 0;

	for (int i = 0; i < J->w; i++)
		J->run[i].row = -1, J->run[i].v = 0;
	for (int k = 0; k < J->nb && r == 0; k++) {
		if (band_part(J, &p, k, "s", path, e) < 0 ||
		    name_of(epath, J->filled, "e", p.y0, e) < 0)
			return -1;
		r = part_read(&p, STATE_MAGIC, path, e);
		if (r == 0)
			r = tl_pread(J->bfd, J->below, n, (long long)k * n,
			    "scratch file", e);
		if (r == 0) {
			part edge = p;
			edge.v1 = J->run, edge.v2 = J->below, edge.n = rank;
			edge.zoff = (uint64_t)zoff, edge.moff = (uint64_t)moff;
			r = part_write(&edge, EDGE_MAGIC, epath, e);
			for (int i = 0; i < J->w; i++)
				if (p.v2[i].row >= 0)
					J->run[i] = p.v2[i];
			for (int j = p.y0; j < p.y1; j++)
				rank += p.flags[j - p.y0];
		}
		part_free(&p);
	}
	return r;
}

/* FILLED.tmp with its final header and bitmap, at its final size; a
 * join run again starts it afresh, so the bands' pass 2 must run again:
 * their done marks go first. */
static int
make_tmp(join *J, const names *N, long long *zoff, long long *moff,
    tl_err *e)
{
	char path[4096];
	long long size;
	int fd, r;

	for (int k = 0; k < J->nb; k++) {
		if (name_of(path, J->filled, "d", k * J->band_rows, e) < 0)
			return -1;
		if (unlink(path) != 0 && errno != ENOENT)
			return tl_failsys(e, "%s: cannot remove", path);
	}
	if ((fd = open(N->tmp, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC,
	    0666)) < 0)
		return tl_failsys(e, "%s: cannot create", N->tmp);
	r = dem_filled_head(fd, N->tmp, J->w, J->h, J->rowvoid, J->voids,
	    J->print, zoff, moff, &size, e);
	if (r == 0 && ftruncate(fd, (off_t)size) != 0)
		r = tl_failsys(e, "%s: cannot size to %lld bytes", N->tmp, size);
	if (close(fd) != 0 && r == 0)
		r = tl_failsys(e, "%s: close", N->tmp);
	return r;
}

static int
join_run(join *J, const names *N, tl_err *e)
{
	long long zoff, moff;

	if (sweep_up(J, e) < 0)
		return -1;
	if (J->voids == (long long)J->w * J->h)
		return tl_fail(e, "%s: no valid samples (every sample is a "
		    "void)", J->filled);
	if (make_tmp(J, N, &zoff, &moff, e) < 0)
		return -1;
	return sweep_down(J, zoff, moff, e);
}

/* The header of the DEM, as every part reads it: its size and the
 * fingerprint its filled DEM file carries. */
static int
dem_head(const char *dem_path, const dem_opts *o, int *w, int *h,
    uint64_t *print, tl_err *e)
{
	dem *d = dem_open_info(dem_path, o, e);

	if (d == NULL)
		return -1;
	*w = d->g.width, *h = d->g.height, *print = d->print;
	dem_close(d);
	return 0;
}

static int
bands_of(int band_rows, int h, int *nb, tl_err *e)
{
	if (band_rows < 1)
		return tl_fail(e, "band height %d: not 1 or more rows",
		    band_rows);
	*nb = (int)(((long long)h + band_rows - 1) / band_rows);
	return 0;
}

int
dem_fill_join(const char *dem_path, const dem_opts *o, const char *filled,
    int band_rows, tl_err *e)
{
	join J = { .filled = filled, .band_rows = band_rows, .bfd = -1 };
	names N;
	int r = -1;

	if (names_of(&N, filled, e) < 0 ||
	    dem_head(dem_path, o, &J.w, &J.h, &J.print, e) < 0 ||
	    bands_of(band_rows, J.h, &J.nb, e) < 0)
		return -1;
	J.rowvoid = tl_alloc((size_t)J.h / 8 + 1, 1, e);
	J.run = tl_alloc((size_t)J.w, sizeof *J.run, e);
	J.below = tl_alloc((size_t)J.w, sizeof *J.below, e);
	if (J.rowvoid != NULL && J.run != NULL && J.below != NULL &&
	    (J.bfd = tl_scratch(e)) >= 0) {
		for (int i = 0; i < J.w; i++)
			J.run[i].row = -1;
		r = join_run(&J, &N, e);
	}
	if (J.bfd >= 0)
		close(J.bfd);
	free(J.rowvoid);
	free(J.run);
	free(J.below);
	return r;
}

/* --- pass 2 -------------------------------------------------------------- */

/* The band's rows, filled, into FILLED.tmp: it reads FILLED.raw and its
 * edges only, so a rerun writes the same bytes. */
static int
fill_band(const part *p, const names *N, tl_err *e)
{
	unsigned char *rowvoid = tl_alloc((size_t)p->h / 8 + 1, 1, e);
	dem_fill_band b = { -1, -1, 0, (long long)p->zoff,
	    (long long)p->moff, (long long)p->n, p->y0, p->y1, p->v1, p->v2,
	    N->raw, N->tmp };
	int r = -1;

	if (rowvoid == NULL)
		return -1;
	for (int j = p->y0; j < p->y1; j++)
		if (p->flags[j - p->y0])
			dem_setbit(rowvoid, j);
	if ((b.in = open(N->raw, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0)
		tl_failsys(e, "%s: cannot open (pass 1 has not run?)", N->raw);
	else if ((b.out = open(N->tmp, O_WRONLY | O_NONBLOCK | O_CLOEXEC)) < 0)
		tl_failsys(e, "%s: cannot open (the join has not run?)",
		    N->tmp);
	else
		r = dem_fill_rows(&b, rowvoid, p->w, p->h, e);
	if (b.out >= 0 && close(b.out) != 0 && r == 0)
		r = tl_failsys(e, "%s: close", N->tmp);
	if (b.in >= 0)
		close(b.in);
	free(rowvoid);
	return r;
}

/* The mark that the band's rows are in FILLED.tmp. */
static int
mark_done(const part *p, const char *path, tl_err *e)
{
	unsigned char b[PART_HEAD] = DONE_MAGIC;
	tl_outfile out;

	le_put32(b + 8, (uint32_t)p->w), le_put32(b + 12, (uint32_t)p->h);
	le_put32(b + 16, (uint32_t)p->y0), le_put32(b + 20, (uint32_t)p->y1);
	le_put64(b + 32, p->print);
	if (tl_out_begin(&out, path, e) < 0)
		return -1;
	if (tl_pwrite(out.fd, b, sizeof b, 0, path, e) < 0) {
		tl_out_abort(&out);
		return -1;
	}
	return tl_out_commit(&out, e);
}

int
dem_fill_pass2(const char *dem_path, const dem_opts *o, const char *filled,
    int y0, int y1, tl_err *e)
{
	char epath[4096], dpath[4096];
	uint64_t print;
	names N;
	part p;
	int w, h, r;

	if (names_of(&N, filled, e) < 0 ||
	    name_of(epath, filled, "e", y0, e) < 0 ||
	    name_of(dpath, filled, "d", y0, e) < 0 ||
	    dem_head(dem_path, o, &w, &h, &print, e) < 0)
		return -1;
	if (y0 < 0 || y0 >= y1 || y1 > h)
		return tl_fail(e, "rows %d .. %d: outside the DEM's 0 .. %d",
		    y0, y1 - 1, h - 1);
	if (part_alloc(&p, w, h, y0, y1, e) < 0)
		return -1;
	p.print = print;
	r = part_read(&p, EDGE_MAGIC, epath, e);
	if (r == 0)
		r = fill_band(&p, &N, e);
	if (r == 0)
		r = mark_done(&p, dpath, e);
	part_free(&p);
	return r;
}

/* --- commit -------------------------------------------------------------- */

/* Every band's pass 2 done, for this DEM and these bands. */
static int
check_done(const char *filled, int w, int h, uint64_t print, int band_rows,
    int nb, tl_err *e)
{
	char path[4096];

	for (int k = 0; k < nb; k++) {
		int y0 = k * band_rows, y1 = y0 + band_rows < h ?
		    y0 + band_rows : h;
		unsigned char *b;
		int ok;
		if (name_of(path, filled, "d", y0, e) < 0 ||
		    (b = slurp(path, PART_HEAD, e)) == NULL)
			return -1;
		ok = memcmp(b, DONE_MAGIC, 8) == 0 &&
		    le_get32(b + 8) == (uint32_t)w &&
		    le_get32(b + 12) == (uint32_t)h &&
		    le_get32(b + 16) == (uint32_t)y0 &&
		    le_get32(b + 20) == (uint32_t)y1 &&
		    le_get64(b + 32) == print;
		free(b);
		if (!ok)
			return tl_fail(e, "%s: not the pass 2 mark of rows %d .. "
			    "%d of this DEM", path, y0, y1 - 1);
	}
	return 0;
}

/* Removes the parts: best effort, the file is already in place. */
static void
remove_parts(const char *filled, const names *N, int band_rows, int nb)
{
	static const char *const kinds[] = { "s", "e", "d" };
	char path[4096];
	tl_err e;

	unlink(N->raw);
	for (int k = 0; k < nb; k++)
		for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
			if (name_of(path, filled, kinds[i], k * band_rows,
			    &e) == 0)
				unlink(path);
}

int
dem_fill_commit(const char *dem_path, const dem_opts *o, const char *filled,
    int band_rows, tl_err *e)
{
	uint64_t print;
	names N;
	dem *d;
	int w, h, nb = 0;

	if (names_of(&N, filled, e) < 0 ||
	    dem_head(dem_path, o, &w, &h, &print, e) < 0 ||
	    bands_of(band_rows, h, &nb, e) < 0 ||
	    check_done(filled, w, h, print, band_rows, nb, e) < 0)
		return -1;
	/* its header, size and fingerprint, as a band job will check them */
	if ((d = dem_open_filled(dem_path, o, N.tmp, e)) == NULL)
		return -1;
	dem_close(d);
	if (rename(N.tmp, filled) != 0)
		return tl_failsys(e, "%s: cannot rename to %s", N.tmp, filled);
	remove_parts(filled, &N, band_rows, nb);
	return 0;
}
