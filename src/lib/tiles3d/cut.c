/* cut.c - a block's selection at a tolerance, with each triangle's bound
 * from the saturated errors (t3_impl.h). */
#include <stdlib.h>

#include "tiles3d/t3_impl.h"

typedef struct {
	const pyramid_block *b;
	double tau, lmax;
	int cmax, rmax;
	t3_tris *t;
	int failed;
} sel;

/* Twice the squared length, in cells, of the hypotenuse whose midpoint
 * is vertex (c, r): k the largest power of 2 dividing both, the
 * hypotenuse is a diagonal 2k long a side when c / k and r / k are both
 * odd, else a row or column 2k long. It grows up the hierarchy, so that
 * splitting every vertex past a length keeps the selection a matching. */
static double
hyp2(int c, int r)
{
	int k = 1;

	while (k < BT_CELLS && !((c | r) & k))
		k <<= 1;
	return (c & r & k) ? 16.0 * k * k : 8.0 * k * k;
}

static int
split(void *ctx, int c, int r)
{
	const sel *s = ctx;

	return s->b->e[r * BT_SIZE + c] > s->tau ||
	    hyp2(c, r) > 2 * s->lmax * s->lmax;
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
t3_cut(const pyramid_block *b, double tau, double lmax, int cmax, int rmax,
    t3_tris *t, tl_err *e)
{
	sel s = { b, tau, lmax, cmax, rmax, t, 0 };

	t->n = 0;
	bt_select(0, 0, split, &s, emit, &s);
	if (s.failed)
		return tl_fail(e, "block %d/%d_%d: out of memory for its "
		    "triangles", b->level, b->bj, b->bi);
	return 0;
}
