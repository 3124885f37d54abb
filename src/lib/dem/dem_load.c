/* dem_load.c - what the format adapters call back (dem_impl.h): the sink
 * that converts source samples to metres in the scratch file
 * (dem_load_begin, dem_load_encoding, dem_load_put, a band of rows at a
 * time with dem_load_band and dem_load_flush, in memory of dem_map),
 * the fingerprint of
 * that conversion (dem_fingerprint), and how messages name a file
 * (dem_name). A leaf: the reader dem.c dispatches to the adapters
 * (dem_gdal.c, dem_oiio.c, dem_list.c, dem_mosaic.c), they call this, and
 * this calls none of them. */
#include "dem/dem_impl.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "base/byteorder.h"
#include "geo/vdatum.h"

/* --- conversion ---------------------------------------------------------- */

static double
sample(const void *p, int t, size_t k)
{
	switch (t) {
	case TL_PX_U8: return ((const uint8_t *)p)[k];
	case TL_PX_I8: return ((const int8_t *)p)[k];
	case TL_PX_U16: return ((const uint16_t *)p)[k];
	case TL_PX_I16: return ((const int16_t *)p)[k];
	case TL_PX_U32: return ((const uint32_t *)p)[k];
	case TL_PX_I32: return ((const int32_t *)p)[k];
	case TL_PX_F32: return ((const float *)p)[k];
	case TL_PX_F64: return ((const double *)p)[k];
	}
	return NAN;
}

/* Height of pixel k (stride samples apart) in the file's unit, before
 * the void test. The RGB encodings read the first three bytes. */
static double
decode(const dem_load *L, const void *p, int t, size_t k, int stride)
{
	const uint8_t *c = (const uint8_t *)p + k * stride;

	switch (L->enc) {
	case DEM_ENC_TERRAINRGB:
		return (c[0] * 65536.0 + c[1] * 256.0 + c[2]) / 10 - 10000;
	case DEM_ENC_TERRARIUM:
		return c[0] * 256.0 + c[1] + c[2] / 256.0 - 32768;
	default:
		return sample(p, t, k * stride);
	}
}

/* Nodata is a raw value (GDAL's convention), so it is tested before
 * scale and offset. */
static int
is_void(const dem_load *L, double v)
{
	if (isnan(v))
		return 1;
	return L->has_nodata &&
	    (L->f32 ? (float)v == (float)L->nodata : v == L->nodata);
}

/* Raw value to metres. Without scale and offset the expression is the
 * one it always was, so heights stay bit-identical. */
static double
metres(const dem_load *L, double v)
{
	if (L->scale != 1 || L->offset != 0)
		v = v * L->scale + L->offset;
	return v * L->zunit;
}

/* Samples i0 .. i1-1 of the n at p (dem_load_put's) into o: the voids
 * among them. */
static int
put_any(const dem_load *L, const void *p, int t, int stride, int n, int i0,
    int i1, const unsigned char *mask, float *o)
{
	int nv = 0;

	for (int i = i0; i < i1; i++) {
		int k = L->flip_x ? n - 1 - i : i;
		double v = decode(L, p, t, (size_t)k, stride), z;
		z = is_void(L, v) || (mask != NULL && mask[k] == 0) ? NAN :
		    metres(L, v);
		if (!isfinite(z) || fabs(z) > DEM_MAXABS) {
			o[i - i0] = NAN;
			nv++;
		} else {
			o[i - i0] = (float)z;
		}
	}
	return nv;
}

/* The common case, float64 grey samples side by side (GDAL's buffers),
 * no flip, no mask: is_void's and metres' expressions, the same bits,
 * without a dispatch a sample. Returns the voids among the n. */
