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
 * One operation in one file, over 600 lines: dem_read_mosaic, its checks
 * (the sections below, in the order it runs them) sharing the tiles'
 * table and the GDAL handles, then the VRT they vouch for. */
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

#include "dem/dem_gdal.h"

#define CMP_SAMPLES (1 << 18)  /* per overlap window and tile */

/* A tile's place in the mosaic's grid: columns col .. col+w-1, rows
 * row .. row+h-1. */
typedef struct {
	const char *path;
	int col, row, w, h;
	int dup;           /* the earlier entry naming the same file, or -1 */
	dev_t dev;         /* the file, to know it listed again */
	ino_t ino;
} tile;

/* --- headers ------------------------------------------------------------- */

static GDALDatasetH
tile_open(const char *path, tl_err *e)
{
	GDALDatasetH ds;
	dem_gdal_msg c;
	char name[DEM_NAME];

	dem_name(path, name);
	dem_gdal_catch(&c);
	ds = dem_gdal_open(path);
	dem_gdal_release();
	if (ds == NULL && (c.msg[0] == '\0' || strstr(c.msg,
	    "not recognized") != NULL))
		tl_fail(e, "%s: not a raster GDAL reads (a mosaic's tiles are "
		    "read by GDAL)", name);
	else if (ds == NULL)
		tl_fail(e, "%s: truncated or corrupt: %s", name, c.msg);
	else if (GDALGetRasterCount(ds) < 1) {
		GDALClose(ds);
		ds = NULL;
		tl_fail(e, "%s: no raster band", name);
	}
	return ds;
}

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
		GDALDatasetH ds = tile_open(paths[k], e);
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

/* A tile by one of its edges (or a span by its start), and its index. */
typedef struct {
	int at, k;
} key;

static int
cmp_key(const void *a, const void *b)
{
	const key *x = a, *y = b;

	return x->at != y->at ? (x->at > y->at) - (x->at < y->at) :
	    (x->k > y->k) - (x->k < y->k);
}

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

/* --- overlaps ---------------------------------------------------------- */

typedef struct {
	int has_nodata, f32, masks;
	double nodata;
	double *pa, *pb;           /* a window of each tile */
	unsigned char *ma, *mb;    /* their masks, when the tiles have some */
} cmpbuf;

/* Two overlapping tiles, open. */
typedef struct {
	const tile *a, *b;
	GDALDatasetH da, db;
} pair;

static int
void_at(const cmpbuf *c, const double *p, const unsigned char *m, size_t k)
{
	double v = p[k];

	if (isnan(v) || (c->masks && m[k] == 0))
		return 1;
	return c->has_nodata &&
	    (c->f32 ? (float)v == (float)c->nodata : v == c->nodata);
}

/* A real mask (alpha, per dataset, explicit), not one nodata makes. */
static int
has_mask(GDALDatasetH ds)
{
	return !(GDALGetMaskFlags(GDALGetRasterBand(ds, 1)) &
	    (GMF_ALL_VALID | GMF_NODATA));
}

static int
read_win(const cmpbuf *c, GDALDatasetH ds, const tile *t, int band,
    const int win[4], double *p, unsigned char *m, tl_err *e)
{
	GDALRasterBandH b = GDALGetRasterBand(ds, band);
	int x = win[0] - t->col, y = win[1] - t->row;
	dem_gdal_msg g;
	char name[DEM_NAME];
	CPLErr err;

	dem_gdal_catch(&g);
	err = GDALRasterIO(b, GF_Read, x, y, win[2], win[3], p, win[2],
	    win[3], GDT_Float64, 0, 0);
	if (err == CE_None && c->masks)
		err = GDALRasterIO(GDALGetMaskBand(b), GF_Read, x, y, win[2],
		    win[3], m, win[2], win[3], GDT_Byte, 0, 0);
	dem_gdal_release();
	return err == CE_None ? 0 : tl_fail(e, "%s: truncated or corrupt: %s",
	    dem_name(t->path, name), g.msg[0] ? g.msg : "GDAL cannot read it");
}

static void
value_label(const cmpbuf *c, const double *p, const unsigned char *m,
    size_t k, char *buf, size_t n)
{
	if (void_at(c, p, m, k))
		snprintf(buf, n, "void");
	else
		snprintf(buf, n, "%.17g", p[k]);
}

