/* dem_mosaic.c - several DEM files read as one (dem2fqm(1), MOSAICS).
 * Each tile is checked against the first: CRS, pixel size, one grid,
 * bands, sample type, nodata, scale and offset, unit, AREA_OR_POINT;
 * tiles that overlap (SRTM tiles share their edge row and column) are
 * compared where they do. GDALBuildVRT then makes them one in-memory
 * VRT, which the GDAL adapter reads like any dataset (dem_gdal.c). The
 * checks sort (by west edge, by inode), so that thousands of tiles cost
 * O(n log n), not a pass over every pair; a file listed twice is read
 * once. A tile's header, and a VRT file's sources (what they say that
 * the VRT lost, and that GDAL would not resample them), are dem_vrt.c's.
 *
 * Only headers are held, one per tile: samples stream through GDAL's
 * block cache; at most two tiles are open at once besides the VRT's own
 * pool of open sources, which GDAL bounds.
 *
 * Here dem_read_mosaic and its checks of the tiles' headers, of files
 * listed twice and of gaps, then the VRT they vouch for (dem_mosaic_vrt,
 * which dem2rgb's warp reads too: dem_warp_list.c); the samples of
 * overlapping tiles compared in dem_mosaic_overlap.c; a tile opened in
 * dem_mosaic_tile.c (dem_mosaic.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <cpl_minixml.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include "dem/dem_mosaic.h"

/* --- agreement with the first tile ---------------------------------------- */

static const char *
crs_label(OGRSpatialReferenceH s)
{
	const char *n = s != NULL ? OSRGetName(s) : NULL;

	return s == NULL ? "none" : n != NULL ? n : "unnamed";
}

static void
nodata_label(const dem_head *h, char *buf, size_t n)
{
	if (!h->has_nodata)
		snprintf(buf, n, "none");
	else
		snprintf(buf, n, "%.17g", h->nodata);
}

static const char *
type_label(const dem_head *h)
{
	return h->i8 ? "Int8 (signed Byte)" : GDALGetDataTypeName(h->type);
}

/* The tile's place on the first's grid (t->col, t->row): the same pixel
 * size and an origin a whole number of pixels away. A pixel size may
 * differ only so little that the tile's far edge stays on the grid. */
static int
agree_grid(const dem_head *r, const dem_head *h, tile *t, tl_err *e)
{
	double fx = (h->gt[0] - r->gt[0]) / r->gt[1];
	double fy = (h->gt[3] - r->gt[3]) / r->gt[5];

	if (fabs(h->gt[1] / r->gt[1] - 1) * h->w > DEM_GRID_TOL ||
	    fabs(h->gt[5] / r->gt[5] - 1) * h->h > DEM_GRID_TOL)
		return tl_fail(e, "%s: pixel size %.10g x %.10g, the first "
		    "file's (%s) %.10g x %.10g: tiles are never resampled "
		    "(gdalwarp -tr them to one grid first)", h->name, h->gt[1],
		    -h->gt[5], r->name, r->gt[1], -r->gt[5]);
	if (fabs(fx) > DEM_MAXDIM || fabs(fy) > DEM_MAXDIM)
		return tl_fail(e, "%s: more than %d pixels from the first file "
		    "(%s): too far for one DEM", h->name, DEM_MAXDIM, r->name);
	if (fabs(fx - round(fx)) > DEM_GRID_TOL ||
	    fabs(fy - round(fy)) > DEM_GRID_TOL)
		return tl_fail(e, "%s: origin off the first file's (%s) grid by "
		    "%.3g pixel in x and %.3g in y: tiles must share one grid "
		    "(gdalwarp them onto it first)", h->name, r->name,
		    fx - round(fx), fy - round(fy));
	t->col = (int)round(fx);
	t->row = (int)round(fy);
	t->w = h->w;
	t->h = h->h;
	return 0;
}

/* Nodata equal, NaN to NaN; -N overrides them all, so then it does not
 * matter. */
static int
agree_nodata(const dem_head *r, const dem_head *h, const dem_opts *o,
    tl_err *e)
{
	char a[64], b[64];

	if (o->has_nodata || (!r->has_nodata && !h->has_nodata) ||
	    (r->has_nodata && h->has_nodata && (r->nodata == h->nodata ||
	    (isnan(r->nodata) && isnan(h->nodata)))))
		return 0;
	nodata_label(h, a, sizeof a);
	nodata_label(r, b, sizeof b);
	return tl_fail(e, "%s: nodata %s, the first file's (%s) %s", h->name,
	    a, r->name, b);
}

