/* dem.c - DEM input. TIFF through libtiff (pixels) and libgeotiff
 * (georeferencing), SRTM .hgt through a reader of its own, everything else
 * through OpenImageIO in the tl_oiio.so plugin, loaded only when needed.
 *
 * The source is converted once to float32 rows in an anonymous scratch
 * file, voids as NaN. Voids are then filled for geometry (fill() below
 * documents the method) in two streaming passes, and the scratch file
 * holds the filled rows followed by a validity mask for each row that has
 * voids, so any row can be read back in any order with O(width) memory. */
#include "dem.h"

#include <ctype.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <geotiff/geo_normalize.h>
#include <geotiff/geotiff.h>
#include <geotiff/geovalues.h>
#include <geotiff/xtiffio.h>
#include <proj.h>
#include <tiffio.h>

#include "oiio_plugin.h"

#ifndef TL_LIBDIR
#define TL_LIBDIR "/usr/local/lib/terrain-lod"
#endif

#define MAXDIM (1 << 26)
#define MAXABS 1e6      /* |z| beyond this (metres) is a void */
#define PX_F16 100      /* half floats in TIFF; tl_px has no such type */
#define TAG_GDAL_METADATA 42112
#define TAG_GDAL_NODATA   42113

struct dem {
	georef g;
	int fd;                  /* filled rows, then masks of void rows */
	long long voids;
	unsigned char *rowvoid;  /* one bit per row: the row has voids */
	char what[256];          /* the file, for messages */
};

/* The input file: a named file, or stdin spooled to a scratch file. */
typedef struct {
	const char *what;
	int fd;
	long long size;
	int spooled;
	unsigned char magic[8];
	int nmagic;
} input;

/* The conversion of source samples into the scratch file. */
typedef struct {
	const char *what;
	int w, h, fd;
	enum dem_encoding enc;  /* resolved: never AUTO */
	int has_nodata, f32;    /* f32: compare nodata in float precision */
	double nodata, zunit;
	float *seg;             /* w floats */
	unsigned char *rowvoid;
	long long voids;
} load;

static int
bit(const unsigned char *b, long long i)
{
	return b[i >> 3] >> (i & 7) & 1;
}

/* --- conversion --------------------------------------------------------- */

static float
half_to_float(uint16_t h)
{
	int ex = h >> 10 & 0x1f, m = h & 0x3ff;
	double v;

	if (ex == 0)
		v = ldexp(m, -24);
	else if (ex == 31)
		v = m ? NAN : INFINITY;
	else
		v = ldexp(m | 0x400, ex - 25);
	return (float)(h & 0x8000 ? -v : v);
}

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
	case PX_F16: return half_to_float(((const uint16_t *)p)[k]);
	}
	return NAN;
}

static size_t
px_size(int t)
{
	switch (t) {
	case TL_PX_U8: case TL_PX_I8: return 1;
	case TL_PX_U16: case TL_PX_I16: case PX_F16: return 2;
	case TL_PX_U32: case TL_PX_I32: case TL_PX_F32: return 4;
	}
	return 8;
}

/* Height of pixel k (stride samples apart) before the void test. */
static double
decode(const load *L, const void *p, int t, size_t k, int stride)
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

static int
is_void(const load *L, double v)
{
	if (isnan(v))
		return 1;
	if (L->has_nodata &&
	    (L->f32 ? (float)v == (float)L->nodata : v == L->nodata))
		return 1;
	return !isfinite(v * L->zunit) || fabs(v * L->zunit) > MAXABS;
}

/* Converts n pixels of row y starting at column x0 and stores them. */
static int
put(load *L, const void *p, int t, int stride, int x0, int y, int n,
    tl_err *e)
{
	int nv = 0;

	for (int i = 0; i < n; i++) {
		double v = decode(L, p, t, (size_t)i, stride);
		if (is_void(L, v)) {
			L->seg[i] = NAN;
			nv++;
		} else {
			L->seg[i] = (float)(v * L->zunit);
		}
	}
	if (nv > 0) {
		L->voids += nv;
		L->rowvoid[y >> 3] |= 1 << (y & 7);
	}
	return tl_pwrite(L->fd, L->seg, (size_t)n * sizeof(float),
	    ((long long)y * L->w + x0) * (long long)sizeof(float),
	    "scratch file", e);
}

/* Sets up the conversion once the size and georeferencing are known. */
static int
load_begin(load *L, dem *d, const dem_opts *o, int w, int h, int t,
    tl_err *e)
{
	if (w < 1 || h < 1 || w > MAXDIM || h > MAXDIM)
		return tl_fail(e, "%s: unsupported size %d x %d (1 .. %d a "
		    "side)", L->what, w, h, MAXDIM);
	d->g.width = L->w = w;
	d->g.height = L->h = h;
	L->has_nodata = o->has_nodata ? 1 : d->g.has_nodata;
	L->nodata = o->has_nodata ? o->nodata : d->g.nodata;
	L->f32 = t == TL_PX_F32 || t == PX_F16;
	if (L->zunit == 0)
		L->zunit = 1;
	L->fd = d->fd = tl_scratch(e);
	if (d->fd < 0)
		return -1;
	L->seg = tl_alloc((size_t)w, sizeof(float), e);
	L->rowvoid = d->rowvoid = tl_alloc((size_t)h / 8 + 1, 1, e);
	return L->seg != NULL && L->rowvoid != NULL ? 0 : -1;
}

/* Resolves AUTO: Terrain-RGB for 8-bit images with >= 3 channels. */
static int
encoding(load *L, const dem_opts *o, int t, int nch, tl_err *e)
{
	L->enc = o->encoding;
	if (L->enc == DEM_ENC_AUTO)
		L->enc = t == TL_PX_U8 && nch >= 3 ? DEM_ENC_TERRAINRGB :
		    DEM_ENC_GREY;
	if (L->enc != DEM_ENC_GREY && (t != TL_PX_U8 || nch < 3))
		return tl_fail(e, "%s: %s encoding needs an 8-bit image with "
		    "3 or more channels", L->what,
		    L->enc == DEM_ENC_TERRAINRGB ? "Terrain-RGB" : "Terrarium");
	return 0;
}

