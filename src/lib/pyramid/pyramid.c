/* pyramid.c - a level's block arrays and the block files (raster.h);
 * index.json is pyramid_index.c. */
#include "pyramid/pyramid.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/attr_names.h"

int
pyramid_nblocks(int n)
{
	int b = (n - 1 + BT_CELLS - 1) / BT_CELLS;

	return b < 1 ? 1 : b;
}

int
pyramid_level_init(pyramid_level *L, int level, int w, int h, tl_err *e)
{
	size_t nb;

	memset(L, 0, sizeof *L);
	L->level = level;
	L->size[0] = w, L->size[1] = h;
	L->blocks[0] = pyramid_nblocks(w), L->blocks[1] = pyramid_nblocks(h);
	nb = (size_t)L->blocks[0] * L->blocks[1];
	L->zmin = tl_alloc(nb, sizeof *L->zmin, e);
	L->zmax = tl_alloc(nb, sizeof *L->zmax, e);
	L->base = tl_alloc(nb, sizeof *L->base, e);
	L->emax = tl_alloc(nb, sizeof *L->emax, e);
	if (!L->zmin || !L->zmax || !L->base || !L->emax)
		return -1;
	return 0;
}

void
pyramid_block_path(char *buf, size_t n, const char *dir, int level, int bi,
    int bj)
{
	snprintf(buf, n, VGIS_BLOCK_PATH, dir, level, bj, bi);
}

int
pyramid_block_alloc(pyramid_block *b, int displaced, tl_err *e)
{
	memset(b, 0, sizeof *b);
	b->displaced = displaced;
	b->z = tl_alloc(PYRAMID_N, sizeof *b->z, e);
	b->e = tl_alloc(PYRAMID_N, sizeof *b->e, e);
	if (displaced) {
		b->x = tl_alloc(PYRAMID_N, sizeof *b->x, e);
		b->y = tl_alloc(PYRAMID_N, sizeof *b->y, e);
	}
	if (!b->z || !b->e || (displaced && (!b->x || !b->y))) {
		pyramid_block_free(b);
		return -1;
	}
	return 0;
}

void
pyramid_block_free(pyramid_block *b)
{
	free(b->z), free(b->e), free(b->x), free(b->y);
	b->z = b->e = b->x = b->y = NULL;
}

/* Channel order in the file (sorted): E X Y Z, or E Z. */
static void
planes(const pyramid_block *b, float *p[4], int *n)
{
	*n = 0;
	p[(*n)++] = b->e;
	if (b->displaced) {
		p[(*n)++] = b->x;
		p[(*n)++] = b->y;
	}
	p[(*n)++] = b->z;
}

int
pyramid_block_write(const char *path, const pyramid_block *b,
    const rs_header *attrs, tl_err *e)
{
	return pyramid_block_write_z(path, b, attrs, RS_ZIP, 0, e);
}

int
pyramid_block_write_z(const char *path, const pyramid_block *b,
    const rs_header *attrs, enum rs_compression comp, int in_tree,
    tl_err *e)
{
	rs_header h;
	rs_writer *w;
	float row[4 * BT_SIZE], *p[4];
	int n, r = -1;

	if (rs_header_copy(&h, attrs, e) < 0)
		return -1;
	h.width = h.height = BT_SIZE;
	rs_clear_channels(&h);
	planes(b, p, &n);
	if (rs_add_channel(&h, "E", e) < 0 || rs_add_channel(&h, "Z", e) < 0 ||
	    (b->displaced && (rs_add_channel(&h, "X", e) < 0 ||
	    rs_add_channel(&h, "Y", e) < 0)) ||
	    rs_set_int(&h, VGIS_ATTR_VERSION, VGIS_VERSION, e) < 0 ||
	    rs_set_int(&h, VGIS_ATTR_LEVEL, b->level, e) < 0 ||
	    rs_set_v2i(&h, VGIS_ATTR_BLOCK, b->bi, b->bj, e) < 0 ||
	    rs_set_v2i(&h, VGIS_ATTR_ORIGIN, b->bi * BT_CELLS, b->bj * BT_CELLS,
	    e) < 0 ||
	    rs_set_double(&h, VGIS_ATTR_BASE_ERROR, b->base, e) < 0 ||
	    rs_set_v2d(&h, VGIS_ATTR_ZRANGE, b->zmin, b->zmax, e) < 0)
		goto done;
	if ((w = (in_tree ? rs_create_tree : rs_create_fresh)(path, &h, comp,
	    e)) == NULL)
		goto done;
	for (int j = 0; j < BT_SIZE; j++) {
		for (int c = 0; c < n; c++)
			memcpy(row + c * BT_SIZE, p[c] + j * BT_SIZE,
			    BT_SIZE * sizeof *row);
		if (rs_write_row(w, row, e) < 0) {
			rs_abort(w);
			goto done;
		}
	}
	r = rs_finish(w, e);
done:
	rs_header_free(&h);
	return r;
}

