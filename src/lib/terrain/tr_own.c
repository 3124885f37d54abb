/* tr_own.c - a thread's kept tiles of a projected sweep (tr_export.h,
 * tr_batch_own; kept by tr_level.c's sweep) measured in one pass over
 * the level-0 blocks they meet: a block read once for all of them, not
 * once a level, and a sample's foot and normal computed once. Apart
 * from tr_batch.c, which calls tr_level.c's tries: no call loop. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/tr_export.h"

/* Thread k's kept tiles (a sweep's ancestor's: tr_level.c) measured in
 * one pass over the level-0 blocks they meet, each block read once for
 * all and a projected one's feet computed once a vertex, when a tile
 * first needs it (as tr_block_feet would: the same doubles); their
 * distances into their levels' parts p; the tiles freed. */
int
tr_batch_own(tr_export *x, int k, tr_part *p, tl_err *e)
{
	tr_work *w = &x->w[k];
	const pyramid_level *L0 = &x->ix.lev[0];
	double *dd = NULL;
	int r = -1;

	if (w->nkept == 0)
		return 0;
	if ((dd = calloc(2 * (size_t)w->nkept, sizeof *dd)) == NULL) {
		tl_fail(e, "tile: out of memory");
		goto done;
	}
	if (x->g.projected && w->fok == NULL && (w->fu != NULL || (w->fu =
	    malloc(6 * (size_t)PYRAMID_N * sizeof *w->fu)) != NULL))
		w->fok = malloc(PYRAMID_N); /* NULL: each tile its own */
	for (int b = L0->blocks[0] * L0->blocks[1] - 1; b >= 0; b--) {
		int bi = b % L0->blocks[0], bj = b / L0->blocks[0];
		const double *lon, *lat, *bx = NULL;
		const pyramid_block *pb;
		double band;
		if (tr_kept_meeting(&x->g, w->kept, w->nkept, b, &band) == 0)
			continue;
		if ((pb = tr_block_band(w, bi, bj, band, &lon, &lat, e)) == NULL)
			goto done;
		if (x->g.projected)
			bx = tr_far_boxes(w, pb, lon, lat);
		if (w->fok != NULL)
			memset(w->fok, 0, PYRAMID_N);
		for (int i = 0; i < w->nkept; i++)
			if (tr_kept_block(&x->g, w->kept[i].k, b, bi, bj, pb, lon,
			    lat, w->fok ? w->fu : NULL, w->fok, bx, dd + 2 * i,
			    e) < 0)
				goto done;
	}
	for (int i = 0; i < w->nkept; i++) {
		tr_part *q = &p[w->kept[i].z];
		q->err = fmax(q->err, dd[2 * i]);
		q->direct = fmax(q->direct, dd[2 * i + 1]);
	}
	r = 0;
done:
	free(dd);
	for (int i = 0; i < w->nkept; i++)
		tr_kept_free(w->kept[i].k);
	w->nkept = 0, w->kbytes = 0;
	return r;
}
