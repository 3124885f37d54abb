/* level.c - a level's runs (see level.h): their state set up and freed,
 * the pieces and parts cut, windows found. The pass is level_crew.c, its
 * rings level_ring.c, the kernel exact_error.c and undisplaced_scan.c,
 * the saturation level_saturate.c, the block hand-out level_blocks.c. */
#include "pack/level.h"
#include "pack/level_impl.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static void
shares_free(state *s)
{
	for (int i = 0; s->shares != NULL && i < s->nshare; i++) {
		share *t = &s->shares[i];
		free(t->base);
		pyramid_block_free(&t->blk);
		for (int k = 0; k < 8; k++)
			free(t->vc[k].x), free(t->vc[k].y);
	}
	free(s->shares);
}

static void
state_free(state *s)
{
	free(s->z), free(s->ox), free(s->oy), free(s->sx), free(s->sy);
	free(s->nk), free(s->nu);
	free(s->acc), free(s->satband);
	free(s->dz), free(s->dv);
	free(s->dd);
	shares_free(s);
}

/* A share's base errors and, displaced, its rows of positions
 * (vertex_at, exact_error.c). */
static int
share_init(state *s, share *t, int lo, int hi, tl_err *e)
{
	t->s = s, t->lo = lo, t->hi = hi;
	if ((t->base = tl_alloc((size_t)(s->b1 - s->b0) * s->by,
	    sizeof *t->base, e)) == NULL ||
	    pyramid_block_alloc(&t->blk, s->L->displaced,
	    e) < 0)
		return -1;
	for (int hk = 0; (1 << hk) <= BT_MAXH; hk++) {
		t->vc[hk].n = (s->P - 1) / (1 << hk) + 1;
		for (int r = 0; r < VC_ROWS; r++)
			t->vc[hk].tag[r] = -1;
		if (!s->L->displaced)
			continue;
		t->vc[hk].x = tl_alloc((size_t)VC_ROWS * t->vc[hk].n,
		    sizeof *t->vc[hk].x, e);
		t->vc[hk].y = tl_alloc((size_t)VC_ROWS * t->vc[hk].n,
		    sizeof *t->vc[hk].y, e);
		if (t->vc[hk].x == NULL || t->vc[hk].y == NULL)
			return -1;
	}
	return 0;
}

/* The centres whose local errors the piece's saturation reads (its
 * block columns and REACH either side), in n shares of nearly equal
 * width (fewer when they are fewer than n columns); its blocks likewise. */
static int
shares_init(state *s, int n, tl_err *e)
{
	int lo = s->lo, hi = s->hi, nb = s->b1 - s->b0;

	if (n > hi - lo - 1)
		n = hi - lo - 1;
	if (n < 1)
		n = 1;
	if ((s->shares = tl_alloc(n, sizeof *s->shares, e)) == NULL)
		return -1;
	s->nshare = n;
	for (int k = 0; k < n; k++) {
		share *t = &s->shares[k];
		if (share_init(s, t, lo + (int)((long)(hi - lo) * k / n),
		    lo + (int)((long)(hi - lo) * (k + 1) / n), e) < 0)
			return -1;
		t->blo = s->b0 + nb * k / n, t->bhi = s->b0 + nb * (k + 1) / n;
	}
	return 0;
}

/* The centres whose local errors saturating piece p reads: its block
 * columns and REACH either side. */
static void
centres(const level_args *L, const level_piece *p, int *lo, int *hi)
{
	int Pl = pyramid_nblocks(L->size[0]) * BT_CELLS + 1;

	*lo = p->b0 * BT_CELLS - REACH, *hi = p->b1 * BT_CELLS + REACH + 1;
	*lo = *lo > 0 ? *lo : 0, *hi = *hi < Pl ? *hi : Pl;
}

/* The rows a run reads: a part's, or every one. */
static void
state_rows(state *s, const level_part *q)
{
	if (q != NULL) {
		s->lo = q->lo, s->hi = q->hi;
		s->y0 = q->y0, s->y1 = q->y1;
		s->r0 = q->r0, s->r1 = q->r1;
		s->next_out = q->g0;
	} else {
		centres(s->L, &(level_piece){ s->b0, s->b1 }, &s->lo, &s->hi);
		s->y0 = 0, s->y1 = s->d != NULL ? dem_georef(s->d)->height : 0;
		s->r0 = 0, s->r1 = s->Q;
	}
	s->loaded = s->r0;
}

