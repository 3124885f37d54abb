/* verify_border.c - vertices stored twice agree: shared borders of
 * neighbouring blocks bit for bit, padding past the level's size a copy
 * of the nearest real vertex ("border", "padding" violations). */
#include "verify/verify_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Vertices past the level's size copy the nearest real one, which is in
 * the same block (only the last block column and row hold padding). */
void
vf_border_padding(vf_lv *v, const vf_blk *b, int bi, int bj)
{
	for (int k = 0; k < VF_NV; k++) {
		int gi = bi * BT_CELLS + k % BT_SIZE;
		int gj = bj * BT_CELLS + k / BT_SIZE, ri, rj, q;
		if (gi < v->L->size[0] && gj < v->L->size[1])
			continue;
		ri = gi < v->L->size[0] ? gi : v->L->size[0] - 1;
		rj = gj < v->L->size[1] ? gj : v->L->size[1] - 1;
		q = (rj - bj * BT_CELLS) * BT_SIZE + ri - bi * BT_CELLS;
		if (q < 0 || q >= VF_NV)
			continue; /* a level larger than its blocks: index */
		if (b->z[k] != b->z[q] || (v->disp &&
		    (b->x[k] != 0 || b->y[k] != 0)))
			VNOTE(v, VF_PADDING, bi, bj, k, NAN, "Z %.9g X %g "
			    "Y %g, the edge vertex (%d,%d) has Z %.9g", b->z[k],
			    v->disp ? b->x[k] : 0.0, v->disp ? b->y[k] : 0.0,
			    ri, rj, b->z[q]);
	}
}

static int
differ(float a, float b)
{
	return memcmp(&a, &b, sizeof a) != 0;
}

/* Vertex ka of block a and kb of block b are one level vertex. */
static void
border_pair(vf_lv *v, const vf_blk *a, int ai, int aj, int ka,
    const vf_blk *b, int bi, int bj, int kb)
{
	char buf[160];
	size_t n = 0;
	const char *name[4] = { "Z", "E", "X", "Y" };
	const float *pa[4] = { a->z, a->e, a->x, a->y };
	const float *pb[4] = { b->z, b->e, b->x, b->y };

	buf[0] = '\0';
	for (int q = 0; q < (v->disp ? 4 : 2); q++)
		if (differ(pa[q][ka], pb[q][kb]) && n < sizeof buf)
			n += snprintf(buf + n, sizeof buf - n,
			    "%s%s %.9g vs %.9g", n ? ", " : "", name[q],
			    pa[q][ka], pb[q][kb]);
	if (n > 0)
		VNOTE(v, VF_BORDER, ai, aj, ka, NAN, "%s in block (%d,%d)",
		    buf, bi, bj);
}

void
vf_border_check(vf_lv *v, int bi, int bj)
{
	const vf_blk *b = &v->row[1][bi], *left, *up;

	if (bi > 0 && (left = &v->row[1][bi - 1])->ok)
		for (int r = 0; r < BT_SIZE; r++)
			border_pair(v, b, bi, bj, r * BT_SIZE, left, bi - 1, bj,
			    r * BT_SIZE + BT_CELLS);
	if (bj > 0 && (up = &v->row[0][bi])->ok)
		for (int c = 0; c < BT_SIZE; c++)
			border_pair(v, b, bi, bj, c, up, bi, bj - 1,
			    BT_CELLS * BT_SIZE + c);
}
