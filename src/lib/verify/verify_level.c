/* verify_level.c - one level, a block row at a time: the taus of its
 * sweep, the blocks read, each check run on them, stray files. */
#include "verify/verify_impl.h"

#include <assert.h>
#include <dirent.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The level's taus: --tau's (0 first), or 0 and a geometric sweep up to
 * the largest finite E. */
static int
make_taus(vf_lv *v)
{
	const vf_opts *o = &v->c->o;
	double emax = 0;
	size_t nb = (size_t)v->bx * v->by;
	int n, zero = 0;

	for (size_t k = 0; k < nb; k++)
		if (v->L->emax[k] >= 0 && v->L->emax[k] < FLT_MAX)
			emax = fmax(emax, v->L->emax[k]);
	if (o->tau != NULL) {
		for (int k = 0; k < o->ntau; k++)
			zero |= o->tau[k] == 0;
		n = o->ntau + !zero;
	} else
		n = emax > 0 && o->nsweep > 1 ? o->nsweep : 1;
	v->tau = tl_alloc(n, sizeof *v->tau, v->c->e);
	v->R->tau = tl_alloc(n, sizeof *v->R->tau, v->c->e);
	if (v->tau == NULL || v->R->tau == NULL)
		return -1;
	v->ntau = v->R->ntau = n;
	if (o->tau != NULL) {
		/* tau 0 first: the coverage check runs on it */
		v->tau[0] = 0;
		for (int k = 0, q = 1; k < o->ntau; k++) {
			if (o->tau[k] == 0 && zero) {
				zero = 0;
				continue;
			}
			v->tau[q++] = o->tau[k];
		}
	} else
		for (int k = 1; k < n; k++)
			v->tau[k] = n == 2 ? emax :
			    emax * pow(1000, -(double)(n - 1 - k) / (n - 2));
	for (int k = 0; k < n; k++) {
		v->R->tau[k].tau = v->tau[k];
		v->R->tau[k].maxerr = v->c->dem ? 0 : NAN;
	}
	return 0;
}

static int
blk_alloc(vf_blk *b, int disp, tl_err *e)
{
	memset(b, 0, sizeof *b);
	b->z = tl_alloc(VF_NV, sizeof *b->z, e);
	b->e = tl_alloc(VF_NV, sizeof *b->e, e);
	b->px = tl_alloc(VF_NV, sizeof *b->px, e);
	b->py = tl_alloc(VF_NV, sizeof *b->py, e);
	if (disp) {
		b->x = tl_alloc(VF_NV, sizeof *b->x, e);
		b->y = tl_alloc(VF_NV, sizeof *b->y, e);
	}
	return b->z && b->e && b->px && b->py && (!disp || (b->x && b->y)) ?
	    0 : -1;
}

static void
blk_free(vf_blk *b)
{
	free(b->z), free(b->e), free(b->x), free(b->y);
	free(b->px), free(b->py);
}

static void
lv_free(vf_lv *v)
{
	for (int q = 0; q < 2; q++) {
		for (int bi = 0; v->row[q] && bi < v->bx; bi++)
			blk_free(&v->row[q][bi]);
		free(v->row[q]);
		free(v->bot[q]);
	}
	free(v->inside), free(v->sel), free(v->used), free(v->emit);
	free(v->w0), free(v->w1), free(v->w.z), free(v->w.f);
	free(v->tau);
}

/* Level l's state: two block rows of blocks, the selections' scratch,
 * the DEM rows of each block row. */
