/* bintree.h - the right-triangle bintree (4-8 mesh) of the 129x129 blocks,
 * the contract between tilepack and tileplay (vgis(5), "The triangulation").
 *
 * Coordinates are a level's global vertex indices (gi, gj); blocks start at
 * multiples of 128, so a vertex has the same role in every block that holds
 * it. A block's roots are the two triangles on its diagonal (0,0)-(128,128);
 * a triangle with hypotenuse (a, b) and apex p splits at m = (a+b)/2 into
 * (a, p; apex m) and (p, b; apex m); legs of length 1 are leaves.
 *
 * Every vertex that is not a block corner has a scale h in 1..64 (the
 * lowest set bit of gi | gj) and a kind:
 *   BT_SQUARE  gi/h, gj/h both odd: its diamond is the square of side 2h
 *              around it, split by the diagonal whose ends are coarser;
 *              parents: the other two corners (BT_EDGE, scale 2h);
 *              children: the four side midpoints (BT_EDGE, scale h).
 *   BT_EDGE_H  gi/h odd, gj/h even: hypotenuse (gi-h,gj)-(gi+h,gj);
 *   BT_EDGE_V  gi/h even, gj/h odd: hypotenuse (gi,gj-h)-(gi,gj+h);
 *              an edge vertex's diamond is the rotated square of its
 *              hypotenuse, parents the two apexes (BT_SQUARE, scale h),
 *              children (gi +- h/2, gj +- h/2) (BT_SQUARE, scale h/2),
 *              none at h = 1.
 * Parents and children may lie past the level's edges (callers drop them)
 * and in a neighbouring block. */
#ifndef TL_BINTREE_H
#define TL_BINTREE_H

#define BT_CELLS 128 /* cells a block side */
#define BT_SIZE 129  /* vertices a block side */
#define BT_MAXH 64   /* largest scale below the block corners */

enum bt_kind { BT_CORNER, BT_SQUARE, BT_EDGE_H, BT_EDGE_V };

typedef struct {
	enum bt_kind kind;
	int h; /* scale; 128 for corners */
} bt_class;

bt_class bt_classify(int gi, int gj);

/* Parents (apexes of the diamond's triangles): 0 for corners, else 2. */
int bt_parents(int gi, int gj, int p[2][2]);
/* Children (split vertices of the triangles its split creates): 0 or 4. */
int bt_children(int gi, int gj, int c[4][2]);
/* The diamond's two triangles without m, each as (hypotenuse end,
 * hypotenuse end, apex); 0 for corners. Triangles here and from
 * bt_select alternate in orientation: renderers must not cull by it. */
int bt_diamond(int gi, int gj, int tri[2][3][2]);

/* Top-down selection in one block whose (0,0) vertex is (gi0, gj0): the
 * triangles of the bintree refined wherever split(ctx, gi, gj) says so
 * for the hypotenuse midpoint (gi, gj); emit() gets each final triangle
 * as (a, b, apex), hypotenuse a-b. No forced splits: with saturated
 * errors the result is a matching triangulation. Returns the number of
 * triangles. */
typedef int (*bt_split_fn)(void *ctx, int gi, int gj);
typedef void (*bt_emit_fn)(void *ctx, const int tri[3][2]);
long bt_select(int gi0, int gj0, bt_split_fn split, void *sctx,
    bt_emit_fn emit, void *ectx);

#endif
