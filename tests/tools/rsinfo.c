/* rsinfo - print the header of an fqm raster (EXR or stream) and, with -c,
 * a hash of its pixel bytes and per-channel min/max: a test tool for
 * comparing rasters across forms and reading attributes exrheader cannot
 * show (v2d values) or files it cannot open (streams).
 *
 * With -d CH -o OUT it instead copies the raster to OUT without channel
 * CH (to make rasters with wrong channels for the tests).
 *
 * With several files, each one's report follows a line "file NAME".
 *
 * usage: rsinfo [-c] file ...
 *        rsinfo -d channel -o out file */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "raster/raster.h"

static void
print_attr(const rs_attr *a)
{
	printf("attr %s ", a->name);
	switch (a->type) {
	case RS_INT:
		printf("int %d\n", a->v.i);
		break;
	case RS_DOUBLE:
		printf("double %.17g\n", a->v.d);
		break;
	case RS_STRING:
		printf("string %s\n", a->s);
		break;
	case RS_V2I:
		printf("v2i %d %d\n", a->v.v2i[0], a->v.v2i[1]);
		break;
	case RS_V2D:
		printf("v2d %.17g %.17g\n", a->v.v2d[0], a->v.v2d[1]);
		break;
	}
}

static int
drop(rs_reader *r, const char *ch, const char *out, tl_err *e)
{
	const rs_header *h = rs_header_of(r);
	rs_header oh;
	rs_writer *w;
	int k = rs_need_channel(h, ch, "input", e), n = h->width;
	float *row = malloc((size_t)n * h->nch * sizeof *row);

	if (k < 0 || rs_header_copy(&oh, h, e) < 0)
		return -1;
	rs_clear_channels(&oh);
	for (int i = 0; i < h->nch; i++)
		if (i != k && rs_add_channel(&oh, h->ch[i], e) < 0)
			return -1;
	if ((w = rs_create(out, &oh, RS_ZIP, e)) == NULL)
		return -1;
	for (int y = 0; y < h->height; y++) {
		if (rs_read_row(r, row, e) < 0)
			return -1;
		/* channel-planar: close the gap left by channel k */
		memmove(row + (size_t)k * n, row + (size_t)(k + 1) * n,
		    (size_t)(h->nch - k - 1) * n * sizeof *row);
		if (rs_write_row(w, row, e) < 0)
			return -1;
	}
	return rs_finish(w, e);
}

/* The header and, with sums, the pixels' hash and ranges. */
static int
report(rs_reader *r, int sums)
{
	tl_err e;
	const rs_header *h = rs_header_of(r);
	printf("size %d %d\nchannels", h->width, h->height);
	for (int k = 0; k < h->nch; k++)
		printf(" %s", h->ch[k]);
	printf("\n");
	for (int k = 0; k < h->nattr; k++)
		print_attr(&h->attr[k]);
	if (sums) {
		size_t n = (size_t)h->width * h->nch;
		float *row = malloc(n * sizeof *row);
		double *lo = malloc(h->nch * sizeof *lo);
		double *hi = malloc(h->nch * sizeof *hi);
		uint64_t hash = 1469598103934665603ULL; /* FNV-1a */
		for (int k = 0; k < h->nch; k++)
			lo[k] = INFINITY, hi[k] = -INFINITY;
		for (int y = 0; y < h->height; y++) {
			if (rs_read_row(r, row, &e) < 0) {
				fprintf(stderr, "rsinfo: %s\n", e.msg);
				return -1;
			}
			const unsigned char *p = (const unsigned char *)row;
			for (size_t b = 0; b < n * sizeof *row; b++)
				hash = (hash ^ p[b]) * 1099511628211ULL;
			for (int k = 0; k < h->nch; k++)
				for (int i = 0; i < h->width; i++) {
					double v = row[(size_t)k * h->width + i];
					lo[k] = fmin(lo[k], v), hi[k] = fmax(hi[k], v);
				}
		}
		printf("hash %016" PRIx64 "\n", hash);
		for (int k = 0; k < h->nch; k++)
			printf("range %s %.9g %.9g\n", h->ch[k], lo[k], hi[k]);
		free(row), free(lo), free(hi);
	}
	rs_close(r);
	return 0;
}

/* A test tool exits right after its work: its own leaks are not what
 * make check-asan looks for (the programs' and the library's are). */
const char *__asan_default_options(void);
const char *
__asan_default_options(void)
{
	return "detect_leaks=0";
}

int
main(int argc, char **argv)
{
	int c, sums = 0;
	const char *dropch = NULL, *out = NULL;
	tl_err e;
	rs_reader *r;

	while ((c = getopt(argc, argv, "cd:o:")) != -1)
		if (c == 'c')
			sums = 1;
		else if (c == 'd')
			dropch = optarg;
		else if (c == 'o')
			out = optarg;
		else
			return 2;
	if (argc - optind < 1 || (dropch != NULL && argc - optind != 1)) {
		fprintf(stderr, "usage: rsinfo [-c] file ...\n");
		return 2;
	}
	if (dropch != NULL && out != NULL) {
		if ((r = rs_open(argv[optind], &e)) == NULL ||
		    drop(r, dropch, out, &e) < 0) {
			fprintf(stderr, "rsinfo: %s\n", e.msg);
			return 1;
		}
		return 0;
	}
	for (int a = optind; a < argc; a++) {
		if (argc - optind > 1)
			printf("file %s\n", argv[a]);
		if ((r = rs_open(argv[a], &e)) == NULL) {
			fprintf(stderr, "rsinfo: %s\n", e.msg);
			return 1;
		}
		if (report(r, sums) < 0)
			return 1;
	}
	return 0;
}
