/* dem.c - DEM input: the dem object, stdin, and the front door to the
 * format adapters (the options are dem_opts.c's). The formats are the
 * adapters' business, each a table of methods (dem_adapter, dem_impl.h)
 * tried in the order of the table here: GDAL reads every raster it
 * knows (dem_gdal.c), a list of DEM files is a mosaic of them
 * (dem_list.c, dem_mosaic.c), OpenImageIO reads the EXRs GDAL 3.6
 * cannot (dem_oiio.c). They convert their samples through the sink
 * they share (dem_load.c), never calling back here.
 *
 * The source is converted once to float32 rows in an anonymous scratch
 * file, voids as NaN. Voids are then filled for geometry (dem_voidfill.c) and
 * the scratch file holds the filled rows followed by a validity mask for
 * each row that has voids, so any row can be read back in any order with
 * O(width) memory. Opened streamed, the fill's second pass, top-down,
 * runs in a thread of its own once the open has returned: a read of a
 * row it has not yet filled waits for it, so that the rows flow to the
 * reader (dem2fqm's level 0, tilepack's) while the rest is filled. A dem may instead read them from a filled DEM file
 * (dem_filled.c sets its span method), which this file does not know. */
#include "dem/dem_impl.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"
#include "geo/vdatum.h"

/* --- input --------------------------------------------------------------- */

/* A DEM on stdin is copied to a file in a private directory, under the
 * name -n gives (so that GDAL recognises N44W072.hgt by its name) or
 * "stdin"; the directory is registered for removal by a signal. */
typedef struct {
	tl_outfile dir;
	char path[4096];
} spool;

static int
spool_stdin(spool *s, const char *name, tl_err *e)
{
	char tmpl[4096];
	const char *b;
	long long n;
	int fd;

	b = name != NULL && strrchr(name, '/') ? strrchr(name, '/') + 1 : name;
	if (b == NULL || *b == '\0' || strcmp(b, ".") == 0 ||
	    strcmp(b, "..") == 0)
		b = "stdin";
	snprintf(tmpl, sizeof tmpl, "%s/dem-stdin", tl_tmpdir());
	if (tl_outdir_begin(&s->dir, tmpl, e) < 0)
		return -1;
	if ((size_t)snprintf(s->path, sizeof s->path, "%s/%s", s->dir.tmp, b) >=
	    sizeof s->path)
		return tl_fail(e, "-n %s: name too long", name);
	if ((fd = open(s->path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC,
	    0600)) < 0)
		return tl_failsys(e, "%s: cannot create", s->path);
	n = tl_copy_fd(STDIN_FILENO, "stdin: read", fd, 0, "stdin spool", e);
	close(fd);
	if (n == 0)
		return tl_fail(e, "stdin: empty");
	return n < 0 ? -1 : 0;
}

/* The adapters, in the order they are tried on the inputs they take. */
static const dem_adapter *const adapters[] = {
	&dem_gdal_adapter, &dem_list_adapter, &dem_oiio_adapter,
};

/* A named file: refuse what cannot be a raster before GDAL guesses, and
 * tell by the first bytes an EXR, a format GDAL reads that we know by
 * its magic (so that GDAL's refusal means damage), or nothing. */