static int
lv_init(vf_lv *v, vf_checker *c, int l)
{
	tl_err *e = c->e;

	memset(v, 0, sizeof *v);
	v->c = c;
	v->L = &c->ix.lev[l];
	v->R = &c->r->lev[l];
	v->l = l;
	v->s = 1 << l;
	v->bx = v->L->blocks[0], v->by = v->L->blocks[1];
	v->disp = v->L->displaced;
	if (make_taus(v) < 0)
		return -1;
	for (int q = 0; q < 2; q++) {
		v->row[q] = tl_alloc(v->bx, sizeof *v->row[q], e);
		v->bot[q] = tl_alloc((size_t)v->ntau * v->bx, BT_SIZE, e);
		if (v->row[q] == NULL || v->bot[q] == NULL)
			return -1;
		for (int bi = 0; bi < v->bx; bi++)
			if (blk_alloc(&v->row[q][bi], v->disp, e) < 0)
				return -1;
	}
	v->inside = tl_alloc((size_t)v->bx, VF_NV, e);
	v->sel = tl_alloc(VF_NV, 1, e);
	v->used = tl_alloc(VF_NV, 1, e);
	v->emit = tl_alloc(VF_LEAVES, sizeof *v->emit, e);
	v->w0 = tl_alloc(v->by, sizeof *v->w0, e);
	v->w1 = tl_alloc(v->by, sizeof *v->w1, e);
	if (!v->inside || !v->sel || !v->used || !v->emit || !v->w0 || !v->w1)
		return -1;
	return c->dem != NULL ? vf_dem_plan(v) : 0;
}

/* Nothing in DIR/<level> but the blocks the index lists. */
static void
check_strays(vf_lv *v)
{
	char path[4096], want[64];
	struct dirent *de;
	DIR *d;

	snprintf(path, sizeof path, "%s/%d", v->c->dir, v->l);
	if ((d = opendir(path)) == NULL) {
		vf_note(v->c, VF_INDEX, v->l, -1, -1, -1, -1, NAN, "%s: no "
		    "level directory", path);
		return;
	}
	while ((de = readdir(d)) != NULL) {
		int r, c;
		if (strcmp(de->d_name, ".") == 0 ||
		    strcmp(de->d_name, "..") == 0)
			continue;
		if (sscanf(de->d_name, "%d_%d.exr", &r, &c) == 2) {
			snprintf(want, sizeof want, "%d_%d.exr", r, c);
			if (strcmp(want, de->d_name) == 0 && r >= 0 && c >= 0 &&
			    r < v->by && c < v->bx)
				continue;
		}
		vf_note(v->c, VF_INDEX, v->l, -1, -1, -1, -1, NAN, "%s/%s: not "
		    "a block of the index", path, de->d_name);
	}
	closedir(d);
}

/* Block row bj: each block read and checked on its own and against its
 * neighbours left and above, then against the DEM, then each tau's
 * selection; this row then becomes the one above. */
static int
check_row(vf_lv *v, int bj)
{
	vf_blk *tmp = v->row[0];
	unsigned char *bot;

	assert(bj >= 0 && bj < v->by);
	v->row[0] = v->row[1], v->row[1] = tmp;
	for (int bi = 0; bi < v->bx; bi++) {
		vf_blk *b = &v->row[1][bi];
		vf_block_load(v, b, bi, bj, 0);
		if (!b->ok)
			continue;
		v->R->blocks_read++;
		vf_block_content(v, b, bi, bj);
		vf_border_padding(v, b, bi, bj);
		vf_sat_check(v, b, bi, bj);
		vf_border_check(v, bi, bj);
	}
	if (v->c->dem != NULL) {
		if (vf_dem_slide(v, v->w0[bj], v->w1[bj]) < 0)
			return -1;
		for (int bi = 0; bi < v->bx; bi++)
			if (v->row[1][bi].ok)
				vf_error_base_local(v, bi, bj);
	}
	for (int t = 0; t < v->ntau; t++) {
		for (int bi = 0; bi < v->bx; bi++)
			if (v->row[1][bi].ok)
				vf_match_block(v, bi, bj, t);
		vf_match_borders(v, bj, t);
	}
	bot = v->bot[0];
	v->bot[0] = v->bot[1], v->bot[1] = bot;
	return 0;
}

int
vf_level_check(vf_checker *c, int l)
{
	vf_lv v;
	int r = -1;

	if (lv_init(&v, c, l) < 0)
		goto done;
	v.R->tight = NAN;
	v.R->base_real = v.R->local_max = c->dem ? 0 : NAN;
	for (int bj = 0; bj < v.by; bj++)
		if (check_row(&v, bj) < 0)
			goto done;
	if (c->dem != NULL)
		vf_dem_finish(&v, v.w.j0 + v.w.n);
	check_strays(&v);
	r = 0;
done:
	lv_free(&v);
	return r;
}
