/* exr.c - rasters at rest: OpenEXR scanline files through OpenEXRCore.
 * Rows are gathered into one chunk (16 lines for ZIP) and encoded or
 * decoded a chunk at a time, so memory never depends on the height.
 * OpenEXRCore does its I/O through our callbacks on a descriptor we own,
 * and reports errors to a handler that keeps the first message for ours
 * (its default handler would print to stderr). */
#include "core/rs_impl.h"

#include <errno.h>
#include <openexr.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Shared by reader and writer: what the callbacks need. */
struct exr_io {
	int fd;
	long long base; /* where the EXR begins in fd */
	long long size; /* its length (reading) */
	char msg[512];  /* OpenEXRCore's first complaint since last cleared */
};

static void
on_error(exr_const_context_t c, exr_result_t code, const char *msg)
{
	void *u = NULL;
	struct exr_io *io;

	(void)code;
	if (c == NULL || exr_get_user_data(c, &u) != EXR_ERR_SUCCESS ||
	    u == NULL)
		return;
	io = u;
	if (io->msg[0] == '\0')
		snprintf(io->msg, sizeof io->msg, "%s", msg);
}

/* "name: what: why", why being OpenEXRCore's message or its code's. */
static int
exr_fail(tl_err *e, struct exr_io *io, exr_result_t rv, const char *name,
    const char *fmt, ...)
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
	struct exr_io *io = u;
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
	return ((struct exr_io *)u)->size;
}

static int64_t
io_write(exr_const_context_t c, void *u, const void *buf, uint64_t sz,
    uint64_t off, exr_stream_error_func_ptr_t ecb)
{
	struct exr_io *io = u;
	const char *p = buf;
	uint64_t put = 0;

	while (put < sz) {
		ssize_t r = pwrite(io->fd, p + put, sz - put,
		    (off_t)(off + put));
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			ecb(c, EXR_ERR_WRITE_IO, "write: %s", strerror(errno));
			return -1;
		}
		put += (uint64_t)r;
	}
	return (int64_t)sz;
}

/* Points OpenEXRCore's channels at a buffer of rows laid out as ours:
 * channel-planar within a row, rows one after the other, float32. */
static void
bind(exr_coding_channel_info_t *ch, int n, const rs_header *h, float *buf)
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

/* --- writing ---------------------------------------------------------- */

/* The caller fills one chunk buffer while an encoder thread compresses and
 * writes the other, so computing rows and ZIP overlap. Between the header
 * and exr_finish only the encoder calls OpenEXRCore, in chunk order: the
 * file is the same byte for byte as a single thread would write. */
struct exr_wr {
	struct exr_io io;
	tl_outfile o;
	exr_context_t ctx;
	exr_encode_pipeline_t enc;
	int enc_init;
	int lpc;          /* lines per chunk */
	int n;            /* rows gathered in buf[cur] */
	int cur;
	float *buf[2];
	pthread_t th;
	int th_on;
	pthread_mutex_t mu;
	pthread_cond_t cv;
	int job_y0, job_n, job_buf; /* job_n > 0: a chunk is queued or busy */
	int quit, failed; /* failed: the encoder's error is in err */
	tl_err err;
	int zipped;       /* ZIP or ZIPS: compress through zip_fixed */
	exr_result_t (*zip)(exr_encode_pipeline_t *); /* the library's */
	uint8_t *raw;     /* zip_fixed's copy of a chunk's packed bytes */
	size_t rawsz;
};

/* OpenEXRCore 3.1.5 stores a ZIP chunk that does not compress with its
 * bytes still reordered and delta-coded, instead of raw as the format
 * says: every reader then gets garbage (seen on a lone last row of 129
 * noisy floats; ZIPS too). Keep the packed bytes and, in that case, put
 * them back. */
