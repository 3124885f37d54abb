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

/* Shared by reader and writer: what the callbacks need. */
struct rs_exr_io {
	int fd;
	long long base; /* where the EXR begins in fd */
	long long size; /* its length (reading) */
	char msg[512];  /* OpenEXRCore's first complaint since last cleared */
};

/* A context initializer whose I/O goes through io's descriptor (pread
 * from io->base, or pwrite) and whose errors are kept in io->msg. */
void rs_exr_init_read(exr_context_initializer_t *init, struct rs_exr_io *io);
void rs_exr_init_write(exr_context_initializer_t *init, struct rs_exr_io *io);

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
