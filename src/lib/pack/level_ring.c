/* level_ring.c - the rings of a level's rows: heights, offsets, local
 * errors and metres per step, loaded in order as the scan and the
 * saturation reach them, each overwriting a row no one reads any more
 * (see level_impl.h, RINGV and RINGE). */
#include "pack/level_impl.h"

#include <assert.h>
#include <string.h>

/* The first level rows of heights and of local errors still to be read:
 * the rings' rows below them may be overwritten. A part reads heights
 * 2 x 64 (+ margin) rows above its batch's first DEM row and gives out
 * local errors from next_out; blocks read their saturation bands. */
static int
keep_v(const state *s)
{
	return s->part != NULL ? s->yfirst - 2 * BT_MAXH - 2 :
	    s->next_bj * BT_CELLS;
}

static int
keep_e(const state *s)
{
	return s->part != NULL ? s->next_out : s->next_bj * BT_CELLS - REACH;
}

/* Loads level row r (the next one): a real row, or past the last one a
 * copy of it; columns past the last real one copy its height (padding).
 * Its local errors start at 0, or are read (level_run_merged). */
static int
load_row(state *s, int r, tl_err *e)
{
	const level_args *L = s->L;
	int n = L->size[0], m = L->size[1];
	size_t o;
	long J = (long)r << L->level;

	/* the rows it overwrites are behind every row still to be read */
	assert(r == s->loaded && r < s->r1);
	assert(r - RINGV < keep_v(s) || r - RINGV < s->r0);
	assert(r - RINGE < keep_e(s) || r - RINGE < s->r0);
	s->loaded++;
	/* the window's real columns: c0 .. nr-1 (the piece's first block
	 * column is a real one, so n - 1 >= c0) */
	int nr = s->cend < n ? s->cend : n, c = s->c0;
	o = slot(s, r);
	assert(n - 1 >= c);
	if (r < m) {
		if (L->row(L->row_ctx, r, c, nr - c, s->z + o,
		    L->displaced ? s->ox + o : NULL,
		    L->displaced ? s->oy + o : NULL, e) < 0)
			return -1;
	} else {
		memcpy(s->z + o, s->z + slot(s, m - 1),
		    (size_t)(nr - c) * sizeof *s->z);
		if (L->displaced) {
			memset(s->ox + o, 0, (size_t)(nr - c) * sizeof *s->ox);
			memset(s->oy + o, 0, (size_t)(nr - c) * sizeof *s->oy);
		}
	}
	for (int i = nr - c; i < s->P; i++) { /* padding: level columns n.. */
		s->z[o + i] = s->z[o + n - 1 - c];
		if (L->displaced)
			s->ox[o + i] = s->oy[o + i] = 0;
	}
	memset(s->acc + eslot(s, r), 0, (size_t)s->P * sizeof *s->acc);
	if (s->in != NULL && s->in(s->in_ctx, r, s->acc + eslot(s, r) +
	    (s->lo - s->c0), e) < 0)
		return -1;
	o = (size_t)(r & (RINGV - 1)) * s->nn; /* this row's scales */
	geo_row_sx(L->m, (double)J, s->sx + o);
	geo_row_sy(L->m, (double)J, s->sy + o);
	return 0;
}

int
lv_ensure(state *s, int r, tl_err *e)
{
	if (r > s->r1 - 1)
		r = s->r1 - 1;
	while (s->loaded <= r)
		if (load_row(s, s->loaded, e) < 0)
			return -1;
	return 0;
}