static exr_result_t
zip_fixed(exr_encode_pipeline_t *enc)
{
	struct exr_wr *x = enc->encoding_user_data;
	exr_result_t rv;

	if (x->rawsz < enc->packed_bytes) {
		uint8_t *p = realloc(x->raw, enc->packed_bytes);
		if (p == NULL)
			return EXR_ERR_OUT_OF_MEMORY;
		x->raw = p, x->rawsz = enc->packed_bytes;
	}
	memcpy(x->raw, enc->packed_buffer, enc->packed_bytes);
	rv = x->zip(enc);
	if (rv == EXR_ERR_SUCCESS && enc->compressed_bytes >= enc->packed_bytes)
		memcpy(enc->compressed_buffer, x->raw, enc->packed_bytes);
	return rv;
}

static int
set_attr(rs_writer *w, const rs_attr *a)
{
	exr_context_t c = ((struct exr_wr *)w->impl)->ctx;

	switch (a->type) {
	case RS_INT:
		return exr_attr_set_int(c, 0, a->name, a->v.i);
	case RS_DOUBLE:
		return exr_attr_set_double(c, 0, a->name, a->v.d);
	case RS_STRING:
		return exr_attr_set_string(c, 0, a->name, a->s);
	case RS_V2I:
		return exr_attr_set_v2i(c, 0, a->name,
		    &(exr_attr_v2i_t){ .x = a->v.v2i[0], .y = a->v.v2i[1] });
	case RS_V2D:
		return exr_attr_set_v2d(c, 0, a->name,
		    &(exr_attr_v2d_t){ .x = a->v.v2d[0], .y = a->v.v2d[1] });
	}
	return EXR_ERR_INVALID_ARGUMENT;
}

static int
write_header(rs_writer *w, exr_compression_t comp, tl_err *e)
{
	struct exr_wr *x = w->impl;
	const rs_header *h = &w->h;
	exr_result_t rv;
	int part, longnames = 0;

	if ((rv = exr_add_part(x->ctx, NULL, EXR_STORAGE_SCANLINE, &part)) ||
	    (rv = exr_initialize_required_attr_simple(x->ctx, part, h->width,
	    h->height, comp)))
		return exr_fail(e, &x->io, rv, w->name, "header");
	for (int i = 0; i < h->nch; i++)
		if ((rv = exr_add_channel(x->ctx, part, h->ch[i],
		    EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1)))
			return exr_fail(e, &x->io, rv, w->name, "channel %s",
			    h->ch[i]);
	/* Names past 31 bytes need the long-name flag, which older readers
	 * refuse: set it only when a name needs it. */
	for (int i = 0; i < h->nattr; i++)
		if (strlen(h->attr[i].name) > 31)
			longnames = 1;
	if (longnames && (rv = exr_set_longname_support(x->ctx, 1)))
		return exr_fail(e, &x->io, rv, w->name, "long names");
	for (int i = 0; i < h->nattr; i++)
		if ((rv = set_attr(w, &h->attr[i])))
			return exr_fail(e, &x->io, rv, w->name,
			    "attribute %s", h->attr[i].name);
	if ((rv = exr_write_header(x->ctx)) ||
	    (rv = exr_get_scanlines_per_chunk(x->ctx, part, &x->lpc)))
		return exr_fail(e, &x->io, rv, w->name, "header");
	return 0;
}

/* Encodes rows y0 .. y0+n-1 from chunk (encoder thread). */
static int
put_chunk(rs_writer *w, const float *chunk, int y0, tl_err *e)
{
	struct exr_wr *x = w->impl;
	exr_chunk_info_t ci;
	exr_result_t rv;

	x->io.msg[0] = '\0';
	if ((rv = exr_write_scanline_chunk_info(x->ctx, 0, y0, &ci)))
		return exr_fail(e, &x->io, rv, w->name, "row %d", y0);
	if (x->enc_init)
		rv = exr_encoding_update(x->ctx, 0, &ci, &x->enc);
	else if ((rv = exr_encoding_initialize(x->ctx, 0, &ci, &x->enc)) == 0)
		x->enc_init = 1;
	if (rv)
		return exr_fail(e, &x->io, rv, w->name, "row %d", y0);
	bind(x->enc.channels, x->enc.channel_count, &w->h, (float *)chunk);
	if (x->enc_init == 1) {
		if ((rv = exr_encoding_choose_default_routines(x->ctx, 0,
		    &x->enc)))
			return exr_fail(e, &x->io, rv, w->name, "encoder");
		if (x->zipped) {
			x->zip = x->enc.compress_fn;
			x->enc.compress_fn = zip_fixed;
			x->enc.encoding_user_data = x;
		}
		x->enc_init = 2;
	}
	if ((rv = exr_encoding_run(x->ctx, 0, &x->enc)))
		return exr_fail(e, &x->io, rv, w->name, "row %d", y0);
	return 0;
}