/* --- SRTM .hgt ----------------------------------------------------------- */

static int
hgt_georef(georef *g, const char *name, int n, double cx, double cy)
{
	const char *b = strrchr(name, '/');
	int lat, lon;
	char ns, ew;

	geo_init_none(g, cx, cy);
	g->has_nodata = 1;
	g->nodata = -32768;
	b = b != NULL ? b + 1 : name;
	if (strlen(b) < 7 || n < 2 ||
	    !isdigit((unsigned char)b[1]) || !isdigit((unsigned char)b[2]) ||
	    !isdigit((unsigned char)b[4]) || !isdigit((unsigned char)b[5]) ||
	    !isdigit((unsigned char)b[6]) || isdigit((unsigned char)b[7]))
		return -1;
	ns = toupper((unsigned char)b[0]);
	ew = toupper((unsigned char)b[3]);
	if ((ns != 'N' && ns != 'S') || (ew != 'E' && ew != 'W'))
		return -1;
	lat = (b[1] - '0') * 10 + (b[2] - '0');
	lon = (b[4] - '0') * 100 + (b[5] - '0') * 10 + (b[6] - '0');
	lat = ns == 'S' ? -lat : lat;
	lon = ew == 'W' ? -lon : lon;
	if (lat < -90 || lat > 89 || lon < -180 || lon > 179)
		return -1;
	g->model = GEO_GEOGRAPHIC;
	g->epsg = 4326;
	snprintf(g->crs, sizeof g->crs, "EPSG:4326");
	g->point = 1;
	g->origin[0] = lon;
	g->origin[1] = lat + 1;
	g->step[0] = 1.0 / (n - 1);
	g->step[1] = -1.0 / (n - 1);
	g->unit = 0;
	snprintf(g->vdatum, sizeof g->vdatum, "EPSG:5773");
	return 0;
}

/* n when size is 2 n^2 with n >= 2, else 0. */
static int
hgt_side(long long size)
{
	long long n;

	if (size < 8 || size % 2 != 0)
		return 0;
	n = llround(sqrt((double)(size / 2)));
	return n * n * 2 == size && n <= MAXDIM ? (int)n : 0;
}

static int
read_hgt(dem *d, load *L, const input *in, const char *name,
    const dem_opts *o, tl_err *e)
{
	int n = hgt_side(in->size), r = -1;
	unsigned char *raw;
	int16_t *v;

	hgt_georef(&d->g, name ? name : "", n, o->cell[0], o->cell[1]);
	L->enc = DEM_ENC_GREY;
	if (load_begin(L, d, o, n, n, TL_PX_I16, e) < 0)
		return -1;
	raw = tl_alloc((size_t)n, 2, e);
	v = tl_alloc((size_t)n, sizeof *v, e);
	if (raw == NULL || v == NULL)
		goto out;
	for (int j = 0; j < n; j++) {
		if (tl_pread(in->fd, raw, (size_t)n * 2, (long long)j * n * 2,
		    in->what, e) < 0)
			goto out;
		for (int i = 0; i < n; i++) /* big-endian, two's complement */
			v[i] = (int16_t)(uint16_t)(raw[2 * i] << 8 | raw[2 * i + 1]);
		if (put(L, v, TL_PX_I16, 1, 0, j, n, e) < 0)
			goto out;
	}
	r = 0;
out:
	free(raw);
	free(v);
	return r;
}

/* --- libtiff tag registration ------------------------------------------ */

/* libtiff keeps its tag extenders in one process-wide chain: the parent
 * extender and the once-flag are the static state it forces on us. */
static TIFFExtendProc parent_extender;
static pthread_once_t tags_once = PTHREAD_ONCE_INIT;

static void
gdal_tags(TIFF *tif)
{
	static const TIFFFieldInfo fi[] = {
		{ TAG_GDAL_METADATA, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0,
		    "GDALMetadata" },
		{ TAG_GDAL_NODATA, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0,
		    "GDALNoDataValue" },
	};

	TIFFMergeFieldInfo(tif, fi, sizeof fi / sizeof fi[0]);
	if (parent_extender != NULL)
		parent_extender(tif);
}

static void
register_once(void)
{
	XTIFFInitialize(); /* the GeoTIFF tags, libgeotiff's own extender */
	parent_extender = TIFFSetTagExtender(gdal_tags);
}

static void
tiff_register(void)
{
	pthread_once(&tags_once, register_once);
}

/* --- TIFF ------------------------------------------------------------------ */

/* libtiff I/O on our descriptor with pread: works for the stdin spool, and
 * never maps the file (mapped pages would count in our RSS). */
typedef struct {
	int fd;
	uint64_t pos, size;
	char err[512];  /* first libtiff error */
} tio;

static tmsize_t
tio_read(thandle_t h, void *buf, tmsize_t n)
{
	tio *t = (tio *)h;
	tmsize_t done = 0;

	while (done < n) {
		ssize_t r = pread(t->fd, (char *)buf + done, (size_t)(n - done),
		    (off_t)t->pos);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return done > 0 ? done : -1;
		if (r == 0)
			break;
		done += r;
		t->pos += (uint64_t)r;
	}
	return done;
}

static tmsize_t
tio_write(thandle_t h, void *buf, tmsize_t n)
{
	errno = EBADF;
	return -1;
}

static toff_t
tio_seek(thandle_t h, toff_t off, int whence)
{
	tio *t = (tio *)h;

	if (whence == SEEK_CUR)
		off += t->pos;
	else if (whence == SEEK_END)
		off += t->size;
	t->pos = off;
	return off;
}

static int
tio_close(thandle_t h)
{
	return 0; /* the descriptor belongs to the input */
}

static toff_t
tio_size(thandle_t h)
{
	return ((tio *)h)->size;
}

static int
tio_map(thandle_t h, void **base, toff_t *size)
{
	return 0;
}

static void
tio_unmap(thandle_t h, void *base, toff_t size)
{
}

/* Per-handle handlers (libtiff >= 4.5): nothing is printed, and no
 * process-wide handler is touched. Returning 1 stops libtiff from also
 * calling the global handlers. */