/* A run of piece pc: scanning d (all its rows, or part q's), or with d
 * NULL reading its local errors; w0 is the DEM's width. */
static int
state_init(state *s, const level_args *L, const level_piece *pc, int w0,
    dem *d, const level_part *q, tl_err *e)
{
	level_window win;
	size_t ring;

	memset(s, 0, sizeof *s);
	s->L = L, s->d = d;
	s->W0 = w0;
	s->bx = pyramid_nblocks(L->size[0]);
	s->by = pyramid_nblocks(L->size[1]);
	s->Pl = s->bx * BT_CELLS + 1, s->Q = s->by * BT_CELLS + 1;
	s->step = (double)(1L << L->level);
	level_piece_window(L, s->W0, pc, &win);
	s->b0 = pc->b0, s->b1 = pc->b1;
	s->c0 = win.c0, s->cend = win.c1, s->P = win.c1 - win.c0;
	s->d0 = win.d0, s->dend = win.d1;
	state_rows(s, q);
	/* QEM-3D offsets stay within half a cell (fqmsolve(1)) */
	s->margin = L->displaced ? 0.5 + 1e-6 : EPS;
	s->scan = !L->displaced && s->step <= SCAN_MAXSTEP;
#if defined(__x86_64__) || defined(__i386__)
	/* TL_NO_AVX2 set: the plain copies (t_level compares the two) */
	s->avx2 = __builtin_cpu_supports("avx2") &&
	    getenv("TL_NO_AVX2") == NULL;
#endif
	s->ref = getenv("TL_EXACT_REF") != NULL;
	ring = (size_t)RINGV * s->P;
	s->z = tl_alloc(ring, sizeof *s->z, e);
	s->acc = tl_alloc((size_t)RINGE * s->P, sizeof *s->acc, e);
	s->nn = geo_row_nodes(L->m);
	if (L->displaced && s->nn > 1) {
		s->nk = tl_alloc(s->P, sizeof *s->nk, e);
		s->nu = tl_alloc(s->P, sizeof *s->nu, e);
	}
	s->sx = tl_alloc((size_t)RINGV * s->nn, sizeof *s->sx, e);
	s->sy = tl_alloc((size_t)RINGV * s->nn, sizeof *s->sy, e);
	if (q == NULL) /* a part saturates nothing */
		s->satband = tl_alloc((size_t)SAT_BAND * s->P,
		    sizeof *s->satband, e);
	if (d != NULL) {
		s->dz = tl_alloc(s->dend - s->d0, sizeof *s->dz, e);
		s->dv = tl_alloc(s->dend - s->d0, 1, e);
		s->dd = tl_alloc((size_t)BATCH * (s->dend - s->d0 + 1),
		    sizeof *s->dd, e);
	}
	if (L->displaced) {
		s->ox = tl_alloc(ring, sizeof *s->ox, e);
		s->oy = tl_alloc(ring, sizeof *s->oy, e);
	}
	if (!s->z || !s->acc || !s->sx || !s->sy ||
	    (q == NULL && !s->satband) ||
	    (L->displaced && s->nn > 1 && (!s->nk || !s->nu)) ||
	    (d != NULL && (!s->dz || !s->dv || !s->dd)) ||
	    (L->displaced && (!s->ox || !s->oy)) ||
	    shares_init(s, L->threads, e) < 0) {
		state_free(s);
		return -1;
	}
	if (s->nk != NULL)
		lv_node_columns(s);
	return 0;
}


/* How far past its blocks a piece's window reaches. Saturating a block
 * reads the local errors of its vertices' descendants: the farthest, 126
 * columns past the block's edge, is an edge(1) diamond down the chain
 * square(64) at the block's centre, edge(64) on its edge, square(32),
 * edge(32), ..., edge(1), and the vertices of that chain's diamonds
 * reach 127 columns past the edge (their triangles too; displaced, half
 * a column more). So 128 columns of heights and 128 x step of DEM
 * samples suffice, and 128 keeps the window's first column a multiple
 * of 128, so that saturation's parities are the level's. t_level checks
 * pieces against the whole level. */
#define HALO REACH