static void *
encoder(void *arg)
{
	rs_writer *w = arg;
	struct exr_wr *x = w->impl;
	int r;

	pthread_mutex_lock(&x->mu);
	for (;;) {
		while (x->job_n == 0 && !x->quit)
			pthread_cond_wait(&x->cv, &x->mu);
		if (x->job_n == 0)
			break;
		pthread_mutex_unlock(&x->mu);
		r = x->failed ? 0 : put_chunk(w, x->buf[x->job_buf],
		    x->job_y0, &x->err);
		pthread_mutex_lock(&x->mu);
		x->failed |= r < 0;
		x->job_n = 0;
		pthread_cond_broadcast(&x->cv);
	}
	pthread_mutex_unlock(&x->mu);
	return NULL;
}

/* Waits for the encoder to go idle; -1 with its error if it failed. */
static int
idle(struct exr_wr *x, tl_err *e)
{
	int failed;

	pthread_mutex_lock(&x->mu);
	while (x->job_n > 0)
		pthread_cond_wait(&x->cv, &x->mu);
	failed = x->failed;
	pthread_mutex_unlock(&x->mu);
	if (failed && e != NULL)
		*e = x->err;
	return failed ? -1 : 0;
}

static void
stop(struct exr_wr *x)
{
	if (!x->th_on)
		return;
	pthread_mutex_lock(&x->mu);
	x->quit = 1;
	pthread_cond_broadcast(&x->cv);
	pthread_mutex_unlock(&x->mu);
	pthread_join(x->th, NULL);
	pthread_mutex_destroy(&x->mu);
	pthread_cond_destroy(&x->cv);
	x->th_on = 0;
}

static int
exr_write_row(rs_writer *w, const float *row, tl_err *e)
{
	struct exr_wr *x = w->impl;
	size_t n = (size_t)w->h.nch * (size_t)w->h.width;

	memcpy(x->buf[x->cur] + (size_t)x->n * n, row, n * sizeof *row);
	if (++x->n < x->lpc && w->y < w->h.height - 1)
		return 0;
	if (idle(x, e) < 0)
		return -1;
	pthread_mutex_lock(&x->mu);
	x->job_buf = x->cur;
	x->job_y0 = w->y + 1 - x->n;
	x->job_n = x->n;
	pthread_cond_broadcast(&x->cv);
	pthread_mutex_unlock(&x->mu);
	x->cur ^= 1;
	x->n = 0;
	return 0;
}

/* Ends OpenEXRCore's side; on success its offset table is in the file. */
static int
wr_end(struct exr_wr *x)
{
	exr_result_t rv = 0;

	stop(x);
	x->io.msg[0] = '\0';
	if (x->enc_init)
		exr_encoding_destroy(x->ctx, &x->enc);
	x->enc_init = 0;
	if (x->ctx != NULL)
		rv = exr_finish(&x->ctx);
	x->ctx = NULL;
	free(x->buf[0]);
	free(x->buf[1]);
	free(x->raw);
	x->buf[0] = x->buf[1] = NULL;
	return rv;
}

static void
exr_abort_w(rs_writer *w)
{
	struct exr_wr *x = w->impl;

	if (x == NULL)
		return;
	wr_end(x);
	tl_out_abort(&x->o);
	free(x);
	w->impl = NULL;
}

static int
exr_finish_w(rs_writer *w, tl_err *e)
{
	struct exr_wr *x = w->impl;
	exr_result_t rv;

	if (idle(x, e) < 0) {
		exr_abort_w(w);
		return -1;
	}
	if ((rv = wr_end(x))) {
		exr_fail(e, &x->io, rv, w->name, "finish");
		exr_abort_w(w);
		return -1;
	}
	rv = tl_out_commit(&x->o, e);
	free(x);
	w->impl = NULL;
	return rv;
}

