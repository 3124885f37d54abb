/* bintree.c - the 4-8 hierarchy of a block (see bintree.h). */
#include "pyramid/bintree.h"

#include <assert.h>
#include <stddef.h>

static int
lowbit(int v)
{
	return v & -v;
}

bt_class
bt_classify(int gi, int gj)
{
	bt_class c = { BT_CORNER, BT_CELLS };
	int h = lowbit(gi | gj);

	if ((gi | gj) == 0 || h >= BT_CELLS)
		return c;
	c.h = h;
	assert(h >= 1 && h <= BT_MAXH);
	if ((gi / h) & 1)
		c.kind = (gj / h) & 1 ? BT_SQUARE : BT_EDGE_H;
	else
		c.kind = BT_EDGE_V;
	return c;
}

static void
set(int v[2], int i, int j)
{
	v[0] = i, v[1] = j;
}

int
bt_diamond(int gi, int gj, int tri[2][3][2])
{
	bt_class c = bt_classify(gi, gj);
	int h = c.h;

	switch (c.kind) {
	case BT_CORNER:
		return 0;
	case BT_SQUARE:
		/* the hypotenuse joins the corners with x/2h + y/2h even,
		 * in block coordinates: every block's roots split on its
		 * own (0,0)-(128,128) diagonal */
		if (((((gi % BT_CELLS) - h) / (2 * h)) +
		    (((gj % BT_CELLS) - h) / (2 * h))) % 2 == 0) {
			set(tri[0][0], gi - h, gj - h);
			set(tri[0][1], gi + h, gj + h);
			set(tri[0][2], gi + h, gj - h);
			set(tri[1][0], gi + h, gj + h);
			set(tri[1][1], gi - h, gj - h);
			set(tri[1][2], gi - h, gj + h);
		} else {
			set(tri[0][0], gi + h, gj - h);
			set(tri[0][1], gi - h, gj + h);
			set(tri[0][2], gi - h, gj - h);
			set(tri[1][0], gi - h, gj + h);
			set(tri[1][1], gi + h, gj - h);
			set(tri[1][2], gi + h, gj + h);
		}
		return 2;
	case BT_EDGE_H:
		set(tri[0][0], gi + h, gj), set(tri[0][1], gi - h, gj);
		set(tri[0][2], gi, gj - h);
		set(tri[1][0], gi - h, gj), set(tri[1][1], gi + h, gj);
		set(tri[1][2], gi, gj + h);
		return 2;
	case BT_EDGE_V:
		set(tri[0][0], gi, gj - h), set(tri[0][1], gi, gj + h);
		set(tri[0][2], gi - h, gj);
		set(tri[1][0], gi, gj + h), set(tri[1][1], gi, gj - h);
		set(tri[1][2], gi + h, gj);
		return 2;
	}
	return 0;
}

int
bt_parents(int gi, int gj, int p[2][2])
{
	int tri[2][3][2], n = bt_diamond(gi, gj, tri);

	for (int k = 0; k < n; k++)
		set(p[k], tri[k][2][0], tri[k][2][1]);
	return n;
}

int
bt_children(int gi, int gj, int c[4][2])
{
	bt_class k = bt_classify(gi, gj);
	int h = k.h, g = h / 2;

	switch (k.kind) {
	case BT_CORNER:
		return 0;
	case BT_SQUARE:
		set(c[0], gi - h, gj), set(c[1], gi + h, gj);
		set(c[2], gi, gj - h), set(c[3], gi, gj + h);
		return 4;
	case BT_EDGE_H:
	case BT_EDGE_V:
		if (h == 1)
			return 0;
		set(c[0], gi - g, gj - g), set(c[1], gi + g, gj - g);
		set(c[2], gi - g, gj + g), set(c[3], gi + g, gj + g);
		return 4;
	}
	return 0;
}

typedef struct {
	int o[2]; /* the block's (0,0) vertex */
	bt_split_fn split;
	void *sctx;
	bt_emit_fn emit;
	void *ectx;
	long n;
} walk;

static int
inblock(const walk *w, const int v[2])
{
	return v[0] >= w->o[0] && v[1] >= w->o[1] &&
	    v[0] <= w->o[0] + BT_CELLS && v[1] <= w->o[1] + BT_CELLS;
}

static void
descend(walk *w, const int a[2], const int b[2], const int p[2])
{
	int m[2];

	/* a right isosceles triangle of the block: the apex equidistant
	 * from both ends, every corner inside */
	assert((p[0] - a[0]) * (p[0] - a[0]) + (p[1] - a[1]) * (p[1] - a[1]) ==
	    (p[0] - b[0]) * (p[0] - b[0]) + (p[1] - b[1]) * (p[1] - b[1]));
	assert(inblock(w, a) && inblock(w, b) && inblock(w, p));
	/* legs of length 1 (hypotenuse midpoint off the grid): a leaf */
	if (((a[0] + b[0]) & 1) == 0 && ((a[1] + b[1]) & 1) == 0) {
		m[0] = (a[0] + b[0]) / 2, m[1] = (a[1] + b[1]) / 2;
		if (w->split(w->sctx, m[0], m[1])) {
			descend(w, a, p, m);
			descend(w, p, b, m);
			return;
		}
	}
	if (w->emit != NULL) {
		int t[3][2] = { { a[0], a[1] }, { b[0], b[1] },
			{ p[0], p[1] } };
		w->emit(w->ectx, t);
	}
	w->n++;
}

long
bt_select(int gi0, int gj0, bt_split_fn split, void *sctx, bt_emit_fn emit,
    void *ectx)
{
	walk w = { { gi0, gj0 }, split, sctx, emit, ectx, 0 };
	int o[2] = { gi0, gj0 }, f[2] = { gi0 + BT_CELLS, gj0 + BT_CELLS };
	int tr[2] = { gi0 + BT_CELLS, gj0 }, bl[2] = { gi0, gj0 + BT_CELLS };

	/* blocks start at multiples of 128 (the roles of vertices) */
	assert(gi0 >= 0 && gj0 >= 0 && gi0 % BT_CELLS == 0 &&
	    gj0 % BT_CELLS == 0);
	descend(&w, o, f, tr);
	descend(&w, f, o, bl);
	return w.n;
}
