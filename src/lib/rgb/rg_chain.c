/* rg_chain.c - the quadric chain of one segment of zooms, in one pass
 * over its level-0 rows: each level-0 FQM row is solved and pushed into
 * level 1's filter, each row that filter gives is solved and pushed into
 * level 2's, and so on, so that every level streams (a window of rows
 * each, never a level) and every row reaches emit once; with each level
 * row after the first, the zoom's row of pixel centres above it
 * (rg_centre.c: a level holds two rows more). A window of the level-0
 * columns (a plan's part, rg_split.c) runs on those columns alone, the
 * metric and the filters told where it lies, so that its columns far
 * enough from its edges come out as the whole grid's. */
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "rgb/rg_impl.h"
#include "qem/fqm0.h"
#include "qem/filter.h"
#include "qem/solve.h"

typedef struct {
	int nl, l0;
	enum solve_mode mode;
	const geo_ground *m;
	filter_state f[RG_SEG + 1];  /* f[l]: level l-1 into level l */
	solve_state s[RG_SEG + 1];
	fqm_vertex *row[RG_SEG + 1];
	fqm_vertex *prev[RG_SEG + 1]; /* the level's previous row */
	solve_vertex *sv, *sprev[RG_SEG + 1];
	double *h, *v;
	int next[RG_SEG + 1];        /* the next row of each level */
	int w[RG_SEG + 1], hl[RG_SEG + 1];
	rg_emit emit;
	void *ctx;
} chain;

/* The centre row between level l's rows j (held) and jb (its current
 * row: j + 1, or j itself at the last row). */
static int
centres(chain *c, int l, int j, int jb, const fqm_vertex *a,
    const fqm_vertex *b, const solve_vertex *sa, const solve_vertex *sb,
    tl_err *e)
{
	rg_centre_in in = { c->m, c->mode, l, j, jb, c->w[l],
	    rg_centre_frac(c->l0 + l), a, b, sa, sb };

	rg_centre_row(&in, c->h, c->v);
	return c->emit(c->ctx, l, j, c->h, c->v, c->w[l], 1, e);
}

static int
push(chain *c, int l, tl_err *e)
{
	int r = c->next[l]++, w = c->w[l];

	solve_row(&c->s[l], c->row[l], c->sv);
	for (int i = 0; i < w; i++)
		c->h[i] = c->sv[i].z, c->v[i] = c->sv[i].v;
	if (c->emit(c->ctx, l, r, c->h, c->v, w, 0, e) < 0)
		return -1;
	if (c->l0 + l == 0) { /* the deepest zoom: its centres */
		if (c->emit(c->ctx, l, r, c->h, c->v, w, 1, e) < 0)
			return -1;
	} else {
		if (r > 0 && centres(c, l, r - 1, r, c->prev[l], c->row[l],
		    c->sprev[l], c->sv, e) < 0)
			return -1;
		if (r == c->hl[l] - 1 && centres(c, l, r, r, c->row[l],
		    c->row[l], c->sv, c->sv, e) < 0)
			return -1;
		memcpy(c->prev[l], c->row[l], (size_t)w * sizeof *c->row[l]);
		memcpy(c->sprev[l], c->sv, (size_t)w * sizeof *c->sv);
	}
	if (l + 1 >= c->nl)
		return 0;
	filter_push(&c->f[l + 1], c->row[l]);
	while (filter_ready(&c->f[l + 1])) {
		filter_pull(&c->f[l + 1], c->row[l + 1]);
		if (push(c, l + 1, e) < 0)
			return -1;
	}
	return 0;
}

static int
setup(chain *c, const georef *g, int x0, int w0, const geo_ground *m,
    enum solve_mode mode, tl_err *e)
{
	const filter_kernel *k = filter_find("binomial");
	int h0 = g->height;

	for (int l = 0; l < c->nl; l++) {
		int w = geo_level_size(w0, l), h = geo_level_size(h0, l);
		c->w[l] = w, c->hl[l] = h;
		if (l > 0 && filter_init(&c->f[l], k, l - 1,
		    geo_level_size(w0, l - 1), geo_level_size(h0, l - 1),
		    g->width, h0, m, e) < 0)
			return -1;
		if (l > 0) /* the window's column 0 on level l - 1 */
			c->f[l].x0 = x0 >> (l - 1);
		if (solve_init(&c->s[l], mode, l, w, h, m, e) < 0 ||
		    (c->row[l] = tl_alloc(w, sizeof *c->row[l], e)) == NULL ||
		    (c->prev[l] = tl_alloc(w, sizeof *c->prev[l], e)) == NULL ||
		    (c->sprev[l] = tl_alloc(w, sizeof *c->sprev[l], e)) == NULL)
			return -1;
	}
	if ((c->sv = tl_alloc(w0, sizeof *c->sv, e)) == NULL ||
	    (c->h = tl_alloc(w0, sizeof *c->h, e)) == NULL ||
	    (c->v = tl_alloc(w0, sizeof *c->v, e)) == NULL)
		return -1;
	return 0;
}

int
rg_chain(dem *d, int x0, int n, int nl, int l0, enum solve_mode mode,
    rg_emit emit, void *ctx, tl_err *e)
{
	const georef *g = dem_georef(d);
	geo_ground m = { 0 };
	fqm0_state f0 = { 0 };
	chain c = { .nl = nl, .l0 = l0, .mode = mode, .m = &m, .emit = emit,
	    .ctx = ctx };
	int r = -1;

	assert(nl >= 1 && nl <= RG_SEG + 1);
	assert(x0 % (1 << (nl - 1)) == 0 && x0 >= 0 && x0 + n <= g->width);
	if (geo_ground_init(&m, g, e) < 0)
		return -1;
	m.x0 = x0; /* the metric answers in the window's columns */
	if (setup(&c, g, x0, n, &m, mode, e) == 0 &&
	    fqm0_init_cols(&f0, d, &m, x0, n, e) == 0) {
		r = 0;
		for (int y = 0; r == 0 && y < g->height; y++)
			if ((r = fqm0_row(&f0, y, c.row[0], e)) == 0)
				r = push(&c, 0, e);
	}
	for (int l = 0; l < nl; l++) {
		if (l > 0)
			filter_free(&c.f[l]);
		solve_free(&c.s[l]);
		free(c.row[l]), free(c.prev[l]), free(c.sprev[l]);
	}
	free(c.sv), free(c.h), free(c.v);
	fqm0_free(&f0);
	geo_ground_free(&m);
	return r;
}