/* What the samples mean: bands, type, nodata, scale, unit, point. */
static int
agree_samples(const dem_head *r, const dem_head *h, const dem_opts *o,
    tl_err *e)
{
	if (h->nbands != r->nbands)
		return tl_fail(e, "%s: %d bands, the first file's (%s) %d",
		    h->name, h->nbands, r->name, r->nbands);
	if (h->type != r->type || h->i8 != r->i8)
		return tl_fail(e, "%s: %s samples, the first file's (%s) %s",
		    h->name, type_label(h), r->name, type_label(r));
	if (agree_nodata(r, h, o, e) < 0)
		return -1;
	if (h->scale != r->scale || h->offset != r->offset)
		return tl_fail(e, "%s: scale %g and offset %g, the first file's "
		    "(%s) %g and %g", h->name, h->scale, h->offset, r->name,
		    r->scale, r->offset);
	if (strcasecmp(h->unit, r->unit) != 0)
		return tl_fail(e, "%s: heights in '%s', the first file's (%s) "
		    "in '%s'", h->name, h->unit, r->name, r->unit);
	if (h->point != r->point)
		return tl_fail(e, "%s: pixel-is-%s, the first file's (%s) "
		    "pixel-is-%s: their georeferencing differs by half a pixel",
		    h->name, h->point ? "point" : "area", r->name,
		    r->point ? "point" : "area");
	return 0;
}

static int
agree(const dem_head *r, const dem_head *h, tile *t, const dem_opts *o,
    tl_err *e)
{
	if ((r->srs == NULL) != (h->srs == NULL) ||
	    (r->srs != NULL && !OSRIsSame(r->srs, h->srs)))
		return tl_fail(e, "%s: CRS %s, the first file's (%s) %s",
		    h->name, crs_label(h->srs), r->name, crs_label(r->srs));
	if (agree_grid(r, h, t, e) < 0)
		return -1;
	return agree_samples(r, h, o, e);
}

/* Every tile's header against the first's (kept in r), one file open at
 * a time; places moved so that the grid starts at (0, 0). */
static int
check_all(char *const *paths, int n, tile *tl, dem_head *r, dem_tiles *dt,
    const dem_opts *o, tl_err *e)
{
	int mincol = 0, minrow = 0;

	for (int k = 0; k < n; k++) {
		GDALDatasetH ds = dem_mosaic_open(paths[k], e);
		dem_head h;
		int rc;

		if (ds == NULL)
			return -1;
		rc = dem_head_read(ds, paths[k], k == 0 ? r : &h, e);
		/* a VRT entry: what its tiles say */
		if (rc == 0)
			rc = dem_head_vrt(ds, k == 0 ? r : &h, o, 0, e);
		GDALClose(ds);
		if (rc < 0)
			return -1;
		tl[k].path = paths[k];
		rc = agree(r, k == 0 ? r : &h, &tl[k], o, e);
		dem_tiles_note(dt, k == 0 ? r : &h, k == 0);
		if (k > 0 && h.srs != NULL)
			OSRDestroySpatialReference(h.srs);
		if (rc < 0)
			return -1;
		mincol = tl[k].col < mincol ? tl[k].col : mincol;
		minrow = tl[k].row < minrow ? tl[k].row : minrow;
	}
	for (int k = 0; k < n; k++)
		tl[k].col -= mincol, tl[k].row -= minrow;
	return 0;
}

/* --- a file listed again ----------------------------------------------- */

typedef struct {
	dev_t dev;
	ino_t ino;
	int k;
} ident;

static int
cmp_ident(const void *a, const void *b)
{
	const ident *x = a, *y = b;

	if (x->dev != y->dev)
		return x->dev < y->dev ? -1 : 1;
	if (x->ino != y->ino)
		return x->ino < y->ino ? -1 : 1;
	return (x->k > y->k) - (x->k < y->k);
}

/* Marks each entry naming the file of an earlier one (by device and
 * inode, so ./a.tif and ../d/a.tif are one), tl[k].dup: it lies where
 * that one does with the same samples, so it is neither compared again
 * nor read again. /vsi paths are never the same. Sorted: O(n log n). */
static int
mark_dups(tile *tl, int n, tl_err *e)
{
	ident *id = tl_alloc((size_t)n, sizeof *id, e);
	struct stat st;
	int m = 0;

	if (id == NULL)
		return -1;
	for (int k = 0; k < n; k++) {
		tl[k].dup = -1;
		if (strncmp(tl[k].path, "/vsi", 4) != 0 &&
		    stat(tl[k].path, &st) == 0)
			id[m].dev = st.st_dev, id[m].ino = st.st_ino,
			    id[m++].k = k;
	}
	qsort(id, (size_t)m, sizeof *id, cmp_ident);
	for (int k = 1; k < m; k++)
		if (id[k].dev == id[k - 1].dev && id[k].ino == id[k - 1].ino)
			tl[id[k].k].dup = tl[id[k - 1].k].dup >= 0 ?
			    tl[id[k - 1].k].dup : id[k - 1].k;
	free(id);
	return 0;
}

