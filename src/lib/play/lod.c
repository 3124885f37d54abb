/* lod.c - the blocks of a frame and their tolerances (see lod.h). */
#include "play/lod.h"

#include <assert.h>
#include <string.h>

typedef struct {
	const world *w;
	const camera *c;
	double planes[6][4];
	double pixels;
	lod_ready_fn ready;
	void *ctx;
	lod_block *out;
	int n, max;
} lod;

int
lod_box_outside(const double planes[6][4], const double lo[3],
    const double hi[3])
{
	for (int i = 0; i < 6; i++) {
		/* the box corner farthest along the plane's normal */
		double p[3];
		for (int k = 0; k < 3; k++)
			p[k] = planes[i][k] >= 0 ? hi[k] : lo[k];
		if (planes[i][0] * p[0] + planes[i][1] * p[1] +
		    planes[i][2] * p[2] + planes[i][3] < 0)
			return 1;
	}
	return 0;
}

static void
emit(lod *s, int l, int bi, int bj, double dist)
{
	lod_block *b;

	if (s->n >= s->max)
		return;
	b = &s->out[s->n++];
	b->level = l, b->bi = bi, b->bj = bj;
	b->tau = s->pixels > 0 && !world_block_curved(s->w, l, bi, bj) ?
	    s->pixels / camera_pixels_per_metre(s->c, dist) : -1;
}

/* Every existing child of (l, bi, bj) ready (asking loads them)? */
static int
children_ready(lod *s, int l, int bi, int bj)
{
	int ok = 1;

	for (int k = 0; k < 4; k++) {
		int ci = 2 * bi + (k & 1), cj = 2 * bj + (k >> 1);
		if (world_block_exists(s->w, l - 1, ci, cj) &&
		    s->ready != NULL && !s->ready(s->ctx, l - 1, ci, cj))
			ok = 0; /* no early exit: every child is asked for */
	}
	return ok;
}

static void
visit(lod *s, int l, int bi, int bj)
{
	double lo[3], hi[3], cull_lo[3], dist, base;
	const pyramid_level *L = &s->w->ix.lev[l];

	assert(world_block_exists(s->w, l, bi, bj));
	world_block_box(s->w, l, bi, bj, lo, hi);
	memcpy(cull_lo, lo, sizeof lo);
	cull_lo[2] = s->w->base; /* skirts */
	if (lod_box_outside(s->planes, cull_lo, hi))
		return;
	dist = camera_box_distance(s->c, lo, hi);
	base = L->base[bj * L->blocks[0] + bi];
	if (l == 0 || (s->pixels > 0 &&
	    base * camera_pixels_per_metre(s->c, dist) <= s->pixels) ||
	    !children_ready(s, l, bi, bj)) {
		emit(s, l, bi, bj, dist);
		return;
	}
	for (int k = 0; k < 4; k++) {
		int ci = 2 * bi + (k & 1), cj = 2 * bj + (k >> 1);
		if (world_block_exists(s->w, l - 1, ci, cj))
			visit(s, l - 1, ci, cj);
	}
}

int
lod_select(const world *w, const camera *c, double pixels,
    lod_ready_fn ready, void *ctx, lod_block *out, int max)
{
	lod s = { w, c, { { 0 } }, pixels, ready, ctx, out, 0, max };
	int top = w->ix.nlevels - 1;
	const pyramid_level *L = &w->ix.lev[top];

	camera_frustum(c, s.planes);
	for (int bj = 0; bj < L->blocks[1]; bj++)
		for (int bi = 0; bi < L->blocks[0]; bi++)
			if (ready == NULL || ready(ctx, top, bi, bj))
				visit(&s, top, bi, bj);
	return s.n;
}
