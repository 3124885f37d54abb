/* raster.c - the front door of both forms: rs_open finds out by magic
 * whether it reads EXR, the fqm(5) stream or a band list of either
 * (rs_list.c), rs_create picks EXR for a file name and the stream for
 * "-". It dispatches to the backends; what they share (the header and
 * its attributes) is the leaf rs_header.c, so no backend calls back here
 * but the band list, whose bands are rasters opened here. */
#include "raster/rs_impl.h"

#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* --- reading ---------------------------------------------------------- */

static int
read_some(int fd, unsigned char *p, int n)
{
	int got = 0;

	while (got < n) {
		ssize_t r = read(fd, p + got, (size_t)(n - got));
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return -1;
		if (r == 0)
			break;
		got += (int)r;
	}
	return got;
}

/* Copies the pipe, the magic already read included, to a scratch file:
 * OpenEXRCore reads its offset table and chunks by position. */
static int
spool(rs_reader *r, tl_err *e)
{
	char rwhat[sizeof e->msg];
	int fd;

	if ((fd = tl_scratch(e)) < 0)
		return -1;
	snprintf(rwhat, sizeof rwhat, "%s: read", r->name);
	if (tl_pwrite(fd, r->pre, (size_t)r->npre, 0, "scratch file", e) < 0 ||
	    tl_copy_fd(r->fd, rwhat, fd, r->npre, "scratch file", e) < 0) {
		close(fd);
		return -1;
	}
	if (r->ownfd)
		close(r->fd);
	r->fd = fd;
	r->ownfd = 1;
	return 0;
}

static int
open_fd(rs_reader *r, const char *path, tl_err *e)
{
	if (strcmp(path, "-") == 0) {
		r->fd = STDIN_FILENO;
		return 0;
	}
	r->fd = open(path, O_RDONLY | O_CLOEXEC);
	if (r->fd < 0)
		return tl_failsys(e, "%s: cannot open", path);
	r->ownfd = 1;
	return 0;
}

/* Finds the form by its magic and hands the reader to its backend; lists:
 * a band list is welcome (not as one of a list's bands). */
