/* dem_vrt.c - a GDAL dataset's header as a mosaic's tile (dem_head), and
 * what the sources of a VRT agree on (dem_vrt_tiles): what they say that
 * the VRT lost (AREA_OR_POINT, the unit, the driver, signed bytes, the
 * block height), and that GDAL would not resample them. Shared by the
 * GDAL adapter (a VRT file, dem_gdal.c) and the mosaics (dem_mosaic.c),
 * which call it; it calls neither. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <cpl_minixml.h>
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include "dem/dem_gdal.h"

/* --- a tile's header ------------------------------------------------------ */

/* The tile's place on Earth: a north-up geotransform, since the VRT
 * places tiles by it and cannot turn them. */
static int
head_place(GDALDatasetH ds, dem_head *h, tl_err *e)
{
	double *gt = h->gt;

	if (GDALGetGeoTransform(ds, gt) != CE_None)
		return tl_fail(e, "%s: no geotransform: a mosaic places its "
		    "tiles by theirs", h->name);
	if (gt[2] != 0 || gt[4] != 0)
		return tl_fail(e, "%s: rotated or sheared georeferencing is not "
		    "supported: warp it north-up first (gdalwarp)", h->name);
	if (!isfinite(gt[0]) || !isfinite(gt[3]) || !(gt[1] > 0) ||
	    !(gt[5] < 0) || !isfinite(gt[1]) || !isfinite(gt[5]))
		return tl_fail(e, "%s: pixel size %g x %g: a mosaic's tiles "
		    "must run east and south (gdalwarp them north-up first)",
		    h->name, gt[1], gt[5]);
	return 0;
}

int
dem_head_read(GDALDatasetH ds, const char *path, dem_head *h, tl_err *e)
{
	GDALRasterBandH b = GDALGetRasterBand(ds, 1);
	OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
	const char *p;
	int bx, ok;

	memset(h, 0, sizeof *h);
	h->path = path;
	dem_name(path, h->name);
	if (head_place(ds, h, e) < 0)
		return -1;
	if (srs != NULL && (h->srs = OSRClone(srs)) == NULL)
		return tl_fail(e, "%s: out of memory", h->name);
	h->w = GDALGetRasterXSize(ds);
	h->h = GDALGetRasterYSize(ds);
	GDALGetBlockSize(b, &bx, &h->bh);
	h->nbands = GDALGetRasterCount(ds);
	h->type = GDALGetRasterDataType(b);
	p = GDALGetMetadataItem(b, "PIXELTYPE", "IMAGE_STRUCTURE");
	h->i8 = h->type == GDT_Byte && p != NULL && strcmp(p, "SIGNEDBYTE") == 0;
	h->nodata = GDALGetRasterNoDataValue(b, &h->has_nodata);
	h->scale = GDALGetRasterScale(b, &ok);
	h->offset = GDALGetRasterOffset(b, &ok);
	snprintf(h->driver, sizeof h->driver, "%s",
	    GDALGetDriverShortName(GDALGetDatasetDriver(ds)));
	p = GDALGetMetadataItem(ds, "AREA_OR_POINT", NULL);
	snprintf(h->aop, sizeof h->aop, "%s", p != NULL ? p : "");
	h->point = strcasecmp(h->aop, "Point") == 0;
	p = GDALGetRasterUnitType(b);
	snprintf(h->unit, sizeof h->unit, "%s", p != NULL ? p : "");
	return 0;
}

/* What the tiles agree on for the reader (dem_tiles): an empty field
 * once two differ. */
void
dem_tiles_note(dem_tiles *t, const dem_head *h, int first)
{
	if (first) {
		snprintf(t->driver, sizeof t->driver, "%s", h->driver);
		snprintf(t->aop, sizeof t->aop, "%s", h->aop);
		snprintf(t->unit, sizeof t->unit, "%s", h->unit);
		t->signed_byte = h->i8;
	}
	if (strcmp(t->driver, h->driver) != 0)
		t->driver[0] = '\0';
	if (strcasecmp(t->aop, h->aop) != 0)
		t->aop[0] = '\0';
	if (strcasecmp(t->unit, h->unit) != 0)
		t->unit[0] = '\0';
	t->signed_byte &= h->i8;
	if (h->bh > t->rows)
		t->rows = h->bh;
}