void
level_piece_window(const level_args *L, int w0, const level_piece *p,
    level_window *w)
{
	int Pl = pyramid_nblocks(L->size[0]) * BT_CELLS + 1;
	long S = 1L << L->level, c1;

	assert(p->b0 >= 0 && p->b0 < p->b1 &&
	    p->b1 <= pyramid_nblocks(L->size[0]));
	w->b0 = p->b0, w->b1 = p->b1;
	w->c0 = p->b0 * BT_CELLS - HALO;
	w->c0 = w->c0 > 0 ? w->c0 : 0;
	assert(w->c0 % (2 * BT_MAXH) == 0);
	c1 = (long)p->b1 * BT_CELLS + HALO + 1;
	w->c1 = c1 < Pl ? (int)c1 : Pl;
	w->d0 = (long)w->c0 * S;
	w->d1 = ((long)w->c1 - 1) * S + 1;
	w->d1 = w->d1 < w0 ? w->d1 : w0;
}

int
level_pieces(const level_args *L, int cols, level_piece *p, int max)
{
	int bx = pyramid_nblocks(L->size[0]), n = (bx + cols - 1) / cols;

	assert(cols >= 1);
	for (int k = 0; k < n && k < max; k++) {
		p[k].b0 = (int)((long)bx * k / n);
		p[k].b1 = (int)((long)bx * (k + 1) / n);
	}
	return n;
}

int
level_run(const level_args *L, dem *d, level_stats *st, tl_err *e)
{
	level_piece all = { 0, pyramid_nblocks(L->size[0]) };

	return level_run_piece(L, &all, d, st, e);
}

void
level_part_window(const level_args *L, const level_piece *p, int y0,
    int y1, level_part *q)
{
	int Q = pyramid_nblocks(L->size[1]) * BT_CELLS + 1;
	long S = 1L << L->level;

	assert(y0 >= 0 && y0 < y1);
	q->y0 = y0, q->y1 = y1;
	centres(L, p, &q->lo, &q->hi);
	/* a DEM row at level row y reaches centres y - 64 - margin ..
	 * y + 64 + margin (margin < 1), their vertices 64 rows further */
	q->g0 = (int)(y0 / S) - BT_MAXH - 1;
	q->g1 = (int)((y1 - 1) / S) + BT_MAXH + 2;
	q->g0 = q->g0 > 0 ? q->g0 : 0, q->g1 = q->g1 < Q ? q->g1 : Q;
	q->r0 = q->g0 - BT_MAXH, q->r1 = q->g1 + BT_MAXH;
	q->r0 = q->r0 > 0 ? q->r0 : 0, q->r1 = q->r1 < Q ? q->r1 : Q;
}


int
level_run_piece(const level_args *L, const level_piece *pc, dem *d,
    level_stats *st, tl_err *e)
{
	state s;
	int r;

	assert(L->threads <= LEVEL_MAXTHREADS);
	memset(st, 0, sizeof *st);
	if (state_init(&s, L, pc, dem_georef(d)->width, d, NULL, e) < 0)
		return -1;
	r = lv_run(&s, st, e);
	state_free(&s);
	return r;
}

int
level_run_part(const level_args *L, const level_piece *pc,
    const level_part *q, dem *d, level_err_fn out, void *ctx, double *base,
    level_stats *st, tl_err *e)
{
	size_t nb;
	state s;
	int r;

	assert(L->threads <= LEVEL_MAXTHREADS);
	assert(q->y1 <= dem_georef(d)->height);
	memset(st, 0, sizeof *st);
	if (state_init(&s, L, pc, dem_georef(d)->width, d, q, e) < 0)
		return -1;
	s.part = q, s.out = out, s.out_ctx = ctx;
	r = lv_run(&s, st, e);
	/* the shares' base errors, merged (a maximum: any order) */
	nb = (size_t)(s.b1 - s.b0) * s.by;
	for (size_t i = 0; r == 0 && i < nb; i++) {
		base[i] = 0;
		for (int k = 0; k < s.nshare; k++)
			base[i] = dmax(base[i], s.shares[k].base[i]);
	}
	state_free(&s);
	return r;
}

int
level_run_merged(const level_args *L, const level_piece *pc, int w0,
    level_err_fn in, void *ctx, const double *base, level_stats *st,
    tl_err *e)
{
	state s;
	int r;

	assert(L->threads <= LEVEL_MAXTHREADS);
	memset(st, 0, sizeof *st);
	if (state_init(&s, L, pc, w0, NULL, NULL, e) < 0)
		return -1;
	s.in = in, s.in_ctx = ctx;
	/* the parts' base errors, as the first share's */
	memcpy(s.shares[0].base, base, (size_t)(s.b1 - s.b0) * s.by *
	    sizeof *base);
	r = lv_run(&s, st, e);
	state_free(&s);
	return r;
}

