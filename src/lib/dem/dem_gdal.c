/* dem_gdal.c - the DEM adapter for every raster GDAL reads: its
 * georeferencing (geotransform, CRS, AREA_OR_POINT), nodata, mask band,
 * scale/offset and vertical unit, and its samples, read window by window
 * with GDAL's block cache bounded, so memory does not grow with the DEM.
 * A dataset already open (a mosaic's VRT, dem_mosaic.c) reads the same
 * way. "band" here is GDAL's: a raster band of the dataset (the first
 * holds the heights). dem_gdal_adapter is its table of methods. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include "dem/dem_gdal.h"

typedef struct {
	GDALDatasetH ds;
	GDALRasterBandH band;
	const char *driver;    /* the format, or the tiles' of a VRT */
	const dem_tiles *t;    /* what a VRT's tiles agree on, or NULL */
	int w, h, nbands;
	int i8;        /* GDAL 3.6's signed bytes: Byte with PIXELTYPE */
	int vrt;       /* a VRT: read in windows of whole rows */
	dem_gdal_msg c;
} src;

/* --- georeferencing ------------------------------------------------------ */

/* Undoing GDAL's half-pixel shift of a point raster can miss the file's
 * value by an ulp; a value within 4 ulps of a 9-decimal number is that
 * number (what the file said). */
static double
snap(double v)
{
	double r = round(v * 1e9) / 1e9;

	return fabs(r - v) <= 4 * (nextafter(fabs(v), INFINITY) - fabs(v)) ?
	    r : v;
}

static int
geotransform(const src *s, georef *g, dem_load *L, tl_err *e)
{
	double gt[6];

	if (GDALGetGeoTransform(s->ds, gt) != CE_None) {
		if (GDALGetGCPCount(s->ds) > 0)
			return tl_fail(e, "%s: georeferenced by ground control "
			    "points only: warp it to a grid first (gdalwarp)",
			    L->what);
		return 1; /* no grid */
	}
	if (gt[2] != 0 || gt[4] != 0)
		return tl_fail(e, "%s: rotated or sheared georeferencing "
		    "(geotransform terms %g, %g) is not supported: warp it "
		    "north-up first (gdalwarp)", L->what, gt[2], gt[4]);
	for (int k = 0; k < 6; k++)
		if (!isfinite(gt[k]) || gt[1] == 0 || gt[5] == 0)
			return tl_fail(e, "%s: invalid georeferencing: pixel "
			    "size %g x %g", L->what, gt[1], gt[5]);
	/* west-running columns, south-running rows: read them turned */
	L->flip_x = gt[1] < 0;
	L->flip_y = gt[5] > 0;
	g->step[0] = fabs(gt[1]);
	g->step[1] = -fabs(gt[5]);
	g->origin[0] = L->flip_x ? gt[0] + s->w * gt[1] : gt[0];
	g->origin[1] = L->flip_y ? gt[3] + s->h * gt[5] : gt[3];
	if (g->point) {
		g->origin[0] = snap(g->origin[0] + 0.5 * g->step[0]);
		g->origin[1] = snap(g->origin[1] + 0.5 * g->step[1]);
	}
	return 0;
}

/* The EPSG code of h: its own, else that of the one EPSG CRS PROJ finds
 * equivalent with full confidence (an ESRI .prj names none); 0 if none. */
static int
epsg_of(OGRSpatialReferenceH h)
{
	const char *auth = OSRGetAuthorityName(h, NULL);
	const char *code = OSRGetAuthorityCode(h, NULL);
	OGRSpatialReferenceH *m;
	int n = 0, *conf = NULL, r = 0;

	if (auth != NULL && code != NULL)
		return strcasecmp(auth, "EPSG") == 0 ? atoi(code) : 0;
	m = OSRFindMatches(h, NULL, &n, &conf);
	if (m != NULL && n >= 1 && conf[0] == 100 &&
	    (n == 1 || conf[1] < 100) &&
	    (auth = OSRGetAuthorityName(m[0], NULL)) != NULL &&
	    strcasecmp(auth, "EPSG") == 0 &&
	    (code = OSRGetAuthorityCode(m[0], NULL)) != NULL)
		r = atoi(code);
	OSRFreeSRSArray(m);
	CPLFree(conf);
	return r;
}