/* The first sample of window win (x, y, width, height) where the tiles
 * differ, as read: a void equals a void, whatever says so (NaN, nodata,
 * mask). */
static int
differ(const cmpbuf *c, const pair *p, int band, const int win[4],
    tl_err *e)
{
	size_t n = (size_t)win[2] * win[3];
	char va[40], vb[40], na[DEM_NAME], nb[DEM_NAME];

	for (size_t k = 0; k < n; k++) {
		int i = win[0] + (int)(k % win[2]);
		int j = win[1] + (int)(k / win[2]);
		int da = void_at(c, c->pa, c->ma, k);
		int db = void_at(c, c->pb, c->mb, k);
		if (da == db && (da || c->pa[k] == c->pb[k]))
			continue;
		value_label(c, c->pa, c->ma, k, va, sizeof va);
		value_label(c, c->pb, c->mb, k, vb, sizeof vb);
		return tl_fail(e, "%s: sample %d,%d%s is %s where it overlaps "
		    "%s, whose sample %d,%d is %s: overlapping tiles must agree",
		    dem_name(p->b->path, nb), i - p->b->col, j - p->b->row,
		    band > 1 ? " of a band past the first" : "", vb,
		    dem_name(p->a->path, na),
		    i - p->a->col, j - p->a->row, va);
	}
	return 0;
}

static int
compare_win(cmpbuf *c, const pair *p, int band, const int win[4],
    tl_err *e)
{
	if (read_win(c, p->da, p->a, band, win, c->pa, c->ma, e) < 0 ||
	    read_win(c, p->db, p->b, band, win, c->pb, c->mb, e) < 0)
		return -1;
	return differ(c, p, band, win, e);
}

/* The pair where it overlaps, band by band, window by window. */
static int
compare_pair(cmpbuf *c, const pair *p, int nbands, tl_err *e)
{
	const tile *a = p->a, *b = p->b;
	int x0 = a->col > b->col ? a->col : b->col;
	int y0 = a->row > b->row ? a->row : b->row;
	int x1 = a->col + a->w < b->col + b->w ? a->col + a->w : b->col + b->w;
	int y1 = a->row + a->h < b->row + b->h ? a->row + a->h : b->row + b->h;
	int cw = x1 - x0 < CMP_SAMPLES ? x1 - x0 : CMP_SAMPLES;
	int ch = CMP_SAMPLES / cw, win[4];

	c->masks = has_mask(p->da) || has_mask(p->db);
	for (int band = 1; band <= nbands; band++)
		for (win[1] = y0; win[1] < y1; win[1] += ch)
			for (win[0] = x0; win[0] < x1; win[0] += cw) {
				win[2] = x1 - win[0] < cw ? x1 - win[0] : cw;
				win[3] = y1 - win[1] < ch ? y1 - win[1] : ch;
				if (compare_win(c, p, band, win, e) < 0)
					return -1;
			}
	return 0;
}

static int
overlap(const tile *a, const tile *b)
{
	return a->col < b->col + b->w && b->col < a->col + a->w &&
	    a->row < b->row + b->h && b->row < a->row + a->h;
}

/* Appends the pair i < j to *v (*n of them, room for *cap). */
static int
pair_add(key **v, size_t *n, size_t *cap, int i, int j, tl_err *e)
{
	key *nv;

	if (*n == *cap) {
		*cap = *cap ? 2 * *cap : 1024;
		if ((nv = realloc(*v, *cap * sizeof *nv)) == NULL)
			return tl_fail(e, "out of memory (overlapping tiles)");
		*v = nv;
	}
	(*v)[*n].at = i < j ? i : j;
	(*v)[(*n)++].k = i < j ? j : i;
	return 0;
}

/* Every pair of tiles that overlap (a tile listed again, dup, is left
 * out: it is the same file in the same place), in the order i < j, by i
 * then j, that the check has always taken: tiles sorted by their west
 * edge, each paired only with those that start before it ends, so that
 * tiles on a grid cost O(n log n), not n^2. */