static exr_compression_t
exr_comp(enum rs_compression c)
{
	switch (c) {
	case RS_NONE:
		return EXR_COMPRESSION_NONE;
	case RS_RLE:
		return EXR_COMPRESSION_RLE;
	case RS_ZIPS:
		return EXR_COMPRESSION_ZIPS;
	case RS_PIZ:
		return EXR_COMPRESSION_PIZ;
	default:
		return EXR_COMPRESSION_ZIP;
	}
}

int
exr_create(rs_writer *w, const char *path, enum rs_compression c,
    tl_err *e)
{
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	struct exr_wr *x;
	exr_result_t rv;

	w->row = exr_write_row;
	w->finish = exr_finish_w;
	w->abort = exr_abort_w;
	if ((x = tl_alloc(1, sizeof *x, e)) == NULL)
		return -1;
	w->impl = x;
	x->zipped = c == RS_ZIP || c == RS_ZIPS;
	if (tl_out_begin(&x->o, path, e) < 0)
		return -1;
	x->io.fd = x->o.fd;
	init.error_handler_fn = on_error;
	init.user_data = &x->io;
	init.write_fn = io_write;
	if ((rv = exr_start_write(&x->ctx, path, EXR_WRITE_FILE_DIRECTLY,
	    &init))) {
		x->ctx = NULL;
		return exr_fail(e, &x->io, rv, w->name, "create");
	}
	if (write_header(w, exr_comp(c), e) < 0)
		return -1;
	for (int i = 0; i < 2; i++)
		if ((x->buf[i] = tl_alloc((size_t)x->lpc * (size_t)w->h.nch,
		    (size_t)w->h.width * sizeof(float), e)) == NULL)
			return -1;
	pthread_mutex_init(&x->mu, NULL);
	pthread_cond_init(&x->cv, NULL);
	if ((errno = pthread_create(&x->th, NULL, encoder, w)) != 0) {
		pthread_mutex_destroy(&x->mu);
		pthread_cond_destroy(&x->cv);
		return tl_failsys(e, "%s: encoder thread", w->name);
	}
	x->th_on = 1;
	return 0;
}

/* --- reading ---------------------------------------------------------- */

struct exr_rd {
	struct exr_io io;
	exr_context_t ctx;
	exr_decode_pipeline_t dec;
	int dec_init;
	int ymin;     /* data window origin: rows count from it */
	int lpc;      /* lines per chunk */
	int cy, cn;   /* the chunk buffer holds rows cy .. cy+cn-1 */
	float *chunk;
};

/* Structural attributes: EXR's own business, not the raster's. */
static int
standard(const char *name)
{
	static const char *const std[] = {
		"channels", "compression", "dataWindow", "displayWindow",
		"lineOrder", "pixelAspectRatio", "screenWindowCenter",
		"screenWindowWidth", "name", "type", "version", "chunkCount",
		"tiles",
	};

	for (size_t i = 0; i < sizeof std / sizeof std[0]; i++)
		if (strcmp(name, std[i]) == 0)
			return 1;
	return 0;
}

static int
get_attr(rs_reader *r, const exr_attribute_t *a, tl_err *e)
{
	rs_header *h = &r->h;
	char *s;
	int rv;

	if (standard(a->name) || strlen(a->name) >= sizeof h->attr[0].name)
		return 0;
	switch (a->type) {
	case EXR_ATTR_INT:
		return rs_set_int(h, a->name, a->i, e);
	case EXR_ATTR_DOUBLE:
		return rs_set_double(h, a->name, a->d, e);
	case EXR_ATTR_V2I:
		return rs_set_v2i(h, a->name, a->v2i->x, a->v2i->y, e);
	case EXR_ATTR_V2D:
		return rs_set_v2d(h, a->name, a->v2d->x, a->v2d->y, e);
	case EXR_ATTR_STRING:
		/* Not NUL-terminated in every version: copy by length. */
		s = tl_alloc((size_t)a->string->length + 1, 1, e);
		if (s == NULL)
			return -1;
		if (a->string->length > 0)
			memcpy(s, a->string->str, (size_t)a->string->length);
		rv = rs_set_string(h, a->name, s, e);
		free(s);
		return rv;
	default:
		return 0;
	}
}