/* "EPSG:n" when the CRS is one EPSG code, else its WKT2 on one line. */
static int
crs_name(OGRSpatialReferenceH h, georef *g, const char *what, tl_err *e)
{
	const char *opts[] = { "FORMAT=WKT2_2019", "MULTILINE=NO", NULL };
	char *wkt = NULL;

	if ((g->epsg = epsg_of(h)) > 0) {
		snprintf(g->crs, sizeof g->crs, "EPSG:%d", g->epsg);
		return 0;
	}
	/* PROJ names no code when it cannot open its database either */
	if (tl_fds_exhausted())
		return tl_fail_fds(e, what, "PROJ's database");
	if (OSRExportToWktEx(h, &wkt, opts) != OGRERR_NONE || wkt == NULL)
		return tl_fail(e, "%s: cannot describe its CRS", what);
	if (strlen(wkt) >= sizeof g->crs) {
		CPLFree(wkt);
		return tl_fail(e, "%s: CRS definition too long", what);
	}
	snprintf(g->crs, sizeof g->crs, "%s", wkt);
	CPLFree(wkt);
	return 0;
}

/* Model, name and unit of the horizontal CRS h. */
static int
horizontal(OGRSpatialReferenceH h, georef *g, const char *what, tl_err *e)
{
	if (OSRIsGeocentric(h))
		return tl_fail(e, "%s: geocentric CRS: not a height grid", what);
	if (OSRIsGeographic(h)) {
		if (fabs(OSRGetAngularUnits(h, NULL) * 180 / M_PI - 1) > 1e-9)
			return tl_fail(e, "%s: geographic CRS in angular units "
			    "other than degrees: not supported", what);
		g->model = GEO_GEOGRAPHIC;
		g->unit = 0;
	} else if (OSRIsProjected(h)) {
		g->model = GEO_PROJECTED;
		g->unit = OSRGetLinearUnits(h, NULL);
	} else {
		/* a local (engineering) CRS: a unit, no place on Earth */
		g->model = GEO_NONE;
		g->unit = OSRGetLinearUnits(h, NULL);
		return g->unit > 0 ? 0 : tl_fail(e, "%s: CRS without a linear "
		    "unit", what);
	}
	return crs_name(h, g, what, e);
}

/* The vertical CRS of a compound CRS, and its unit. */
static void
vertical(OGRSpatialReferenceH srs, georef *g, double *zunit)
{
	const char *code = OSRGetAuthorityCode(srs, "VERT_CS");
	const char *name = OSRGetAttrValue(srs, "VERT_CS", 0);

	if (!OSRIsVertical(srs))
		return;
	if (code != NULL)
		snprintf(g->vdatum, sizeof g->vdatum, "EPSG:%s", code);
	else if (name != NULL)
		snprintf(g->vdatum, sizeof g->vdatum, "%s", name);
	*zunit = OSRGetTargetLinearUnits(srs, "VERT_CS", NULL);
}

static int
crs(const src *s, georef *g, double *zunit, const char *what, tl_err *e)
{
	OGRSpatialReferenceH srs = GDALGetSpatialRef(s->ds), h;
	int r;

	if (srs == NULL || !(OSRIsGeographic(srs) || OSRIsProjected(srs) ||
	    OSRIsLocal(srs) || OSRIsGeocentric(srs)))
		return 1; /* none, or only a vertical CRS */
	if ((h = OSRClone(srs)) == NULL)
		return tl_fail(e, "%s: out of memory", what);
	OSRStripVertical(h);
	r = horizontal(h, g, what, e);
	OSRDestroySpatialReference(h);
	if (r == 0)
		vertical(srs, g, zunit);
	return r;
}

