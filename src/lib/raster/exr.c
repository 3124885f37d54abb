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

static int64_t
io_read(exr_const_context_t c, void *u, void *buf, uint64_t sz,
    uint64_t off, exr_stream_error_func_ptr_t ecb)
{
	struct rs_exr_io *io = u;
	char *p = buf;
	uint64_t got = 0;

	while (got < sz) {
		ssize_t r = pread(io->fd, p + got, sz - got,
		    (off_t)(io->base + (long long)(off + got)));
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			ecb(c, EXR_ERR_READ_IO, "read: %s", strerror(errno));
			return -1;
		}
		if (r == 0)
			break;
		got += (uint64_t)r;
	}
	return (int64_t)got;
}

static int64_t
io_size(exr_const_context_t c, void *u)
{
	(void)c;
	return ((struct rs_exr_io *)u)->size;
}

static int64_t
io_write(exr_const_context_t c, void *u, const void *buf, uint64_t sz,
    uint64_t off, exr_stream_error_func_ptr_t ecb)
{
	struct rs_exr_io *io = u;
	const char *p = buf;
	uint64_t put = 0;

	while (put < sz) {
		ssize_t r = pwrite(io->fd, p + put, sz - put,
		    (off_t)(off + put));
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			if (io->msg[0] == '\0')
				snprintf(io->msg, sizeof io->msg, "write: %s",
				    strerror(errno));
			ecb(c, EXR_ERR_WRITE_IO, "write: %s", strerror(errno));
			return -1;
		}
		put += (uint64_t)r;
	}
	return (int64_t)sz;
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