static int
put_f64(const dem_load *L, const double *v, float *o, int n)
{
	const int nodata = L->has_nodata, f32 = L->f32;
	const int lin = L->scale != 1 || L->offset != 0;
	const double nd = L->nodata, scale = L->scale, offset = L->offset;
	const double zunit = L->zunit;
	const float ndf = (float)nd;
	int nv = 0;

	for (int i = 0; i < n; i++) {
		double x = v[i], z;
		int vd = isnan(x) || (nodata && (f32 ? (float)x == ndf :
		    x == nd));
		z = vd ? NAN : (lin ? x * scale + offset : x) * zunit;
		if (!isfinite(z) || fabs(z) > DEM_MAXABS) {
			o[i] = NAN;
			nv++;
		} else {
			o[i] = (float)z;
		}
	}
	return nv;
}

int
dem_load_put(dem_load *L, const void *p, int t, int stride, int x0, int y,
    int n, const unsigned char *mask, tl_err *e)
{
	int nv = 0, a, b, staged;
	long long kw;
	float *seg;

	if (x0 < 0 || y < 0 || n < 0 || x0 + n > L->w || y >= L->h)
		return tl_fail(e, "%s: sample window outside the raster",
		    L->what);
	if (L->flip_y)
		y = L->h - 1 - y;
	if (L->flip_x)
		x0 = L->w - x0 - n;
	if (y < L->cy0 || y >= L->cy1)
		return 0;
	/* north-up columns a .. b-1: those of the n kept */
	a = x0 > L->cx0 ? x0 : L->cx0;
	b = x0 + n < L->cx1 ? x0 + n : L->cx1;
	if (a >= b)
		return 0;
	kw = L->cx1 - L->cx0;
	staged = y >= L->by0 && y < L->by1;
	seg = staged ? L->band + (y - L->by0) * kw + (a - L->cx0) : L->seg;
	if (L->enc == DEM_ENC_GREY && t == TL_PX_F64 && stride == 1 &&
	    !L->flip_x && mask == NULL)
		nv = put_f64(L, (const double *)p + (a - x0), seg, b - a);
	else
		nv = put_any(L, p, t, stride, n, a - x0, b - x0, mask, seg);
	if (L->vd != NULL && vdatum_apply(L->vd, y, a, b - a, seg, e) < 0)
		return -1;
	if (nv > 0) {
		L->voids += nv;
		dem_setbit(L->rowvoid, y);
	}
	if (staged) {
		L->staged += (size_t)(b - a);
		return 0;
	}
	return tl_pwrite(L->fd, seg, (size_t)(b - a) * sizeof(float),
	    ((long long)y * kw + a - L->cx0) * (long long)sizeof(float),
	    "scratch file", e);
}

int
dem_load_band(dem_load *L, int y, int n, tl_err *e)
{
	long long lo = L->flip_y ? L->h - y - n : y, hi = lo + n;
	size_t size;

	assert(L->by1 == L->by0 && n > 0);
	lo = lo > L->cy0 ? lo : L->cy0;
	hi = hi < L->cy1 ? hi : L->cy1;
	if (lo >= hi)
		return 0;
	size = (size_t)(hi - lo) * (size_t)(L->cx1 - L->cx0);
	if ((long long)size * (long long)sizeof(float) > DEM_BANDBYTES)
		return 0;
	if (size > L->bandcap) {
		dem_unmap(L->band, L->bandcap * sizeof(float));
		L->bandcap = 0;
		if ((L->band = dem_map(size * sizeof(float), e)) == NULL)
			return -1;
		L->bandcap = size;
	}
	L->by0 = (int)lo, L->by1 = (int)hi, L->staged = 0;
	return 0;
}

int
dem_load_flush(dem_load *L, tl_err *e)
{
	long long kw = L->cx1 - L->cx0, y0 = L->by0;
	size_t n = (size_t)(L->by1 - L->by0) * (size_t)kw;

	if (n == 0)
		return 0;
	assert(L->staged == n);
	L->by0 = L->by1 = 0;
	return tl_pwrite(L->fd, L->band, n * sizeof(float),
	    y0 * kw * (long long)sizeof(float), "scratch file", e);
}