/* Metres per height unit from the band's unit type; 0 when it names
 * none we know (the vertical CRS's unit then holds). */
static double
unit_type(const char *u)
{
	static const struct {
		const char *name;
		double m;
	} units[] = {
		{ "m", 1 }, { "metre", 1 }, { "meter", 1 }, { "metres", 1 },
		{ "meters", 1 }, { "ft", 0.3048 }, { "foot", 0.3048 },
		{ "feet", 0.3048 }, { "international foot", 0.3048 },
		{ "us-ft", 1200.0 / 3937 }, { "ftUS", 1200.0 / 3937 },
		{ "US survey foot", 1200.0 / 3937 },
		{ "foot_us", 1200.0 / 3937 },
	};

	for (size_t k = 0; u != NULL && k < sizeof units / sizeof units[0];
	    k++)
		if (strcasecmp(u, units[k].name) == 0)
			return units[k].m;
	return 0;
}

/* Everything about the grid but its samples. */
static int
describe(const src *s, georef *g, dem_load *L, const dem_opts *o,
    tl_err *e)
{
	const char *aop = GDALGetMetadataItem(s->ds, "AREA_OR_POINT", NULL);
	const char *p;
	char unit[64];
	double zunit = 1, u;
	int ok, r, point;

	/* what a VRT lost of its tiles; GDAL's strings are used at once,
	 * since its next call (a GeoTIFF's first band query loads more
	 * metadata) may free them */
	if (aop == NULL && s->t != NULL && s->t->aop[0] != '\0')
		aop = s->t->aop;
	point = aop != NULL && strcasecmp(aop, "Point") == 0;
	p = GDALGetRasterUnitType(s->band);
	if ((p == NULL || p[0] == '\0') && s->t != NULL)
		p = s->t->unit;
	snprintf(unit, sizeof unit, "%s", p != NULL ? p : "");

	memset(g, 0, sizeof *g);
	g->unit = 1;
	g->point = point;
	g->nodata = GDALGetRasterNoDataValue(s->band, &ok);
	g->has_nodata = ok != 0;
	L->scale = GDALGetRasterScale(s->band, &ok);
	L->offset = GDALGetRasterOffset(s->band, &ok);
	if ((r = geotransform(s, g, L, e)) < 0)
		return -1;
	if (r > 0) { /* no grid: the user's cell size, else 1 m */
		double nd = g->nodata;
		int has = g->has_nodata;
		geo_init_none(g, o->cell[0], o->cell[1]);
		g->nodata = nd, g->has_nodata = has;
	} else if (crs(s, g, &zunit, L->what, e) < 0) {
		return -1;
	} else if (o->cell[0] > 0) {
		g->cell[0] = o->cell[0];
		g->cell[1] = o->cell[1] > 0 ? o->cell[1] : o->cell[0];
	}
	/* SRTM heights are EGM96 by definition; the format does not say */
	if (g->vdatum[0] == '\0' && strcmp(s->driver, "SRTMHGT") == 0)
		snprintf(g->vdatum, sizeof g->vdatum, "EPSG:5773");
	u = unit_type(unit);
	L->zunit = u > 0 ? u : zunit > 0 ? zunit : 1;
	return 0;
}

/* --- samples --------------------------------------------------------- */

/* A VRT's windows: whole rows, as many as its tiles' tallest block (so
 * that each block is decoded once while GDAL's cache holds one band of
 * them) within 1 to 2 million samples. Its own 128 x 128 blocks would
 * decode every strip of a tile once per block column. */
