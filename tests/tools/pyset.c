/* pyset - one value of a block file (or any EXR raster) changed in place,
 * everything else (channels, attributes) kept: hostile pyramids for the
 * tests. A test tool.
 *
 * usage: pyset file channel col row value     ("nan", "inf", "-1", ...) */
#include <stdio.h>
#include <stdlib.h>

#include "raster/raster.h"

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
	rs_reader *r;
	rs_writer *w;
	rs_header h;
	float *rows;
	size_t n;
	int c, col, row;
	tl_err e;

	if (argc != 6) {
		fprintf(stderr, "usage: pyset file channel col row value\n");
		return 2;
	}
	if ((r = rs_open(argv[1], &e)) == NULL ||
	    rs_header_copy(&h, rs_header_of(r), &e) < 0 ||
	    (c = rs_need_channel(&h, argv[2], argv[1], &e)) < 0)
		goto fail;
	col = atoi(argv[3]), row = atoi(argv[4]);
	if (col < 0 || row < 0 || col >= h.width || row >= h.height) {
		fprintf(stderr, "pyset: %d,%d outside %dx%d\n", col, row,
		    h.width, h.height);
		return 2;
	}
	n = (size_t)h.width * h.nch;
	if ((rows = calloc(n * h.height, sizeof *rows)) == NULL)
		return 1;
	for (int j = 0; j < h.height; j++)
		if (rs_read_row(r, rows + j * n, &e) < 0)
			goto fail;
	rs_close(r);
	rows[row * n + (size_t)c * h.width + col] = strtof(argv[5], NULL);
	if ((w = rs_create(argv[1], &h, RS_ZIP, &e)) == NULL)
		goto fail;
	for (int j = 0; j < h.height; j++)
		if (rs_write_row(w, rows + j * n, &e) < 0)
			goto fail;
	if (rs_finish(w, &e) < 0)
		goto fail;
	return 0;
fail:
	fprintf(stderr, "pyset: %s\n", e.msg);
	return 1;
}