static int
get_channels(rs_reader *r, tl_err *e)
{
	struct exr_rd *x = r->impl;
	const exr_attr_chlist_t *cl;
	exr_result_t rv;

	if ((rv = exr_get_channels(x->ctx, 0, &cl)))
		return exr_fail(e, &x->io, rv, r->name, "channels");
	if (cl->num_channels < 1 || cl->num_channels > RS_MAXCH)
		return tl_fail(e, "%s: %d channels (1 to %d)", r->name,
		    cl->num_channels, RS_MAXCH);
	for (int i = 0; i < cl->num_channels; i++) {
		const exr_attr_chlist_entry_t *c = &cl->entries[i];
		const char *n = c->name.str;
		if (c->pixel_type != EXR_PIXEL_FLOAT &&
		    c->pixel_type != EXR_PIXEL_HALF &&
		    c->pixel_type != EXR_PIXEL_UINT)
			return tl_fail(e, "%s: channel %s: unknown pixel type",
			    r->name, n);
		if (c->x_sampling != 1 || c->y_sampling != 1)
			return tl_fail(e, "%s: channel %s: subsampled",
			    r->name, n);
		if (rs_add_channel(&r->h, n, e) < 0)
			return tl_fail(e, "%s: channel %s: name too long or "
			    "repeated", r->name, n);
	}
	return 0;
}

/* Only single-part scanline images of sane size. */
static int
get_header(rs_reader *r, tl_err *e)
{
	struct exr_rd *x = r->impl;
	const exr_attribute_t *a;
	exr_attr_box2i_t dw;
	exr_storage_t st;
	exr_result_t rv;
	int n;
	long long w, h;

	if ((rv = exr_get_count(x->ctx, &n)))
		return exr_fail(e, &x->io, rv, r->name, "parts");
	if (n != 1)
		return tl_fail(e, "%s: multi-part EXR (%d parts)", r->name, n);
	if ((rv = exr_get_storage(x->ctx, 0, &st)) ||
	    (rv = exr_get_data_window(x->ctx, 0, &dw)))
		return exr_fail(e, &x->io, rv, r->name, "header");
	if (st != EXR_STORAGE_SCANLINE)
		return tl_fail(e, "%s: tiled or deep EXR, not scanline",
		    r->name);
	w = (long long)dw.max.x - dw.min.x + 1;
	h = (long long)dw.max.y - dw.min.y + 1;
	if (w < 1 || h < 1 || w > RS_MAXDIM || h > RS_MAXDIM)
		return tl_fail(e, "%s: bad data window", r->name);
	rs_header_init(&r->h, (int)w, (int)h);
	x->ymin = dw.min.y;
	if (get_channels(r, e) < 0 || rs_check_size(&r->h, r->name, e) < 0)
		return -1;
	if ((rv = exr_get_attribute_count(x->ctx, 0, &n)))
		return exr_fail(e, &x->io, rv, r->name, "attributes");
	for (int i = 0; i < n; i++) {
		if ((rv = exr_get_attribute_by_index(x->ctx, 0,
		    EXR_ATTR_LIST_FILE_ORDER, i, &a)))
			return exr_fail(e, &x->io, rv, r->name, "attributes");
		if (get_attr(r, a, e) < 0)
			return tl_fail(e, "%s: attribute %s: too many "
			    "attributes", r->name, a->name);
	}
	return 0;
}

/* A file cut short loses its last chunk first: say so now, before the
 * caller has done any work. */
static int
check_last_chunk(rs_reader *r, tl_err *e)
{
	struct exr_rd *x = r->impl;
	exr_chunk_info_t ci;
	exr_result_t rv;

	x->io.msg[0] = '\0';
	rv = exr_read_scanline_chunk_info(x->ctx, 0, x->ymin + r->h.height - 1,
	    &ci);
	if (rv)
		return exr_fail(e, &x->io, rv, r->name, "truncated or corrupt "
		    "EXR (last chunk)");
	if ((long long)ci.data_offset + (long long)ci.packed_size > x->io.size)
		return tl_fail(e, "%s: truncated (last chunk ends at byte %llu, "
		    "file has %lld)", r->name, (unsigned long long)
		    (ci.data_offset + ci.packed_size), x->io.size);
	return 0;
}

