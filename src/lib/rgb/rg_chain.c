/* rg_chain.c - the quadric chain of one segment of zooms, in one pass
 * over its level-0 rows: each level-0 FQM row is solved and pushed into
 * level 1's filter, each row that filter gives is solved and pushed into
 * level 2's, and so on, so that every level streams (a window of rows
 * each, never a level) and every row reaches emit once. */
#include <assert.h>
#include <stdlib.h>

#include "rgb/rg_impl.h"
#include "qem/fqm0.h"
#include "qem/filter.h"
#include "qem/solve.h"

typedef struct {
	int nl;
	filter_state f[RG_SEG + 1];  /* f[l]: level l-1 into level l */
	solve_state s[RG_SEG + 1];
	fqm_vertex *row[RG_SEG + 1];
	solve_vertex *sv;
	double *h, *v;
	int next[RG_SEG + 1];        /* the next row of each level */
	int w[RG_SEG + 1];
	rg_emit emit;
	void *ctx;
} chain;

static int
push(chain *c, int l, tl_err *e)
{
	int r = c->next[l]++;

	solve_row(&c->s[l], c->row[l], c->sv);
	for (int i = 0; i < c->w[l]; i++)
		c->h[i] = c->sv[i].z, c->v[i] = c->sv[i].v;
	if (c->emit(c->ctx, l, r, c->h, c->v, c->w[l], e) < 0)
		return -1;
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
setup(chain *c, const georef *g, const geo_ground *m, enum solve_mode mode,
    tl_err *e)
{
	const filter_kernel *k = filter_find("binomial");
	int w0 = g->width, h0 = g->height;

	for (int l = 0; l < c->nl; l++) {
		int w = geo_level_size(w0, l), h = geo_level_size(h0, l);
		c->w[l] = w;
		if (l > 0 && filter_init(&c->f[l], k, l - 1,
		    geo_level_size(w0, l - 1), geo_level_size(h0, l - 1), w0,
		    h0, m, e) < 0)
			return -1;
		if (solve_init(&c->s[l], mode, l, w, h, m, e) < 0 ||
		    (c->row[l] = tl_alloc(w, sizeof *c->row[l], e)) == NULL)
			return -1;
	}
	if ((c->sv = tl_alloc(w0, sizeof *c->sv, e)) == NULL ||
	    (c->h = tl_alloc(w0, sizeof *c->h, e)) == NULL ||
	    (c->v = tl_alloc(w0, sizeof *c->v, e)) == NULL)
		return -1;
	return 0;
}

int
rg_chain(dem *d, int nl, enum solve_mode mode, rg_emit emit, void *ctx,
    tl_err *e)
{
	const georef *g = dem_georef(d);
	geo_ground m = { 0 };
	fqm0_state f0 = { 0 };
	chain c = { .nl = nl, .emit = emit, .ctx = ctx };
	int r = -1;

	assert(nl >= 1 && nl <= RG_SEG + 1);
	if (geo_ground_init(&m, g, e) < 0)
		return -1;
	if (setup(&c, g, &m, mode, e) == 0 && fqm0_init(&f0, d, &m, e) == 0) {
		r = 0;
		for (int y = 0; r == 0 && y < g->height; y++)
			if ((r = fqm0_row(&f0, y, c.row[0], e)) == 0)
				r = push(&c, 0, e);
	}
	for (int l = 0; l < nl; l++) {
		if (l > 0)
			filter_free(&c.f[l]);
		solve_free(&c.s[l]);
		free(c.row[l]);
	}
	free(c.sv), free(c.h), free(c.v);
	fqm0_free(&f0);
	geo_ground_free(&m);
	return r;
}
