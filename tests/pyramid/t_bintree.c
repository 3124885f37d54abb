/* t_bintree - the 4-8 hierarchy: parents and children agree, diamonds
 * are those of the split rule, and a top-down selection over saturated
 * random errors is a matching triangulation (every selected vertex a
 * corner, no T-vertex, area exact) across a 2x2 block level. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "pyramid/bintree.h"
#include "tap.h"

#define N (2 * BT_CELLS + 1) /* a level of 2x2 blocks */

static float E[N][N];
static double tau;
static unsigned char used[N][N];
static long area2, bad_tri;

static int
in(int i, int j)
{
	return i >= 0 && j >= 0 && i < N && j < N;
}

static int
split(void *ctx, int gi, int gj)
{
	(void)ctx;
	return E[gj][gi] > tau;
}

static void
emit(void *ctx, const int t[3][2])
{
	long cr = (long)(t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) -
	    (long)(t[1][1] - t[0][1]) * (t[2][0] - t[0][0]);

	(void)ctx;
	area2 += cr < 0 ? -cr : cr;
	for (int k = 0; k < 3; k++)
		used[t[k][1]][t[k][0]] = 1;
	/* no selected vertex strictly inside any edge */
	for (int k = 0; k < 3; k++) {
		const int *p = t[k], *q = t[(k + 1) % 3];
		int di = (q[0] > p[0]) - (q[0] < p[0]);
		int dj = (q[1] > p[1]) - (q[1] < p[1]);
		for (int i = p[0] + di, j = p[1] + dj; i != q[0] || j != q[1];
		    i += di, j += dj)
			if (E[j][i] > tau)
				bad_tri++;
	}
}

/* Children's parents include the vertex; m is the midpoint of its
 * diamond's hypotenuses. */
static void
relations(void)
{
	long inconsistent = 0;

	for (int j = 0; j < N; j++)
		for (int i = 0; i < N; i++) {
			int c[4][2], p[2][2], nc = bt_children(i, j, c);
			int tri[2][3][2], nt = bt_diamond(i, j, tri);
			for (int k = 0; k < nc; k++) {
				int np = bt_parents(c[k][0], c[k][1], p), found = 0;
				for (int q = 0; q < np; q++)
					found |= p[q][0] == i && p[q][1] == j;
				inconsistent += !found;
			}
			for (int k = 0; k < nt; k++)
				inconsistent += tri[k][0][0] + tri[k][1][0] != 2 * i ||
				    tri[k][0][1] + tri[k][1][1] != 2 * j;
		}
	ok(inconsistent == 0, "children's parents include the vertex; "
	    "m is the midpoint of its diamond's hypotenuses (%ld bad)",
	    inconsistent);
}

/* Random local errors, saturated bottom-up by scale; corners FLT_MAX. */
static void
saturated_errors(unsigned s)
{
	for (int j = 0; j < N; j++)
		for (int i = 0; i < N; i++) {
			s = s * 1103515245u + 12345u;
			E[j][i] = (float)((s >> 16) % 1000) *
			    (float)bt_classify(i, j).h;
		}
	for (int h = 1; h <= BT_MAXH; h *= 2)
		for (int pass = 0; pass < 2; pass++) /* edges, then squares */
			for (int j = 0; j < N; j++)
				for (int i = 0; i < N; i++) {
					bt_class k = bt_classify(i, j);
					int c[4][2], nc;
					if (k.h != h || (k.kind == BT_SQUARE) != pass)
						continue;
					nc = bt_children(i, j, c);
					for (int q = 0; q < nc; q++)
						if (in(c[q][0], c[q][1]) &&
						    E[c[q][1]][c[q][0]] > E[j][i])
							E[j][i] = E[c[q][1]][c[q][0]];
				}
	for (int j = 0; j < N; j += BT_CELLS)
		for (int i = 0; i < N; i += BT_CELLS)
			E[j][i] = FLT_MAX;
}

/* Selected vertices that are no triangle's corner, or whose parent is
 * not selected, at the current tau. */
static void
unused_orphans(long *unused, long *orphans)
{
	*unused = *orphans = 0;
	for (int j = 0; j < N; j++)
		for (int i = 0; i < N; i++) {
			int p[2][2], np = bt_parents(i, j, p);
			if (E[j][i] <= tau)
				continue;
			*unused += !used[j][i];
			for (int q = 0; q < np; q++)
				if (in(p[q][0], p[q][1]) &&
				    E[p[q][1]][p[q][0]] <= tau)
					(*orphans)++;
		}
}

/* At a sweep of taus the 2x2 blocks' selections match. */
static void
matching(void)
{
	for (tau = 0; tau < 64000; tau = tau * 3 + 100) {
		long unused, orphans, tris = 0;
		memset(used, 0, sizeof used);
		area2 = bad_tri = 0;
		for (int bj = 0; bj < 2; bj++)
			for (int bi = 0; bi < 2; bi++)
				tris += bt_select(bi * BT_CELLS, bj * BT_CELLS,
				    split, NULL, emit, NULL);
		unused_orphans(&unused, &orphans);
		ok(unused == 0 && orphans == 0 && bad_tri == 0 &&
		    area2 == 2L * 4 * BT_CELLS * BT_CELLS,
		    "tau %g: %ld triangles, matching (unused %ld, orphans %ld, "
		    "T-vertices %ld, area ok %d)", tau, tris, unused, orphans,
		    bad_tri, area2 == 2L * 4 * BT_CELLS * BT_CELLS);
	}
}

int
main(void)
{
	long leaves;

	relations();
	tau = -1;
	for (int j = 0; j < N; j++)
		for (int i = 0; i < N; i++)
			E[j][i] = 1;
	leaves = bt_select(0, 0, split, NULL, NULL, NULL);
	ok(leaves == 2L * BT_CELLS * BT_CELLS, "full refinement: %ld "
	    "triangles, 2 per cell", leaves);
	saturated_errors(5);
	matching();
	return tap_done();
}
