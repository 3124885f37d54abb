/* level_blocks.c - the block hand-out: a saturated block row cut into
 * blocks (heights, offsets, E, base error, extent) and given to the
 * level's block callback, each share its own blocks. */
#include "pack/level_impl.h"

#include <assert.h>
#include <float.h>
#include <math.h>

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
	double emax = 0;

	b->level = s->L->level, b->bi = bi, b->bj = bj;
	b->base = 0; /* the shares' base errors, merged */
	for (int k = 0; k < s->nshare; k++)
		b->base = dmax(b->base, *base_at(&s->shares[k],
		    bj * BT_CELLS, bi * BT_CELLS));
	b->zmin = INFINITY, b->zmax = -INFINITY;
	for (int r = 0; r < BT_SIZE; r++) {
		int gj = bj * BT_CELLS + r;
		size_t o = slot(s, gj) + (size_t)(bi * BT_CELLS - s->c0);
		/* the block's rows lie in the saturation band's middle */
		assert(gj - g0 >= REACH && gj - g0 < SAT_BAND - REACH);
		const float *sat = s->satband + (size_t)(gj - g0) * s->P +
		    (size_t)(bi * BT_CELLS - s->c0);
		for (int c = 0; c < BT_SIZE; c++) {
			int k = r * BT_SIZE + c;
			int corner = r % BT_CELLS == 0 && c % BT_CELLS == 0;
			b->z[k] = s->z[o + c];
			b->e[k] = corner ? FLT_MAX : sat[c];
			if (!corner && b->e[k] > emax)
				emax = b->e[k];
			if (b->displaced) {
				b->x[k] = s->ox[o + c];
				b->y[k] = s->oy[o + c];
			}
			b->zmin = lmin(b->zmin, b->z[k]);
			b->zmax = lmax(b->zmax, b->z[k]);
		}
	}
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