static int
tio_error(TIFF *tif, void *ud, const char *module, const char *fmt,
    va_list ap)
{
	tio *t = ud;
	size_t n;

	if (t->err[0] != '\0')
		return 1;
	n = (size_t)snprintf(t->err, sizeof t->err, "%s%s",
	    module ? module : "", module ? ": " : "");
	if (n < sizeof t->err)
		vsnprintf(t->err + n, sizeof t->err - n, fmt, ap);
	return 1;
}

static int
tio_warning(TIFF *tif, void *ud, const char *module, const char *fmt,
    va_list ap)
{
	return 1; /* unknown tags and the like: harmless for a DEM */
}

static int
tiff_fail(const load *L, const tio *t, const char *fallback, tl_err *e)
{
	return tl_fail(e, "%s: truncated or corrupt: %s", L->what,
	    t->err[0] ? t->err : fallback);
}

static TIFF *
tiff_open(tio *t, const input *in, tl_err *e)
{
	TIFFOpenOptions *opt = TIFFOpenOptionsAlloc();
	TIFF *tif;

	if (opt == NULL) {
		tl_fail(e, "%s: out of memory", in->what);
		return NULL;
	}
	memset(t, 0, sizeof *t);
	t->fd = in->fd;
	t->size = (uint64_t)in->size;
	TIFFOpenOptionsSetErrorHandlerExtR(opt, tio_error, t);
	TIFFOpenOptionsSetWarningHandlerExtR(opt, tio_warning, t);
	tiff_register();
	tif = TIFFClientOpenExt(in->what, "rm", (thandle_t)t, tio_read,
	    tio_write, tio_seek, tio_close, tio_size, tio_map, tio_unmap, opt);
	TIFFOpenOptionsFree(opt);
	if (tif == NULL)
		tl_fail(e, "%s: truncated or corrupt: %s", in->what,
		    t->err[0] ? t->err : "cannot read the TIFF header");
	return tif;
}

/* --- GeoTIFF ------------------------------------------------------------ */

/* libgeotiff and PROJ messages, kept instead of printed. */
typedef struct {
	char gt[256];
	char proj[256];
} gt_msgs;

static void
gt_error(GTIF *gt, int level, const char *fmt, ...)
{
	gt_msgs *m = GTIFGetUserData(gt);
	va_list ap;

	if (m == NULL || level != LIBGEOTIFF_ERROR || m->gt[0] != '\0')
		return;
	va_start(ap, fmt);
	vsnprintf(m->gt, sizeof m->gt, fmt, ap);
	va_end(ap);
}

static void
proj_log(void *ud, int level, const char *msg)
{
	gt_msgs *m = ud;

	if (level == PJ_LOG_ERROR && m->proj[0] == '\0')
		snprintf(m->proj, sizeof m->proj, "%s", msg);
}

/* A double-array tag: libgeotiff registers them TIFF_VARIABLE (16-bit
 * count); ask libtiff rather than guess, in case it knows them itself. */
static int
get_doubles(TIFF *tif, uint32_t tag, double **v)
{
	const TIFFField *f = TIFFFieldWithTag(tif, tag);
	uint16_t n16 = 0;
	uint32_t n32 = 0;

	*v = NULL;
	if (f == NULL)
		return 0;
	if (TIFFFieldReadCount(f) == TIFF_VARIABLE2) {
		if (!TIFFGetField(tif, tag, &n32, v))
			return 0;
		return *v != NULL ? (int)(n32 > INT_MAX ? INT_MAX : n32) : 0;
	}
	if (!TIFFGetField(tif, tag, &n16, v))
		return 0;
	return *v != NULL ? n16 : 0;
}

static int
key_short(GTIF *gt, geokey_t k, int *v)
{
	unsigned short s;

	if (GTIFKeyGetSHORT(gt, k, &s, 0, 1) != 1)
		return 0;
	*v = s;
	return 1;
}

/* EPSG code of a GeoKey, 0 when absent or user-defined. */
static int
key_epsg(GTIF *gt, geokey_t k)
{
	int v;

	if (!key_short(gt, k, &v) || v <= 0 || v >= KvUserDefined)
		return 0;
	return v;
}

static void
gdal_nodata(georef *g, TIFF *tif)
{
	const char *s = NULL;
	char *end;
	double v;

	if (TIFFFieldWithTag(tif, TAG_GDAL_NODATA) == NULL ||
	    !TIFFGetField(tif, TAG_GDAL_NODATA, &s) || s == NULL)
		return;
	while (isspace((unsigned char)*s))
		s++;
	v = strtod(s, &end);
	if (end == s)
		return;
	g->has_nodata = 1;
	g->nodata = v;
}

/* Origin and step from the transformation matrix or tie point + scale. */
static int
grid_tags(georef *g, TIFF *tif, const char *what, tl_err *e)
{
	double *tie, *scale, *mat;
	int ntie = get_doubles(tif, TIFFTAG_GEOTIEPOINTS, &tie);
	int nscale = get_doubles(tif, TIFFTAG_GEOPIXELSCALE, &scale);
	int nmat = get_doubles(tif, TIFFTAG_GEOTRANSMATRIX, &mat);

	if (nmat >= 16) {
		/* x = m0 I + m1 J + m3, y = m4 I + m5 J + m7 */
		if (mat[1] != 0 || mat[4] != 0)
			return tl_fail(e, "%s: rotated or sheared georeferencing "
			    "(ModelTransformation) is not supported", what);
		g->origin[0] = mat[3], g->origin[1] = mat[7];
		g->step[0] = mat[0], g->step[1] = mat[5];
	} else if (ntie >= 6 && nscale >= 2) {
		g->step[0] = scale[0], g->step[1] = -scale[1];
		g->origin[0] = tie[3] - tie[0] * g->step[0];
		g->origin[1] = tie[4] - tie[1] * g->step[1];
	} else if (ntie >= 6) {
		return tl_fail(e, "%s: georeferenced by ground control points "
		    "only (no pixel scale): not supported", what);
	} else {
		return 1; /* no grid */
	}
	if (!isfinite(g->step[0]) || !isfinite(g->step[1]) ||
	    g->step[0] == 0 || g->step[1] == 0 ||
	    !isfinite(g->origin[0]) || !isfinite(g->origin[1]))
		return tl_fail(e, "%s: invalid georeferencing: pixel size "
		    "%g x %g", what, g->step[0], g->step[1]);
	return 0;
}

