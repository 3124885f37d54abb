/* exr_write.c - an EXR scanline file written row by row: rows gathered
 * into a chunk, chunks encoded and written by a thread of their own,
 * the file built under a temporary name and renamed when complete (or,
 * inside a tree this process builds, under its final name: outfile.h). */
#include "raster/exr_impl.h"
#include "base/outfile.h"

#include <errno.h>
#include <libdeflate.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* The caller fills one chunk buffer while an encoder thread compresses and
 * writes the other, so computing rows and ZIP overlap. A small file (a
 * pyramid block) is encoded in the caller's thread: starting a thread
 * and two hand-overs per chunk cost more than the overlap gains there
 * (9 % of tilepack's time on one core). Between the header
 * and exr_finish only the encoder calls OpenEXRCore, in chunk order: the
 * file is the same byte for byte as a single thread would write. */
struct exr_wr {
	struct rs_exr_io io;
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
	int sync;         /* no encoder thread: put_chunk in the caller's */
	pthread_mutex_t mu;
	pthread_cond_t cv;
	int job_y0, job_n, job_buf; /* job_n > 0: a chunk is queued or busy */
	int quit, failed; /* failed: the encoder's error is in err */
	tl_err err;
	int zipped;       /* ZIP or ZIPS: compressed by zip_chunk */
	struct libdeflate_compressor *dfl;
	uint8_t *scratch, *zbuf; /* zip_chunk's: zcap bytes each */
	size_t zcap;
};

/* ZIP and ZIPS chunks are compressed here (exr_zip.c) rather than by
 * OpenEXRCore 3.1's zlib, which took half of tilepack's time; the
 * library would also store a chunk that does not shrink with its bytes
 * still reordered, which every reader takes for garbage. The compressed
 * bytes are ours (zbuf): an allocated size of 0 tells the library not
 * to free them. */
/* Files of at most this many bytes of pixels are encoded without a
 * thread of their own. */
#define SYNC_BYTES (1 << 20)

static exr_result_t
zip_chunk(exr_encode_pipeline_t *enc)
{
	struct exr_wr *x = enc->encoding_user_data;
	size_t n = enc->packed_bytes;

	if (x->dfl == NULL &&
	    (x->dfl = libdeflate_alloc_compressor(RS_EXR_ZIP_LEVEL)) == NULL)
		return EXR_ERR_OUT_OF_MEMORY;
	if (x->zcap < n) {
		free(x->scratch), free(x->zbuf);
		x->scratch = malloc(n), x->zbuf = malloc(n);
		x->zcap = x->scratch && x->zbuf ? n : 0;
		if (x->zcap == 0)
			return EXR_ERR_OUT_OF_MEMORY;
	}
	enc->compressed_buffer = x->zbuf;
	enc->compressed_alloc_size = 0;
	enc->compressed_bytes = rs_exr_zip(x->dfl, enc->packed_buffer, n,
	    x->scratch, x->zbuf);
	return EXR_ERR_SUCCESS;
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
		return rs_exr_fail(e, &x->io, rv, w->name, "header");
	for (int i = 0; i < h->nch; i++)
		if ((rv = exr_add_channel(x->ctx, part, h->ch[i],
		    EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1)))
			return rs_exr_fail(e, &x->io, rv, w->name, "channel %s",
			    h->ch[i]);
	/* Names past 31 bytes need the long-name flag, which older readers
	 * refuse: set it only when a name needs it. */
	for (int i = 0; i < h->nattr; i++)
		if (strlen(h->attr[i].name) > 31)
			longnames = 1;
	if (longnames && (rv = exr_set_longname_support(x->ctx, 1)))
		return rs_exr_fail(e, &x->io, rv, w->name, "long names");
	for (int i = 0; i < h->nattr; i++)
		if ((rv = rs_exr_attr_put(x->ctx, &h->attr[i])))
			return rs_exr_fail(e, &x->io, rv, w->name,
			    "attribute %s", h->attr[i].name);
	if ((rv = exr_write_header(x->ctx)) ||
	    (rv = exr_get_scanlines_per_chunk(x->ctx, part, &x->lpc)))
		return rs_exr_fail(e, &x->io, rv, w->name, "header");
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
		return rs_exr_fail(e, &x->io, rv, w->name, "row %d", y0);
	if (x->enc_init)
		rv = exr_encoding_update(x->ctx, 0, &ci, &x->enc);
	else if ((rv = exr_encoding_initialize(x->ctx, 0, &ci, &x->enc)) == 0)
		x->enc_init = 1;
	if (rv)
		return rs_exr_fail(e, &x->io, rv, w->name, "row %d", y0);
	rs_exr_bind(x->enc.channels, x->enc.channel_count, &w->h,
	    (float *)chunk);
	if (x->enc_init == 1) {
		if ((rv = exr_encoding_choose_default_routines(x->ctx, 0,
		    &x->enc)))
			return rs_exr_fail(e, &x->io, rv, w->name, "encoder");
		if (x->zipped) {
			x->enc.compress_fn = zip_chunk;
			x->enc.encoding_user_data = x;
		}
		x->enc_init = 2;
	}
	if ((rv = exr_encoding_run(x->ctx, 0, &x->enc)))
		return rs_exr_fail(e, &x->io, rv, w->name, "row %d", y0);
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

	if (x->sync)
		return 0;
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
	if (x->sync) {
		int y0 = w->y + 1 - x->n;
		x->n = 0;
		return put_chunk(w, x->buf[0], y0, e);
	}
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
	free(x->scratch), free(x->zbuf);
	if (x->dfl != NULL)
		libdeflate_free_compressor(x->dfl);
	x->dfl = NULL, x->scratch = x->zbuf = NULL, x->zcap = 0;
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
	rs_exr_io_free(&x->io);
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
	if ((rv = wr_end(x)) || rs_exr_flush(&x->io) < 0) {
		rs_exr_fail(e, &x->io, rv ? rv : EXR_ERR_WRITE_IO, w->name,
		    "finish");
		exr_abort_w(w);
		return -1;
	}
	rs_exr_io_free(&x->io);
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
rs_exr_create(rs_writer *w, const char *path, enum rs_compression c,
    enum rs_begin how, tl_err *e)
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
	if ((how == RS_BEGIN_TREE ? tl_out_begin_tree(&x->o, path, e) :
	    how == RS_BEGIN_FRESH ? tl_out_begin_fresh(&x->o, path, e) :
	    tl_out_begin(&x->o, path, e)) < 0)
		return -1;
	x->io.fd = x->o.fd;
	rs_exr_init_write(&init, &x->io);
	if ((rv = exr_start_write(&x->ctx, path, EXR_WRITE_FILE_DIRECTLY,
	    &init))) {
		x->ctx = NULL;
		return rs_exr_fail(e, &x->io, rv, w->name, "create");
	}
	if (write_header(w, exr_comp(c), e) < 0)
		return -1;
	x->sync = (double)w->h.width * w->h.height * w->h.nch *
	    sizeof(float) <= SYNC_BYTES;
	for (int i = 0; i < 2 - x->sync; i++)
		if ((x->buf[i] = tl_alloc((size_t)x->lpc * (size_t)w->h.nch,
		    (size_t)w->h.width * sizeof(float), e)) == NULL)
			return -1;
	if (x->sync)
		return 0;
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
