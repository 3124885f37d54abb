/* exr_read.c - an EXR scanline file read row by row: the header (one
 * part, scanlines, sane size), a check that the last chunk is there, then
 * a chunk decoded whenever the next row is past the one held. */
#include "raster/exr_impl.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

const unsigned char rs_exr_magic[4] = { 0x76, 0x2f, 0x31, 0x01 };

struct exr_rd {
	struct rs_exr_io io;
	exr_context_t ctx;
	exr_decode_pipeline_t dec;
	int dec_init;
	int ymin;     /* data window origin: rows count from it */
	int lpc;      /* lines per chunk */
	int cap;      /* rows the chunk buffer holds: min(lpc, height) */
	int cy, cn;   /* the chunk buffer holds rows cy .. cy+cn-1 */
	long long px; /* bytes of a pixel as stored, all channels */
	float *chunk;
};

static int
get_channels(rs_reader *r, tl_err *e)
{
	struct exr_rd *x = r->impl;
	const exr_attr_chlist_t *cl;
	exr_result_t rv;

	if ((rv = exr_get_channels(x->ctx, 0, &cl)))
		return rs_exr_fail(e, &x->io, rv, r->name, "channels");
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
		x->px += c->pixel_type == EXR_PIXEL_HALF ? 2 : 4;
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
		return rs_exr_fail(e, &x->io, rv, r->name, "parts");
	if (n != 1)
		return tl_fail(e, "%s: multi-part EXR (%d parts)", r->name, n);
	if ((rv = exr_get_storage(x->ctx, 0, &st)) ||
	    (rv = exr_get_data_window(x->ctx, 0, &dw)))
		return rs_exr_fail(e, &x->io, rv, r->name, "header");
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
		return rs_exr_fail(e, &x->io, rv, r->name, "attributes");
	for (int i = 0; i < n; i++) {
		if ((rv = exr_get_attribute_by_index(x->ctx, 0,
		    EXR_ATTR_LIST_FILE_ORDER, i, &a)))
			return rs_exr_fail(e, &x->io, rv, r->name,
			    "attributes");
		if (rs_exr_attr_get(&r->h, a, e) < 0)
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
		return rs_exr_fail(e, &x->io, rv, r->name,
		    "truncated or corrupt EXR (last chunk)");
	if ((long long)ci.data_offset + (long long)ci.packed_size > x->io.size)
		return tl_fail(e, "%s: truncated (last chunk ends at byte "
		    "%llu, file has %lld)", r->name, (unsigned long long)
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
	    ci.start_y + ci.height <= x->ymin + r->y || ci.height > x->cap)
		return tl_fail(e, "%s: corrupt chunk at row %d of %d", r->name,
		    r->y, r->h.height);
	rs_exr_bind(x->dec.channels, x->dec.channel_count, &r->h, x->chunk);
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
	return rs_exr_fail(e, &x->io, rv, r->name,
	    "corrupt data at row %d of %d", r->y, r->h.height);
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
	rs_exr_io_free(&x->io);
	free(x);
	r->impl = NULL;
}

/* The data a header declares must be data the file can hold, before a
 * chunk buffer is allocated for it: a 4 KB file declaring 9 rows of 14.5
 * million 13-channel pixels (6.8 GB decoded, a 12 GB chunk buffer) is
 * refused here, not by the allocator or after hours of work.
 *
 * The bound is a compression ratio: no codec this reader decodes for our
 * data stores more than about 1032 decoded bytes in one stored byte.
 * ZIP and ZIPS are deflate, whose ratio cannot exceed 1032:1 (a 258-byte
 * match in at best 2 bits); RLE's runs of at most 128 bytes cost 2 (64:1);
 * PIZ's Huffman codes runs of at most 271 16-bit values in 10 bits or
 * more (about 430:1); PXR24 stores floats in 24 bits before deflate
 * (1376:1); B44 at best 32 bytes of halves in 3 (11:1); NONE 1:1. (DWA
 * deflates an RLE stream for channels named like alpha, which could
 * exceed it in theory; no quadric or vertex map is lossy DWA.) So decoded
 * bytes above 2048 x the file's bytes, plus 1 MiB for tiny files whose
 * header dominates, cannot come from this file: it is damaged or forged. */
#define EXR_MAXRATIO 2048
#define EXR_SLACK (1LL << 20)

static int
check_ratio(rs_reader *r, tl_err *e)
{
	struct exr_rd *x = r->impl;
	long long bytes = (long long)r->h.width * r->h.height * x->px;

	if (bytes / EXR_MAXRATIO > x->io.size + EXR_SLACK / EXR_MAXRATIO)
		return tl_fail(e, "%s: the header declares %dx%d pixels of %lld "
		    "bytes (%lld bytes decoded), more than a file of %lld bytes "
		    "can hold (%d:1 at most): damaged or forged", r->name,
		    r->h.width, r->h.height, x->px, bytes, x->io.size,
		    EXR_MAXRATIO);
	return 0;
}

int
rs_exr_open_read(rs_reader *r, long long base, tl_err *e)
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
	rs_exr_init_read(&init, &x->io);
	rs_exr_preload(&x->io);
	if ((rv = exr_start_read(&x->ctx, r->name, &init))) {
		x->ctx = NULL;
		return rs_exr_fail(e, &x->io, rv, r->name,
		    "truncated or corrupt EXR header");
	}
	x->io.msg[0] = '\0'; /* warnings of a header that parsed */
	if (get_header(r, e) < 0 || check_last_chunk(r, e) < 0)
		return -1;
	if ((rv = exr_get_scanlines_per_chunk(x->ctx, 0, &x->lpc)))
		return rs_exr_fail(e, &x->io, rv, r->name, "header");
	if (check_ratio(r, e) < 0)
		return -1;
	x->cap = x->lpc < r->h.height ? x->lpc : r->h.height;
	x->chunk = tl_alloc((size_t)x->cap * (size_t)r->h.nch,
	    (size_t)r->h.width * sizeof(float), e);
	return x->chunk == NULL ? -1 : 0;
}