/* Metres per vertical unit from an EPSG unit code. */
static double
zunit_of(int code)
{
	switch (code) {
	case 9002: return 0.3048;           /* foot */
	case 9003: return 1200.0 / 3937.0;  /* US survey foot */
	default: return 1;
	}
}

static void
vertical(georef *g, GTIF *gt, double *zunit)
{
	char cit[sizeof g->vdatum];
	int v;

	if ((v = key_epsg(gt, VerticalCSTypeGeoKey)) != 0)
		snprintf(g->vdatum, sizeof g->vdatum, "EPSG:%d", v);
	else if (GTIFKeyGetASCII(gt, VerticalCitationGeoKey, cit,
	    sizeof cit) > 0 && cit[0] != '\0')
		snprintf(g->vdatum, sizeof g->vdatum, "%s", cit);
	else if ((v = key_epsg(gt, VerticalDatumGeoKey)) != 0)
		snprintf(g->vdatum, sizeof g->vdatum, "EPSG datum %d", v);
	*zunit = key_short(gt, VerticalUnitsGeoKey, &v) ? zunit_of(v) : 1;
}

/* CRS name and unit through the normalised definition (EPSG database).
 * A projected CRS whose unit PROJ could not look up fails: guessing metres
 * would silently scale a DEM in feet. */
static int
crs(georef *g, GTIF *gt, const gt_msgs *m, const char *what, tl_err *e)
{
	GTIFDefn *d = GTIFAllocDefn();
	int ok, unitkey;

	if (d == NULL)
		return tl_fail(e, "%s: out of memory", what);
	ok = GTIFGetDefn(gt, d) && d->DefnSet;
	if (g->model == GEO_PROJECTED) {
		g->epsg = key_epsg(gt, ProjectedCSTypeGeoKey);
		g->unit = ok && d->UOMLengthInMeters > 0 ? d->UOMLengthInMeters : 1;
		if (m->proj[0] != '\0' &&
		    !key_short(gt, ProjLinearUnitsGeoKey, &unitkey)) {
			GTIFFreeDefn(d);
			return tl_fail(e, "%s: EPSG:%d: unknown linear unit: %s",
			    what, g->epsg, m->proj);
		}
	} else {
		g->epsg = key_epsg(gt, GeographicTypeGeoKey);
		g->unit = 0;
		if (ok && d->UOMAngleInDegrees > 0 &&
		    fabs(d->UOMAngleInDegrees - 1) > 1e-12) {
			GTIFFreeDefn(d);
			return tl_fail(e, "%s: geographic CRS in angular units "
			    "other than degrees: not supported", what);
		}
	}
	if (g->epsg != 0) {
		snprintf(g->crs, sizeof g->crs, "EPSG:%d", g->epsg);
	} else if (ok) {
		char *p = GTIFGetProj4Defn(d);
		if (p != NULL) {
			size_t n = strlen(p);
			while (n > 0 && isspace((unsigned char)p[n - 1]))
				n--;
			snprintf(g->crs, sizeof g->crs, "%.*s", (int)n, p);
			GTIFFreeMemory(p);
		}
	}
	GTIFFreeDefn(d);
	return 0;
}

static int
keys(georef *g, GTIF *gt, const gt_msgs *m, const char *what, double cx,
    double cy, double *zunit, tl_err *e)
{
	int model = 0, raster = RasterPixelIsArea;

	key_short(gt, GTModelTypeGeoKey, &model);
	key_short(gt, GTRasterTypeGeoKey, &raster);
	if (model == 0) {
		/* A grid without a CRS: nothing says what its units are. */
		double nd = g->nodata;
		int has = g->has_nodata;
		geo_init_none(g, cx, cy);
		g->has_nodata = has, g->nodata = nd;
		return 0;
	}
	if (model != ModelTypeGeographic && model != ModelTypeProjected)
		return tl_fail(e, "%s: GeoTIFF model type %d (geocentric or "
		    "unknown) is not supported", what, model);
	g->model = model == ModelTypeGeographic ? GEO_GEOGRAPHIC :
	    GEO_PROJECTED;
	g->point = raster == RasterPixelIsPoint;
	vertical(g, gt, zunit);
	return crs(g, gt, m, what, e);
}

/* Georeferencing of an open TIFF; GEO_NONE (cx, cy) when it has none.
 * *zunit gets metres per height unit (VerticalUnitsGeoKey). The PROJ
 * context is ours so that PROJ logs to us, not to stderr. */
static int
geotiff(georef *g, TIFF *tif, const char *what, double cx, double cy,
    double *zunit, tl_err *e)
{
	gt_msgs msgs = { "", "" };
	PJ_CONTEXT *pj;
	GTIF *gt;
	int r;

	geo_init_none(g, cx, cy);
	*zunit = 1;
	gdal_nodata(g, tif);
	/* No grid (r > 0): GEO_NONE, perhaps with a nodata value. */
	if ((r = grid_tags(g, tif, what, e)) != 0)
		return r > 0 ? 0 : -1;
	if ((pj = proj_context_create()) == NULL)
		return tl_fail(e, "%s: cannot create a PROJ context", what);
	proj_log_func(pj, &msgs, proj_log);
	if ((gt = GTIFNewEx(tif, gt_error, &msgs)) == NULL) {
		proj_context_destroy(pj);
		return tl_fail(e, "%s: corrupt GeoTIFF keys%s%s", what,
		    msgs.gt[0] ? ": " : "", msgs.gt);
	}
	GTIFAttachPROJContext(gt, pj);
	r = keys(g, gt, &msgs, what, cx, cy, zunit, e);
	GTIFFree(gt);
	proj_context_destroy(pj);
	return r;
}

