/* solve_fold.h - the streaming fold fix of QEM-3D (solve_fold.c), inside
 * the qem layer: solve.c places a row's vertices, then asks it to keep
 * every foldable triangle touching the row positive (solve.h's contract
 * for solve_row). Not a public interface. */
#ifndef TL_SOLVE_FOLD_H
#define TL_SOLVE_FOLD_H

#include "qem/solve.h"

/* Level-0 row (or column) of level row (column) j. */
static inline double
row0(const solve_state *s, int j)
{
	return (double)j * (double)(1L << s->level);
}

static inline double
cross(const double o[2], const double a[2], const double b[2])
{
	return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Fixes row j (offsets cur, placed), rows j-1 and j-2 final (s->hist),
 * s's metric cached for rows j-2 .. j+2. */
void solve_fix_folds(solve_state *s, int j, solve_vertex *cur);
/* 1 when every offset of a row is zero. */
int solve_zero_row(const solve_vertex *o, int w);

#endif