static int
dispatch(rs_reader *r, int lists, tl_err *e)
{
	struct stat st;
	off_t pos;

	if (fstat(r->fd, &st) != 0)
		return tl_failsys(e, "%s: stat", r->name);
	if (S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: is a directory", r->name);
	if (isatty(r->fd))
		return tl_fail(e, "%s: is a terminal; give a file or a pipe",
		    r->name);
	if ((r->npre = read_some(r->fd, r->pre, 8)) < 0)
		return tl_failsys(e, "%s: read", r->name);
	if (r->npre == 8 && memcmp(r->pre, rs_stream_magic, 8) == 0)
		return rs_stream_open_read(r, e);
	if (r->npre == 8 && memcmp(r->pre, rs_list_magic, 8) == 0)
		return lists ? rs_list_open_read(r, e) :
		    tl_fail(e, "%s: a band list cannot be a band", r->name);
	if (r->npre < 4 || memcmp(r->pre, rs_exr_magic, 4) != 0)
		return tl_fail(e, "%s: %s", r->name, r->npre == 0 ?
		    "empty input" : "not an fqm stream or EXR file");
	if (!S_ISREG(st.st_mode)) {
		if (spool(r, e) < 0)
			return -1;
		return rs_exr_open_read(r, 0, e);
	}
	/* A regular file, maybe stdin not at its start: EXR offsets count
	 * from where the file's EXR begins. */
	if ((pos = lseek(r->fd, 0, SEEK_CUR)) < 0)
		return tl_failsys(e, "%s: seek", r->name);
	return rs_exr_open_read(r, (long long)pos - r->npre, e);
}

static rs_reader *
open_reader(const char *path, int lists, tl_err *e)
{
	rs_reader *r = tl_alloc(1, sizeof *r, e);

	if (r == NULL)
		return NULL;
	r->fd = -1;
	r->name = strdup(strcmp(path, "-") == 0 ? "stdin" : path);
	if (r->name == NULL) {
		tl_fail(e, "%s: out of memory", path);
		free(r);
		return NULL;
	}
	if (strcmp(path, "-") == 0 && rs_ring_bound(0)) {
		if (rs_ring_open_read(r, e) == 0)
			return r; /* a thread's stdin: rows from a ring */
		rs_close(r);
		return NULL;
	}
	if (open_fd(r, path, e) < 0 || dispatch(r, lists, e) < 0) {
		rs_close(r);
		return NULL;
	}
	return r;
}

rs_reader *
rs_open(const char *path, tl_err *e)
{
	return open_reader(path, 1, e);
}

/* A raster that must be a file on disk (a pyramid's block): anything
 * else, a FIFO included, is refused at once, before it can block. */
rs_reader *
rs_open_regular(const char *path, tl_err *e)
{
	rs_reader *r;
	int fd = tl_open_regular(path, e);

	if (fd < 0)
		return NULL;
	if ((r = tl_alloc(1, sizeof *r, e)) == NULL ||
	    (r->name = strdup(path)) == NULL) {
		if (r != NULL)
			tl_fail(e, "%s: out of memory", path);
		free(r);
		close(fd);
		return NULL;
	}
	r->fd = fd, r->ownfd = 1;
	if (dispatch(r, 0, e) < 0) {
		rs_close(r);
		return NULL;
	}
	return r;
}

rs_reader *
rs_open_listed(const char *path, tl_err *e)
{
	return open_reader(path, 0, e);
}

const rs_header *
rs_header_of(const rs_reader *r)
{
	return &r->h;
}

int
rs_read_row(rs_reader *r, float *row, tl_err *e)
{
	if (r->failed)
		return tl_fail(e, "%s: read after an error", r->name);
	if (r->y >= r->h.height)
		return tl_fail(e, "%s: read past the last row (%d)", r->name,
		    r->h.height);
	if (r->row(r, row, e) < 0) {
		r->failed = 1;
		return -1;
	}
	r->y++;
	return 0;
}

const float *
rs_read_row_view(rs_reader *r, float *buf, tl_err *e)
{
	const float *p;

	if (r->view == NULL)
		return rs_read_row(r, buf, e) < 0 ? NULL : buf;
	if (r->failed)
		return tl_fail(e, "%s: read after an error", r->name), NULL;
	if (r->y >= r->h.height)
		return tl_fail(e, "%s: read past the last row (%d)", r->name,
		    r->h.height), NULL;
	if ((p = r->view(r, e)) == NULL) {
		r->failed = 1;
		return NULL;
	}
	r->y++;
	return p;
}

int
rs_read_span(rs_reader *r, int x0, int n, float *dst, tl_err *e)
{
	size_t w = (size_t)r->h.width;
	int k = 1;

	if (r->failed)
		return tl_fail(e, "%s: read after an error", r->name);
	if (r->y >= r->h.height)
		return tl_fail(e, "%s: read past the last row (%d)", r->name,
		    r->h.height);
	assert(x0 >= 0 && n >= 1 && (size_t)x0 + (size_t)n <= w);
	if (r->full == NULL && r->span != NULL)
		k = r->span(r, x0, n, dst, e);
	if (k == 1) {
		if (r->full == NULL &&
		    (r->full = tl_alloc(w * r->h.nch, sizeof *r->full, e)) == NULL)
			k = -1;
		else if ((k = r->row(r, r->full, e)) == 0)
			for (int c = 0; c < r->h.nch; c++)
				memcpy(dst + (size_t)c * n, r->full + c * w + x0,
				    (size_t)n * sizeof *dst);
	}
	if (k < 0) {
		r->failed = 1;
		return -1;
	}
	r->y++;
	return 0;
}

void
rs_close(rs_reader *r)
{
	if (r == NULL)
		return;
	if (r->close != NULL)
		r->close(r);
	if (r->ownfd && r->fd >= 0)
		close(r->fd);
	rs_header_free(&r->h);
	free(r->full);
	free(r->name);
	free(r);
}

/* --- writing ---------------------------------------------------------- */

int
rs_compression_parse(const char *s, enum rs_compression *c)
{
	static const struct {
		const char *name;
		enum rs_compression c;
	} tab[] = {
		{ "zip", RS_ZIP }, { "none", RS_NONE }, { "rle", RS_RLE },
		{ "zips", RS_ZIPS }, { "piz", RS_PIZ },
	};

	for (size_t i = 0; i < sizeof tab / sizeof tab[0]; i++)
		if (strcasecmp(s, tab[i].name) == 0) {
			*c = tab[i].c;
			return 0;
		}
	return -1;
}

/* What both forms can represent; checked before anything is created. */
static int
check_header(const rs_header *h, const char *name, tl_err *e)
{
	if (rs_check_size(h, name, e) < 0)
		return -1;
	for (int i = 1; i < h->nch; i++)
		if (strcmp(h->ch[i - 1], h->ch[i]) >= 0)
			return tl_fail(e, "%s: channels not sorted", name);
	for (int i = 0; i < h->nattr; i++) {
		const rs_attr *a = &h->attr[i];
		if (a->type == RS_STRING &&
		    (a->s == NULL || strlen(a->s) > RS_MAXSTR))
			return tl_fail(e, "%s: attribute %s: string missing "
			    "or longer than %d bytes", name, a->name,
			    RS_MAXSTR);
	}
	return 0;
}

static rs_writer *
create(const char *path, const rs_header *h, enum rs_compression c,
    enum rs_begin how, tl_err *e)
{
	int stream = strcmp(path, "-") == 0;
	rs_writer *w;

	if (check_header(h, stream ? "stdout" : path, e) < 0)
		return NULL;
	if ((w = tl_alloc(1, sizeof *w, e)) == NULL)
		return NULL;
	if ((w->name = strdup(stream ? "stdout" : path)) == NULL) {
		free(w);
		tl_fail(e, "%s: out of memory", path);
		return NULL;
	}
	if (rs_header_copy(&w->h, h, e) < 0) {
		free(w->name);
		free(w);
		return NULL;
	}
	if ((stream && rs_ring_bound(1) ? rs_ring_create(w, e) :
	    stream ? rs_stream_create(w, rs_ring_outfd() >= 0 ?
	    rs_ring_outfd() : STDOUT_FILENO, e) :
	    rs_exr_create(w, path, c, how, e)) < 0) {
		rs_abort(w);
		return NULL;
	}
	return w;
}

rs_writer *
rs_create(const char *path, const rs_header *h, enum rs_compression c,
    tl_err *e)
{
	return create(path, h, c, RS_BEGIN, e);
}

rs_writer *
rs_create_fresh(const char *path, const rs_header *h, enum rs_compression c,
    tl_err *e)
{
	return create(path, h, c, RS_BEGIN_FRESH, e);
}

rs_writer *
rs_create_tree(const char *path, const rs_header *h, enum rs_compression c,
    tl_err *e)
{
	return create(path, h, c, RS_BEGIN_TREE, e);
}

int
rs_write_row(rs_writer *w, const float *row, tl_err *e)
{
	if (w->failed)
		return tl_fail(e, "%s: write after an error", w->name);
	if (w->y >= w->h.height)
		return tl_fail(e, "%s: more than %d rows written", w->name,
		    w->h.height);
	if (w->row(w, row, e) < 0) {
		w->failed = 1;
		return -1;
	}
	w->y++;
	return 0;
}

float *
rs_write_row_buffer(rs_writer *w, float *own, tl_err *e)
{
	float *p;

	if (w->slot == NULL || w->failed || w->y >= w->h.height)
		return own; /* rs_write_row tells what is wrong */
	if ((p = w->slot(w, e)) == NULL)
		w->failed = 1;
	return p;
}

static void
writer_free(rs_writer *w)
{
	rs_header_free(&w->h);
	free(w->name);
	free(w);
}

/* Always consumes w: on failure the output is discarded as by rs_abort. */
int
rs_finish(rs_writer *w, tl_err *e)
{
	int r;

	if (w->failed || w->y != w->h.height) {
		if (!w->failed)
			tl_fail(e, "%s: %d of %d rows written", w->name, w->y,
			    w->h.height);
		else
			tl_fail(e, "%s: finish after an error", w->name);
		rs_abort(w);
		return -1;
	}
	r = w->finish(w, e);
	writer_free(w);
	return r;
}

void
rs_abort(rs_writer *w)
{
	if (w == NULL)
		return;
	if (w->abort != NULL)
		w->abort(w);
	writer_free(w);
}
