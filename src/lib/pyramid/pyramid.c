/* pyramid.c - a level's block arrays and the block files (raster.h);
 * index.json is pyramid_index.c. */
#include "pyramid/pyramid.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
	if ((w = rs_create_fresh(path, &h, RS_ZIP, e)) == NULL)
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

int
pyramid_block_read(const char *path, pyramid_block *b, tl_err *e)
{
	rs_reader *r;
	float row[4 * BT_SIZE], *p[4];
	int n, level, blk[2], ret = -1;
	double zr[2];

	if ((r = rs_open(path, e)) == NULL)
		return -1;
	const rs_header *h = rs_header_of(r);
	planes(b, p, &n);
	if (h->width != BT_SIZE || h->height != BT_SIZE) {
		tl_fail(e, "%s: %dx%d, a block is %dx%d", path, h->width,
		    h->height, BT_SIZE, BT_SIZE);
		goto done;
	}
	if (h->nch != n || rs_channel(h, "E") != 0 ||
	    rs_channel(h, "Z") != n - 1 ||
	    (b->displaced && (rs_channel(h, "X") != 1 ||
	    rs_channel(h, "Y") != 2))) {
		tl_fail(e, "%s: channels must be %s", path,
		    b->displaced ? "E X Y Z" : "E Z");
		goto done;
	}
	if (rs_get_int(h, VGIS_ATTR_LEVEL, &level) < 0 ||
	    rs_get_v2i(h, VGIS_ATTR_BLOCK, blk) < 0 ||
	    rs_get_double(h, VGIS_ATTR_BASE_ERROR, &b->base) < 0 ||
	    rs_get_v2d(h, VGIS_ATTR_ZRANGE, zr) < 0) {
		tl_fail(e, "%s: vgis:level, vgis:block, vgis:base_error or "
		    "vgis:zrange missing", path);
		goto done;
	}
	if (level != b->level || blk[0] != b->bi || blk[1] != b->bj) {
		tl_fail(e, "%s: says level %d block (%d,%d), expected level %d "
		    "block (%d,%d)", path, level, blk[0], blk[1], b->level,
		    b->bi, b->bj);
		goto done;
	}
	b->zmin = zr[0], b->zmax = zr[1];
	for (int j = 0; j < BT_SIZE; j++) {
		if (rs_read_row(r, row, e) < 0)
			goto done;
		for (int c = 0; c < n; c++)
			memcpy(p[c] + j * BT_SIZE, row + c * BT_SIZE,
			    BT_SIZE * sizeof *row);
	}
	ret = 0;
done:
	rs_close(r);
	return ret;
}