/* The vertical datum conversion, once the georeferencing is known. */
static int
datum(dem_load *L, georef *g, const dem_opts *o, tl_err *e)
{
	const char *from = o->vdatum != NULL ? o->vdatum : g->vdatum;

	if (o->heights == NULL)
		return 0;
	if (g->model == GEO_NONE)
		return tl_fail(e, "%s: -H %s: the DEM has no CRS, so its "
		    "heights cannot change datum", L->what, o->heights);
	if ((L->vd = vdatum_open(g, from, o->heights, e)) == NULL) {
		char why[sizeof e->msg];
		snprintf(why, sizeof why, "%s", e->msg);
		return tl_fail(e, "%s: %s", L->what, why);
	}
	snprintf(g->vdatum, sizeof g->vdatum, "%s", vdatum_target_name(L->vd));
	return 0;
}

int
dem_load_begin(dem_load *L, georef *g, const dem_opts *o, int w, int h,
    int f32, tl_err *e)
{
	if (w < 1 || h < 1 || w > DEM_MAXDIM || h > DEM_MAXDIM)
		return tl_fail(e, "%s: unsupported size %d x %d (1 .. %d a "
		    "side)", L->what, w, h, DEM_MAXDIM);
	if ((long long)w * h > DEM_MAXSAMPLES)
		return tl_fail(e, "%s: %d x %d samples, more than 2^40: refused "
		    "before reading (a damaged header, or a DEM to cut into "
		    "tiles first)", L->what, w, h);
	if ((long long)w * DEM_SAMPLEBYTES > DEM_MAXROW)
		return tl_fail(e, "%s: rows of %d samples, more than %lld bytes "
		    "each: refused before reading", L->what, w,
		    (long long)DEM_MAXROW);
	g->width = L->w = w;
	g->height = L->h = h;
	if (L->cx1 == 0)
		L->cx0 = 0, L->cx1 = w;
	if (L->cy1 == 0)
		L->cy0 = 0, L->cy1 = h;
	if (L->cy0 < 0 || L->cy0 >= L->cy1 || L->cy1 > h)
		return tl_fail(e, "%s: rows %d .. %d outside 0 .. %d",
		    L->what, L->cy0, L->cy1 - 1, h - 1);
	if (L->cx0 < 0 || L->cx0 >= L->cx1 || L->cx1 > w)
		return tl_fail(e, "%s: columns %d .. %d outside 0 .. %d",
		    L->what, L->cx0, L->cx1 - 1, w - 1);
	L->has_nodata = o->has_nodata ? 1 : g->has_nodata;
	L->nodata = o->has_nodata ? o->nodata : g->nodata;
	L->f32 = f32;
	if (L->zunit == 0)
		L->zunit = 1;
	if (L->scale == 0)
		L->scale = 1;
	L->print = dem_fingerprint(L, g, o);
	if (datum(L, g, o, e) < 0)
		return -1;
	if (L->info)
		return 0;
	/* dem_open_rows: the caller's file */
	if (L->fd < 0 && (L->fd = tl_scratch(e)) < 0)
		return -1;
	L->seg = tl_alloc((size_t)w, sizeof(float), e);
	L->rowvoid = tl_alloc((size_t)h / 8 + 1, 1, e);
	return L->seg != NULL && L->rowvoid != NULL ? 0 : -1;
}

int
dem_load_encoding(dem_load *L, const dem_opts *o, int type, int nch,
    tl_err *e)
{
	L->enc = o->encoding;
	if (L->enc == DEM_ENC_AUTO)
		L->enc = type == TL_PX_U8 && nch >= 3 ? DEM_ENC_TERRAINRGB :
		    DEM_ENC_GREY;
	if (L->enc != DEM_ENC_GREY && (type != TL_PX_U8 || nch < 3))
		return tl_fail(e, "%s: %s encoding needs an 8-bit image with "
		    "3 or more channels", L->what,
		    L->enc == DEM_ENC_TERRAINRGB ? "Terrain-RGB" : "Terrarium");
	return 0;
}

