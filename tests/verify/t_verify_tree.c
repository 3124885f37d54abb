/* t_verify_tree - the checker's explicit bintree (verify_tree.c) against
 * bintree.c, which it does not use: over a 3x3-block level the diamonds,
 * parents and children read off the built trees are those of the split
 * rule as bintree.c computes it, and vf_select emits bt_select's
 * triangles on saturated random errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pyramid/bintree.h"
#include "verify/verify.h"
#include "tap.h"

#define NV (BT_SIZE * BT_SIZE)

static int
same_tri(const int a[3][2], const int b[3][2])
{
	int ends = (a[0][0] == b[0][0] && a[0][1] == b[0][1] &&
	    a[1][0] == b[1][0] && a[1][1] == b[1][1]) ||
	    (a[0][0] == b[1][0] && a[0][1] == b[1][1] &&
	    a[1][0] == b[0][0] && a[1][1] == b[0][1]);

	return ends && a[2][0] == b[2][0] && a[2][1] == b[2][1];
}

static int
inside(int n, const int p[2])
{
	return p[0] >= 0 && p[1] >= 0 && p[0] <= n && p[1] <= n;
}

/* Sets of points: equal when each of a is in b and the sizes match. */
static int
same_points(int na, int a[][2], int nb, int b[][2])
{
	if (na != nb)
		return 0;
	for (int i = 0; i < na; i++) {
		int found = 0;
		for (int j = 0; j < nb; j++)
			found |= a[i][0] == b[j][0] && a[i][1] == b[j][1];
		if (!found)
			return 0;
	}
	return 1;
}

static void
test_relations(const vf_tree *t)
{
	int nb = 3, n = nb * BT_CELLS;
	long bad_d = 0, bad_p = 0, bad_c = 0, checked = 0;

	for (int j = 0; j <= n; j++)
		for (int i = 0; i <= n; i++) {
			int td[2][3][2], vd[2][3][2], tp[2][2], vp[2][2];
			int tc[4][2], vc[4][2], keep[4][2], ntd, nvd, k = 0;
			int ntp, ntc;
			/* bintree.c's triangles, parents, children within
			 * the level's blocks */
			ntd = bt_diamond(i, j, td);
			nvd = vf_diamond(t, nb, nb, i, j, vd);
			for (int q = 0; q < ntd; q++)
				if (inside(n, td[q][2])) {
					int hit = 0;
					for (int r = 0; r < nvd; r++)
						hit |= same_tri(td[q], vd[r]);
					k++;
					if (!hit && bad_d++ < 8)
						printf("# (%d,%d): bt_diamond has "
						    "(%d,%d)-(%d,%d) apex (%d,%d), "
						    "the block's tree not\n", i, j,
						    td[q][0][0], td[q][0][1],
						    td[q][1][0], td[q][1][1],
						    td[q][2][0], td[q][2][1]);
				}
			bad_d += k != nvd;
			ntp = bt_parents(i, j, tp);
			for (int q = k = 0; q < ntp; q++)
				if (inside(n, tp[q]))
					memcpy(keep[k++], tp[q], sizeof keep[0]);
			bad_p += !same_points(k, keep, vf_parents(t, nb, nb, i,
			    j, vp), vp);
			ntc = bt_children(i, j, tc);
			for (int q = k = 0; q < ntc; q++)
				if (inside(n, tc[q]))
					memcpy(keep[k++], tc[q], sizeof keep[0]);
			bad_c += !same_points(k, keep, vf_children(t, nb, nb, i,
			    j, vc), vc);
			checked++;
		}
	ok(bad_d == 0, "diamonds from the explicit trees = bt_diamond over a "
	    "3x3-block level (%ld vertices, %ld differ)", checked, bad_d);
	ok(bad_p == 0, "parents = bt_parents (%ld differ)", bad_p);
	ok(bad_c == 0, "children = bt_children (%ld differ)", bad_c);
}

/* bt_select's and vf_select's triangles, sorted, for one block. */
typedef struct {
	int n;
	int (*tri)[6];
} tris;

