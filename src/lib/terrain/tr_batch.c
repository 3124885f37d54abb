/* tr_batch.c - the coarse levels measured in one pass over level 0
 * (tr_export.h). A tile is measured (where its bound, tr_bound.c, does
 * not clear it) against every level-0 sample under it, so a level of
 * few large tiles reads and decodes all of level 0;
 * made one after the other, levels 0 to 9 read it ten times. Here
 * their tiles are made at try 0 and kept (their locators, tr_keep) up
 * to a bound on memory, then measured together, each level-0 block
 * read once and its samples put to every kept tile over it. A tile's
 * distances are maxima over its samples, the same in any order, so the
 * levels' parts, and which of them hold, are tr_settle's; a level that
 * does not hold is made again from try 1, as tr_settle would. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/tr_export.h"

#define TR_BATCH 64               /* tiles a level, at most */

int
tr_batch_depth(const tr_export *x)
{
	int z = 0;

	while (z < x->maxz && tr_count(x, z + 1) <= TR_BATCH)
		z++;
	return z;
}

/* The kept tiles of every thread, in one list: thread 0's first. */
static struct tr_keptz *
kept_list(const tr_export *x, int *n)
{
	struct tr_keptz *l;
	int m = 0;

	*n = 0;
	for (int k = 0; k < x->nt; k++)
		*n += x->w[k].nkept;
	if ((l = malloc((size_t)(*n ? *n : 1) * sizeof *l)) == NULL)
		return NULL;
	for (int k = 0; k < x->nt; k++)
		for (int i = 0; i < x->w[k].nkept; i++)
			l[m++] = x->w[k].kept[i];
	return l;
}

/* Block b of level 0, read once (when a kept tile meets it) and
 * measured for every kept tile: thread k's d into dd. */
static void
pass_block(tr_export *x, int k, int b, double *dd)
{
	tr_work *w = &x->w[k];
	const pyramid_level *L0 = &x->ix.lev[0];
	const struct tr_keptz *l = x->kl;
	int bi = b % L0->blocks[0], bj = b / L0->blocks[0], any = 0;
	const double *lon, *lat, *bx = NULL;
	double *fu = NULL;
	const pyramid_block *pb;
	double band;

	if ((any = tr_kept_meeting(&x->g, l, x->nkeep, b, &band)) == 0)
		return;
	if ((pb = tr_block_band(w, bi, bj, band, &lon, &lat, &x->err[k])) ==
	    NULL) {
		x->failed[k] = 1;
		return;
	}
	/* a projected block's feet once for the tiles (one a level) that
	 * measure it whole: their sines and cosines were a fifth of the
	 * export; without the memory, or for the sides' band alone, each
	 * tile its own */
	if (x->g.projected && any > 1 && band == INFINITY && (w->fu != NULL ||
	    (w->fu = malloc(6 * (size_t)PYRAMID_N * sizeof *w->fu)) != NULL)) {
		tr_block_feet(&x->g, lon, lat, bi, bj, w->fu);
		fu = w->fu;
	}
	if (x->g.projected)
		bx = tr_far_boxes(w, pb, lon, lat);
	for (int i = 0; i < x->nkeep; i++)
		if (tr_kept_block(&x->g, l[i].k, b, bi, bj, pb, lon, lat,
		    fu, NULL, bx, dd + 2 * i, &x->err[k]) < 0) {
			x->failed[k] = 1;
			break;
		}
}

/* The blocks of level 0, a few at a time (tr_take): thread k's d
 * into x->dd. */
static void
pass_range(void *arg, int k, int r0, int r1)
{
	tr_export *x = arg;
	double *dd = x->dd + 2 * (size_t)k * x->nkeep;
	int i0, i1, chunk = x->count / (8 * x->nt);

	(void)r0, (void)r1;
	while (!x->failed[k] && tr_take(x, x->count, chunk > 0 ? chunk : 1,
	    &i0, &i1))
		for (int b = i0; b < i1 && !x->failed[k]; b++)
			pass_block(x, k, b, dd);
}

/* The kept tiles measured, their distances into their levels' parts. */
static int
pass(tr_export *x, tr_part *p, tl_err *e)
{
	const pyramid_level *L0 = &x->ix.lev[0];
	struct tr_keptz *l = kept_list(x, &x->nkeep);
	int r = -1;

	x->dd = l ? calloc(2 * (size_t)x->nt * x->nkeep + 1, sizeof *x->dd) :
	    NULL;
	if (x->dd == NULL) {
		tl_fail(e, "tile: out of memory");
		goto done;
	}
	x->kl = l;
	memset(x->failed, 0, (size_t)x->nt * sizeof *x->failed);
	x->count = L0->blocks[0] * L0->blocks[1], x->next = 0;
	tl_pool_for(x->pool, x->count, pass_range, x);
	for (int k = 0; k < x->nt; k++)
		if (x->failed[k]) {
			*e = x->err[k];
			goto done;
		}
	for (int k = 0; k < x->nt; k++)
		for (int i = 0; i < x->nkeep; i++) {
			const double *d = x->dd + 2 * ((size_t)k * x->nkeep + i);
			p[l[i].z].err = fmax(p[l[i].z].err, d[0]);
			p[l[i].z].direct = fmax(p[l[i].z].direct, d[1]);
		}
	r = 0;
done:
	free(l), free(x->dd);
	x->kl = NULL, x->dd = NULL, x->nkeep = 0;
	return r;
}

static void
unkeep(tr_export *x)
{
	for (int k = 0; k < x->nt; k++) {
		tr_work *w = &x->w[k];
		for (int i = 0; i < w->nkept; i++)
			tr_kept_free(w->kept[i].k);
		w->nkept = 0, w->kbytes = 0;
	}
	x->keep = 0;
}

int
tr_batch(tr_export *x, const char *tmp, int z1, tr_part *p, tl_err *e)
{
	tr_choice c;
	int r = -1;

	x->keep = TR_KEEP / (size_t)x->nt;
	for (int z = 0; z <= z1; z++)
		if (tr_dirs(x, tmp, z, e) < 0 || tr_try(x, tmp, z, 0,
		    (int)tr_count(x, z), 0, &p[z], e) < 0)
			goto done;
	if (pass(x, p, e) < 0)
		goto done;
	unkeep(x);
	for (int z = 0; z <= z1; z++) {
		/* tr_try's test, now that every tile is measured */
		tr_choose(&x->ix, z, 0, &c);
		p[z].held = fmax(c.tau, c.base) + p[z].err <= c.el;
		if (!p[z].held && tr_settle(x, tmp, z, 0, (int)tr_count(x, z),
		    1, &p[z], e) < 0)
			goto done;
	}
	r = 0;
done:
	unkeep(x);
	return r;
}
