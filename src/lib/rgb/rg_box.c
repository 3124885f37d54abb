/* rg_box.c - dem2rgb -m average (rg_impl.h): zoom z - 1's pixel the mean
 * of the 2 x 2 pixels of zoom z it covers (its centre is theirs' centre,
 * exactly), the valid ones where any is (else all four, the fill), rows
 * streamed zoom to zoom from the deepest zoom's. */
#include <stdlib.h>
#include <string.h>

#include "rgb/rg_impl.h"

int
rg_box_open(rg_box *b, rg_job *j, const dem_mgrid *g, int minz, tl_err *e)
{
	memset(b, 0, sizeof *b);
	b->j = j, b->minz = minz;
	for (int z = g->z; z >= minz; z--) {
		int l = g->z - z;
		dem_mgrid zg = { z, g->dim, g->x0 >> l, g->y0 >> l, 0, 0 };
		zg.w = (int)(((g->x0 + g->w - 1) >> l) - zg.x0 + 1);
		zg.h = (int)(((g->y0 + g->h - 1) >> l) - zg.y0 + 1);
		if (rg_zoom_open(j, z, &zg, e) < 0 ||
		    (b->acc[z] = tl_alloc((size_t)zg.w * 6, sizeof(double),
		    e)) == NULL)
			return -1;
	}
	return 0;
}

void
rg_box_free(rg_box *b)
{
	for (int z = 0; z <= RG_MAXZOOM; z++)
		free(b->acc[z]);
}

/* Zoom z - 1's row p from the sums: its heights and validity. */
static int
parent(rg_box *b, int z, int p, tl_err *e)
{
	int w = b->j->zoom[z - 1].g.w;
	double *a = b->acc[z - 1], *h = a + 4 * (size_t)w, *v = a + 5 *
	    (size_t)w;

	for (int c = 0; c < w; c++) {
		double sa = a[c], sv = a[w + c], na = a[2 * w + c],
		    nv = a[3 * w + c];
		h[c] = nv > 0 ? sv / nv : sa / na;
		v[c] = nv / na;
	}
	memset(a, 0, (size_t)w * 4 * sizeof *a);
	return rg_box_row(b, z - 1, p, h, v, e);
}

int
rg_box_row(rg_box *b, int z, int r, const double *h, const double *v,
    tl_err *e)
{
	const dem_mgrid *g = &b->j->zoom[z].g, *pg;
	long long y = g->y0 + r;
	double *a;
	int pw;

	if (rg_zoom_row(b->j, z, r, h, v, e) < 0)
		return -1;
	if (z == b->minz)
		return 0;
	pg = &b->j->zoom[z - 1].g, pw = pg->w, a = b->acc[z - 1];
	for (int i = 0; i < g->w; i++) {
		int c = (int)(((g->x0 + i) >> 1) - pg->x0);
		a[c] += h[i], a[2 * pw + c] += 1;
		if (v[i] > 0)
			a[pw + c] += h[i], a[3 * pw + c] += 1;
	}
	if ((y & 1) || r == g->h - 1)
		return parent(b, z, (int)((y >> 1) - pg->y0), e);
	return 0;
}
