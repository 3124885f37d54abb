/* exr.c - rasters at rest: OpenEXR scanline files through OpenEXRCore,
 * the part reader and writer share. Rows are gathered into one chunk (16
 * lines for ZIP) and encoded (exr_write.c) or decoded (exr_read.c) a
 * chunk at a time, so memory never depends on the height; exr_attr.c
 * translates header attributes. OpenEXRCore does its I/O through the
 * callbacks here on a descriptor we own, and reports errors to a handler
 * that keeps the first message for ours (its default handler would print
 * to stderr). */
#include "raster/exr_impl.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void
on_error(exr_const_context_t c, exr_result_t code, const char *msg)
{
	void *u = NULL;
	struct rs_exr_io *io;

	(void)code;
	if (c == NULL || exr_get_user_data(c, &u) != EXR_ERR_SUCCESS ||
	    u == NULL)
		return;
	io = u;
	if (io->msg[0] == '\0')
		snprintf(io->msg, sizeof io->msg, "%s", msg);
}

/* A writer's handler does nothing: OpenEXRCore 3.1 calls it while
 * exr_write_header holds the context's lock, which exr_get_user_data
 * takes again (a disk full while a header is written hung for good).
 * io_write keeps its own message instead; other write errors are told
 * by their code. */
static void
on_error_write(exr_const_context_t c, exr_result_t code, const char *msg)
{
	(void)c, (void)code, (void)msg;
}

int
rs_exr_fail(tl_err *e, struct rs_exr_io *io, exr_result_t rv,
    const char *name, const char *fmt, ...)
{
	char what[512];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(what, sizeof what, fmt, ap);
	va_end(ap);
	tl_fail(e, "%s: %s: %s", name, what, io->msg[0] != '\0' ? io->msg :
	    exr_get_default_error_message(rv));
	io->msg[0] = '\0';
	return -1;
}

/* pread's loop: the bytes read, short at the end of the file; -1 with
 * errno on an error. */
static int64_t
read_at(int fd, char *p, uint64_t sz, long long off)
{
	uint64_t got = 0;

	while (got < sz) {
		ssize_t r = pread(fd, p + got, sz - got,
		    (off_t)(off + (long long)got));
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return -1;
		if (r == 0)
			break;
		got += (uint64_t)r;
	}
	return (int64_t)got;
}

void
rs_exr_preload(struct rs_exr_io *io)
{
	int64_t got;

	if (io->size <= 0 || io->size > RS_EXR_WINDOW ||
	    (io->win = malloc((size_t)io->size)) == NULL)
		return;
	got = read_at(io->fd, (char *)io->win, (uint64_t)io->size, io->base);
	if (got <= 0) {
		rs_exr_io_free(io);
		return;
	}
	io->wcap = (size_t)io->size;
	io->wlen = (size_t)got; /* less if the file shrank: pread sees that */
}

/* What the window holds, then the descriptor for the rest: a file that
 * changes under us reads as it would have without the window. */
static int64_t
io_read(exr_const_context_t c, void *u, void *buf, uint64_t sz,
    uint64_t off, exr_stream_error_func_ptr_t ecb)
{
	struct rs_exr_io *io = u;
	char *p = buf;
	uint64_t n = 0;
	int64_t r;

	if (off < io->wlen) {
		n = io->wlen - off < sz ? io->wlen - off : sz;
		memcpy(p, io->win + off, n);
		if (n == sz)
			return (int64_t)sz;
	}
	r = read_at(io->fd, p + n, sz - n, io->base + (long long)(off + n));
	if (r < 0) {
		ecb(c, EXR_ERR_READ_IO, "read: %s", strerror(errno));
		return -1;
	}
	return (int64_t)n + r;
}

static int64_t
io_size(exr_const_context_t c, void *u)
{
	(void)c;
	return ((struct rs_exr_io *)u)->size;
}