/* --- memory for bands of rows -------------------------------------------- */

void *
dem_map(size_t n, tl_err *e)
{
	void *p = mmap(NULL, n, PROT_READ | PROT_WRITE,
	    MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);

	if (p == MAP_FAILED) {
		tl_failsys(e, "mapping of %zu bytes", n);
		return NULL;
	}
	return p;
}

void
dem_unmap(void *p, size_t n)
{
	if (p != NULL)
		munmap(p, n);
}

/* --- the fingerprint ----------------------------------------------------- */

uint64_t
dem_fnv(uint64_t h, const void *p, size_t n)
{
	const unsigned char *c = p;

	while (n--)
		h = (h ^ *c++) * 0x100000001b3ULL;
	return h;
}

/* Numbers hash as little-endian bytes: the same fingerprint on any host. */
static uint64_t
fnv_u64(uint64_t h, uint64_t v)
{
	unsigned char b[8];

	le_put64(b, v);
	return dem_fnv(h, b, sizeof b);
}

static uint64_t
fnv_int(uint64_t h, long long v)
{
	return fnv_u64(h, (uint64_t)v);
}

/* Every NaN is one NaN (a NaN nodata equals a NaN nodata). */
static uint64_t
fnv_double(uint64_t h, double v)
{
	uint64_t u;

	if (isnan(v))
		v = NAN;
	memcpy(&u, &v, sizeof u);
	return fnv_u64(h, u);
}

/* Length first, so that fields cannot run into each other; NULL unlike
 * any string. */
static uint64_t
fnv_str(uint64_t h, const char *s)
{
	if (s == NULL)
		return fnv_u64(h, UINT64_MAX);
	h = fnv_u64(h, strlen(s));
	return dem_fnv(h, s, strlen(s));
}

static uint64_t
fnv_georef(uint64_t h, const georef *g)
{
	h = fnv_int(h, g->width);
	h = fnv_int(h, g->height);
	h = fnv_int(h, g->model);
	h = fnv_int(h, g->epsg);
	h = fnv_str(h, g->crs);
	h = fnv_int(h, g->point);
	for (int k = 0; k < 2; k++) {
		h = fnv_double(h, g->origin[k]);
		h = fnv_double(h, g->step[k]);
		h = fnv_double(h, g->cell[k]);
	}
	h = fnv_double(h, g->unit);
	h = fnv_str(h, g->vdatum);
	h = fnv_int(h, g->has_nodata);
	return g->has_nodata ? fnv_double(h, g->nodata) : h;
}

/* The cell size (-s) changes no height but is hashed with the rest of
 * the georeferencing: a band job must not carry another. The encoding
 * and nodata are hashed as resolved, so -e grey on a grey file matches
 * no -e. */
uint64_t
dem_fingerprint(const dem_load *L, const georef *g, const dem_opts *o)
{
	uint64_t h = dem_fnv(DEM_FNV0, "dem_fingerprint 1", 17);

	h = fnv_georef(h, g);
	h = fnv_int(h, L->enc);
	h = fnv_int(h, L->has_nodata);
	if (L->has_nodata)
		h = fnv_double(h, L->nodata);
	h = fnv_int(h, L->f32);
	h = fnv_double(h, L->scale);
	h = fnv_double(h, L->offset);
	h = fnv_double(h, L->zunit);
	h = fnv_int(h, L->flip_x);
	h = fnv_int(h, L->flip_y);
	h = fnv_str(h, o->heights);
	return fnv_str(h, o->vdatum);
}

/* --- names -------------------------------------------------------------- */

const char *
dem_name(const char *path, char *buf)
{
	size_t n = strlen(path), tail = DEM_NAME / 2;

	if (n < DEM_NAME)
		memcpy(buf, path, n + 1);
	else
		snprintf(buf, DEM_NAME, "%.*s...%s", (int)(DEM_NAME - tail - 4),
		    path, path + n - tail);
	return buf;
}