static void
vrt_window(const src *s, int *ww, int *wh)
{
	double lo = fmax(1, floor((1 << 20) / (double)s->w));
	double hi = fmax(1, floor((1 << 21) / (double)s->w));
	int rows = s->t != NULL ? s->t->rows : 0;

	*ww = s->w;
	*wh = (int)fmin(fmax(rows, lo), hi);
	if (*wh > s->h)
		*wh = s->h;
}

/* Windows of whole GDAL blocks, about a million samples each, so every
 * block is decoded once and the buffers stay small. */
static void
window_size(const src *s, int *ww, int *wh)
{
	int bx, by;

	if (s->vrt) {
		vrt_window(s, ww, wh);
		return;
	}
	GDALGetBlockSize(s->band, &bx, &by);
	bx = bx < 1 || bx > s->w ? s->w : bx;
	by = by < 1 || by > s->h ? s->h : by;
	*ww = bx;
	*wh = by;
	if (bx == s->w) /* strips: as many rows as make ~1 M samples */
		*wh = by * (int)fmax(1, floor((1 << 20) / ((double)s->w * by)));
	if (*wh > s->h)
		*wh = s->h;
}

typedef struct {
	void *px;
	unsigned char *mask;
	int use_mask, rgb, i8;
	int type;      /* enum tl_px of px as delivered */
	size_t size;   /* bytes per pixel in px */
} buffers;

static int
read_window(const src *s, dem_load *L, buffers *b, int x0, int y0, int nx,
    int ny, tl_err *e)
{
	static int rgb_bands[3] = { 1, 2, 3 };
	CPLErr err;

	if (b->rgb)
		err = GDALDatasetRasterIO(s->ds, GF_Read, x0, y0, nx, ny, b->px,
		    nx, ny, GDT_Byte, 3, rgb_bands, 3, (GSpacing)3 * nx, 1);
	else
		err = GDALRasterIO(s->band, GF_Read, x0, y0, nx, ny, b->px, nx,
		    ny, b->i8 ? GDT_Byte : GDT_Float64, 0, 0);
	if (err == CE_None && b->use_mask)
		err = GDALRasterIO(GDALGetMaskBand(s->band), GF_Read, x0, y0,
		    nx, ny, b->mask, nx, ny, GDT_Byte, 0, 0);
	if (err != CE_None)
		return tl_fail(e, "%s: truncated or corrupt: %s", L->what,
		    s->c.msg[0] ? s->c.msg : "GDAL cannot read it");
	for (int k = 0; k < ny; k++) {
		size_t off = (size_t)k * nx;
		const char *row = (char *)b->px + off * b->size;
		if (dem_load_put(L, row, b->type, b->rgb ? 3 : 1, x0, y0 + k, nx,
		    b->use_mask ? b->mask + off : NULL, e) < 0)
			return -1;
	}
	return 0;
}

static int
samples(const src *s, dem_load *L, tl_err *e)
{
	int ww, wh, x0, x1, y0, y1, bx, by, r = 0;
	int flags = GDALGetMaskFlags(s->band);
	buffers b = { 0 };

	window_size(s, &ww, &wh);
	/* the source rows of the kept ones (dem_open_rows), from a block's
	 * first row so that windows stay whole blocks */
	y0 = L->flip_y ? s->h - L->cy1 : L->cy0;
	y1 = L->flip_y ? s->h - L->cy0 : L->cy1;
	GDALGetBlockSize(s->band, &bx, &by);
	if (!s->vrt && by > 0)
		y0 -= y0 % by;
	/* the source columns of the kept ones (dem_open_cols): whole
	 * blocks of a file, just those of a VRT, which has none */
	x0 = L->flip_x ? s->w - L->cx1 : L->cx0;
	x1 = L->flip_x ? s->w - L->cx0 : L->cx1;
	if (s->vrt)
		ww = x1 - x0;
	else
		x0 -= x0 % ww;
	b.rgb = L->enc != DEM_ENC_GREY;
	b.i8 = s->i8 && !b.rgb;
	b.type = b.rgb ? TL_PX_U8 : b.i8 ? TL_PX_I8 : TL_PX_F64;
	b.size = b.rgb ? 3 : b.i8 ? 1 : sizeof(double);
	/* a real mask (alpha, per-dataset, explicit); nodata we test
	 * ourselves, so that -N overrides it */
	b.use_mask = !(flags & (GMF_ALL_VALID | GMF_NODATA));
	b.px = tl_alloc((size_t)ww * wh, b.size, e);
	b.mask = b.use_mask ? tl_alloc((size_t)ww * wh, 1, e) : NULL;
	if (b.px == NULL || (b.use_mask && b.mask == NULL))
		r = -1;
	/* a band of windows' rows, staged and written at once */
	for (int y = y0; y < y1 && r == 0; y += wh) {
		int ny = y1 - y < wh ? y1 - y : wh;
		r = dem_load_band(L, y, ny, e);
		for (int x = x0; x < x1 && r == 0; x += ww)
			r = read_window(s, L, &b, x, y, x1 - x < ww ? x1 - x : ww,
			    ny, e);
		if (r == 0)
			r = dem_load_flush(L, e);
	}
	free(b.px);
	free(b.mask);
	return r;
}

