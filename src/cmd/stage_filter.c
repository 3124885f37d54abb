/* stage_filter.c - fqmfilter's work (stage.h): one level of QEM
 * filtering, the coarse level's rows made as the fine rows come in. */
#include "stage.h"
#include "qem/fqm_input.h"
#include "base/paths.h"
#include "raster/rowpipe.h"

/* The work: the fine rows read so far, the filter. */
typedef struct {
	fqm_input in;
	filter_state f;
} job;

static int
coarse_row(void *ctx, int y, float *row, tl_err *e)
{
	job *j = ctx;

	while (!filter_ready(&j->f)) {
		if (fqm_input_read(&j->in, e) < 0)
			return -1;
		filter_push_row(&j->f, &j->in.L, j->in.row);
	}
	filter_pull_row(&j->f, &j->in.L, row);
	return 0;
}

int
stage_fqmfilter(const cli *c, const stage_filter *o, tl_err *e)
{
	job j = { 0 };
	rs_header oh;
	const rs_header *h;
	int r = -1;

	rs_header_init(&oh, 0, 0);
	if (tl_path_check_raster(o->out, o->in, "FQM", e) < 0 ||
	    fqm_input_open(&j.in, o->in, e) < 0)
		goto done;
	h = j.in.h;
	if (h->width <= 2 && h->height <= 2) {
		tl_fail(e, "%s: level %d is %dx%d: nothing left to reduce",
		    j.in.what, j.in.fi.level, h->width, h->height);
		goto done;
	}
	/* a window sub-samples on the level's grid: coarse vertex k at fine
	 * 2k counts from the level's column 0 */
	if (j.in.fi.x0 % 2 != 0) {
		tl_fail(e, "%s: a window from column %d: odd, so not on the "
		    "coarse grid", j.in.what, j.in.fi.x0);
		goto done;
	}
	if (filter_init(&j.f, o->kernel, j.in.fi.level, h->width, h->height,
	    j.in.fi.size0[0], j.in.fi.size0[1], &j.in.m, e) < 0 ||
	    rs_header_copy(&oh, h, e) < 0)
		goto done;
	j.f.x0 = j.in.fi.x0;
	oh.width = j.f.cw, oh.height = j.f.ch;
	rs_unset(&oh, RS_ATTR_X0);
	if (rs_set_int(&oh, FQM_ATTR_LEVEL, j.in.fi.level + 1, e) < 0 ||
	    rs_set_string(&oh, FQM_ATTR_KERNEL, o->kernel->name, e) < 0 ||
	    (j.f.x0 != 0 && rs_set_int(&oh, RS_ATTR_X0, j.f.x0 / 2, e) < 0))
		goto done;
	r = rowpipe_run_cut(c->prog, o->out, &oh, o->has_cut ? o->cut : NULL,
	    c->comp, coarse_row, &j, e);
done:
	fqm_input_close(&j.in);
	rs_header_free(&oh);
	filter_free(&j.f);
	return r;
}