/* pwrite's loop, every byte or -1 with io->werr and io->msg set. */
static int
write_at(struct rs_exr_io *io, const unsigned char *p, size_t sz,
    long long off)
{
	size_t put = 0;

	while (put < sz) {
		ssize_t r = pwrite(io->fd, p + put, sz - put,
		    (off_t)(off + (long long)put));
		if (r < 0 && errno == EINTR)
			continue;
		if (r <= 0) {
			io->werr = r < 0 ? errno : ENOSPC;
			if (io->msg[0] == '\0')
				snprintf(io->msg, sizeof io->msg, "write: %s",
				    strerror(io->werr));
			return -1;
		}
		put += (size_t)r;
	}
	return 0;
}

int
rs_exr_flush(struct rs_exr_io *io)
{
	if (io->werr) {
		if (io->msg[0] == '\0')
			snprintf(io->msg, sizeof io->msg, "write: %s",
			    strerror(io->werr));
		return -1;
	}
	if (io->wlen > 0 && write_at(io, io->win, io->wlen, io->wbase) < 0)
		return -1;
	io->wbase += (long long)io->wlen;
	io->wlen = 0;
	return 0;
}

void
rs_exr_io_free(struct rs_exr_io *io)
{
	free(io->win);
	io->win = NULL;
	io->wcap = io->wlen = 0;
}

/* Puts off .. off+sz in the window if it fits there (bytes between what
 * it held and off are past the file's end: zeros, as a hole reads). */
static int
to_window(struct rs_exr_io *io, const void *buf, size_t sz, long long off)
{
	size_t at, end;

	if (off < io->wbase || off - io->wbase > RS_EXR_WINDOW ||
	    sz > RS_EXR_WINDOW - (size_t)(off - io->wbase))
		return 0;
	at = (size_t)(off - io->wbase);
	end = at + sz;
	if (end > io->wcap) {
		size_t cap = io->wcap ? io->wcap : 1 << 16;
		unsigned char *w;
		while (cap < end)
			cap *= 2;
		if (cap > RS_EXR_WINDOW)
			cap = RS_EXR_WINDOW;
		if ((w = realloc(io->win, cap)) == NULL)
			return 0; /* written directly instead */
		io->win = w;
		io->wcap = cap;
	}
	if (at > io->wlen)
		memset(io->win + io->wlen, 0, at - io->wlen);
	memcpy(io->win + at, buf, sz);
	if (end > io->wlen)
		io->wlen = end;
	return 1;
}

/* Into the window, or (once it is written out) into the file: the
 * file's bytes are those of the writes in their order either way. */
static int64_t
io_write(exr_const_context_t c, void *u, const void *buf, uint64_t sz,
    uint64_t off, exr_stream_error_func_ptr_t ecb)
{
	struct rs_exr_io *io = u;
	long long end = (long long)(off + sz);

	if (io->werr == 0 && to_window(io, buf, sz, (long long)off))
		return (int64_t)sz;
	if (rs_exr_flush(io) < 0)
		goto fail;
	if (to_window(io, buf, sz, (long long)off))
		return (int64_t)sz;
	if (write_at(io, buf, sz, (long long)off) < 0)
		goto fail;
	if (end > io->wbase)
		io->wbase = end;
	return (int64_t)sz;
fail:
	ecb(c, EXR_ERR_WRITE_IO, "write: %s", strerror(io->werr));
	return -1;
}

void
rs_exr_init_read(exr_context_initializer_t *init, struct rs_exr_io *io)
{
	init->error_handler_fn = on_error;
	init->user_data = io;
	init->read_fn = io_read;
	init->size_fn = io_size;
	init->max_image_width = RS_MAXDIM;
	init->max_image_height = RS_MAXDIM;
}

void
rs_exr_init_write(exr_context_initializer_t *init, struct rs_exr_io *io)
{
	init->error_handler_fn = on_error_write;
	init->user_data = io;
	init->write_fn = io_write;
}

void
rs_exr_bind(exr_coding_channel_info_t *ch, int n, const rs_header *h,
    float *buf)
{
	for (int i = 0; i < n; i++) {
		int k = rs_channel(h, ch[i].channel_name);
		ch[i].decode_to_ptr = (uint8_t *)(buf + (size_t)k * h->width);
		ch[i].user_pixel_stride = 4;
		ch[i].user_line_stride = h->nch * h->width * 4;
		ch[i].user_data_type = EXR_PIXEL_FLOAT;
		ch[i].user_bytes_per_element = 4;
	}
}