/* The header of a block at `path`: size, channels for its level's
 * displacement, and its vgis:* attributes what b's place says. */
static int
block_header(const rs_header *h, const char *path, pyramid_block *b,
    tl_err *e)
{
	int n = b->displaced ? 4 : 2, v, level, blk[2], org[2];
	double zr[2];

	if (h->width != BT_SIZE || h->height != BT_SIZE)
		return tl_fail(e, "%s: %dx%d, a block is %dx%d", path, h->width,
		    h->height, BT_SIZE, BT_SIZE);
	if (h->nch != n || rs_channel(h, "E") != 0 ||
	    rs_channel(h, "Z") != n - 1 ||
	    (b->displaced && (rs_channel(h, "X") != 1 ||
	    rs_channel(h, "Y") != 2)))
		return tl_fail(e, "%s: channels must be %s (the index says "
		    "level %d is %sdisplaced)", path, b->displaced ? "E X Y Z" :
		    "E Z", b->level, b->displaced ? "" : "not ");
	if (rs_get_int(h, VGIS_ATTR_VERSION, &v) < 0 ||
	    rs_get_int(h, VGIS_ATTR_LEVEL, &level) < 0 ||
	    rs_get_v2i(h, VGIS_ATTR_BLOCK, blk) < 0 ||
	    rs_get_v2i(h, VGIS_ATTR_ORIGIN, org) < 0 ||
	    rs_get_double(h, VGIS_ATTR_BASE_ERROR, &b->base) < 0 ||
	    rs_get_v2d(h, VGIS_ATTR_ZRANGE, zr) < 0)
		return tl_fail(e, "%s: vgis:version, vgis:level, vgis:block, "
		    "vgis:origin, vgis:base_error or vgis:zrange missing",
		    path);
	if (v != VGIS_VERSION)
		return tl_fail(e, "%s: vgis:version %d, this program reads %d",
		    path, v, VGIS_VERSION);
	if (level != b->level || blk[0] != b->bi || blk[1] != b->bj ||
	    org[0] != b->bi * BT_CELLS || org[1] != b->bj * BT_CELLS)
		return tl_fail(e, "%s: says level %d block (%d,%d) origin "
		    "(%d,%d), expected level %d block (%d,%d)", path, level,
		    blk[0], blk[1], org[0], org[1], b->level, b->bi, b->bj);
	if (!isfinite(b->base) || b->base < 0)
		return tl_fail(e, "%s: vgis:base_error %g: not a finite "
		    "error >= 0", path, b->base);
	if (!isfinite(zr[0]) || !isfinite(zr[1]) || zr[0] > zr[1])
		return tl_fail(e, "%s: vgis:zrange %g..%g: not a finite range",
		    path, zr[0], zr[1]);
	b->zmin = zr[0], b->zmax = zr[1];
	return 0;
}

static int
corner(int k)
{
	return k == 0 || k == BT_CELLS || k == BT_CELLS * BT_SIZE ||
	    k == PYRAMID_N - 1;
}

/* The content vgis(5) allows: Z (X, Y) finite, inside vgis:zrange, which
 * it spans; E FLT_MAX at the four corners, finite and >= 0 elsewhere.
 * Sets b->emax. */
static int
block_content(const char *path, pyramid_block *b, tl_err *e)
{
	double lo = INFINITY, hi = -INFINITY;

	b->emax = 0;
	for (int k = 0; k < PYRAMID_N; k++) {
		int r = k / BT_SIZE, c = k % BT_SIZE;
		if (!isfinite(b->z[k]) || (b->displaced &&
		    (!isfinite(b->x[k]) || !isfinite(b->y[k]))))
			return tl_fail(e, "%s: vertex (%d,%d): Z %g%s: not "
			    "finite", path, c, r, b->z[k], b->displaced ?
			    " or X, Y" : "");
		if (corner(k) ? b->e[k] != FLT_MAX :
		    !(b->e[k] >= 0 && b->e[k] < FLT_MAX))
			return tl_fail(e, "%s: vertex (%d,%d): E %g: %s", path,
			    c, r, b->e[k], corner(k) ? "a corner's E must be "
			    "FLT_MAX" : "not a finite error >= 0");
		/* finite here: comparisons, not libm's fmin and fmax calls
		 * (vgis2terrain reads a block once per level) */
		lo = b->z[k] < lo ? b->z[k] : lo, hi = b->z[k] > hi ? b->z[k] : hi;
		if (!corner(k) && b->e[k] > b->emax)
			b->emax = b->e[k];
	}
	if (lo != b->zmin || hi != b->zmax)
		return tl_fail(e, "%s: Z ranges %.9g..%.9g, vgis:zrange says "
		    "%.9g..%.9g", path, lo, hi, b->zmin, b->zmax);
	return 0;
}