/* --- gaps ---------------------------------------------------------------- */

typedef struct {
	int lo, hi;
} span;

static int
cmp_int(const void *a, const void *b)
{
	int x = *(const int *)a, y = *(const int *)b;

	return (x > y) - (x < y);
}

static int
cmp_span(const void *a, const void *b)
{
	return cmp_int(&((const span *)a)->lo, &((const span *)b)->lo);
}

/* Whether the m row spans v (of the tiles over one column slab) cover
 * rows 0 .. h. */
static int
rows_covered(span *v, int m, int h)
{
	int reach = 0;

	qsort(v, (size_t)m, sizeof *v, cmp_span);
	for (int k = 0; k < m && reach < h; k++) {
		if (v[k].lo > reach)
			return 0;
		reach = v[k].hi > reach ? v[k].hi : reach;
	}
	return reach >= h;
}

/* Whether the tiles leave a hole in the rectangle they span: a sweep over
 * the column slabs between tiles' edges, tiles sorted by their west edge
 * and only those over a slab (the active ones) looked at: O(n log n) for
 * tiles on a grid, headers only. */
static int
has_gaps(const tile *tl, int n, tl_err *e)
{
	key *west = tl_alloc((size_t)n, sizeof *west, e);
	int *xs = tl_alloc((size_t)n * 2, sizeof *xs, e);
	int *act = tl_alloc((size_t)n, sizeof *act, e);
	span *v = tl_alloc((size_t)n, sizeof *v, e);
	int h = 0, gap = 0, nx = 0, na = 0, next = 0;

	if (west == NULL || xs == NULL || act == NULL || v == NULL)
		gap = -1;
	for (int k = 0; k < n && gap == 0; k++) {
		west[k].at = tl[k].col, west[k].k = k;
		xs[nx++] = tl[k].col, xs[nx++] = tl[k].col + tl[k].w;
		h = tl[k].row + tl[k].h > h ? tl[k].row + tl[k].h : h;
	}
	if (gap == 0) {
		qsort(west, (size_t)n, sizeof *west, cmp_key);
		qsort(xs, (size_t)nx, sizeof *xs, cmp_int);
	}
	for (int k = 0; gap == 0 && k + 1 < nx; k++) {
		int m = 0, keep = 0;
		if (xs[k] == xs[k + 1])
			continue;
		/* no edge lies inside the slab: a tile over its west edge
		 * covers it whole */
		while (next < n && west[next].at <= xs[k])
			act[na++] = west[next++].k;
		for (int a = 0; a < na; a++)
			if (tl[act[a]].col + tl[act[a]].w > xs[k])
				act[keep++] = act[a];
		na = keep;
		for (int a = 0; a < na; a++)
			v[m].lo = tl[act[a]].row, v[m++].hi = tl[act[a]].row +
			    tl[act[a]].h;
		gap = !rows_covered(v, m, h);
	}
	free(west), free(xs), free(act), free(v);
	return gap;
}

/* --- the VRT --------------------------------------------------------- */

/* The void of a type that has no nodata: its lowest value, NaN for
 * floats (dem2fqm(1) says so). */
static double
lowest(const dem_head *r)
{
	if (GDALDataTypeIsFloating(r->type))
		return NAN;
	if (r->i8)
		return -128;
	if (!GDALDataTypeIsSigned(r->type))
		return 0;
	return -ldexp(1, GDALGetDataTypeSizeBits(r->type) - 1);
}

/* GDALBuildVRT's options: the first tile's pixel size exactly (its
 * default, the average, may round), our CRS check instead of its own,
 * and what makes a gap a void: the nodata (-N's, the tiles', else the
 * type's lowest) or, for an RGB-encoded DEM, an alpha band. */
