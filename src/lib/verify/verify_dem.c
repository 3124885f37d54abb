/* verify_dem.c - the window of DEM rows a block row's triangles reach,
 * slid down a level once, and coverage: a valid sample that leaves the
 * window without a triangle of tau 0 holding it is a hole ("coverage"). */
#include "verify/verify_impl.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rows [w->j0, upto) are final: their valid samples must be covered. */
void
vf_dem_finish(vf_lv *v, int upto)
{
	const vf_checker *c = v->c;
	vf_dwin *w = &v->w;
	int last = w->j0 + w->n;

	for (int J = w->j0; J < upto && J < last; J++) {
		const unsigned char *f = w->f + (size_t)(J - w->j0) * c->W;
		for (int I = 0; I < c->W; I++) {
			int bi, bj;
			if (!(f[I] & 1))
				continue;
			v->R->samples++;
			if (f[I] & 2)
				continue;
			bi = I / (BT_CELLS * v->s), bj = J / (BT_CELLS * v->s);
			bi = bi < v->bx ? bi : v->bx - 1;
			bj = bj < v->by ? bj : v->by - 1;
			vf_note(v->c, VF_COVERAGE, v->l, bi, bj, -1, -1, 0,
			    "DEM sample (%d,%d) lies in no triangle at tau 0",
			    I, J);
		}
	}
}

/* Moves the window to rows a..b (a never decreases). */
int
vf_dem_slide(vf_lv *v, int a, int b)
{
	vf_checker *c = v->c;
	vf_dwin *w = &v->w;
	int drop = a - w->j0;

	assert(drop >= 0);
	vf_dem_finish(v, a);
	if (drop >= w->n)
		w->n = 0;
	else if (drop > 0) {
		w->n -= drop;
		memmove(w->z, w->z + (size_t)drop * c->W,
		    (size_t)w->n * c->W * sizeof *w->z);
		memmove(w->f, w->f + (size_t)drop * c->W, (size_t)w->n * c->W);
	}
	w->j0 = a;
	for (int J = a + w->n; J <= b; J++) {
		size_t off = (size_t)(J - a) * c->W;
		assert(J - a < w->cap); /* vf_dem_plan sized it */
		if (dem_read_row(c->dem, J, w->z + off, w->f + off, c->e) < 0)
			return -1;
		w->n++;
	}
	return 0;
}

/* DEM rows each block row's triangles reach (a pre-pass reads the
 * blocks of displaced levels), made monotone and contiguous so that a
 * sliding window meets every row once and rows it leaves are final. */
int
vf_dem_plan(vf_lv *v)
{
	const vf_checker *c = v->c;
	int by = v->by, *lo, *hi, cap = 1;
	vf_blk *b = &v->row[0][0];

	lo = tl_alloc(by, sizeof *lo, c->e);
	hi = tl_alloc(by, sizeof *hi, c->e);
	if (lo == NULL || hi == NULL) {
		free(lo), free(hi);
		return -1;
	}
	for (int bj = 0; bj < by; bj++) {
		double ymin = (double)bj * BT_CELLS * v->s;
		double ymax = (double)(bj + 1) * BT_CELLS * v->s;
		for (int bi = 0; v->disp && bi < v->bx; bi++) {
			vf_block_load(v, b, bi, bj, 1);
			for (int k = 0; b->ok && k < VF_NV; k++)
				ymin = fmin(ymin, b->py[k]),
				ymax = fmax(ymax, b->py[k]);
		}
		lo[bj] = (int)fmax(0, fmin(c->H - 1, floor(ymin)));
		hi[bj] = (int)fmax(0, fmin(c->H - 1, ceil(ymax)));
	}
	b->ok = 0;
	for (int bj = by - 2; bj >= 0; bj--)
		lo[bj] = lo[bj] < lo[bj + 1] ? lo[bj] : lo[bj + 1];
	for (int bj = 1; bj < by; bj++)
		hi[bj] = hi[bj] > hi[bj - 1] ? hi[bj] : hi[bj - 1];
	for (int bj = 0; bj < by; bj++) {
		v->w0[bj] = bj == 0 ? 0 : lo[bj] < hi[bj - 1] + 1 ? lo[bj] :
		    hi[bj - 1] + 1;
		v->w1[bj] = bj == by - 1 ? c->H - 1 : hi[bj];
		if (v->w1[bj] - v->w0[bj] + 1 > cap)
			cap = v->w1[bj] - v->w0[bj] + 1;
	}
	free(lo), free(hi);
	v->w.cap = cap;
	v->w.z = tl_alloc((size_t)cap * c->W, sizeof *v->w.z, c->e);
	v->w.f = tl_alloc((size_t)cap * c->W, 1, c->e);
	return v->w.z && v->w.f ? 0 : -1;
}
