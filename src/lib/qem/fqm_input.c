/* fqm_input.c - an FQM read row by row (fqm_input.h). */
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "qem/fqm_input.h"
#include "base/simd.h"

int
fqm_input_open(fqm_input *in, const char *path, tl_err *e)
{
	memset(in, 0, sizeof *in);
	in->what = tl_name(path, 0);
	if ((in->r = fqm_open(path, &in->fi, &in->L, e)) == NULL)
		return -1;
	in->h = rs_header_of(in->r);
	if (geo_ground_init(&in->m, &in->fi.geo, e) < 0)
		return -1;
	/* a window's metric answers in its own columns */
	in->m.x0 = (double)in->fi.x0 * (double)(1L << in->fi.level);
	in->buf = tl_alloc((size_t)in->h->width * in->h->nch, sizeof *in->buf,
	    e);
	in->v = tl_alloc(in->h->width, sizeof *in->v, e);
	return in->buf != NULL && in->v != NULL ? 0 : -1;
}

int
fqm_input_read(fqm_input *in, tl_err *e)
{
	size_t n = (size_t)in->h->width * (size_t)in->h->nch;

	assert(in->y < in->h->height);
	if ((in->row = rs_read_row_view(in->r, in->buf, e)) == NULL)
		return -1;
	/* the vector test first; fqm_check_row names the first bad value */
	if (!vec_all_finite(in->row, n) && fqm_check_row(in->row, 0,
	    in->h->width, in->h->nch, in->y, in->what, e) < 0)
		return -1;
	in->y++;
	return 0;
}

int
fqm_input_next(fqm_input *in, tl_err *e)
{
	if (fqm_input_read(in, e) < 0)
		return -1;
	fqm_decode(&in->L, in->row, in->h->width, in->v);
	return 0;
}

void
fqm_input_close(fqm_input *in)
{
	rs_close(in->r);
	geo_ground_free(&in->m);
	free(in->buf), free(in->v);
	memset(in, 0, sizeof *in);
}
