/* stage_level0.c - dem2fqm's work (stage.h): a DEM's level-0 FQM, or of
 * a window of its filled samples for a plan's band job; its header. */
#include <string.h>

#include "stage.h"
#include "qem/fqm0.h"
#include "base/paths.h"
#include "raster/rowpipe.h"

static int
convert(const cli *c, const stage_level0 *o, dem *d, tl_err *e)
{
	fqm_info fi = { .geo = *dem_georef(d) };
	int win[2] = { o->win[0], o->win[1] };
	rs_header h;
	geo_ground m = { 0 };
	fqm0_source j = { 0 };
	char note[512];
	int r = -1;

	fi.size0[0] = fi.geo.width, fi.size0[1] = fi.geo.height;
	if (fi.geo.width < 3 || fi.geo.height < 3)
		return tl_fail(e, "%s: %dx%d samples: a DEM needs at least 3x3",
		    tl_name(o->in, 0), fi.geo.width, fi.geo.height);
	if (!o->has_win)
		win[0] = 0, win[1] = fi.geo.width;
	else if (win[1] > fi.geo.width || win[1] - win[0] < 3)
		return tl_fail(e, "-w %d,%d: not 3 or more of the DEM's %d "
		    "columns", win[0], win[1], fi.geo.width);
	fi.x0 = win[0];
	if (dem_ground_note(d, &c->dem, tl_name(o->in, 0), note, sizeof note))
		cli_warn(c, "%s", note);
	rs_header_init(&h, 0, 0);
	if (geo_ground_init(&m, &fi.geo, e) == 0 &&
	    fqm_header(&h, &fi, "none", e) == 0 &&
	    fqm_layout_of(&h, &j.L, c->prog, e) == 0) {
		/* the window's columns, its metric answering in them */
		h.width = win[1] - win[0];
		m.x0 = win[0];
		if (fqm0_init_cols(&j.s, d, &m, win[0], h.width, e) == 0)
			r = rowpipe_run(c->prog, o->out, &h, c->comp,
			    fqm0_encoded_row, &j, e);
	}
	fqm0_free(&j.s);
	rs_header_free(&h);
	geo_ground_free(&m);
	return r;
}

int
stage_guard(const char *dem_path, const char *filled_in,
    const char *const *outs, int n, tl_err *e)
{
	tl_paths s = { 0 };
	int r;

	if (n == 0)
		return 0;
	r = dem_paths(&s, dem_path, e);
	if (r == 0 && filled_in != NULL)
		r = tl_paths_add(&s, filled_in, 0, e, "the input filled DEM %s",
		    filled_in);
	for (int k = 0; r == 0 && k < n; k++)
		r = tl_paths_check(&s, outs[k], e);
	tl_paths_free(&s);
	return r;
}

int
stage_dem2fqm(const cli *c, const stage_level0 *o, tl_err *e)
{
	int n = !o->info && strcmp(o->out, "-") != 0;
	dem *d;
	int r;

	if (stage_guard(o->in, o->filled, &o->out, n, e) < 0)
		return -1;
	/* -I reads the header only; -II and the conversion every sample;
	 * -F the header, the samples from the filled DEM */
	if (o->open != NULL)
		d = o->open(o->open_ctx, e);
	else if (o->info == 1)
		d = dem_open_info(o->in, &c->dem, e);
	else if (o->filled != NULL)
		d = dem_open_filled(o->in, &c->dem, o->filled, e);
	else if (o->info)
		d = dem_open(o->in, &c->dem, e);
	else /* rows in order: they flow while the fill goes on */
		d = dem_open_streamed(o->in, &c->dem, e);
	if (d == NULL)
		return -1;
	r = o->info ? dem_info_print(d, stdout, e) : convert(c, o, d, e);
	if (o->open == NULL)
		dem_close(d);
	return r;
}
