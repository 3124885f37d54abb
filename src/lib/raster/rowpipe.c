/* rowpipe.c - the row loop every filter drives (rowpipe.h). */
#include <stdlib.h>
#include <string.h>

#include "raster/attr_names.h"
#include "raster/rowpipe.h"
#include "base/progress.h"

int
rowpipe_run(const char *label, const char *out, const rs_header *h,
    enum rs_compression comp, rowpipe_fn fn, void *ctx, tl_err *e)
{
	rs_writer *w = NULL;
	float *own, *row;
	tl_progress pr;
	int r = -1;

	if ((own = tl_alloc((size_t)h->width * h->nch, sizeof *own, e)) == NULL)
		return -1;
	/* created after the caller's set-up, so a bad input leaves no file */
	if ((w = rs_create(out, h, comp, e)) == NULL)
		goto done;
	tl_progress_start(&pr, label, h->height);
	for (int y = 0; y < h->height; y++) {
		/* made in place where the output is a ring of rows */
		if ((row = rs_write_row_buffer(w, own, e)) == NULL ||
		    fn(ctx, y, row, e) < 0 || rs_write_row(w, row, e) < 0)
			goto done;
		tl_progress_step(&pr, y + 1);
	}
	tl_progress_end(&pr);
	r = rs_finish(w, e);
	w = NULL;
done:
	rs_abort(w);
	free(own);
	return r;
}

/* rowpipe_run_cut's callback: fn's whole row, then the kept columns. */
typedef struct {
	rowpipe_fn fn;
	void *ctx;
	int w, nch, c0, n;
	float *full;
} cutter;

static int
cut_row(void *ctx, int y, float *row, tl_err *e)
{
	const cutter *k = ctx;

	if (k->fn(k->ctx, y, k->full, e) < 0)
		return -1;
	for (int c = 0; c < k->nch; c++)
		memcpy(row + (size_t)c * k->n, k->full + (size_t)c * k->w +
		    k->c0, (size_t)k->n * sizeof *row);
	return 0;
}

int
rowpipe_run_cut(const char *label, const char *out, const rs_header *h,
    const int *cut, enum rs_compression comp, rowpipe_fn fn, void *ctx,
    tl_err *e)
{
	cutter k = { fn, ctx, h->width, h->nch, 0, 0, NULL };
	rs_header ch;
	int x0 = 0, r = -1;

	if (cut == NULL)
		return rowpipe_run(label, out, h, comp, fn, ctx, e);
	if (rs_get_int(h, RS_ATTR_X0, &x0) < 0)
		x0 = 0;
	k.c0 = cut[0] - x0, k.n = cut[1] - cut[0];
	if (k.c0 < 0 || k.n < 1 || k.c0 + k.n > h->width)
		return tl_fail(e, "-C %d,%d: not inside the columns made, "
		    "%d..%d", cut[0], cut[1], x0, x0 + h->width - 1);
	rs_header_init(&ch, 0, 0);
	if (rs_header_copy(&ch, h, e) < 0)
		return -1;
	ch.width = k.n;
	rs_unset(&ch, RS_ATTR_X0);
	if ((cut[0] == 0 || rs_set_int(&ch, RS_ATTR_X0, cut[0], e) == 0) &&
	    (k.full = tl_alloc((size_t)h->width * h->nch, sizeof *k.full,
	    e)) != NULL)
		r = rowpipe_run(label, out, &ch, comp, cut_row, &k, e);
	free(k.full);
	rs_header_free(&ch);
	return r;
}