static GDALBuildVRTOptions *
vrt_options(const dem_head *r, int gaps, const dem_opts *o, char nd[64],
    char tr[2][32])
{
	const char *argv[12];
	int k = 0, rgb = r->type == GDT_Byte && r->nbands >= 3 &&
	    o->encoding != DEM_ENC_GREY;

	snprintf(tr[0], 32, "%.17g", r->gt[1]);
	snprintf(tr[1], 32, "%.17g", -r->gt[5]);
	argv[k++] = "-tr", argv[k++] = tr[0], argv[k++] = tr[1];
	argv[k++] = "-allow_projection_difference";
	nd[0] = '\0';
	if (o->has_nodata)
		snprintf(nd, 64, "%.17g", o->nodata);
	else if (r->has_nodata)
		snprintf(nd, 64, "%.17g", r->nodata);
	else if (gaps && rgb)
		argv[k++] = "-addalpha";
	else if (gaps)
		snprintf(nd, 64, "%.17g", lowest(r));
	if (nd[0] != '\0') {
		argv[k++] = "-srcnodata", argv[k++] = nd;
		argv[k++] = "-vrtnodata", argv[k++] = nd;
	}
	argv[k] = NULL;
	return GDALBuildVRTOptionsNew((char **)argv, NULL);
}

/* What GDALBuildVRT drops and the georeferencing or the heights depend
 * on, copied from the tiles: AREA_OR_POINT (half a pixel), the unit,
 * signed bytes; scale and offset it keeps, but it is said once more. */
static void
vrt_metadata(GDALDatasetH vrt, const dem_head *r)
{
	GDALRasterBandH b = GDALGetRasterBand(vrt, 1);

	if (r->aop[0] != '\0')
		GDALSetMetadataItem(vrt, "AREA_OR_POINT", r->aop, NULL);
	if (r->unit[0] != '\0')
		GDALSetRasterUnitType(b, r->unit);
	if (r->i8)
		GDALSetMetadataItem(b, "PIXELTYPE", "SIGNEDBYTE",
		    "IMAGE_STRUCTURE");
	GDALSetRasterScale(b, r->scale);
	GDALSetRasterOffset(b, r->offset);
}

static GDALDatasetH
vrt_build(char *const *paths, int n, const dem_head *r, int gaps,
    const dem_opts *o, const char *what, tl_err *e)
{
	char nd[64], tr[2][32];
	GDALBuildVRTOptions *bo = vrt_options(r, gaps, o, nd, tr);
	GDALDatasetH vrt = NULL;
	dem_gdal_msg c;
	int usage = 0;

	dem_gdal_catch(&c);
	if (bo != NULL)
		vrt = GDALBuildVRT("", n, NULL, (const char *const *)paths, bo,
		    &usage);
	GDALBuildVRTOptionsFree(bo);
	dem_gdal_release();
	if (vrt == NULL) {
		tl_fail(e, "%s: GDALBuildVRT: %s", what, c.msg[0] ? c.msg :
		    "failed");
		return NULL;
	}
	/* it skips a tile it dislikes with a mere warning; ours are checked,
	 * so a warning is a check missing here */
	if (c.warning[0] != '\0') {
		GDALClose(vrt);
		tl_fail(e, "%s: GDALBuildVRT: %s", what, c.warning);
		return NULL;
	}
	vrt_metadata(vrt, r);
	return vrt;
}

GDALDatasetH
dem_mosaic_vrt(char *const *paths, int n, const dem_opts *o, int samples,
    const char *what, dem_tiles *dt, tl_err *e)
{
	tile *tl = tl_alloc((size_t)n, sizeof *tl, e);
	char **once = tl_alloc((size_t)n, sizeof *once, e);
	GDALDatasetH vrt = NULL;
	dem_head r = { 0 };
	int gaps, m = 0;

	dem_gdal_init();
	memset(dt, 0, sizeof *dt);
	if (tl == NULL || once == NULL || n < 1 ||
	    check_all(paths, n, tl, &r, dt, o, e) < 0 ||
	    mark_dups(tl, n, e) < 0 || (gaps = has_gaps(tl, n, e)) < 0)
		goto out;
	/* -I reads no sample: the overlaps wait for the samples' reading */
	if (samples && dem_mosaic_overlaps(tl, n, &r, o, e) < 0)
		goto out;
	/* a file listed again paints what it painted (overlaps agree) */
	for (int k = 0; k < n; k++)
		if (tl[k].dup < 0)
			once[m++] = paths[k];
	vrt = vrt_build(once, m, &r, gaps, o, what, e);
out:
	if (r.srs != NULL)
		OSRDestroySpatialReference(r.srs);
	free(tl);
	free(once);
	return vrt;
}

int
dem_read_mosaic(dem_load *L, georef *g, char *const *paths, int n,
    const dem_opts *o, tl_err *e)
{
	dem_tiles dt;
	GDALDatasetH vrt;
	int rc;

	if ((vrt = dem_mosaic_vrt(paths, n, o, !L->info, L->what, &dt,
	    e)) == NULL)
		return -1;
	rc = dem_read_dataset(L, g, vrt, &dt, o, e);
	GDALClose(vrt);
	return rc;
}
