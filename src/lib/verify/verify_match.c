/* verify_match.c - the selection at each tau: parents of selected
 * vertices selected, every selected vertex a corner of an emitted
 * triangle, none strictly inside an emitted edge here or across a block
 * border, areas summing to the block's ("matching"); displaced triangles
 * neither flipped nor flat ("fold"). */
#include "verify/verify_impl.h"

#include <math.h>
#include <string.h>

/* Twice the signed grid area of node d's triangle. */
static long long
cross2(const vf_node *d)
{
	long long ux = d->b[0] - d->a[0], uy = d->b[1] - d->a[1];
	long long wx = d->p[0] - d->a[0], wy = d->p[1] - d->a[1];

	return ux * wy - uy * wx;
}

/* Marks the grid points strictly inside edge p-q (axis or diagonal). */
static void
mark_edge(unsigned char *in, const unsigned char p[2],
    const unsigned char q[2])
{
	int di = (q[0] > p[0]) - (q[0] < p[0]);
	int dj = (q[1] > p[1]) - (q[1] < p[1]);

	for (int i = p[0] + di, j = p[1] + dj; i != q[0] || j != q[1];
	    i += di, j += dj)
		in[j * BT_SIZE + i] = 1;
}

/* Displaced corners keep the triangle's orientation and area. */
static void
check_fold(vf_lv *v, const vf_blk *b, const vf_node *d, int bi, int bj,
    double tau)
{
	double x[3], y[3], z[3], s;

	vf_error_tri(b, d, x, y, z);
	s = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
	if (!(s * (double)cross2(d) > 0))
		VNOTE(v, VF_FOLD, bi, bj, d->p[1] * BT_SIZE + d->p[0], tau,
		    "triangle (%d,%d)-(%d,%d) apex here: displaced area %.3g, "
		    "grid area %.3g", bi * BT_CELLS + d->a[0],
		    bj * BT_CELLS + d->a[1], bi * BT_CELLS + d->b[0],
		    bj * BT_CELLS + d->b[1], s / 2, cross2(d) / 2.0);
}

/* The n emitted triangles (v->emit) of block (bi, bj) at tau t: the
 * vertices they use and hold strictly inside an edge, their area, fold
 * and error; the level's largest error and tightness at t. */
static void
emitted(vf_lv *v, const vf_blk *b, int bi, int bj, int t, long n)
{
	const vf_tree *tr = &v->c->tree;
	unsigned char *in = v->inside + (size_t)bi * VF_NV;
	double tau = v->tau[t], worst = 0;
	double base = v->L->base[(size_t)bj * v->bx + bi];
	long long area2 = 0;

	memset(v->used, 0, VF_NV);
	memset(in, 0, VF_NV);
	for (long q = 0; q < n; q++) {
		const vf_node *d = &tr->node[v->emit[q]];
		long long a = cross2(d);
		v->used[d->a[1] * BT_SIZE + d->a[0]] = 1;
		v->used[d->b[1] * BT_SIZE + d->b[0]] = 1;
		v->used[d->p[1] * BT_SIZE + d->p[0]] = 1;
		mark_edge(in, d->a, d->b);
		mark_edge(in, d->b, d->p);
		mark_edge(in, d->p, d->a);
		area2 += a < 0 ? -a : a;
		if (v->disp)
			check_fold(v, b, d, bi, bj, tau);
		if (v->c->dem != NULL)
			vf_error_check(v, b, d, bi, bj, t, &worst);
	}
	if (area2 != 2L * BT_CELLS * BT_CELLS)
		vf_note(v->c, VF_MATCHING, v->l, bi, bj, -1, -1, tau,
		    "triangle areas sum to %g cells, the block has %d",
		    area2 / 2.0, BT_CELLS * BT_CELLS);
	if (v->c->dem == NULL)
		return;
	v->R->tau[t].maxerr = fmax(v->R->tau[t].maxerr, worst);
	if (tau > base && (isnan(v->R->tight) || worst / tau > v->R->tight)) {
		v->R->tight = worst / tau;
		v->R->tight_tau = tau;
		v->R->tight_block[0] = bi, v->R->tight_block[1] = bj;
	}
}