/* Our pixel type for a TIFF sample format; -1 if unsupported. */
static int
tiff_type(int sf, int bps)
{
	if (sf == SAMPLEFORMAT_UINT)
		return bps == 8 ? TL_PX_U8 : bps == 16 ? TL_PX_U16 :
		    bps == 32 ? TL_PX_U32 : -1;
	if (sf == SAMPLEFORMAT_INT)
		return bps == 8 ? TL_PX_I8 : bps == 16 ? TL_PX_I16 :
		    bps == 32 ? TL_PX_I32 : -1;
	if (sf == SAMPLEFORMAT_IEEEFP)
		return bps == 16 ? PX_F16 : bps == 32 ? TL_PX_F32 :
		    bps == 64 ? TL_PX_F64 : -1;
	return -1;
}

static int
tiff_strips(load *L, TIFF *tif, tio *t, int type, int stride, tl_err *e)
{
	tmsize_t sz = TIFFScanlineSize(tif);
	void *buf;
	int r = 0;

	if (sz < (tmsize_t)(px_size(type) * (size_t)stride * (size_t)L->w))
		return tiff_fail(L, t, "bad scanline size", e);
	if ((buf = tl_alloc((size_t)sz, 1, e)) == NULL)
		return -1;
	for (int j = 0; j < L->h && r == 0; j++) {
		if (TIFFReadScanline(tif, buf, (uint32_t)j, 0) < 0)
			r = tiff_fail(L, t, "cannot read a scanline", e);
		else
			r = put(L, buf, type, stride, 0, j, L->w, e);
	}
	free(buf);
	return r;
}

static int
tiff_tiles(load *L, TIFF *tif, tio *t, int type, int stride, tl_err *e)
{
	uint32_t tw = 0, th = 0;
	tmsize_t sz = TIFFTileSize(tif);
	size_t rowbytes;
	char *buf;
	int r = 0;

	TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tw);
	TIFFGetField(tif, TIFFTAG_TILELENGTH, &th);
	rowbytes = px_size(type) * (size_t)stride * tw;
	if (tw == 0 || th == 0 || sz < (tmsize_t)(rowbytes * th))
		return tiff_fail(L, t, "bad tile size", e);
	if ((buf = tl_alloc((size_t)sz, 1, e)) == NULL)
		return -1;
	for (uint32_t y = 0; y < (uint32_t)L->h && r == 0; y += th)
		for (uint32_t x = 0; x < (uint32_t)L->w && r == 0; x += tw) {
			uint32_t nx = L->w - x < tw ? L->w - x : tw;
			uint32_t ny = L->h - y < th ? L->h - y : th;
			if (TIFFReadTile(tif, buf, x, y, 0, 0) < 0) {
				r = tiff_fail(L, t, "cannot read a tile", e);
				break;
			}
			for (uint32_t k = 0; k < ny && r == 0; k++)
				r = put(L, buf + k * rowbytes, type, stride,
				    (int)x, (int)(y + k), (int)nx, e);
		}
	free(buf);
	return r;
}

static int
read_tiff(dem *d, load *L, const input *in, const dem_opts *o, tl_err *e)
{
	uint32_t w = 0, h = 0;
	uint16_t spp = 1, bps = 1, sf = SAMPLEFORMAT_UINT;
	uint16_t planar = PLANARCONFIG_CONTIG;
	int type, stride, r = -1;
	tio t;
	TIFF *tif = tiff_open(&t, in, e);

	if (tif == NULL)
		return -1;
	TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w);
	TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h);
	TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
	TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bps);
	TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &sf);
	TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
	if ((type = tiff_type(sf, bps)) < 0 || spp < 1) {
		tl_fail(e, "%s: unsupported TIFF sample type (%u-bit, sample "
		    "format %u, %u samples per pixel)", in->what, bps, sf, spp);
		goto out;
	}
	/* Separate planes: plane 0 is the grey channel; stride 1. */
	stride = planar == PLANARCONFIG_SEPARATE ? 1 : spp;
	if (encoding(L, o, type, spp, e) < 0)
		goto out;
	if (L->enc != DEM_ENC_GREY && planar == PLANARCONFIG_SEPARATE) {
		tl_fail(e, "%s: RGB-encoded heights in separate planes are not "
		    "supported", in->what);
		goto out;
	}
	if (geotiff(&d->g, tif, in->what, o->cell[0], o->cell[1],
	    &L->zunit, e) < 0)
		goto out;
	if (w > MAXDIM || h > MAXDIM) {
		tl_fail(e, "%s: unsupported size %lu x %lu (1 .. %d a side)",
		    in->what, (unsigned long)w, (unsigned long)h, MAXDIM);
		goto out;
	}
	if (load_begin(L, d, o, (int)w, (int)h, type, e) < 0)
		goto out;
	r = TIFFIsTiled(tif) ? tiff_tiles(L, tif, &t, type, stride, e) :
	    tiff_strips(L, tif, &t, type, stride, e);
out:
	TIFFClose(tif);
	return r;
}

/* --- everything else: the OpenImageIO plugin ---------------------------- */

/* A plugin that exists but fails to load explains more than a missing
 * one: its message wins. */
static void *
try_plugin(const char *path, char *why, size_t n)
{
	void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);

	if (h == NULL && (why[0] == '\0' || access(path, F_OK) == 0)) {
		const char *m = dlerror();
		size_t k = strlen(m = m ? m : path);
		k = k < n ? k : n - 1; /* a cut message beats none */
		memcpy(why, m, k);
		why[k] = '\0';
	}
	return h;
}

/* $TL_OIIO_PLUGIN, else beside the executable, else in ../lib/terrain-lod
 * from it, else TL_LIBDIR. The plugin
 * stays loaded: unloading OpenImageIO (static state, threads) is unsafe,
 * and dlopen counts references, so loading it again is cheap. */
