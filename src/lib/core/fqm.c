/* fqm.c - FQM and vertex-map headers and rows (see fqm.h, fqm(5)). */
#include "core/fqm.h"

#include <assert.h>
#include <math.h>
#include <string.h>

static const char *const qch[10] = {
	"Q.a11", "Q.a12", "Q.a13", "Q.a22", "Q.a23", "Q.a33",
	"Q.b1", "Q.b2", "Q.b3", "Q.c",
};
_Static_assert(sizeof qch / sizeof qch[0] ==
    sizeof ((fqm_layout *)0)->q / sizeof ((fqm_layout *)0)->q[0],
    "one channel per quadric coefficient");
_Static_assert(FQM_BAND0_DOUBLES == 4 * 6, "4 corners x a[6]");

int
fqm_level_size(int n0, int level)
{
	long long span = n0 - 1, step = 1LL << level;

	return (int)((span + step - 1) / step) + 1;
}

int
fqm_levels(int w0, int h0)
{
	int l = 0;

	while (fqm_level_size(w0, l) > FQM_BLOCK || fqm_level_size(h0, l) >
	    FQM_BLOCK)
		l++;
	return l + 1;
}

static int
set_info(rs_header *h, const fqm_info *fi, const char *kind, tl_err *e)
{
	if (rs_set_int(h, FQM_ATTR_VERSION, FQM_VERSION, e) < 0 ||
	    rs_set_string(h, FQM_ATTR_KIND, kind, e) < 0 ||
	    rs_set_int(h, FQM_ATTR_LEVEL, fi->level, e) < 0 ||
	    rs_set_v2i(h, FQM_ATTR_SIZE0, fi->size0[0], fi->size0[1], e) < 0)
		return -1;
	return geo_to_header(&fi->geo, h, e);
}

int
fqm_header(rs_header *h, const fqm_info *fi, const char *kernel, tl_err *e)
{
	rs_header_init(h, fqm_level_size(fi->size0[0], fi->level),
	    fqm_level_size(fi->size0[1], fi->level));
	for (int k = 0; k < 10; k++)
		if (rs_add_channel(h, qch[k], e) < 0)
			return -1;
	if (rs_add_channel(h, "Z", e) < 0 || rs_add_channel(h, "S", e) < 0 ||
	    rs_add_channel(h, "V", e) < 0)
		return -1;
	if (set_info(h, fi, "fqm", e) < 0)
		return -1;
	return rs_set_string(h, FQM_ATTR_KERNEL, kernel, e);
}

int
fqm_info_of(const rs_header *h, const char *want, fqm_info *fi,
    const char *what, tl_err *e)
{
	const char *kind = rs_get_string(h, FQM_ATTR_KIND);
	int version;

	memset(fi, 0, sizeof *fi);
	if (kind == NULL || rs_get_int(h, FQM_ATTR_VERSION, &version) < 0)
		return tl_fail(e, "%s: not a quadric or vertex map "
		    "(no fqm:kind / fqm:version attribute)", what);
	if (version != FQM_VERSION)
		return tl_fail(e, "%s: fqm version %d, this program reads %d",
		    what, version, FQM_VERSION);
	if (want != NULL && strcmp(kind, want) != 0)
		return tl_fail(e, "%s: is a %s map, expected %s", what, kind,
		    want);
	if (rs_get_int(h, FQM_ATTR_LEVEL, &fi->level) < 0 ||
	    rs_get_v2i(h, FQM_ATTR_SIZE0, fi->size0) < 0)
		return tl_fail(e, "%s: fqm:level or fqm:size0 missing", what);
	if (fi->level < 0 || fi->level > 30 || fi->size0[0] < 1 ||
	    fi->size0[1] < 1)
		return tl_fail(e, "%s: bad fqm:level %d or fqm:size0 %dx%d",
		    what, fi->level, fi->size0[0], fi->size0[1]);
	if (h->width != fqm_level_size(fi->size0[0], fi->level) ||
	    h->height != fqm_level_size(fi->size0[1], fi->level))
		return tl_fail(e, "%s: size %dx%d is not that of level %d of "
		    "a %dx%d DEM", what, h->width, h->height, fi->level,
		    fi->size0[0], fi->size0[1]);
	if (geo_from_header(&fi->geo, h, e) < 0)
		return -1;
	fi->geo.width = fi->size0[0];
	fi->geo.height = fi->size0[1];
	return 0;
}

int
fqm_layout_of(const rs_header *h, fqm_layout *L, const char *what, tl_err *e)
{
	for (int k = 0; k < 10; k++)
		if ((L->q[k] = rs_need_channel(h, qch[k], what, e)) < 0)
			return -1;
	if ((L->z = rs_need_channel(h, "Z", what, e)) < 0 ||
	    (L->s = rs_need_channel(h, "S", what, e)) < 0 ||
	    (L->v = rs_need_channel(h, "V", what, e)) < 0)
		return -1;
	return 0;
}

/* A layout from fqm_layout_of: every channel found. */
static int
layout_ok(const fqm_layout *L)
{
	for (int k = 0; k < 10; k++)
		if (L->q[k] < 0)
			return 0;
	return L->z >= 0 && L->s >= 0 && L->v >= 0;
}