void
vf_match_block(vf_lv *v, int bi, int bj, int t)
{
	const vf_blk *b = &v->row[1][bi];
	const vf_tree *tr = &v->c->tree;
	const unsigned char *in = v->inside + (size_t)bi * VF_NV;
	double tau = v->tau[t];
	long n;

	for (int k = 0; k < VF_NV; k++)
		v->sel[k] = (unsigned char)vf_selected(b, k, tau);
	for (int q = 0; q < VF_NODES; q++) {
		const vf_node *d = &tr->node[q];
		if (d->m >= 0 && v->sel[d->m] &&
		    !v->sel[d->p[1] * BT_SIZE + d->p[0]])
			VNOTE(v, VF_MATCHING, bi, bj, d->m, tau, "selected (E "
			    "%.9g), its parent (%d,%d) is not (E %.9g)",
			    b->e[d->m], bi * BT_CELLS + d->p[0],
			    bj * BT_CELLS + d->p[1],
			    b->e[d->p[1] * BT_SIZE + d->p[0]]);
	}
	n = vf_select(tr, v->sel, v->emit);
	v->R->tau[t].triangles += n;
	emitted(v, b, bi, bj, t, n);
	for (int k = 0; k < VF_NV; k++) {
		if (v->sel[k] && !v->used[k])
			VNOTE(v, VF_MATCHING, bi, bj, k, tau, "selected (E "
			    "%.9g) but a corner of no triangle", b->e[k]);
		if (v->sel[k] && in[k])
			VNOTE(v, VF_MATCHING, bi, bj, k, tau, "selected (E "
			    "%.9g) but strictly inside a triangle's edge "
			    "(T-vertex)", b->e[k]);
	}
}

/* A vertex strictly inside an edge of block a, selected in block b. */
static void
cross_pair(vf_lv *v, const unsigned char *ina, int ai, int aj, int ka,
    const vf_blk *b, int bi, int bj, int kb, double tau)
{
	if (ina[ka] && vf_selected(b, kb, tau))
		VNOTE(v, VF_MATCHING, ai, aj, ka, tau, "strictly inside a "
		    "triangle's edge here, selected in block (%d,%d) (E %.9g): "
		    "T-vertex across the border", bi, bj, b->e[kb]);
}

void
vf_match_borders(vf_lv *v, int bj, int t)
{
	double tau = v->tau[t];
	size_t stride = (size_t)v->bx * BT_SIZE;

	for (int bi = 0; bi < v->bx; bi++) {
		const vf_blk *b = &v->row[1][bi];
		const vf_blk *l = &v->row[1][bi - (bi > 0)];
		const vf_blk *u = &v->row[0][bi];
		const unsigned char *in = v->inside + (size_t)bi * VF_NV;
		const unsigned char *inl = in - (bi > 0 ? VF_NV : 0);
		const unsigned char *up = v->bot[0] + t * stride + bi * BT_SIZE;
		if (!b->ok)
			continue;
		memcpy(v->bot[1] + t * stride + bi * BT_SIZE,
		    in + BT_CELLS * BT_SIZE, BT_SIZE);
		for (int r = 0; bi > 0 && l->ok && r < BT_SIZE; r++) {
			int kb = r * BT_SIZE, kl = kb + BT_CELLS;
			cross_pair(v, in, bi, bj, kb, l, bi - 1, bj, kl, tau);
			cross_pair(v, inl, bi - 1, bj, kl, b, bi, bj, kb, tau);
		}
		for (int c = 0; bj > 0 && u->ok && c < BT_SIZE; c++) {
			int ku = BT_CELLS * BT_SIZE + c;
			cross_pair(v, in, bi, bj, c, u, bi, bj - 1, ku, tau);
			if (up[c] && vf_selected(b, c, tau))
				VNOTE(v, VF_MATCHING, bi, bj - 1, ku, tau,
				    "strictly inside a triangle's edge here, "
				    "selected in block (%d,%d) (E %.9g): "
				    "T-vertex across the border", bi, bj,
				    b->e[c]);
		}
	}
}