static const tl_oiio_api *
plugin(char *why, size_t n)
{
	const char *env = getenv("TL_OIIO_PLUGIN");
	char exe[PATH_MAX], *slash;
	const tl_oiio_api *api;
	tl_oiio_entry_fn f;
	ssize_t len;
	void *h = NULL;

	if (env != NULL && *env != '\0') {
		h = try_plugin(env, why, n);
	} else {
		len = readlink("/proc/self/exe", exe, sizeof exe - 16);
		if (len > 0) {
			exe[len] = '\0';
			if ((slash = strrchr(exe, '/')) != NULL) {
				strcpy(slash + 1, "tl_oiio.so");
				h = try_plugin(exe, why, n);
			}
			/* an installed tree moved as a whole: bin/../lib */
			if (h == NULL && slash != NULL && (size_t)(slash - exe) +
			    sizeof "/../lib/terrain-lod/tl_oiio.so" <= sizeof exe) {
				strcpy(slash, "/../lib/terrain-lod/tl_oiio.so");
				h = try_plugin(exe, why, n);
			}
		}
		if (h == NULL)
			h = try_plugin(TL_LIBDIR "/tl_oiio.so", why, n);
	}
	if (h == NULL)
		return NULL;
	*(void **)&f = dlsym(h, TL_OIIO_ENTRY);
	if (f == NULL || (api = f()) == NULL || api->abi != TL_OIIO_ABI) {
		snprintf(why, n, "tl_oiio.so: not a compatible plugin");
		return NULL;
	}
	return api;
}

static int
oiio_rows(load *L, const tl_oiio_api *api, tl_oiio_img *img,
    const tl_oiio_info *info, int nch, tl_err *e)
{
	size_t rowbytes = px_size(info->type) * (size_t)nch * (size_t)L->w;
	char err[512] = "";
	char *buf = tl_alloc(rowbytes, (size_t)info->chunk, e);
	int r = 0;

	if (buf == NULL)
		return -1;
	for (int y = 0; y < L->h && r == 0; y += info->chunk) {
		int ny = L->h - y < info->chunk ? L->h - y : info->chunk;
		if (api->read_rows(img, y, y + ny, nch, buf, err, sizeof err) < 0) {
			r = tl_fail(e, "%s: truncated or corrupt: %s", L->what, err);
			break;
		}
		for (int k = 0; k < ny && r == 0; k++)
			r = put(L, buf + k * rowbytes, info->type, nch, 0, y + k,
			    L->w, e);
	}
	free(buf);
	return r;
}

/* Returns 1 (not an error) when OpenImageIO cannot open a file whose
 * magic we did not recognise: the caller says "not a raster". */
static int
read_oiio(dem *d, load *L, const input *in, int known, const dem_opts *o,
    tl_err *e)
{
	char why[512] = "", procpath[64];
	const char *path = in->what;
	const tl_oiio_api *api = plugin(why, sizeof why);
	tl_oiio_info info;
	tl_oiio_img *img;
	int nch, r = -1;

	if (api == NULL)
		return known ? tl_fail(e, "%s: reading this format needs the "
		    "OpenImageIO plugin tl_oiio.so ($TL_OIIO_PLUGIN, beside the "
		    "program, or in " TL_LIBDIR "): %s", in->what, why) : 1;
	if (in->spooled) {
		snprintf(procpath, sizeof procpath, "/proc/self/fd/%d", in->fd);
		path = procpath;
	}
	if ((img = api->open(path, &info, why, sizeof why)) == NULL)
		return known ? tl_fail(e, "%s: %s", in->what, why) : 1;
	if (info.chunk < 1)
		info.chunk = 1;
	if (encoding(L, o, info.type, info.nchannels, e) < 0)
		goto out;
	nch = L->enc == DEM_ENC_GREY ? 1 : 3;
	geo_init_none(&d->g, o->cell[0], o->cell[1]);
	if (load_begin(L, d, o, info.width, info.height, info.type, e) < 0)
		goto out;
	r = oiio_rows(L, api, img, &info, nch, e);
out:
	api->close(img);
	return r;
}

const tl_oiio_api *
dem_oiio_plugin(char *why, size_t n)
{
	if (n > 0)
		why[0] = '\0';
	return plugin(why, n);
}

/* --- void filling ----------------------------------------------------------- */

/* Nearest valid sample below, per column, for one row with voids. */
typedef struct {
	float v;
	int32_t row; /* -1: none */
} below;

typedef struct {
	int w, h;
	float *r, *f, *av;      /* raw row, filled row, nearest valid above */
	int32_t *arow, *left;   /* its row (-1 none); nearest valid to the left */
	below *b, *bl;          /* this row's "below" records; running state */
	unsigned char *mask;
} fillbuf;

static void
fillbuf_free(fillbuf *F)
{
	free(F->r), free(F->f), free(F->av), free(F->arow), free(F->left);
	free(F->b), free(F->bl), free(F->mask);
}

static int
fillbuf_alloc(fillbuf *F, int w, int h, tl_err *e)
{
	size_t n = (size_t)w;

	memset(F, 0, sizeof *F);
	F->w = w, F->h = h;
	F->r = tl_alloc(n, sizeof(float), e);
	F->f = tl_alloc(n, sizeof(float), e);
	F->av = tl_alloc(n, sizeof(float), e);
	F->arow = tl_alloc(n, sizeof(int32_t), e);
	F->left = tl_alloc(n, sizeof(int32_t), e);
	F->b = tl_alloc(n, sizeof(below), e);
	F->bl = tl_alloc(n, sizeof(below), e);
	F->mask = tl_alloc(n, 1, e);
	if (!F->r || !F->f || !F->av || !F->arow || !F->left || !F->b ||
	    !F->bl || !F->mask) {
		fillbuf_free(F);
		return -1;
	}
	for (int i = 0; i < w; i++)
		F->arow[i] = F->bl[i].row = -1;
	return 0;
}

static long long
zoff(const fillbuf *F, int j)
{
	return (long long)j * F->w * (long long)sizeof(float);
}

/* Pass 1, bottom-up: for every row with voids, store per column the
 * nearest valid sample below it (sparse: rows without voids stay holes). */
static int
pass_up(const dem *d, fillbuf *F, int bfd, tl_err *e)
{
	for (int j = F->h - 1; j >= 0; j--) {
		if (tl_pread(d->fd, F->r, F->w * sizeof(float), zoff(F, j),
		    "scratch file", e) < 0)
			return -1;
		if (bit(d->rowvoid, j) && tl_pwrite(bfd, F->bl, F->w *
		    sizeof(below), (long long)j * F->w * (long long)sizeof(below),
		    "scratch file", e) < 0)
			return -1;
		for (int i = 0; i < F->w; i++)
			if (!isnan(F->r[i]))
				F->bl[i].v = F->r[i], F->bl[i].row = j;
	}
	return 0;
}

