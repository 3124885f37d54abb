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

/* The x, y parts of the edges e1 = p1 - p0, e2 = p2 - p0 of the cell's
 * triangles (celltri), as quadric_add_triangle would form them from the
 * corners of the trapezoid of widths a (row J) and b (row J + 1) and
 * height dy. They depend on the metric only: one per band for a per-row
 * metric, whose cells are all alike. */
typedef struct {
	double e1[4][2], e2[4][2];
} cell_shape;

static void
cell_shape_of(double a, double b, double dy, cell_shape *s)
{
	const double p[4][2] = {
		{ -0.5 * a, 0 }, { 0.5 * a, 0 }, { 0.5 * b, dy }, { -0.5 * b, dy },
	};

	for (int k = 0; k < 4; k++) {
		const int *c = celltri[k];
		for (int d = 0; d < 2; d++) {
			s->e1[k][d] = p[c[1]][d] - p[c[0]][d];
			s->e2[k][d] = p[c[2]][d] - p[c[0]][d];
		}
	}
}

/* A cell's corner sums C[k] (corner k as in fqm.h): each triangle's A
 * (zero for one with a void corner), the cell's total in the triangles'
 * order, and each corner's total less the triangle that leaves it out.
 * z[] and ok[] are the corners' heights and validity. */
static inline void
cell_corners(const cell_shape *s, const double z[4], const int ok[4],
    double C[4][6])
{
	double t[4][6], total[6];

	for (int k = 0; k < 4; k++) {
		const int *c = celltri[k];
		if (ok[c[0]] && ok[c[1]] && ok[c[2]]) {
			double e1[3] = { s->e1[k][0], s->e1[k][1],
			    z[c[1]] - z[c[0]] };
			double e2[3] = { s->e2[k][0], s->e2[k][1],
			    z[c[2]] - z[c[0]] };
			quadric_triangle_a(e1, e2, 0.5, t[k]);
		} else {
			for (int a = 0; a < 6; a++)
				t[k][a] = 0;
		}
	}
	for (int a = 0; a < 6; a++)
		total[a] = 0 + t[0][a] + t[1][a] + t[2][a] + t[3][a];
	for (int k = 0; k < 4; k++)
		for (int a = 0; a < 6; a++)
			C[k][a] = total[a] - t[without[k]][a];
}

/* The metric along rows J and J + 1, taken at each cell's middle column
 * (one value per row for per-row metrics). */
typedef struct {
	const geo_metric *m;
	double sx0[GEO_MAX_NODES], sx1[GEO_MAX_NODES];
	double y0[GEO_MAX_NODES], y1[GEO_MAX_NODES];
} band_metric;

static void
band_metric_of(const geo_metric *m, int J, band_metric *b)
{
	b->m = m;
	geo_row_sx(m, J, b->sx0), geo_row_sx(m, J + 1, b->sx1);
	geo_row_y(m, J, b->y0), geo_row_y(m, J + 1, b->y1);
}

/* The shape of cell i, computed only where it differs from cell i - 1's
 * (every cell of a per-row metric's band is alike). */
static inline void
cell_shape_at(const band_metric *b, size_t i, cell_shape *s)
{
	const geo_metric *m = b->m;
	double I = i + 0.5;

	if (i == 0 || !m->per_row)
		cell_shape_of(geo_on_row(m, b->sx0, I),
		    geo_on_row(m, b->sx1, I),
		    geo_on_row(m, b->y1, I) - geo_on_row(m, b->y0, I), s);
}

void
fqm_band0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_metric *m,
    double *band)
{
	band_metric b;
	cell_shape s;

	band_metric_of(m, J, &b);
	for (size_t i = 0; i + 1 < (size_t)w; i++) {
		const double z[4] = { z0[i], z0[i + 1], z1[i + 1], z1[i] };
		const int ok[4] = { v0[i], v0[i + 1], v1[i + 1], v1[i] };
		cell_shape_at(&b, i, &s);
		cell_corners(&s, z, ok, (double (*)[6])(band +
		    i * FQM_BAND0_DOUBLES));
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

/* fqm_step0's work: A of row J's vertices into out[].q.a or, encoded,
 * into the channel planes qa[] (the other of the two NULL). Per vertex
 * the sum fqm_row0 makes, in its order: part[] holds the first two terms
 * (the band above), the cells of band J on either side add the last two,
 * and the same cells' upper corners start row J + 1's part[]. */
static inline void
step0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, size_t w, int J, const geo_metric *m,
    double *part, fqm_vertex *out, float *const qa[6])
{
	double c1[6] = { 0 }, c2[6] = { 0 }; /* cell i - 1's corners 1, 2 */
	band_metric b;
	cell_shape s;

	if (z1 == NULL) { /* the last row: no band below */
		for (size_t i = 0; i < w; i++)
			for (int a = 0; a < 6; a++) {
				if (out != NULL)
					out[i].q.a[a] = part[i * 6 + a];
				else
					qa[a][i] = (float)part[i * 6 + a];
			}
		return;
	}
	band_metric_of(m, J, &b);
	for (size_t i = 0; i < w; i++) {
		double C[4][6];
		if (i + 1 < w) {
			const double z[4] = { z0[i], z0[i + 1], z1[i + 1],
			    z1[i] };
			const int ok[4] = { v0[i], v0[i + 1], v1[i + 1], v1[i] };
			cell_shape_at(&b, i, &s);
			cell_corners(&s, z, ok, C);
		}
		for (int a = 0; a < 6; a++) {
			double q = part[i * 6 + a], r = 0;
			if (i > 0)
				q += c1[a], r += c2[a];
			if (i + 1 < w)
				q += C[0][a], r += C[3][a];
			if (out != NULL)
				out[i].q.a[a] = q;
			else
				qa[a][i] = (float)q;
			part[i * 6 + a] = r;
			if (i + 1 < w)
				c1[a] = C[1][a], c2[a] = C[2][a];
		}
	}
}

void
fqm_step0(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_metric *m,
    double *part, fqm_vertex *out)
{
	for (int i = 0; i < w; i++) {
		fqm_vertex *o = &out[i];
		quadric_zero(&o->q);
		o->z = o->s = z0[i];
		o->v = v0[i] ? 1 : 0;
	}
	step0(z0, v0, z1, v1, (size_t)w, J, m, part, out, NULL);
}

void
fqm_step0_encode(const float *z0, const unsigned char *v0, const float *z1,
    const unsigned char *v1, int w, int J, const geo_metric *m,
    double *part, const fqm_layout *L, float *row)
{
	size_t W = (size_t)w;
	float *qa[6];

	assert(layout_ok(L));
	for (int a = 0; a < 6; a++)
		qa[a] = row + (size_t)L->q[a] * W;
	step0(z0, v0, z1, v1, W, J, m, part, NULL, qa);
	/* b = 0 and c = 0: +0.0f is all zero bytes */
	for (int c = 6; c < 10; c++)
		memset(row + (size_t)L->q[c] * W, 0, W * sizeof *row);
	/* Z and S: a finite float is its own double and back */
	memcpy(row + (size_t)L->z * W, z0, W * sizeof *row);
	memcpy(row + (size_t)L->s * W, z0, W * sizeof *row);
	for (size_t i = 0; i < W; i++)
		row[(size_t)L->v * W + i] = v0[i] ? 1 : 0;
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