static key *
overlap_pairs(const tile *tl, int n, size_t *np, tl_err *e)
{
	key *west = tl_alloc((size_t)n, sizeof *west, e), *v = NULL;
	size_t cap = 0;
	int m = 0, bad = west == NULL;

	*np = 0;
	for (int k = 0; !bad && k < n; k++)
		if (tl[k].dup < 0)
			west[m].at = tl[k].col, west[m++].k = k;
	if (!bad)
		qsort(west, (size_t)m, sizeof *west, cmp_key);
	for (int a = 0; !bad && a < m; a++) {
		const tile *t = &tl[west[a].k];
		for (int b = a + 1; !bad && b < m && west[b].at < t->col + t->w;
		    b++)
			if (overlap(t, &tl[west[b].k]) && pair_add(&v, np, &cap,
			    west[a].k, west[b].k, e) < 0)
				bad = 1;
	}
	free(west);
	if (bad) {
		free(v);
		return NULL;
	}
	if (*np > 0)
		qsort(v, *np, sizeof *v, cmp_key);
	return v != NULL ? v : tl_alloc(1, sizeof *v, e);
}

/* The pairs v[0 .. n-1] compared, each first tile opened once for its
 * run of pairs. */
static int
compare_pairs(cmpbuf *c, const tile *tl, const key *v, size_t n,
    int nbands, tl_err *e)
{
	pair p = { NULL, NULL, NULL, NULL };
	int rc = 0;

	for (size_t k = 0; k < n && rc == 0; k++) {
		if (p.a != &tl[v[k].at]) {
			if (p.da != NULL)
				GDALClose(p.da);
			p.a = &tl[v[k].at];
			if ((p.da = tile_open(p.a->path, e)) == NULL)
				return -1;
		}
		p.b = &tl[v[k].k];
		if ((p.db = tile_open(p.b->path, e)) == NULL) {
			rc = -1;
			break;
		}
		rc = compare_pair(c, &p, nbands, e);
		GDALClose(p.db);
	}
	if (p.da != NULL)
		GDALClose(p.da);
	return rc;
}

/* Every pair of tiles that overlap, compared there. */
static int
overlaps(const tile *tl, int n, const dem_head *r, const dem_opts *o,
    tl_err *e)
{
	cmpbuf c = { 0 };
	size_t np = 0;
	key *v = overlap_pairs(tl, n, &np, e);
	int rc = v == NULL ? -1 : 0;

	c.has_nodata = o->has_nodata ? 1 : r->has_nodata;
	c.nodata = o->has_nodata ? o->nodata : r->nodata;
	c.f32 = r->type == GDT_Float32;
	c.pa = tl_alloc(CMP_SAMPLES, sizeof *c.pa, e);
	c.pb = tl_alloc(CMP_SAMPLES, sizeof *c.pb, e);
	c.ma = tl_alloc(CMP_SAMPLES, 1, e);
	c.mb = tl_alloc(CMP_SAMPLES, 1, e);
	if (c.pa == NULL || c.pb == NULL || c.ma == NULL || c.mb == NULL)
		rc = -1;
	if (rc == 0)
		rc = compare_pairs(&c, tl, v, np, r->nbands, e);
	free(v);
	free(c.pa), free(c.pb), free(c.ma), free(c.mb);
	return rc;
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

int
dem_read_mosaic(dem_load *L, georef *g, char *const *paths, int n,
    const dem_opts *o, tl_err *e)
{
	tile *tl = tl_alloc((size_t)n, sizeof *tl, e);
	char **once = tl_alloc((size_t)n, sizeof *once, e);
	GDALDatasetH vrt = NULL;
	dem_tiles dt = { 0 };
	dem_head r = { 0 };
	int gaps, rc = -1, m = 0;

	dem_gdal_init();
	if (tl == NULL || once == NULL || n < 1 ||
	    check_all(paths, n, tl, &r, &dt, o, e) < 0 ||
	    mark_dups(tl, n, e) < 0 || (gaps = has_gaps(tl, n, e)) < 0)
		goto out;
	/* -I reads no sample: the overlaps wait for the samples' reading */
	if (!L->info && overlaps(tl, n, &r, o, e) < 0)
		goto out;
	/* a file listed again paints what it painted (overlaps agree) */
	for (int k = 0; k < n; k++)
		if (tl[k].dup < 0)
			once[m++] = paths[k];
	if ((vrt = vrt_build(once, m, &r, gaps, o, L->what, e)) != NULL)
		rc = dem_read_dataset(L, g, vrt, &dt, o, e);
out:
	if (vrt != NULL)
		GDALClose(vrt);
	if (r.srs != NULL)
		OSRDestroySpatialReference(r.srs);
	free(tl);
	free(once);
	return rc;
}