/* --- a VRT file's sources ------------------------------------------------ */

#define VRT_DEPTH 8  /* VRTs of VRTs looked into; GDAL refuses loops */

/* One source of a VRT (its XML, as the band's "vrt_sources" give it):
 * refused when GDAL would resample it, scaled (SrcRect's size not
 * DstRect's) or placed at a fractional pixel, unless --resample. */
static int
vrt_rect(CPLXMLNode *x, const char *vrt, const dem_opts *o, tl_err *e)
{
	static const char *const k[4] = { "xOff", "yOff", "xSize", "ySize" };
	CPLXMLNode *sr = CPLGetXMLNode(x, "SrcRect");
	CPLXMLNode *dr = CPLGetXMLNode(x, "DstRect");
	const char *f = CPLGetXMLValue(x, "SourceFilename", "?");
	char nv[DEM_NAME], nf[DEM_NAME];
	double s[4], d[4];

	if (o->resample || sr == NULL || dr == NULL)
		return 0;
	for (int i = 0; i < 4; i++) {
		s[i] = CPLAtof(CPLGetXMLValue(sr, k[i], "0"));
		d[i] = CPLAtof(CPLGetXMLValue(dr, k[i], "0"));
	}
	dem_name(vrt, nv), dem_name(f, nf);
	if (fabs(s[2] - d[2]) > DEM_GRID_TOL || fabs(s[3] - d[3]) > DEM_GRID_TOL)
		return tl_fail(e, "%s: its source %s is scaled from %.10g x %.10g "
		    "to %.10g x %.10g pixels: tiles of another pixel size are "
		    "never resampled (gdalwarp -tr them to one grid first), "
		    "unless --resample asks for GDAL's resampling", nv, nf, s[2],
		    s[3], d[2], d[3]);
	for (int i = 0; i < 4; i++)
		if (fabs((i < 2 ? d : s)[i % 2] -
		    round((i < 2 ? d : s)[i % 2])) > DEM_GRID_TOL)
			return tl_fail(e, "%s: its source %s lies off the VRT's "
			    "grid (%s offset %.10g, %.10g): it would be "
			    "resampled; gdalwarp it onto the grid first, or give "
			    "--resample for GDAL's resampling", nv, nf, i < 2 ?
			    "DstRect" : "SrcRect", (i < 2 ? d : s)[0],
			    (i < 2 ? d : s)[1]);
	return 0;
}

/* Every source of every band of the VRT ds, as vrt_rect checks it. */
static int
vrt_rects(GDALDatasetH ds, const dem_opts *o, tl_err *e)
{
	const char *self = GDALGetDescription(ds);

	for (int b = 1; b <= GDALGetRasterCount(ds); b++) {
		char **src = GDALGetMetadata(GDALGetRasterBand(ds, b),
		    "vrt_sources");
		for (int k = 0; src != NULL && src[k] != NULL; k++) {
			const char *v = strchr(src[k], '=');
			CPLXMLNode *x = v != NULL ? CPLParseXMLString(v + 1) :
			    NULL;
			int r = x != NULL ? vrt_rect(x, self, o, e) : 0;
			if (x != NULL)
				CPLDestroyXMLNode(x);
			if (r < 0)
				return -1;
		}
	}
	return 0;
}

/* A VRT source's file must be a regular one: GDAL would wait on a FIFO
 * for ever. */
static int
vrt_file(const char *vrt, const char *f, tl_err *e)
{
	char nv[DEM_NAME], nf[DEM_NAME];
	struct stat st;

	if (strncmp(f, "/vsi", 4) == 0 || stat(f, &st) != 0 ||
	    S_ISREG(st.st_mode))
		return 0;
	return tl_fail(e, "%s: its source %s is not a regular file (%s)",
	    dem_name(vrt, nv), dem_name(f, nf), S_ISDIR(st.st_mode) ?
	    "a directory" : S_ISFIFO(st.st_mode) ? "a FIFO" :
	    "a device or socket");
}

static int vrt_tiles(GDALDatasetH ds, dem_tiles *t, const dem_opts *o,
    int depth, tl_err *e);