void
fqm_decode(const fqm_layout *L, const float *row, int w, fqm_vertex *out)
{
	assert(layout_ok(L));
	for (int i = 0; i < w; i++) {
		fqm_vertex *o = &out[i];
		for (int k = 0; k < 6; k++)
			o->q.a[k] = row[(size_t)L->q[k] * w + i];
		for (int k = 0; k < 3; k++)
			o->q.b[k] = row[(size_t)L->q[6 + k] * w + i];
		o->q.c = row[(size_t)L->q[9] * w + i];
		o->z = row[(size_t)L->z * w + i];
		o->s = row[(size_t)L->s * w + i];
		o->v = row[(size_t)L->v * w + i];
	}
}

void
fqm_encode(const fqm_layout *L, const fqm_vertex *in, int w, float *row)
{
	assert(layout_ok(L));
	for (int i = 0; i < w; i++) {
		const fqm_vertex *o = &in[i];
		for (int k = 0; k < 6; k++)
			row[(size_t)L->q[k] * w + i] = (float)o->q.a[k];
		for (int k = 0; k < 3; k++)
			row[(size_t)L->q[6 + k] * w + i] = (float)o->q.b[k];
		row[(size_t)L->q[9] * w + i] = (float)o->q.c;
		row[(size_t)L->z * w + i] = (float)o->z;
		row[(size_t)L->s * w + i] = (float)o->s;
		row[(size_t)L->v * w + i] = (float)o->v;
	}
}

/* The four triangles of a cell, both diagonals; the corner each one
 * leaves out: a corner's sum is the cell's total minus that triangle. */
static const int celltri[4][3] = {
	{ 0, 1, 2 }, { 0, 2, 3 }, /* diagonal 0-2 */
	{ 0, 1, 3 }, { 1, 2, 3 }, /* diagonal 1-3 */
};
static const int without[4] = { 3, 1, 2, 0 }; /* corner k: all but this */

void
fqm_band0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_metric *m,
    double *band)
{
	/* the metric along rows J and J + 1, taken at each cell's middle
	 * column (one value per row for per-row metrics) */
	double sx0[GEO_MAX_NODES], sx1[GEO_MAX_NODES];
	double y0[GEO_MAX_NODES], y1[GEO_MAX_NODES];

	geo_row_sx(m, J, sx0), geo_row_sx(m, J + 1, sx1);
	geo_row_y(m, J, y0), geo_row_y(m, J + 1, y1);
	for (int i = 0; i + 1 < w; i++) {
		double *out = band + (size_t)i * FQM_BAND0_DOUBLES, I = i + 0.5;
		double a = geo_on_row(m, sx0, I), b = geo_on_row(m, sx1, I);
		double dy = geo_on_row(m, y1, I) - geo_on_row(m, y0, I);
		double p[4][3] = {
			{ -0.5 * a, 0, z0[i] },
			{ 0.5 * a, 0, z0[i + 1] },
			{ 0.5 * b, dy, z1[i + 1] },
			{ -0.5 * b, dy, z1[i] },
		};
		int ok[4] = { v0[i], v0[i + 1], v1[i + 1], v1[i] };
		quadric t[4], total;

		quadric_zero(&total);
		for (int k = 0; k < 4; k++) {
			const int *c = celltri[k];
			quadric_zero(&t[k]);
			if (ok[c[0]] && ok[c[1]] && ok[c[2]])
				quadric_add_triangle(&t[k], p[c[0]], p[c[1]],
				    p[c[2]], 0.5);
			quadric_add(&total, &t[k], 1);
		}
		for (int k = 0; k < 4; k++)
			for (int c = 0; c < 6; c++)
				out[k * 6 + c] = total.a[c] - t[without[k]].a[c];
	}
}

#define BAND FQM_BAND0_DOUBLES

void
fqm_row0(const double *above, const double *below, const float *z,
    const unsigned char *valid, int w, fqm_vertex *out)
{
	for (int i = 0; i < w; i++) {
		fqm_vertex *o = &out[i];
		/* (band, cell, corner) touching vertex i */
		const double *c[4] = {
			above && i > 0 ? above + (size_t)(i - 1) * BAND + 2 * 6 :
			    NULL,
			above && i + 1 < w ? above + (size_t)i * BAND + 3 * 6 :
			    NULL,
			below && i > 0 ? below + (size_t)(i - 1) * BAND + 1 * 6 :
			    NULL,
			below && i + 1 < w ? below + (size_t)i * BAND + 0 * 6 :
			    NULL,
		};
		quadric_zero(&o->q);
		for (int k = 0; k < 4; k++)
			if (c[k] != NULL)
				for (int a = 0; a < 6; a++)
					o->q.a[a] += c[k][a];
		o->z = o->s = z[i];
		o->v = valid[i] ? 1 : 0;
	}
}

rs_reader *
fqm_open(const char *path, fqm_info *fi, fqm_layout *L, tl_err *e)
{
	const char *what = tl_name(path, 0);
	rs_reader *in;

	if ((in = rs_open(path, e)) == NULL)
		return NULL;
	if (fqm_info_of(rs_header_of(in), "fqm", fi, what, e) < 0 ||
	    fqm_layout_of(rs_header_of(in), L, what, e) < 0) {
		rs_close(in);
		return NULL;
	}
	return in;
}

int
fqm_check_row(const float *row, int w, int nch, int y, const char *what,
    tl_err *e)
{
	for (int c = 0; c < nch; c++) {
		const float *p = row + (size_t)c * (size_t)w;
		for (int i = 0; i < w; i++)
			if (!isfinite(p[i]))
				return tl_fail(e, "%s: row %d, channel %d: %s at "
				    "column %d (damaged?)", what, y, c,
				    isnan(p[i]) ? "NaN" : "infinite value", i);
	}
	return 0;
}
