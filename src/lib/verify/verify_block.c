/* verify_block.c - reading a block file as vgis(5) describes it, on its
 * own (no producer code): size, channels, the vgis:* fqm:* geo:*
 * attributes and the content against the index ("index" violations). */
#include "verify/verify_impl.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "raster/attr_names.h"
#include "geo/georef.h"
#include "raster/raster.h"

/* The vgis:* attributes: what the file says it is, and the index's z
 * range and base error. */
static void
check_vgis(vf_lv *v, const rs_header *h, int bi, int bj)
{
	size_t k = (size_t)bj * v->bx + bi;
	int iv, p[2];
	double d, zr[2];

	if (rs_get_int(h, VGIS_ATTR_VERSION, &iv) < 0 || iv != VGIS_VERSION)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:version missing or not %d",
		    VGIS_VERSION);
	if (rs_get_int(h, VGIS_ATTR_LEVEL, &iv) < 0 || iv != v->l)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:level missing or not %d",
		    v->l);
	if (rs_get_v2i(h, VGIS_ATTR_BLOCK, p) < 0 || p[0] != bi || p[1] != bj)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:block missing or not "
		    "(%d,%d)", bi, bj);
	if (rs_get_v2i(h, VGIS_ATTR_ORIGIN, p) < 0 || p[0] != bi * BT_CELLS ||
	    p[1] != bj * BT_CELLS)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:origin missing or not "
		    "(%d,%d)", bi * BT_CELLS, bj * BT_CELLS);
	if (rs_get_double(h, VGIS_ATTR_BASE_ERROR, &d) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:base_error missing");
	else if (d != v->L->base[k])
		BNOTE(v, VF_INDEX, bi, bj, "vgis:base_error %.9g, the index "
		    "says %.9g", d, v->L->base[k]);
	if (rs_get_v2d(h, VGIS_ATTR_ZRANGE, zr) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "vgis:zrange missing");
	else if (zr[0] != v->L->zmin[k] || zr[1] != v->L->zmax[k])
		BNOTE(v, VF_INDEX, bi, bj, "vgis:zrange %.9g..%.9g, the index "
		    "says %.9g..%.9g", zr[0], zr[1], v->L->zmin[k],
		    v->L->zmax[k]);
}

/* The geo:* and fqm:* attributes carried over from the vertex map: the
 * index's georeferencing, level, size0, mode and kernel. */
static void
check_fqm(vf_lv *v, const rs_header *h, int bi, int bj)
{
	const vf_checker *c = v->c;
	georef g;
	tl_err e;
	const char *s, *what;
	int iv, p[2];

	if (rs_get_string(h, GEO_ATTR_MODEL) == NULL ||
	    rs_get_v2d(h, GEO_ATTR_ORIGIN, (double[2]){ 0 }) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "geo:model or geo:origin missing");
	else if (rs_get_georef(&g, h, &e) < 0)
		BNOTE(v, VF_INDEX, bi, bj, "%s", e.msg);
	else if ((what = geo_differs(&g, &c->ix.geo)) != NULL)
		BNOTE(v, VF_INDEX, bi, bj, "geo:%s differs from the index's "
		    "georef", what);
	if (rs_get_int(h, FQM_ATTR_LEVEL, &iv) < 0 || iv != v->l)
		BNOTE(v, VF_INDEX, bi, bj, "fqm:level missing or not %d", v->l);
	if (rs_get_v2i(h, FQM_ATTR_SIZE0, p) < 0 || p[0] != c->ix.size0[0] ||
	    p[1] != c->ix.size0[1])
		BNOTE(v, VF_INDEX, bi, bj, "fqm:size0 missing or not %dx%d",
		    c->ix.size0[0], c->ix.size0[1]);
	if ((s = rs_get_string(h, FQM_ATTR_MODE)) == NULL ||
	    strcmp(s, v->L->mode) != 0)
		BNOTE(v, VF_INDEX, bi, bj, "fqm:mode %s, the index says %s",
		    s ? s : "missing", v->L->mode);
	if ((s = rs_get_string(h, FQM_ATTR_KERNEL)) == NULL ||
	    strcmp(s, v->L->kernel) != 0)
		BNOTE(v, VF_INDEX, bi, bj, "fqm:kernel %s, the index says %s",
		    s ? s : "missing", v->L->kernel);
}

/* Where each vertex stands in level-0 columns and rows: its grid place
 * plus, displaced, its offsets through the metric embedding of fqm(5). */
static void
positions(vf_lv *v, vf_blk *b, int bi, int bj)
{
	for (int k = 0; k < VF_NV; k++) {
		long gi = (long)bi * BT_CELLS + k % BT_SIZE;
		long gj = (long)bj * BT_CELLS + k / BT_SIZE;
		double di = 0, dj = 0;
		if (v->disp && isfinite(b->x[k]) && isfinite(b->y[k]))
			geo_offset_to_grid(&v->c->metric, (double)(gi * v->s),
			    (double)(gj * v->s), b->x[k], b->y[k], &di, &dj);
		b->px[k] = (double)(gi * v->s) + di;
		b->py[k] = (double)(gj * v->s) + dj;
	}
}

