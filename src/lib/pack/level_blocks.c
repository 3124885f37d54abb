/* level_blocks.c - the block hand-out: a saturated block row cut into
 * blocks (heights, offsets, E, base error, extent) and given to the
 * level's block callback, each share its own blocks. */
#include "pack/level_impl.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <string.h>

/* fmin and fmax, inline (glibc's are calls, two per sample here): the
 * same value for any b when a is not NaN, signed zeros included (a tie
 * gives b, as glibc's minsd/maxsd do), and a NaN b leaves a */
static inline double
lmin(double a, double b)
{
	return b <= a ? b : a;
}

static inline double
lmax(double a, double b)
{
	return b >= a ? b : a;
}

/* Block bj, bi of the saturation band, saturated, into b. */
static void
fill_block(const state *s, pyramid_block *b, int bi, int bj)
{
	int g0 = bj * BT_CELLS - REACH;
	double emax = 0, zlo = INFINITY, zhi = -INFINITY;

	b->level = s->L->level, b->bi = bi, b->bj = bj;
	b->base = 0; /* the shares' base errors, merged */
	for (int k = 0; k < s->nshare; k++)
		b->base = dmax(b->base, *base_at(&s->shares[k],
		    bj * BT_CELLS, bi * BT_CELLS));
	for (int r = 0; r < BT_SIZE; r++) {
		int gj = bj * BT_CELLS + r, k0 = r * BT_SIZE;
		size_t o = slot(s, gj) + (size_t)(bi * BT_CELLS - s->c0);
		/* the block's rows lie in the saturation band's middle */
		assert(gj - g0 >= REACH && gj - g0 < SAT_BAND - REACH);
		const float *sat = s->satband + (size_t)(gj - g0) * s->P +
		    (size_t)(bi * BT_CELLS - s->c0);
		float *z = b->z + k0, *e = b->e + k0;
		memcpy(z, s->z + o, BT_SIZE * sizeof *z);
		memcpy(e, sat, BT_SIZE * sizeof *e);
		if (b->displaced) {
			memcpy(b->x + k0, s->ox + o, BT_SIZE * sizeof *b->x);
			memcpy(b->y + k0, s->oy + o, BT_SIZE * sizeof *b->y);
		}
		/* the corners (columns 0 and 128 of rows 0 and 128) have no E */
		for (int c = 0; c < BT_SIZE; c++)
			if ((r % BT_CELLS != 0 || c % BT_CELLS != 0) &&
			    e[c] > emax)
				emax = e[c];
		if (r % BT_CELLS == 0)
			e[0] = e[BT_CELLS] = FLT_MAX;
		/* in the order of the samples: which of two equal zeros
		 * stays depends on it */
		for (int c = 0; c < BT_SIZE; c++) {
			zlo = lmin(zlo, z[c]);
			zhi = lmax(zhi, z[c]);
		}
	}
	b->zmin = zlo, b->zmax = zhi;
	b->emax = emax;
}

/* The share's blocks of block row bj, handed to the caller (in parallel
 * with the other shares': writing a block is mostly compressing it). */
void
lv_emit_share(share *t, int bj)
{
	const state *s = t->s;

	for (int bi = t->blo; bi < t->bhi && !t->failed; bi++) {
		pyramid_block *b = &t->blk;
		fill_block(s, b, bi, bj);
		t->max_e = dmax(t->max_e, b->emax);
		t->max_base = dmax(t->max_base, b->base);
		if (s->L->block(s->L->block_ctx, b, &t->err) < 0)
			t->failed = 1;
	}
}