/* --- opening ------------------------------------------------------------- */

static int
is_hgt_name(const char *path)
{
	size_t n = strlen(path);

	return (n >= 4 && strcasecmp(path + n - 4, ".hgt") == 0) ||
	    (n >= 8 && strcasecmp(path + n - 8, ".hgt.zip") == 0);
}

/* What GDAL could not open: not ours (1), or a reason worth saying. */
static int
not_opened(const dem_gdal_msg *c, const char *path, dem_load *L,
    tl_err *e)
{
	if (is_hgt_name(path))
		return tl_fail(e, "%s: not an SRTM .hgt GDAL can read: an .hgt "
		    "is known by its tile name (N44W072.hgt) and a size of "
		    "2 n^2 bytes; name it so, or give the name with -n", L->what);
	if (c->msg[0] != '\0' && strstr(c->msg, "not recognized") == NULL &&
	    strstr(c->msg, "not recognised") == NULL)
		return tl_fail(e, "%s: truncated or corrupt: %s", L->what,
		    c->msg);
	return 1;
}

/* The open dataset's size, first band and driver, or why it is no DEM. */
static int
open_src(src *s, dem_load *L, tl_err *e)
{
	const char *p;

	s->w = GDALGetRasterXSize(s->ds);
	s->h = GDALGetRasterYSize(s->ds);
	s->nbands = GDALGetRasterCount(s->ds);
	s->driver = GDALGetDriverShortName(GDALGetDatasetDriver(s->ds));
	s->vrt = strcmp(s->driver, "VRT") == 0;
	if (s->vrt && s->t != NULL && s->t->driver[0] != '\0')
		s->driver = s->t->driver;
	if (s->nbands < 1) {
		char **sub = GDALGetMetadata(s->ds, "SUBDATASETS");
		const char *one = CSLFetchNameValue(sub, "SUBDATASET_1_NAME");
		return one != NULL ? tl_fail(e, "%s: a container of rasters: "
		    "name one, e.g. %s", L->what, one) :
		    tl_fail(e, "%s: no raster band", L->what);
	}
	s->band = GDALGetRasterBand(s->ds, 1);
	s->i8 = GDALGetRasterDataType(s->band) == GDT_Byte &&
	    (((p = GDALGetMetadataItem(s->band, "PIXELTYPE",
	    "IMAGE_STRUCTURE")) != NULL && strcmp(p, "SIGNEDBYTE") == 0) ||
	    (p == NULL && s->t != NULL && s->t->signed_byte));
	if (GDALDataTypeIsComplex(GDALGetRasterDataType(s->band)))
		return tl_fail(e, "%s: complex samples are not heights",
		    L->what);
	return 0;
}