/* What a VRT's own sources say, where the VRT h says nothing (a VRT of
 * VRTs of pixel-is-point tiles is pixel-is-point). */
int
dem_head_vrt(GDALDatasetH ds, dem_head *h, const dem_opts *o, int depth,
    tl_err *e)
{
	dem_tiles sub;

	if (strcmp(h->driver, "VRT") != 0 || depth >= VRT_DEPTH)
		return 0;
	if (vrt_tiles(ds, &sub, o, depth + 1, e) < 0)
		return -1;
	if (h->aop[0] == '\0')
		snprintf(h->aop, sizeof h->aop, "%s", sub.aop);
	h->point = strcasecmp(h->aop, "Point") == 0;
	if (h->unit[0] == '\0')
		snprintf(h->unit, sizeof h->unit, "%s", sub.unit);
	if (sub.driver[0] != '\0')
		snprintf(h->driver, sizeof h->driver, "%s", sub.driver);
	h->i8 |= h->type == GDT_Byte && sub.signed_byte;
	h->bh = sub.rows > h->bh ? sub.rows : h->bh;
	return 0;
}

/* The source h of the VRT named vrt against the first, f: a VRT mixing
 * pixel-is-point and pixel-is-area sources shifts some by half a pixel. */
static int
vrt_point(const char *vrt, const dem_head *f, const dem_head *h, tl_err *e)
{
	char nv[DEM_NAME];

	if (f->point == h->point)
		return 0;
	return tl_fail(e, "%s: its source %s is pixel-is-%s, its source %s "
	    "pixel-is-%s: their georeferencing differs by half a pixel "
	    "(gdal_edit.py -mo AREA_OR_POINT= one of them, as it truly is)",
	    dem_name(vrt, nv), h->name, h->point ? "point" : "area", f->name,
	    f->point ? "point" : "area");
}

/* One source file of the VRT ds (not a VRT's own file), noted in t: 1
 * when it does not open (the VRT's reading then says why). */
static int
vrt_source(GDALDatasetH ds, const char *file, dem_tiles *t, dem_head *first,
    int *seen, const dem_opts *o, int depth, tl_err *e)
{
	const char *self = GDALGetDescription(ds);
	GDALDatasetH s;
	dem_head h = { 0 };
	int r = 0;

	if (vrt_file(self, file, e) < 0)
		return -1;
	if ((s = dem_gdal_open(file)) == NULL)
		return 1;
	if (GDALGetRasterCount(s) < 1 || dem_head_read(s, file, &h, e) < 0)
		r = 1;
	else if (dem_head_vrt(s, &h, o, depth, e) < 0 ||
	    vrt_point(self, *seen ? first : &h, &h, e) < 0)
		r = -1;
	else {
		dem_tiles_note(t, &h, *seen == 0);
		if ((*seen)++ == 0)
			*first = h, first->srs = NULL;
	}
	if (h.srs != NULL)
		OSRDestroySpatialReference(h.srs);
	GDALClose(s);
	return r;
}

static int
vrt_tiles(GDALDatasetH ds, dem_tiles *t, const dem_opts *o, int depth,
    tl_err *e)
{
	char **files = GDALGetFileList(ds);
	const char *self = GDALGetDescription(ds);
	dem_head first;
	int seen = 0, r = 0;

	memset(t, 0, sizeof *t);
	if (vrt_rects(ds, o, e) < 0)
		r = -1;
	for (int k = 0; r == 0 && files != NULL && files[k] != NULL; k++)
		if (strcmp(files[k], self) != 0 && (r = vrt_source(ds, files[k],
		    t, &first, &seen, o, depth, e)) > 0)
			memset(t, 0, sizeof *t); /* and no more */
	CSLDestroy(files);
	return r < 0 ? -1 : 0;
}

int
dem_vrt_tiles(GDALDatasetH ds, dem_tiles *t, const dem_opts *o, tl_err *e)
{
	dem_gdal_msg c;
	int r;

	/* quiet: a source that does not open only makes them not agree */
	dem_gdal_catch(&c);
	r = vrt_tiles(ds, t, o, 0, e);
	dem_gdal_release();
	return r;
}