/* Adds v at distance dist to an inverse-distance weighted sum. */
static void
idw(double *s, double *ws, double v, double dist)
{
	*s += v / dist;
	*ws += 1 / dist;
}

/* Samples whose row and column hold no valid sample at all: weighted by
 * the nearest samples left and right that the first stage filled. */
static void
fill_row_only(fillbuf *F)
{
	int last = -1, next = -1, w = F->w;

	for (int i = 0; i < w; i++) {
		F->left[i] = last;
		if (!isnan(F->f[i]))
			last = i;
	}
	for (int i = w - 1; i >= 0; i--) {
		double s = 0, ws = 0;
		if (!isnan(F->f[i])) {
			next = i;
			continue;
		}
		if (F->left[i] >= 0)
			idw(&s, &ws, F->f[F->left[i]], i - F->left[i]);
		if (next >= 0)
			idw(&s, &ws, F->f[next], next - i);
		F->f[i] = (float)(s / ws); /* ws > 0: see fill() */
	}
}

/* One row with voids: F->r raw, F->b its below records, row j. */
static void
fill_row(fillbuf *F, int j)
{
	int last = -1, next = -1, w = F->w, orphans = 0;

	for (int i = 0; i < w; i++) {
		F->left[i] = last;
		if (!isnan(F->r[i]))
			last = i;
	}
	for (int i = w - 1; i >= 0; i--) {
		double s = 0, ws = 0;
		F->mask[i] = !isnan(F->r[i]);
		if (F->mask[i]) {
			F->f[i] = F->r[i];
			next = i;
			continue;
		}
		if (F->left[i] >= 0)
			idw(&s, &ws, F->r[F->left[i]], i - F->left[i]);
		if (next >= 0)
			idw(&s, &ws, F->r[next], next - i);
		if (F->arow[i] >= 0)
			idw(&s, &ws, F->av[i], j - F->arow[i]);
		if (F->b[i].row >= 0)
			idw(&s, &ws, F->b[i].v, F->b[i].row - j);
		F->f[i] = ws > 0 ? (float)(s / ws) : NAN;
		orphans += ws == 0;
	}
	if (orphans > 0)
		fill_row_only(F);
}

/* Pass 2, top-down: fill each row with voids, overwrite it in place and
 * store its validity mask after the rows. */
static int
pass_down(dem *d, fillbuf *F, int bfd, tl_err *e)
{
	long long moff = (long long)F->h * F->w * (long long)sizeof(float);

	for (int j = 0; j < F->h; j++) {
		if (tl_pread(d->fd, F->r, F->w * sizeof(float), zoff(F, j),
		    "scratch file", e) < 0)
			return -1;
		if (bit(d->rowvoid, j)) {
			if (tl_pread(bfd, F->b, F->w * sizeof(below),
			    (long long)j * F->w * (long long)sizeof(below),
			    "scratch file", e) < 0)
				return -1;
			fill_row(F, j);
			if (tl_pwrite(d->fd, F->f, F->w * sizeof(float),
			    zoff(F, j), "scratch file", e) < 0 ||
			    tl_pwrite(d->fd, F->mask, (size_t)F->w,
			    moff + (long long)j * F->w, "scratch file", e) < 0)
				return -1;
		}
		for (int i = 0; i < F->w; i++)
			if (!isnan(F->r[i]))
				F->av[i] = F->r[i], F->arow[i] = j;
	}
	return 0;
}

/* Void filling, for geometry only (dem_read_row's mask keeps voids out of
 * error measures). Each void sample gets the inverse-distance weighted
 * mean (weights 1/d, d in samples) of up to four valid samples: the
 * nearest to its left and to its right in its row, and the nearest above
 * and below in its column, at any distance. A void whose row and column
 * hold no valid sample at all (possible only when its whole row is void)
 * then gets the same weighted mean of the nearest filled samples left and
 * right in its row; one exists, since some column has a valid sample.
 * Every result is a convex combination of valid heights. Two streaming
 * passes: bottom-up records the nearest valid sample below in a scratch
 * file, top-down carries the nearest above in memory. Memory O(width),
 * disk O(width * height); deterministic. */
static int
fill(dem *d, tl_err *e)
{
	fillbuf F;
	int bfd, r;

	if (fillbuf_alloc(&F, d->g.width, d->g.height, e) < 0)
		return -1;
	if ((bfd = tl_scratch(e)) < 0) {
		fillbuf_free(&F);
		return -1;
	}
	r = pass_up(d, &F, bfd, e);
	if (r == 0)
		r = pass_down(d, &F, bfd, e);
	close(bfd);
	fillbuf_free(&F);
	return r;
}

/* --- input and format detection ----------------------------------------- */

static int
spool_stdin(input *in, tl_err *e)
{
	char buf[65536];
	long long off = 0;
	ssize_t n;

	if ((in->fd = tl_scratch(e)) < 0)
		return -1;
	in->spooled = 1;
	for (;;) {
		n = read(STDIN_FILENO, buf, sizeof buf);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return tl_failsys(e, "stdin: read");
		if (n == 0)
			break;
		if (tl_pwrite(in->fd, buf, (size_t)n, off, "stdin spool", e) < 0)
			return -1;
		off += n;
	}
	in->size = off;
	return 0;
}

static int
input_open(input *in, const char *path, tl_err *e)
{
	struct stat st;
	ssize_t n;

	memset(in, 0, sizeof *in);
	in->fd = -1;
	if (strcmp(path, "-") == 0) {
		in->what = "stdin";
		if (spool_stdin(in, e) < 0)
			return -1;
	} else {
		in->what = path;
		if ((in->fd = open(path, O_RDONLY | O_CLOEXEC)) < 0)
			return tl_failsys(e, "%s: cannot open", path);
		if (fstat(in->fd, &st) != 0)
			return tl_failsys(e, "%s: stat", path);
		if (S_ISDIR(st.st_mode))
			return tl_fail(e, "%s: is a directory", path);
		in->size = st.st_size;
	}
	do
		n = pread(in->fd, in->magic, sizeof in->magic, 0);
	while (n < 0 && errno == EINTR);
	if (n < 0)
		return tl_failsys(e, "%s: read", in->what);
	in->nmagic = (int)n;
	return 0;
}

