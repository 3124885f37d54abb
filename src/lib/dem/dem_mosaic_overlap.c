/* dem_mosaic_overlap.c - the samples of a mosaic's overlapping tiles
 * compared where they overlap (SRTM tiles share their edge row and
 * column): the pairs found by sorting the tiles by their west edge, each
 * pair's shared window read in pieces of at most CMP_SAMPLES samples
 * from both, voids and masks honoured; the first difference named. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dem/dem_mosaic.h"

#define CMP_SAMPLES (1 << 18)  /* per overlap window and tile */

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
			if ((p.da = dem_mosaic_open(p.a->path, e)) == NULL)
				return -1;
		}
		p.b = &tl[v[k].k];
		if ((p.db = dem_mosaic_open(p.b->path, e)) == NULL) {
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

int
dem_mosaic_overlaps(const tile *tl, int n, const dem_head *r, const dem_opts *o,
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