/* E Z, or E X Y Z on displaced levels, in any order. */
static int
channels_ok(const vf_lv *v, const rs_header *h)
{
	if (h->nch != (v->disp ? 4 : 2) || rs_channel(h, "E") < 0 ||
	    rs_channel(h, "Z") < 0)
		return 0;
	return !v->disp || (rs_channel(h, "X") >= 0 && rs_channel(h, "Y") >= 0);
}

static void
channel_list(const rs_header *h, char *buf, size_t n)
{
	size_t len = 0;

	buf[0] = '\0';
	for (int c = 0; c < h->nch && len < n; c++)
		len += snprintf(buf + len, n - len, "%s%s", c ? " " : "",
		    h->ch[c]);
}

/* Reads block (bi, bj) into b; quiet: no notes (the pre-pass). */
void
vf_block_load(vf_lv *v, vf_blk *b, int bi, int bj, int quiet)
{
	char path[4096], chs[256];
	float row[4 * BT_SIZE];
	const rs_header *h;
	rs_reader *rd;
	tl_err e;
	int ch[4], n;

	assert(bi >= 0 && bj >= 0 && bi < v->bx && bj < v->by);
	b->ok = 0;
	snprintf(path, sizeof path, VGIS_BLOCK_PATH, v->c->dir, v->l, bj, bi);
	if ((rd = rs_open_regular(path, &e)) == NULL) {
		if (!quiet)
			BNOTE(v, VF_INDEX, bi, bj, "%s", e.msg);
		return;
	}
	h = rs_header_of(rd);
	if (h->width != BT_SIZE || h->height != BT_SIZE) {
		if (!quiet)
			BNOTE(v, VF_INDEX, bi, bj, "%s: %dx%d, a block is "
			    "129x129", path, h->width, h->height);
		goto done;
	}
	if (!channels_ok(v, h)) {
		channel_list(h, chs, sizeof chs);
		if (!quiet)
			BNOTE(v, VF_INDEX, bi, bj, "%s: channels %s, expected "
			    "%s", path, chs, v->disp ? "E X Y Z" : "E Z");
		goto done;
	}
	if (!quiet) {
		check_vgis(v, h, bi, bj);
		check_fqm(v, h, bi, bj);
	}
	n = h->nch;
	ch[0] = rs_channel(h, "Z"), ch[1] = rs_channel(h, "E");
	ch[2] = rs_channel(h, "X"), ch[3] = rs_channel(h, "Y");
	for (int j = 0; j < BT_SIZE; j++) {
		float *dst[4] = { b->z, b->e, b->x, b->y };
		if (rs_read_row(rd, row, &e) < 0) {
			if (!quiet)
				BNOTE(v, VF_INDEX, bi, bj, "%s", e.msg);
			goto done;
		}
		for (int q = 0; q < n; q++)
			memcpy(dst[q] + j * BT_SIZE, row + ch[q] * BT_SIZE,
			    BT_SIZE * sizeof *row);
	}
	positions(v, b, bi, bj);
	b->ok = 1;
done:
	rs_close(rd);
}

/* Z, X, Y finite; the z range and largest finite E those the index
 * lists. */
void
vf_block_content(vf_lv *v, const vf_blk *b, int bi, int bj)
{
	size_t k = (size_t)bj * v->bx + bi;
	double zmin = INFINITY, zmax = -INFINITY, emax = 0;
	int bad = 0;

	for (int q = 0; q < VF_NV; q++) {
		if (!isfinite(b->z[q]) || (v->disp &&
		    (!isfinite(b->x[q]) || !isfinite(b->y[q])))) {
			if (bad++ == 0)
				VNOTE(v, VF_INDEX, bi, bj, q, NAN, "Z %g X %g "
				    "Y %g: not finite", b->z[q],
				    v->disp ? b->x[q] : 0.0,
				    v->disp ? b->y[q] : 0.0);
			continue;
		}
		zmin = fmin(zmin, b->z[q]), zmax = fmax(zmax, b->z[q]);
		if (isfinite(b->e[q]) && b->e[q] < FLT_MAX)
			emax = fmax(emax, b->e[q]);
	}
	if (zmin != v->L->zmin[k] || zmax != v->L->zmax[k])
		BNOTE(v, VF_INDEX, bi, bj, "Z ranges %.9g..%.9g, the index "
		    "says %.9g..%.9g", zmin, zmax, v->L->zmin[k],
		    v->L->zmax[k]);
	if (emax != v->L->emax[k])
		BNOTE(v, VF_INDEX, bi, bj, "largest finite E %.9g, the index "
		    "says %.9g", emax, v->L->emax[k]);
	v->R->emax = fmax(v->R->emax, emax);
}