static int
magic_is(const input *in, const char *m, int n)
{
	return in->nmagic >= n && memcmp(in->magic, m, (size_t)n) == 0;
}

static int
is_tiff(const input *in)
{
	return magic_is(in, "II*\0", 4) || magic_is(in, "MM\0*", 4) ||
	    magic_is(in, "II+\0", 4) || magic_is(in, "MM\0+", 4);
}

static int
has_hgt_suffix(const char *path)
{
	size_t n = strlen(path);

	return n >= 4 && strcasecmp(path + n - 4, ".hgt") == 0;
}

static int
read_any(dem *d, load *L, const input *in, const char *path,
    const dem_opts *o, tl_err *e)
{
	int named = !in->spooled, r;
	int known = magic_is(in, "\x89PNG\r\n\x1a\n", 8) ||
	    magic_is(in, "\x76\x2f\x31\x01", 4);

	if (named && has_hgt_suffix(path)) {
		if (hgt_side(in->size) == 0)
			return tl_fail(e, "%s: not an SRTM .hgt (%lld bytes is "
			    "not 2 n^2)", path, in->size);
		return read_hgt(d, L, in, o->hgt_name ? o->hgt_name : path, o, e);
	}
	if (is_tiff(in))
		return read_tiff(d, L, in, o, e);
	if (!named && !known && hgt_side(in->size) > 0)
		return read_hgt(d, L, in, o->hgt_name, o, e);
	if (in->size == 0)
		return tl_fail(e, "%s: empty file", in->what);
	if ((r = read_oiio(d, L, in, known, o, e)) > 0)
		return tl_fail(e, "%s: not a raster (TIFF, PNG, EXR or SRTM "
		    ".hgt)", in->what);
	return r;
}

dem *
dem_open(const char *path, const dem_opts *o, tl_err *e)
{
	dem_opts none = { DEM_ENC_AUTO, NULL, { 0, 0 }, 0, 0 };
	input in;
	load L;
	dem *d;
	int r;

	if (o == NULL)
		o = &none;
	if ((d = tl_alloc(1, sizeof *d, e)) == NULL)
		return NULL;
	d->fd = -1;
	memset(&L, 0, sizeof L);
	L.fd = -1;
	if (input_open(&in, path, e) == 0) {
		snprintf(d->what, sizeof d->what, "%s", in.what);
		L.what = in.what;
		r = read_any(d, &L, &in, path, o, e);
	} else {
		r = -1;
	}
	if (in.fd >= 0)
		close(in.fd);
	free(L.seg);
	d->voids = L.voids;
	if (r == 0 && L.voids == (long long)L.w * L.h)
		r = tl_fail(e, "%s: no valid samples (every sample is a void)",
		    d->what);
	if (r == 0 && L.voids > 0)
		r = fill(d, e);
	if (r < 0) {
		dem_close(d);
		return NULL;
	}
	return d;
}

const georef *
dem_georef(const dem *d)
{
	return &d->g;
}

long long
dem_voids(const dem *d)
{
	return d->voids;
}

int
dem_read_row(dem *d, int j, float *z, unsigned char *valid, tl_err *e)
{
	long long w = d->g.width, h = d->g.height;

	if (j < 0 || j >= h)
		return tl_fail(e, "%s: row %d outside 0 .. %lld", d->what, j,
		    h - 1);
	if (tl_pread(d->fd, z, (size_t)w * sizeof(float),
	    j * w * (long long)sizeof(float), "DEM scratch file", e) < 0)
		return -1;
	if (valid == NULL)
		return 0;
	if (!bit(d->rowvoid, j)) {
		memset(valid, 1, (size_t)w);
		return 0;
	}
	return tl_pread(d->fd, valid, (size_t)w,
	    h * w * (long long)sizeof(float) + j * w, "DEM scratch file", e);
}

void
dem_close(dem *d)
{
	if (d == NULL)
		return;
	if (d->fd >= 0)
		close(d->fd);
	free(d->rowvoid);
	free(d);
}

/* --- options --------------------------------------------------------- */

static int
parse_cell(const char *s, double cell[2])
{
	char buf[64], *comma;

	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	if ((comma = strchr(buf, ',')) != NULL)
		*comma++ = '\0';
	if (tl_parse_double(buf, &cell[0]) < 0 || cell[0] <= 0)
		return -1;
	cell[1] = cell[0];
	if (comma != NULL && (tl_parse_double(comma, &cell[1]) < 0 ||
	    cell[1] <= 0))
		return -1;
	return 0;
}

int
dem_option(dem_opts *o, int c, const char *arg, tl_err *e)
{
	static const struct {
		const char *name;
		enum dem_encoding enc;
	} encs[] = {
		{ "auto", DEM_ENC_AUTO }, { "grey", DEM_ENC_GREY },
		{ "gray", DEM_ENC_GREY }, { "terrainrgb", DEM_ENC_TERRAINRGB },
		{ "terrarium", DEM_ENC_TERRARIUM },
	};

	switch (c) {
	case 'e':
		for (size_t k = 0; k < sizeof encs / sizeof encs[0]; k++)
			if (strcmp(arg, encs[k].name) == 0) {
				o->encoding = encs[k].enc;
				return 1;
			}
		return tl_fail(e, "-e %s: unknown encoding (auto, grey, "
		    "terrainrgb, terrarium)", arg);
	case 'N':
		if (tl_parse_double(arg, &o->nodata) < 0)
			return tl_fail(e, "-N %s: not a number", arg);
		o->has_nodata = 1;
		return 1;
	case 'n':
		o->hgt_name = arg;
		return 1;
	case 's':
		if (parse_cell(arg, o->cell) < 0)
			return tl_fail(e, "-s %s: expected dx or dx,dy in "
			    "metres, > 0", arg);
		return 1;
	}
	return 0;
}
