/* exr_impl.h - private to the EXR backend of raster.h: exr.c (I/O
 * callbacks, errors, channel binding), exr_read.c, exr_write.c and
 * exr_attr.c (header attributes). OpenEXRCore owns the exr_ prefix; ours
 * is rs_exr_, the raster stream's EXR side. */
#ifndef TL_EXR_IMPL_H
#define TL_EXR_IMPL_H

#include <openexr.h>
#include <stddef.h>
#include <stdint.h>

#include "raster/rs_impl.h"

/* Shared by reader and writer: what the callbacks need. OpenEXRCore
 * reads and writes a header attribute, a chunk's leader and the chunk
 * table a few bytes at a time (about 250 writes and 22 reads of a
 * pyramid block): the bytes go through a window in memory instead.
 * Writing, win holds the file's bytes wbase .. wbase+wlen, none of them
 * in the file yet (the file ends at or before wbase); reading, the
 * first wlen bytes of a small file, read whole. */
struct rs_exr_io {
	int fd;
	long long base; /* where the EXR begins in fd */
	long long size; /* its length (reading) */
	char msg[512];  /* OpenEXRCore's first complaint since last cleared */
	unsigned char *win;
	size_t wcap, wlen; /* allocated, held: wlen <= wcap <= RS_EXR_WINDOW */
	long long wbase;
	int werr;       /* a write failed (errno): every later one fails */
};

/* The window's bound: memory per open EXR file, whatever its size. A
 * pyramid block (129x129 vertices, a few channels, compressed) is far
 * below it, so it is written with one write(2) and read with one
 * read(2); a larger file (a level's vertex or quadric map) goes out in
 * pieces of up to this size, and is read as OpenEXRCore asks. */
#define RS_EXR_WINDOW (1 << 20)

/* A context initializer whose I/O goes through io's descriptor (pread
 * from io->base, or pwrite) and whose errors are kept in io->msg. */
void rs_exr_init_read(exr_context_initializer_t *init, struct rs_exr_io *io);
void rs_exr_init_write(exr_context_initializer_t *init, struct rs_exr_io *io);
/* Reading: a file of at most RS_EXR_WINDOW bytes is read whole now and
 * served from memory (best effort: on any failure the reads go to the
 * descriptor as they would have, and fail there the same way). */
void rs_exr_preload(struct rs_exr_io *io);
/* Writing: the window's bytes into the file; -1 with io->msg set if a
 * write failed, now or before. */
int rs_exr_flush(struct rs_exr_io *io);
/* Frees the window. */
void rs_exr_io_free(struct rs_exr_io *io);

/* "name: what: why", why being OpenEXRCore's message or its code's;
 * clears io->msg; returns -1. */
int rs_exr_fail(tl_err *e, struct rs_exr_io *io, exr_result_t rv,
    const char *name, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

/* Points OpenEXRCore's n channels at a buffer of rows laid out as ours:
 * channel-planar within a row, rows one after the other, float32. */
void rs_exr_bind(exr_coding_channel_info_t *ch, int n, const rs_header *h,
    float *buf);

/* Header attributes: one of ours into part 0 of a file being written;
 * one of the file's into h (EXR's structural attributes and types we do
 * not carry are skipped: 0). */
exr_result_t rs_exr_attr_put(exr_context_t c, const rs_attr *a);
int rs_exr_attr_get(rs_header *h, const exr_attribute_t *a, tl_err *e);

/* EXR's ZIP (and ZIPS) compression of a chunk's n packed bytes into dst
 * (n bytes), through scratch (n bytes): the bytes used, n when stored as
 * packed (it did not shrink). exr_zip.c. */
struct libdeflate_compressor;
/* On an 8193x8193 DEM's pyramid (mosaic of N44W072), tilepack's CPU time
 * and the pyramid's size at libdeflate's levels 1, 2, 4: 16.5 s, 17.9 s,
 * 18.8 s; 405, 397, 394 MB. */
#define RS_EXR_ZIP_LEVEL 2
size_t rs_exr_zip(struct libdeflate_compressor *c, const void *src, size_t n,
    uint8_t *scratch, uint8_t *dst);

#endif
