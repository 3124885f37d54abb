/* verify_tree.c - a block's bintree built explicitly from the split rule
 * of vgis(5), and the relations and selections read off it (verify.h). It
 * shares nothing with bintree.c, which it checks in the tests. */
#include "verify/verify_impl.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

/* Node k: triangle (a, b; apex p) and, unless a leaf, its subtree. */
static int
grow(vf_tree *t, int *n, const int a[2], const int b[2], const int p[2])
{
	int k = (*n)++, m[2], *slot;
	vf_node *d;

	assert(k < VF_NODES);
	d = &t->node[k];
	for (int q = 0; q < 2; q++) {
		d->a[q] = (unsigned char)a[q], d->b[q] = (unsigned char)b[q];
		d->p[q] = (unsigned char)p[q];
	}
	d->m = d->kid[0] = d->kid[1] = -1;
	/* legs of length 1: the hypotenuse midpoint is off the grid */
	if ((a[0] + b[0]) % 2 != 0 || (a[1] + b[1]) % 2 != 0)
		return k;
	m[0] = (a[0] + b[0]) / 2, m[1] = (a[1] + b[1]) / 2;
	d->m = m[1] * BT_SIZE + m[0];
	slot = t->dia[d->m];
	assert(slot[1] < 0); /* two triangles at most share a midpoint */
	slot[slot[0] >= 0] = k;
	d->kid[0] = grow(t, n, a, p, m);
	d->kid[1] = grow(t, n, p, b, m);
	return k;
}

static int
on_border(int k)
{
	int c = k % BT_SIZE, r = k / BT_SIZE;

	return c == 0 || r == 0 || c == BT_CELLS || r == BT_CELLS;
}

int
vf_tree_init(vf_tree *t, tl_err *e)
{
	static const int o[2] = { 0, 0 }, f[2] = { BT_CELLS, BT_CELLS };
	static const int tr[2] = { BT_CELLS, 0 }, bl[2] = { 0, BT_CELLS };
	int n = 0;

	memset(t, 0, sizeof *t);
	t->node = tl_alloc(VF_NODES, sizeof *t->node, e);
	t->dia = tl_alloc(VF_NV, sizeof *t->dia, e);
	if (t->node == NULL || t->dia == NULL) {
		vf_tree_free(t);
		return -1;
	}
	for (int k = 0; k < VF_NV; k++)
		t->dia[k][0] = t->dia[k][1] = -1;
	/* the roots share the diagonal (0,0)-(128,128) */
	t->root[0] = grow(t, &n, o, f, tr);
	t->root[1] = grow(t, &n, f, o, bl);
	assert(n == VF_NODES);
	/* what the split rule implies: one node per border midpoint, two
	 * per inner one */
	for (int k = 0; k < VF_NV; k++) {
		int have = (t->dia[k][0] >= 0) + (t->dia[k][1] >= 0);
		int want = vf_corner(k) ? 0 : on_border(k) ? 1 : 2;
		assert(have == want);
		(void)have, (void)want;
	}
	return 0;
}

void
vf_tree_free(vf_tree *t)
{
	free(t->node);
	free(t->dia);
	t->node = NULL;
	t->dia = NULL;
}

/* The (block, node) pairs whose node has (gi, gj) as its midpoint. */
static int
holders(const vf_tree *t, int bx, int by, int gi, int gj, int hb[2][2],
    int hn[2])
{
	int n = 0;

	if (gi < 0 || gj < 0 || gi > bx * BT_CELLS || gj > by * BT_CELLS)
		return 0;
	for (int bj = gj / BT_CELLS - 1; bj <= gj / BT_CELLS; bj++)
		for (int bi = gi / BT_CELLS - 1; bi <= gi / BT_CELLS; bi++) {
			int c = gi - bi * BT_CELLS, r = gj - bj * BT_CELLS;
			if (bi < 0 || bj < 0 || bi >= bx || bj >= by ||
			    c > BT_CELLS || r > BT_CELLS)
				continue;
			for (int q = 0; q < 2; q++) {
				int k = t->dia[r * BT_SIZE + c][q];
				if (k < 0)
					continue;
				assert(n < 2); /* a diamond: two triangles */
				hb[n][0] = bi, hb[n][1] = bj;
				hn[n++] = k;
			}
		}
	return n;
}

int
vf_diamond(const vf_tree *t, int bx, int by, int gi, int gj,
    int tri[2][3][2])
{
	int hb[2][2], hn[2], n = holders(t, bx, by, gi, gj, hb, hn);

	for (int q = 0; q < n; q++) {
		const vf_node *d = &t->node[hn[q]];
		int ox = hb[q][0] * BT_CELLS, oy = hb[q][1] * BT_CELLS;
		tri[q][0][0] = d->a[0] + ox, tri[q][0][1] = d->a[1] + oy;
		tri[q][1][0] = d->b[0] + ox, tri[q][1][1] = d->b[1] + oy;
		tri[q][2][0] = d->p[0] + ox, tri[q][2][1] = d->p[1] + oy;
	}
	return n;
}

int
vf_parents(const vf_tree *t, int bx, int by, int gi, int gj, int p[2][2])
{
	int tri[2][3][2], n = vf_diamond(t, bx, by, gi, gj, tri);

	for (int q = 0; q < n; q++)
		p[q][0] = tri[q][2][0], p[q][1] = tri[q][2][1];
	return n;
}

int
vf_children(const vf_tree *t, int bx, int by, int gi, int gj, int c[4][2])
{
	int hb[2][2], hn[2], n = holders(t, bx, by, gi, gj, hb, hn), nc = 0;

	for (int q = 0; q < n; q++)
		for (int s = 0; s < 2; s++) {
			int kid = t->node[hn[q]].kid[s], m;
			if (kid < 0 || (m = t->node[kid].m) < 0)
				continue;
			assert(nc < 4);
			c[nc][0] = m % BT_SIZE + hb[q][0] * BT_CELLS;
			c[nc][1] = m / BT_SIZE + hb[q][1] * BT_CELLS;
			nc++;
		}
	return nc;
}

long
vf_select(const vf_tree *t, const unsigned char *sel, int *out)
{
	int stack[64], top = 0;
	long n = 0;

	stack[top++] = t->root[1];
	stack[top++] = t->root[0];
	while (top > 0) {
		const vf_node *d = &t->node[stack[--top]];
		if (d->m >= 0 && sel[d->m]) {
			/* depth 15 per root: a path holds at most 32 */
			assert(top + 2 <= 64);
			stack[top++] = d->kid[1];
			stack[top++] = d->kid[0];
		} else {
			assert(n < VF_LEAVES);
			out[n++] = (int)(d - t->node);
		}
	}
	return n;
}
