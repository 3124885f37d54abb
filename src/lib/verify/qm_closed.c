/* qm_closed.c - whether the surface a tile's triangles draw is closed, for
 * both terrain profiles' checks (qm_tile.c, t3c_tile.c): vertices at one
 * place are one point; every edge inside the tile must belong to two
 * triangles running opposite ways, one on the tile's border to one. An
 * edge inside of one triangle is a crack (a T-junction, or two vertices
 * at one place with other heights); of three or more, or of two running
 * the same way, an overlap. */
#include <stdlib.h>
#include <string.h>

#include "verify/qm.h"

typedef struct {
	double k[3];
	uint32_t i;
} place;

static int
cmpplace(const void *a, const void *b)
{
	const place *p = a, *q = b;

	for (int k = 0; k < 3; k++)
		if (p->k[k] != q->k[k])
			return p->k[k] < q->k[k] ? -1 : 1;
	return p->i < q->i ? -1 : p->i > q->i;
}

typedef struct {
	uint32_t a, b; /* a < b: the edge's ends, one vertex per place */
	int dir;       /* 1 when the triangle runs a to b */
} edge;

static int
cmpedge(const void *x, const void *y)
{
	const edge *p = x, *q = y;

	if (p->a != q->a)
		return p->a < q->a ? -1 : 1;
	return p->b < q->b ? -1 : p->b > q->b;
}

/* Per vertex the first vertex at its place (the same key, bit for bit). */
static uint32_t *
places(const qm_closure_in *in)
{
	place *o = malloc(((size_t)in->n + 1) * sizeof *o);
	uint32_t *c = malloc(((size_t)in->n + 1) * sizeof *c);

	if (o == NULL || c == NULL) {
		free(o), free(c);
		return NULL;
	}
	for (uint32_t i = 0; i < in->n; i++) {
		memcpy(o[i].k, in->key + 3 * (size_t)i, sizeof o[i].k);
		o[i].i = i;
	}
	qsort(o, in->n, sizeof *o, cmpplace);
	for (uint32_t k = 0; k < in->n; k++)
		c[o[k].i] = k > 0 && !memcmp(o[k].k, o[k - 1].k,
		    sizeof o[k].k) ? c[o[k - 1].i] : o[k].i;
	free(o);
	return c;
}

static int
border(const double *uv, uint32_t a, uint32_t b)
{
	for (int k = 0; k < 2; k++)
		if ((uv[2 * a + k] == 0 && uv[2 * b + k] == 0) ||
		    (uv[2 * a + k] == QM_MAXQ && uv[2 * b + k] == QM_MAXQ))
			return 1;
	return 0;
}

/* The vertex at corner k, or -1 when none is named in range. */
static int64_t
corner(const qm_closure_in *in, size_t k)
{
	int64_t v = in->corner ? in->corner[k] : (int64_t)in->corner32[k];

	return v >= 0 && v < in->n ? v : -1;
}

int
qm_closed(const qm_closure_in *in, qm_closure *out)
{
	uint32_t *c = places(in);
	edge *e = malloc((in->ncorner + 1) * sizeof *e);
	size_t n = 0;

	memset(out, 0, sizeof *out);
	if (c == NULL || e == NULL) {
		free(c), free(e);
		return -1;
	}
	for (size_t k = 0; k < in->ncorner; k++) {
		int64_t p = corner(in, k);
		int64_t q = corner(in, k % 3 == 2 ? k - 2 : k + 1);

		if (p < 0 || q < 0 || c[p] == c[q] ||
		    (in->skip && (in->skip[p] || in->skip[q])))
			continue;
		e[n].dir = c[p] < c[q];
		e[n].a = e[n].dir ? c[p] : c[q], e[n].b = e[n].dir ? c[q] : c[p];
		n++;
	}
	qsort(e, n, sizeof *e, cmpedge);
	for (size_t i = 0, j; i < n; i = j) {
		for (j = i + 1; j < n && !cmpedge(&e[i], &e[j]); j++)
			;
		if (j - i == 1 && !border(in->uv, e[i].a, e[i].b) &&
		    !out->open++)
			out->open_edge[0] = e[i].a, out->open_edge[1] = e[i].b;
		if ((j - i > 2 || (j - i == 2 && e[i].dir == e[i + 1].dir)) &&
		    !out->over++)
			out->over_edge[0] = e[i].a, out->over_edge[1] = e[i].b;
	}
	free(c), free(e);
	return 0;
}
