/* fqm_rows.c - FQM rows and their channel layout: a row of floats,
 * channel-planar as raster.h reads it, decoded into vertices and encoded
 * back, and checked for the NaN and infinities that only damage makes
 * (fqm.h). */
#include "qem/fqm.h"

#include <assert.h>
#include <math.h>
#include <string.h>

int
fqm_layout_ok(const fqm_layout *L)
{
	for (int k = 0; k < 10; k++)
		if (L->q[k] < 0)
			return 0;
	return L->z >= 0 && L->s >= 0 && L->v >= 0;
}

void
fqm_decode(const fqm_layout *L, const float *row, int w, fqm_vertex *out)
{
	assert(fqm_layout_ok(L));
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
	assert(fqm_layout_ok(L));
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

int
fqm_check_row(const float *row, int x0, int w, int nch, int y,
    const char *what, tl_err *e)
{
	for (int c = 0; c < nch; c++) {
		const float *p = row + (size_t)c * (size_t)w;
		for (int i = 0; i < w; i++)
			if (!isfinite(p[i]))
				return tl_fail(e, "%s: row %d, channel %d: %s at "
				    "column %d (damaged?)", what, y, c,
				    isnan(p[i]) ? "NaN" : "infinite value", x0 + i);
	}
	return 0;
}
