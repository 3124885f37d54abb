/* exr_zip.c - EXR's ZIP and ZIPS chunk compression by libdeflate.
 *
 * The format (OpenEXR's "ZIP_COMPRESSION"): the chunk's packed bytes
 * split into the even-indexed ones followed by the odd-indexed ones,
 * each byte replaced by its difference from the one before plus 128
 * (mod 256), the result a zlib stream; a chunk that does not shrink is
 * stored as it was packed. Any deflate encoder gives a valid file: this
 * one is libdeflate's, about 3x zlib's speed at a better ratio (and what
 * OpenEXR itself uses from 3.2 on). Its output is deterministic for a
 * given libdeflate version and level. */
#include "raster/exr_impl.h"

#include <libdeflate.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Split and delta-code n bytes of src into dst. */
static void
predict(uint8_t *dst, const uint8_t *src, size_t n)
{
	uint8_t *odd = dst + (n + 1) / 2;
	size_t i, k;

	for (i = 0, k = 0; i + 1 < n; i += 2, k++)
		dst[k] = src[i], odd[k] = src[i + 1];
	if (n & 1)
		dst[k] = src[n - 1];
	for (i = n; i-- > 1;)
		dst[i] = (uint8_t)(dst[i] - dst[i - 1] + 128);
}

size_t
rs_exr_zip(struct libdeflate_compressor *c, const void *src, size_t n,
    uint8_t *scratch, uint8_t *dst)
{
	size_t z;

	if (n == 0)
		return 0;
	predict(scratch, src, n);
	/* room for n - 1 bytes: 0 when it does not shrink */
	z = libdeflate_zlib_compress(c, scratch, n, dst, n - 1);
	if (z == 0) { /* stored as packed: what readers expect */
		memcpy(dst, src, n);
		z = n;
	}
	return z;
}