int
dem_read_dataset(dem_load *L, georef *g, GDALDatasetH ds,
    const dem_tiles *t, const dem_opts *o, tl_err *e)
{
	src s = { .ds = ds, .t = t };
	dem_tiles vt;
	GDALDataType type;
	int r;

	dem_gdal_init();
	/* a VRT from gdalbuildvrt lost what its tiles say */
	if (t == NULL && strcmp(GDALGetDriverShortName(GDALGetDatasetDriver(
	    ds)), "VRT") == 0) {
		if (dem_vrt_tiles(ds, &vt, o, e) < 0)
			return -1;
		s.t = &vt;
	}
	dem_gdal_catch(&s.c);
	if ((r = open_src(&s, L, e)) != 0)
		goto out;
	type = GDALGetRasterDataType(s.band);
	r = -1;
	if (dem_load_encoding(L, o, type == GDT_Byte && !s.i8 ? TL_PX_U8 :
	    TL_PX_F64, type == GDT_Byte ? s.nbands : 1, e) < 0 ||
	    describe(&s, g, L, o, e) < 0 ||
	    dem_load_begin(L, g, o, s.w, s.h, type == GDT_Float32, e) < 0)
		goto out;
	r = L->info ? 0 : samples(&s, L, e);
out:
	dem_gdal_release();
	return r;
}

/* dem_adapter's read: path opened by GDAL (base and in are the reader's
 * business: GDAL knows its formats by itself). */
static int
read_gdal(dem_load *L, georef *g, const char *path, const char *base,
    enum dem_input in, const dem_opts *o, tl_err *e)
{
	GDALDatasetH ds;
	dem_gdal_msg c;
	int r;

	(void)base, (void)in;
	dem_gdal_init();
	dem_gdal_catch(&c);
	ds = dem_gdal_open(path);
	r = ds == NULL ? not_opened(&c, path, L, e) :
	    dem_read_dataset(L, g, ds, NULL, o, e);
	if (ds != NULL)
		GDALClose(ds);
	dem_gdal_release();
	return r;
}

/* --- the files it reads -------------------------------------------------- */

/* dem_adapter's files: what GDAL says the dataset path reads
 * (GDALGetFileList: itself, a VRT's sources, a world file, ...), opened
 * as any raster (no PAM sidecar is read: the list names it). */
static int
gdal_files(const char *path, char ***files, int *n, tl_err *e)
{
	dem_gdal_msg c;
	GDALDatasetH ds;
	char **list, **v;
	int k, m;

	dem_gdal_init();
	dem_gdal_catch(&c);
	ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL,
	    NULL);
	list = ds != NULL ? GDALGetFileList(ds) : NULL;
	if (ds != NULL)
		GDALClose(ds);
	dem_gdal_release();
	if (ds == NULL)
		return 1;
	m = CSLCount(list);
	if ((v = calloc((size_t)m + 1, sizeof *v)) == NULL) {
		CSLDestroy(list);
		return tl_fail(e, "out of memory");
	}
	for (k = 0; k < m && (v[k] = strdup(list[k])) != NULL; k++)
		continue;
	CSLDestroy(list);
	if (k < m) {
		while (k-- > 0)
			free(v[k]);
		free(v);
		return tl_fail(e, "out of memory");
	}
	*files = v, *n = m;
	return 0;
}

int
dem_gdal_is_vrt(const char *path)
{
	GDALDriverH drv;
	dem_gdal_msg c;
	int r;

	dem_gdal_init();
	dem_gdal_catch(&c);
	drv = GDALIdentifyDriver(path, NULL);
	r = drv != NULL && strcmp(GDALGetDriverShortName(drv), "VRT") == 0;
	dem_gdal_release();
	return r;
}

const dem_adapter dem_gdal_adapter = {
	"GDAL", 1u << DEM_IN_VSI | 1u << DEM_IN_NONE | 1u << DEM_IN_KNOWN,
	read_gdal, gdal_files,
};
