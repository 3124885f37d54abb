/* verify_sat.c - saturation: E never below a child's E in the block's
 * explicit bintree, corners FLT_MAX, every other E finite and >= 0
 * ("saturation" violations). Across borders this follows from the
 * border check: a border vertex's E is one value in both blocks. */
#include "verify/verify_impl.h"

#include <float.h>
#include <math.h>

void
vf_sat_check(vf_lv *v, const vf_blk *b, int bi, int bj)
{
	const vf_tree *t = &v->c->tree;

	for (int k = 0; k < VF_NV; k++) {
		float e = b->e[k];
		if (vf_corner(k) ? e != FLT_MAX : !(e >= 0 && e < FLT_MAX))
			VNOTE(v, VF_SATURATION, bi, bj, k, NAN, "E %g: %s", e,
			    vf_corner(k) ? "a corner's E must be FLT_MAX" :
			    "must be finite and >= 0");
	}
	/* apex p is a parent of midpoint m: E(p) >= E(m), NaN failing */
	for (int n = 0; n < VF_NODES; n++) {
		const vf_node *d = &t->node[n];
		int p = d->p[1] * BT_SIZE + d->p[0];
		if (d->m >= 0 && !(b->e[p] >= b->e[d->m]))
			VNOTE(v, VF_SATURATION, bi, bj, d->m, NAN, "E %.9g "
			    "above its parent (%d,%d)'s %.9g", b->e[d->m],
			    bi * BT_CELLS + d->p[0], bj * BT_CELLS + d->p[1],
			    b->e[p]);
	}
}