static void
bt_emit(void *ctx, const int t[3][2])
{
	tris *s = ctx;
	int *o = s->tri[s->n++];

	for (int k = 0; k < 3; k++)
		o[2 * k] = t[k][0], o[2 * k + 1] = t[k][1];
}

static int
cmp6(const void *a, const void *b)
{
	return memcmp(a, b, 6 * sizeof(int));
}

static const float *sel_e;
static double sel_tau;

static int
bt_split(void *ctx, int gi, int gj)
{
	(void)ctx;
	return sel_e[gj * BT_SIZE + gi] > sel_tau;
}

static void
test_select(const vf_tree *t)
{
	static float e[NV];
	static unsigned char sel[NV];
	static int out[2 * BT_CELLS * BT_CELLS];
	tris a, b;
	unsigned s = 7;
	long bad = 0, n = 0, full;

	a.tri = calloc(2 * BT_CELLS * BT_CELLS, sizeof *a.tri);
	b.tri = calloc(2 * BT_CELLS * BT_CELLS, sizeof *b.tri);
	memset(sel, 1, sizeof sel);
	full = vf_select(t, sel, out);
	ok(full == 2L * BT_CELLS * BT_CELLS, "full selection: %ld leaves",
	    full);
	/* random errors scaled by the vertex's scale, saturated by bintree.c */
	for (int k = 0; k < NV; k++) {
		s = s * 1103515245u + 12345u;
		e[k] = (float)((s >> 16) % 1000) *
		    (float)bt_classify(k % BT_SIZE, k / BT_SIZE).h;
	}
	for (int h = 1; h <= BT_MAXH; h *= 2)
		for (int pass = 0; pass < 2; pass++)
			for (int k = 0; k < NV; k++) {
				bt_class c = bt_classify(k % BT_SIZE, k / BT_SIZE);
				int ch[4][2], nc;
				if (c.h != h || (c.kind == BT_SQUARE) != pass)
					continue;
				nc = bt_children(k % BT_SIZE, k / BT_SIZE, ch);
				for (int q = 0; q < nc; q++)
					if (inside(BT_CELLS, ch[q]))
						e[k] = fmaxf(e[k], e[ch[q][1] *
						    BT_SIZE + ch[q][0]]);
			}
	sel_e = e;
	for (sel_tau = 0; sel_tau < 64000; sel_tau = sel_tau * 3 + 100) {
		for (int k = 0; k < NV; k++)
			sel[k] = e[k] > sel_tau;
		a.n = b.n = 0;
		bt_select(0, 0, bt_split, NULL, bt_emit, &a);
		b.n = (int)vf_select(t, sel, out);
		for (int q = 0; q < b.n; q++) {
			const vf_node *d = &t->node[out[q]];
			int *o = b.tri[q];
			o[0] = d->a[0], o[1] = d->a[1], o[2] = d->b[0];
			o[3] = d->b[1], o[4] = d->p[0], o[5] = d->p[1];
		}
		qsort(a.tri, a.n, sizeof *a.tri, cmp6);
		qsort(b.tri, b.n, sizeof *b.tri, cmp6);
		bad += a.n != b.n || memcmp(a.tri, b.tri, a.n * sizeof *a.tri);
		n++;
	}
	ok(bad == 0, "vf_select = bt_select on saturated random errors "
	    "(%ld taus, %ld differ)", n, bad);
	free(a.tri), free(b.tri);
}

int
main(void)
{
	vf_tree t;
	tl_err e;

	if (vf_tree_init(&t, &e) < 0) {
		ok(0, "set up: %s", e.msg);
		return tap_done();
	}
	ok(t.root[0] >= 0 && t.root[1] >= 0 && t.node[t.root[0]].m ==
	    64 * BT_SIZE + 64 && t.node[t.root[1]].m == 64 * BT_SIZE + 64,
	    "the two roots split at the block's centre");
	test_relations(&t);
	test_select(&t);
	vf_tree_free(&t);
	return tap_done();
}