int
pyramid_block_read(const char *path, pyramid_block *b, tl_err *e)
{
	rs_reader *r;
	float row[4 * BT_SIZE], *p[4];
	int n, ret = -1;

	if ((r = rs_open_regular(path, e)) == NULL)
		return -1;
	planes(b, p, &n);
	if (block_header(rs_header_of(r), path, b, e) < 0)
		goto done;
	for (int j = 0; j < BT_SIZE; j++) {
		if (rs_read_row(r, row, e) < 0)
			goto done;
		for (int c = 0; c < n; c++)
			memcpy(p[c] + j * BT_SIZE, row + c * BT_SIZE,
			    BT_SIZE * sizeof *row);
	}
	ret = block_content(path, b, e);
done:
	rs_close(r);
	return ret;
}

/* What the index lists for block k of level L, and says of all its
 * blocks, the block at path must say too. */
static int
against_index(const char *path, const pyramid_block *b,
    const pyramid_level *L, size_t k, tl_err *e)
{
	if (b->zmin != L->zmin[k] || b->zmax != L->zmax[k])
		return tl_fail(e, "%s: vgis:zrange %.9g..%.9g, the index says "
		    "%.9g..%.9g", path, b->zmin, b->zmax, L->zmin[k],
		    L->zmax[k]);
	if (b->base != L->base[k])
		return tl_fail(e, "%s: vgis:base_error %.9g, the index says "
		    "%.9g", path, b->base, L->base[k]);
	if (b->emax != L->emax[k])
		return tl_fail(e, "%s: largest finite E %.9g, the index says "
		    "%.9g", path, b->emax, L->emax[k]);
	return 0;
}

int
pyramid_block_load(const char *dir, const pyramid_index *ix,
    pyramid_block *b, tl_err *e)
{
	char path[4096];
	const pyramid_level *L;

	if (b->level < 0 || b->level >= ix->nlevels)
		return tl_fail(e, "%s: no level %d", dir, b->level);
	L = &ix->lev[b->level];
	if (b->bi < 0 || b->bj < 0 || b->bi >= L->blocks[0] ||
	    b->bj >= L->blocks[1] || b->displaced != L->displaced)
		return tl_fail(e, "%s: level %d has no block (%d,%d)", dir,
		    b->level, b->bi, b->bj);
	pyramid_block_path(path, sizeof path, dir, b->level, b->bi, b->bj);
	if (pyramid_block_read(path, b, e) < 0)
		return -1;
	return against_index(path, b, L,
	    (size_t)b->bj * L->blocks[0] + b->bi, e);
}

/* The fqm:* and geo:* attributes of a block: the index's. */
static int
block_origin(const rs_header *h, const char *path, const pyramid_index *ix,
    int l, tl_err *e)
{
	const pyramid_level *L = &ix->lev[l];
	const char *mode = rs_get_string(h, FQM_ATTR_MODE);
	const char *kernel = rs_get_string(h, FQM_ATTR_KERNEL);
	const char *what;
	int lv, s0[2];
	georef g;

	if (rs_get_georef(&g, h, e) < 0)
		return -1;
	if ((what = geo_differs(&g, &ix->geo)) != NULL)
		return tl_fail(e, "%s: geo:%s differs from the index's georef",
		    path, what);
	if (rs_get_int(h, FQM_ATTR_LEVEL, &lv) < 0 || lv != l ||
	    rs_get_v2i(h, FQM_ATTR_SIZE0, s0) < 0 || s0[0] != ix->size0[0] ||
	    s0[1] != ix->size0[1])
		return tl_fail(e, "%s: fqm:level or fqm:size0 missing or not "
		    "level %d of %dx%d (the index's)", path, l, ix->size0[0],
		    ix->size0[1]);
	if (mode == NULL || strcmp(mode, L->mode) != 0 || kernel == NULL ||
	    strcmp(kernel, L->kernel) != 0)
		return tl_fail(e, "%s: fqm:mode %s fqm:kernel %s, the index "
		    "says %s %s", path, mode ? mode : "missing", kernel ? kernel :
		    "missing", L->mode, L->kernel);
	return 0;
}

int
pyramid_levels_probe(const char *dir, const pyramid_index *ix, tl_err *e)
{
	char path[4096];
	pyramid_block b;
	rs_reader *r;
	int ret = 0;

	for (int l = 0; l < ix->nlevels && ret == 0; l++) {
		memset(&b, 0, sizeof b);
		b.level = l, b.displaced = ix->lev[l].displaced;
		pyramid_block_path(path, sizeof path, dir, l, 0, 0);
		if ((r = rs_open_regular(path, e)) == NULL)
			return -1;
		if (block_header(rs_header_of(r), path, &b, e) < 0 ||
		    block_origin(rs_header_of(r), path, ix, l, e) < 0)
			ret = -1;
		rs_close(r);
	}
	return ret;
}
