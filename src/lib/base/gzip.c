/* gzip.c - whole gzip members in memory (gzip.h). */
#include "base/gzip.h"

#include <stdlib.h>
#include <string.h>

#include <zlib.h>

int
tl_gzip(const void *src, size_t n, unsigned char **out, size_t *outlen,
    tl_err *e)
{
	z_stream z;
	uLong cap;
	unsigned char *o;
	int r;

	memset(&z, 0, sizeof z);
	if (n > (uInt)-1)
		return tl_fail(e, "gzip: %zu bytes: too many for one call", n);
	/* windowBits 31: a gzip header and trailer around the deflate */
	if (deflateInit2(&z, 9, Z_DEFLATED, 31, 8, Z_DEFAULT_STRATEGY) != Z_OK)
		return tl_fail(e, "gzip: zlib: cannot start");
	cap = deflateBound(&z, (uLong)n) + 64;
	if ((o = malloc(cap)) == NULL) {
		deflateEnd(&z);
		return tl_fail(e, "gzip: out of memory");
	}
	z.next_in = (unsigned char *)src, z.avail_in = (uInt)n;
	z.next_out = o, z.avail_out = (uInt)cap;
	r = deflate(&z, Z_FINISH);
	deflateEnd(&z);
	if (r != Z_STREAM_END) {
		free(o);
		return tl_fail(e, "gzip: zlib: deflate failed");
	}
	*out = o, *outlen = z.total_out;
	return 0;
}

int
tl_gunzip(const void *src, size_t n, size_t max, unsigned char **out,
    size_t *outlen, tl_err *e)
{
	const unsigned char *b = src;
	z_stream z;
	size_t cap = n * 4 + 4096, got = 0;
	unsigned char *o = malloc(cap), *p;
	int rc = Z_OK;

	memset(&z, 0, sizeof z);
	if (o == NULL || n > (uInt)-1 ||
	    inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) {
		free(o);
		return tl_fail(e, "gzip: cannot start zlib");
	}
	z.next_in = (unsigned char *)b;
	while (rc != Z_STREAM_END) {
		if (got == cap) {
			if (cap >= max || (p = realloc(o, cap * 2)) == NULL) {
				rc = Z_MEM_ERROR;
				break;
			}
			o = p, cap *= 2;
		}
		z.avail_in = (uInt)(n - (size_t)(z.next_in - b));
		z.next_out = o + got;
		z.avail_out = (uInt)(cap - got);
		rc = inflate(&z, Z_NO_FLUSH);
		got = cap - z.avail_out;
		if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR)
			break;
		if (rc == Z_BUF_ERROR && z.avail_out != 0)
			break; /* input ended inside the stream */
	}
	inflateEnd(&z);
	if (rc != Z_STREAM_END) {
		free(o);
		return tl_fail(e, "gzip stream %s", rc == Z_MEM_ERROR ?
		    "inflates past its limit" : "damaged or cut short");
	}
	*out = o, *outlen = got;
	return 0;
}
