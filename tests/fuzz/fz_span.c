/* fz_span - windowed reads (rs_read_span, what a piece of tilepack
 * reads of a vertex map) against whole rows: spans may never accept a
 * raster that whole rows refuse (damage inside a row passed on, fqm(5)),
 * nor give other values. The first two bytes pick the window (its first
 * column and width, as fractions of the width); the rest is the raster. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/raster.h"
#include "fuzz.h"

/* Every row whole into a (w x nch x h floats); 0 when all were read. */
static int
rows(const char *path, float **a, int *w, int *nch, int *h)
{
	rs_reader *r;
	tl_err e;
	int ok = 0;

	*a = NULL;
	if ((r = rs_open(path, &e)) == NULL)
		return -1;
	*w = rs_header_of(r)->width, *nch = rs_header_of(r)->nch;
	*h = rs_header_of(r)->height;
	*a = malloc((size_t)*w * *nch * *h * sizeof **a);
	for (int y = 0; *a != NULL && y < *h && ok == 0; y++)
		ok = rs_read_row(r, *a + (size_t)y * *w * *nch, &e);
	rs_close(r);
	return *a != NULL && ok == 0 ? 0 : -1;
}

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *path;
	float *a, *span;
	rs_reader *r;
	tl_err e;
	int w, nch, h, x0, n, whole, ok = 0;

	/* a band list's spans read only the bands they overlap (fqm(5)) */
	if (size < 2 || (size >= 10 && memcmp(data + 2, "fqm-band", 8) == 0) ||
	    (path = fuzz_file("s", data + 2, size - 2)) == NULL)
		return 0;
	whole = rows(path, &a, &w, &nch, &h);
	if (a == NULL || (r = rs_open(path, &e)) == NULL) {
		free(a);
		return 0;
	}
	x0 = (int)((long long)data[0] * w / 256);
	n = 1 + (int)((long long)data[1] * (w - x0 - 1) / 255);
	if ((span = malloc((size_t)n * nch * sizeof *span)) == NULL)
		abort();
	for (int y = 0; y < h && ok == 0; y++) {
		if ((ok = rs_read_span(r, x0, n, span, &e)) < 0)
			break;
		for (int c = 0; c < nch && whole == 0; c++)
			if (memcmp(span + (size_t)c * n, a + ((size_t)y * nch +
			    c) * w + x0, (size_t)n * sizeof *span) != 0)
				abort(); /* other values than the rows' */
	}
	/* every span read, the last row's trailer with it: spans accepted */
	if (ok == 0 && whole < 0) {
		fprintf(stderr, "fz_span: spans of %d..%d accepted what rows "
		    "refuse\n", x0, x0 + n - 1);
		abort();
	}
	free(span), free(a);
	rs_close(r);
	return 0;
}
