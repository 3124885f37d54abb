/* cut.c - a block's selection at a tolerance, with each triangle's bound
 * from the saturated errors (t3_impl.h). */
#include <stdlib.h>

#include "tiles3d/t3_impl.h"

typedef struct {
	const pyramid_block *b;
	double tau;
	int cmax, rmax;
	t3_tris *t;
	int failed;
} sel;

static int
split(void *ctx, int c, int r)
{
	const sel *s = ctx;

	return s->b->e[r * BT_SIZE + c] > s->tau;
}

static int
grow(t3_tris *t)
{
	int cap = t->cap ? 2 * t->cap : 4096;
	uint16_t *i = realloc(t->idx, (size_t)cap * 3 * sizeof *i);
	double *b;

	if (i == NULL)
		return -1;
	t->idx = i;
	if ((b = realloc(t->bound, (size_t)cap * sizeof *b)) == NULL)
		return -1;
	t->bound = b, t->cap = cap;
	return 0;
}

/* A triangle whose hypotenuse midpoint m is a vertex was not split: the
 * DEM samples in it lie within the local error of m, so within E(m)
 * (vgis(5)). A leaf (hypotenuse midpoint off the grid) is one of the
 * block's finest triangles: within its base error. */
static void
emit(void *ctx, const int t[3][2])
{
	sel *s = ctx;
	int sc = t[0][0] + t[1][0], sr = t[0][1] + t[1][1], k;
	int c0 = t[0][0], r0 = t[0][1];

	for (int q = 1; q < 3; q++) {
		c0 = t[q][0] < c0 ? t[q][0] : c0;
		r0 = t[q][1] < r0 ? t[q][1] : r0;
	}
	if (c0 >= s->cmax || r0 >= s->rmax) /* all padding */
		return;
	if (s->t->n == s->t->cap && grow(s->t) < 0) {
		s->failed = 1;
		return;
	}
	k = s->t->n++;
	for (int q = 0; q < 3; q++)
		s->t->idx[3 * k + q] = (uint16_t)(t[q][1] * BT_SIZE + t[q][0]);
	s->t->bound[k] = (sc | sr) & 1 ? s->b->base :
	    s->b->e[(sr / 2) * BT_SIZE + sc / 2];
}

int
t3_cut(const pyramid_block *b, double tau, int cmax, int rmax, t3_tris *t,
    tl_err *e)
{
	sel s = { b, tau, cmax, rmax, t, 0 };

	t->n = 0;
	bt_select(0, 0, split, &s, emit, &s);
	if (s.failed)
		return tl_fail(e, "block %d/%d_%d: out of memory for its "
		    "triangles", b->level, b->bj, b->bi);
	return 0;
}
