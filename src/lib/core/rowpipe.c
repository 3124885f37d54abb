/* rowpipe.c - the row loop every filter drives (rowpipe.h). */
#include <stdlib.h>

#include "core/rowpipe.h"
#include "core/progress.h"

int
rowpipe_run(const char *label, const char *out, const rs_header *h,
    enum rs_compression comp, rowpipe_fn fn, void *ctx, tl_err *e)
{
	rs_writer *w = NULL;
	float *row;
	tl_progress pr;
	int r = -1;

	if ((row = tl_alloc((size_t)h->width * h->nch, sizeof *row, e)) == NULL)
		return -1;
	/* created after the caller's set-up, so a bad input leaves no file */
	if ((w = rs_create(out, h, comp, e)) == NULL)
		goto done;
	tl_progress_start(&pr, label, h->height);
	for (int y = 0; y < h->height; y++) {
		if (fn(ctx, y, row, e) < 0 || rs_write_row(w, row, e) < 0)
			goto done;
		tl_progress_step(&pr, y + 1);
	}
	tl_progress_end(&pr);
	r = rs_finish(w, e);
	w = NULL;
done:
	rs_abort(w);
	free(row);
	return r;
}