int
dem_check_file(const char *path, enum dem_input *kind, tl_err *e)
{
	unsigned char m[8];
	struct stat st;
	ssize_t n;
	int fd;

	*kind = DEM_IN_NONE;
	/* O_NONBLOCK: a FIFO's open must not wait for a writer */
	if ((fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0)
		return tl_failsys(e, "%s: cannot open", path);
	if (fstat(fd, &st) != 0) {
		close(fd);
		return tl_failsys(e, "%s: stat", path);
	}
	if (S_ISDIR(st.st_mode)) {
		close(fd);
		return tl_fail(e, "%s: is a directory", path);
	}
	/* GDAL would read a FIFO or a device forever, or seek in vain */
	if (!S_ISREG(st.st_mode)) {
		close(fd);
		return tl_fail(e, "%s: not a regular file (%s): a DEM is read "
		    "from a file, or from standard input as -", path,
		    S_ISFIFO(st.st_mode) ? "a FIFO" : S_ISSOCK(st.st_mode) ?
		    "a socket" : "a device");
	}
	do
		n = pread(fd, m, sizeof m, 0);
	while (n < 0 && errno == EINTR);
	close(fd);
	if (n < 0)
		return tl_failsys(e, "%s: read", path);
	if (n == 0)
		return tl_fail(e, "%s: empty file", path);
	if (n >= 4 && memcmp(m, "\x76\x2f\x31\x01", 4) == 0)
		*kind = DEM_IN_EXR;
	else if (n >= 4 && (memcmp(m, "II*\0", 4) == 0 ||
	    memcmp(m, "MM\0*", 4) == 0 || memcmp(m, "II+\0", 4) == 0 ||
	    memcmp(m, "MM\0+", 4) == 0 ||
	    (n == 8 && memcmp(m, "\x89PNG\r\n\x1a\n", 8) == 0)))
		*kind = DEM_IN_KNOWN;
	return 0;
}

/* Each adapter that takes the input, in turn, until one reads it: GDAL
 * reads every format it knows but EXR, then a list of DEM files is
 * tried on what no magic tells, then OpenImageIO for the few formats
 * only it reads (EXR). base: as dem_adapter's read. */
static int
read_any(dem_load *L, georef *g, const char *path, const char *base,
    const dem_opts *o, tl_err *e)
{
	enum dem_input kind = DEM_IN_VSI;
	int r;

	/* GDAL's virtual file systems (/vsizip/...): GDAL's alone */
	if (strncmp(path, "/vsi", 4) != 0 && dem_check_file(path, &kind, e) < 0)
		return -1;
	for (size_t k = 0; k < sizeof adapters / sizeof adapters[0]; k++)
		if ((adapters[k]->takes & 1u << kind) &&
		    (r = adapters[k]->read(L, g, path, base, kind, o, e)) <= 0)
			return r;
	if (kind == DEM_IN_VSI)
		return tl_fail(e, "%s: not a raster GDAL reads", L->what);
	if (kind == DEM_IN_KNOWN)
		return tl_fail(e, "%s: truncated or corrupt (GDAL cannot open "
		    "it)", L->what);
	return tl_fail(e, "%s: not a raster (any format GDAL reads, "
	    "or EXR) nor a list of DEM files%s", L->what,
	    strcmp(L->what, "stdin") == 0 ?
	    "; a format GDAL knows by its file name (an .hgt) needs "
	    "that name on stdin: -n NAME" : "");
}

/* A failure of the anonymous scratch file (conversion, fill) names its
 * directory and, when it is full or a limit is met, what to do: the copy
 * takes 4 bytes a sample, the fill up to 9 more (nearest samples, masks)
 * for each sample of a row with voids. */
static void
scratch_note(long long w, long long h, int voids, tl_err *e)
{
	const char *dir = tl_tmpdir();
	char m[sizeof e->msg];
	int full;

	if (strncmp(e->msg, "scratch file", 12) != 0)
		return;
	full = strstr(e->msg, strerror(ENOSPC)) != NULL ||
	    strstr(e->msg, strerror(EDQUOT)) != NULL ||
	    strstr(e->msg, strerror(EFBIG)) != NULL;
	snprintf(m, sizeof m, "%s", e->msg + 12);
	tl_fail(e, "scratch file in %.200s%s%s%lld%s", dir, m, full ?
	    " (it needs up to " : "", full ? (w * h * (voids ? 13 : 4) >>
	    20) + 1 : 0, full ? " MiB: set TMPDIR to a directory with room, "
	    "or raise ulimit -f)" : "");
}

/* --- the fill's second pass, beside the readers -------------------------- */

struct dem_async {
	pthread_mutex_t mu;
	pthread_cond_t cv;
	pthread_t th;
	dem_filling *f;
	long long w, h;
	int rows;        /* rows 0 .. rows-1 filled and in place */
	int failed, stop;
	tl_err err;      /* the failure, told to every read after it */
};

static void scratch_note(long long w, long long h, int voids, tl_err *e);

/* dem_fill_down's done: rows 0 .. n-1 may be read; -1 once dem_close
 * wants it stopped. */
static int
filled(void *ctx, int n)
{
	struct dem_async *a = ctx;
	int stop;

	pthread_mutex_lock(&a->mu);
	a->rows = n;
	stop = a->stop;
	pthread_cond_broadcast(&a->cv);
	pthread_mutex_unlock(&a->mu);
	return stop ? -1 : 0;
}

static void *
fill_thread(void *arg)
{
	struct dem_async *a = arg;
	tl_err e = { 0 };
	int r = dem_fill_down(a->f, filled, a, &e);

	if (r < 0)
		scratch_note(a->w, a->h, 1, &e);
	pthread_mutex_lock(&a->mu);
	if (r < 0)
		a->failed = 1, a->err = e;
	else
		a->rows = (int)a->h;
	pthread_cond_broadcast(&a->cv);
	pthread_mutex_unlock(&a->mu);
	return NULL;
}

/* The first pass, then the second in a thread (no signal taken there:
 * they stay the caller's) when behind, or here (also when no thread can
 * be started). */
static int
fill(dem *d, long long w, long long h, int behind, tl_err *e)
{
	struct dem_async *a;
	sigset_t all, old;
	dem_filling *f;
	int r;

	if ((f = dem_fill_up(d->fd, d->rowvoid, (int)w, (int)h, e)) == NULL)
		return -1;
	if (behind && (a = calloc(1, sizeof *a)) != NULL) {
		pthread_mutex_init(&a->mu, NULL);
		pthread_cond_init(&a->cv, NULL);
		a->f = f, a->w = w, a->h = h;
		sigfillset(&all);
		pthread_sigmask(SIG_BLOCK, &all, &old);
		r = pthread_create(&a->th, NULL, fill_thread, a);
		pthread_sigmask(SIG_SETMASK, &old, NULL);
		if (r == 0) {
			d->fill = a;
			return 0;
		}
		pthread_cond_destroy(&a->cv);
		pthread_mutex_destroy(&a->mu);
		free(a);
	}
	r = dem_fill_down(f, NULL, NULL, e);
	dem_fill_free(f);
	return r;
}

/* Waits until rows 0 .. n-1 are filled: 0, or -1 with the fill's
 * failure. */
static int
fill_wait(dem *d, int n, tl_err *e)
{
	struct dem_async *a = d->fill;
	int r = 0;

	pthread_mutex_lock(&a->mu);
	while (!a->failed && a->rows < n)
		pthread_cond_wait(&a->cv, &a->mu);
	if (a->failed)
		*e = a->err, r = -1;
	pthread_mutex_unlock(&a->mu);
	return r;
}

/* Stops the fill where it is and waits for its thread. */
static void
fill_end(dem *d)
{
	struct dem_async *a = d->fill;

	if (a == NULL)
		return;
	pthread_mutex_lock(&a->mu);
	a->stop = 1;
	pthread_mutex_unlock(&a->mu);
	pthread_join(a->th, NULL);
	dem_fill_free(a->f);
	pthread_cond_destroy(&a->cv);
	pthread_mutex_destroy(&a->mu);
	free(a);
	d->fill = NULL;
}

/* info: the header only; cols (2 ints, or NULL): only those columns;
 * rows (2 ints and an fd, or NULL): only those rows, into that file;
 * behind: the fill's second pass in a thread (dem_open_streamed) */
static dem *
open_dem(const char *path, const dem_opts *o, int info, const int *cols,
    const int *rows, int behind, tl_err *e)
{
	static const dem_opts none;
	spool sp = { { NULL, NULL, -1 }, "" };
	dem_load L = { 0 };
	dem *d;
	int r;

	if (o == NULL)
		o = &none;
	if ((d = tl_alloc(1, sizeof *d, e)) == NULL)
		return NULL;
	d->fd = L.fd = -1;
	L.info = info;
	if (cols != NULL)
		L.cx0 = cols[0], L.cx1 = cols[1], d->unfilled = 1;
	if (rows != NULL) {
		L.cy0 = rows[0], L.cy1 = rows[1], d->unfilled = 1;
		if (rows[2] >= 0 &&
		    (L.fd = d->fd = fcntl(rows[2], F_DUPFD_CLOEXEC, 0)) < 0) {
			tl_failsys(e, "%s: dup", path);
			free(d);
			return NULL;
		}
	}
	dem_name(strcmp(path, "-") == 0 ? "stdin" : path, d->what);
	L.what = d->what;
	if (strcmp(path, "-") == 0) {
		r = spool_stdin(&sp, o->hgt_name, e);
		/* a list on stdin: relative to the current directory */
		if (r == 0)
			r = read_any(&L, &d->g, sp.path, ".", o, e);
		if (sp.dir.tmp != NULL)
			tl_outdir_abort(&sp.dir);
	} else {
		r = read_any(&L, &d->g, path, NULL, o, e);
	}
	free(L.seg);
	dem_unmap(L.band, L.bandcap * sizeof(float));
	vdatum_close(L.vd);
	d->fd = L.fd;
	d->rowvoid = L.rowvoid;
	d->voids = info ? -1 : L.voids;
	d->zunit = L.zunit;
	d->print = L.print;
	d->cx0 = L.cx0, d->cw = L.cx1 - L.cx0;
	d->cy0 = L.cy0, d->cy1 = L.cy1;
	/* a window may be all voids, and is not filled: filling reaches
	 * across the whole DEM */
	if (r == 0 && !info && cols == NULL && rows == NULL &&
	    L.voids == (long long)L.w * L.h)
		r = tl_fail(e, "%s: no valid samples (every sample is a void)",
		    d->what);
	if (r == 0 && !info && cols == NULL && rows == NULL && L.voids > 0)
		r = fill(d, L.w, L.h, behind, e);
	if (r < 0)
		scratch_note(L.w, L.h, L.voids > 0, e);
	if (r < 0) {
		dem_close(d);
		return NULL;
	}
	return d;
}

dem *
dem_open(const char *path, const dem_opts *o, tl_err *e)
{
	return open_dem(path, o, 0, NULL, NULL, 0, e);
}

dem *
dem_open_streamed(const char *path, const dem_opts *o, tl_err *e)
{
	return open_dem(path, o, 0, NULL, NULL, 1, e);
}

dem *
dem_open_cols(const char *path, const dem_opts *o, int x0, int x1,
    tl_err *e)
{
	return open_dem(path, o, 0, (const int[]){ x0, x1 }, NULL, 0, e);
}

dem *
dem_open_window(const char *path, const dem_opts *o, int x0, int x1, int y0,
    int y1, tl_err *e)
{
	return open_dem(path, o, 0, (const int[]){ x0, x1 },
	    (const int[]){ y0, y1, -1 }, 0, e);
}

dem *
dem_open_info(const char *path, const dem_opts *o, tl_err *e)
{
	return open_dem(path, o, 1, NULL, NULL, 0, e);
}

dem *
dem_open_rows(const char *path, const dem_opts *o, int y0, int y1, int fd,
    tl_err *e)
{
	return open_dem(path, o, 0, NULL, (const int[]){ y0, y1, fd }, 0, e);
}

const georef *
dem_georef(const dem *d)
{
	return &d->g;
}

long long
dem_voids(const dem *d)
{
	return d->voids;
}

double
dem_zunit(const dem *d)
{
	return d->zunit;
}

int
dem_read_span(dem *d, int j, int x0, int n, float *z, unsigned char *valid,
    tl_err *e)
{
	long long w = d->cw, h = d->g.height;

	if (d->fd < 0)
		return tl_fail(e, "%s: opened for its header only", d->what);
	if (j < 0 || j >= h)
		return tl_fail(e, "%s: row %d outside 0 .. %lld", d->what, j,
		    h - 1);
	if (d->cy1 > 0 && (j < d->cy0 || j >= d->cy1))
		return tl_fail(e, "%s: row %d outside the rows read, %d .. %d",
		    d->what, j, d->cy0, d->cy1 - 1);
	if (x0 < d->cx0 || n < 0 || x0 + (long long)n > d->cx0 + w)
		return tl_fail(e, "%s: columns %d .. %lld outside %d .. %lld",
		    d->what, x0, x0 + (long long)n - 1, d->cx0,
		    d->cx0 + w - 1);
	x0 -= d->cx0;
	if (d->fill != NULL && fill_wait(d, j + 1, e) < 0)
		return -1;
	if (d->span != NULL)
		return d->span(d, j, x0, n, z, valid, e);
	if (tl_pread(d->fd, z, (size_t)n * sizeof(float),
	    (j * w + x0) * (long long)sizeof(float), "DEM scratch file",
	    e) < 0)
		return -1;
	if (valid == NULL)
		return 0;
	if (!dem_bit(d->rowvoid, j)) {
		memset(valid, 1, (size_t)n);
		return 0;
	}
	if (d->unfilled) {
		for (int i = 0; i < n; i++)
			valid[i] = !isnan(z[i]);
		return 0;
	}
	return tl_pread(d->fd, valid, (size_t)n,
	    h * w * (long long)sizeof(float) + j * w + x0, "DEM scratch file",
	    e);
}

int
dem_read_row(dem *d, int j, float *z, unsigned char *valid, tl_err *e)
{
	return dem_read_span(d, j, 0, d->g.width, z, valid, e);
}

void
dem_close(dem *d)
{
	if (d == NULL)
		return;
	fill_end(d);
	if (d->fd >= 0)
		close(d->fd);
	free(d->rowvoid);
	free(d->file);
	free(d);
}