static int
get_chunk(rs_reader *r, tl_err *e)
{
	struct exr_rd *x = r->impl;
	exr_chunk_info_t ci;
	exr_result_t rv;

	x->io.msg[0] = '\0';
	if ((rv = exr_read_scanline_chunk_info(x->ctx, 0, x->ymin + r->y,
	    &ci)))
		goto fail;
	if (x->dec_init)
		rv = exr_decoding_update(x->ctx, 0, &ci, &x->dec);
	else if ((rv = exr_decoding_initialize(x->ctx, 0, &ci, &x->dec)) == 0)
		x->dec_init = 1;
	if (rv)
		goto fail;
	if (ci.width != r->h.width || ci.start_y > x->ymin + r->y ||
	    ci.start_y + ci.height <= x->ymin + r->y || ci.height > x->lpc)
		return tl_fail(e, "%s: corrupt chunk at row %d of %d", r->name,
		    r->y, r->h.height);
	bind(x->dec.channels, x->dec.channel_count, &r->h, x->chunk);
	if (x->dec_init == 1) {
		if ((rv = exr_decoding_choose_default_routines(x->ctx, 0,
		    &x->dec)))
			goto fail;
		x->dec_init = 2;
	}
	if ((rv = exr_decoding_run(x->ctx, 0, &x->dec)))
		goto fail;
	x->cy = ci.start_y - x->ymin;
	x->cn = ci.height;
	return 0;
fail:
	return exr_fail(e, &x->io, rv, r->name, "corrupt data at row %d of %d",
	    r->y, r->h.height);
}

static int
exr_read_row(rs_reader *r, float *row, tl_err *e)
{
	struct exr_rd *x = r->impl;
	size_t n = (size_t)r->h.nch * (size_t)r->h.width;

	if (r->y >= x->cy + x->cn && get_chunk(r, e) < 0)
		return -1;
	memcpy(row, x->chunk + (size_t)(r->y - x->cy) * n, n * sizeof *row);
	return 0;
}

static void
exr_close_r(rs_reader *r)
{
	struct exr_rd *x = r->impl;

	if (x == NULL)
		return;
	if (x->dec_init)
		exr_decoding_destroy(x->ctx, &x->dec);
	if (x->ctx != NULL)
		exr_finish(&x->ctx);
	free(x->chunk);
	free(x);
	r->impl = NULL;
}

int
exr_open_read(rs_reader *r, long long base, tl_err *e)
{
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	struct exr_rd *x;
	struct stat st;
	exr_result_t rv;

	r->row = exr_read_row;
	r->close = exr_close_r;
	if ((x = tl_alloc(1, sizeof *x, e)) == NULL)
		return -1;
	r->impl = x;
	if (fstat(r->fd, &st) != 0)
		return tl_failsys(e, "%s: stat", r->name);
	x->io.fd = r->fd;
	x->io.base = base;
	x->io.size = (long long)st.st_size - base;
	init.error_handler_fn = on_error;
	init.user_data = &x->io;
	init.read_fn = io_read;
	init.size_fn = io_size;
	init.max_image_width = RS_MAXDIM;
	init.max_image_height = RS_MAXDIM;
	if ((rv = exr_start_read(&x->ctx, r->name, &init))) {
		x->ctx = NULL;
		return exr_fail(e, &x->io, rv, r->name,
		    "truncated or corrupt EXR header");
	}
	x->io.msg[0] = '\0'; /* warnings of a header that parsed */
	if (get_header(r, e) < 0 || check_last_chunk(r, e) < 0)
		return -1;
	if ((rv = exr_get_scanlines_per_chunk(x->ctx, 0, &x->lpc)))
		return exr_fail(e, &x->io, rv, r->name, "header");
	x->chunk = tl_alloc((size_t)x->lpc * (size_t)r->h.nch,
	    (size_t)r->h.width * sizeof(float), e);
	return x->chunk == NULL ? -1 : 0;
}
