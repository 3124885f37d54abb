/* rg_image.c - a tile's RGB pixels as a PNG (libpng, lossless, fixed
 * settings) or a lossless WebP (libwebp) in memory (rgb.h). */
#include <stdlib.h>
#include <string.h>

#include <png.h>
#include <webp/encode.h>

#include "rgb/rgb.h"

const char *
rg_format_ext(enum rg_format f)
{
	return f == RG_PNG ? "png" : "webp";
}

typedef struct {
	unsigned char *p;
	size_t n, cap;
	int oom;
} membuf;

static void
put(png_structp png, png_bytep data, png_size_t n)
{
	membuf *m = png_get_io_ptr(png);

	if (m->oom)
		return;
	if (m->n + n > m->cap) {
		size_t cap = (m->cap + n) * 2;
		unsigned char *q = realloc(m->p, cap);
		if (q == NULL) {
			m->oom = 1;
			return;
		}
		m->p = q, m->cap = cap;
	}
	memcpy(m->p + m->n, data, n);
	m->n += n;
}

static void
flush(png_structp png)
{
	(void)png;
}

static int
png_mem(const unsigned char *rgb, int dim, unsigned char **buf, size_t *n,
    tl_err *e)
{
	membuf m = { 0 };
	png_structp png;
	png_infop info = NULL;

	png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	if (png == NULL || (info = png_create_info_struct(png)) == NULL) {
		png_destroy_write_struct(&png, NULL);
		return tl_fail(e, "libpng: out of memory");
	}
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		free(m.p);
		return tl_fail(e, "libpng: cannot encode a tile");
	}
	png_set_write_fn(png, &m, put, flush);
	png_set_IHDR(png, info, dim, dim, 8, PNG_COLOR_TYPE_RGB,
	    PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
	    PNG_FILTER_TYPE_DEFAULT);
	png_set_compression_level(png, 6);
	png_write_info(png, info);
	for (int j = 0; j < dim; j++)
		png_write_row(png, (png_const_bytep)(rgb + (size_t)j * dim * 3));
	png_write_end(png, info);
	png_destroy_write_struct(&png, &info);
	if (m.oom) {
		free(m.p);
		return tl_fail(e, "libpng: out of memory");
	}
	*buf = m.p, *n = m.n;
	return 0;
}

static int
webp_mem(const unsigned char *rgb, int dim, unsigned char **buf, size_t *n,
    tl_err *e)
{
	uint8_t *out = NULL;
	size_t k;

	k = WebPEncodeLosslessRGB(rgb, dim, dim, dim * 3, &out);
	if (k == 0)
		return tl_fail(e, "libwebp: cannot encode a tile");
	/* the caller frees with free(3): copy out of WebP's allocator */
	if ((*buf = malloc(k)) == NULL) {
		WebPFree(out);
		return tl_fail(e, "out of memory");
	}
	memcpy(*buf, out, k);
	WebPFree(out);
	*n = k;
	return 0;
}

int
rg_image(enum rg_format f, const unsigned char *rgb, int dim,
    unsigned char **buf, size_t *n, tl_err *e)
{
	return f == RG_PNG ? png_mem(rgb, dim, buf, n, e) :
	    webp_mem(rgb, dim, buf, n, e);
}
