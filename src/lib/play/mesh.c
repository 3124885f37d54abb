/* mesh.c - block geometry, selections and skirts (see mesh.h). */
#include "play/mesh.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Index of the skirt floor under border vertex (c, r), side by side:
 * top (r 0), bottom (r 128), left (c 0), right (c 128). */
static uint32_t
floor_of(int side, int t)
{
	assert(side >= 0 && side < 4 && t >= 0 && t < MESH_SIDE);
	return (uint32_t)(PYRAMID_N + side * MESH_SIDE + t);
}

/* Positions relative to the block's centre, heights and errors. */
static void
place(const world *w, const pyramid_block *b, mesh_verts *v)
{
	double s = (double)(1L << b->level), p[3];

	world_pos(w, (b->bi * BT_CELLS + BT_CELLS / 2) * s,
	    (b->bj * BT_CELLS + BT_CELLS / 2) * s, 0, 0, 0, v->origin);
	for (int r = 0; r < BT_SIZE; r++)
		for (int c = 0; c < BT_SIZE; c++) {
			int k = r * BT_SIZE + c;
			double X = b->displaced ? b->x[k] : 0;
			double Y = b->displaced ? b->y[k] : 0;
			/* border vertices stay on the border line */
			if (c == 0 || c == BT_CELLS)
				X = 0;
			if (r == 0 || r == BT_CELLS)
				Y = 0;
			world_pos(w, (b->bi * BT_CELLS + c) * s,
			    (b->bj * BT_CELLS + r) * s, X, Y, b->z[k], p);
			for (int a = 0; a < 3; a++)
				v->pos[3 * k + a] = (float)(p[a] - v->origin[a]);
			v->val[2 * k] = b->z[k];
			v->val[2 * k + 1] = b->e[k];
		}
}

/* Normals: central differences of the full grid (one-sided at the
 * edges), so coarse selections still shade with every detail. */
static void
normals(mesh_verts *v)
{
	for (int r = 0; r < BT_SIZE; r++)
		for (int c = 0; c < BT_SIZE; c++) {
			int c0 = c > 0 ? c - 1 : c, c1 = c < BT_CELLS ? c + 1 : c;
			int r0 = r > 0 ? r - 1 : r, r1 = r < BT_CELLS ? r + 1 : r;
			const float *a = &v->pos[3 * (r * BT_SIZE + c0)];
			const float *bb = &v->pos[3 * (r * BT_SIZE + c1)];
			const float *d = &v->pos[3 * (r0 * BT_SIZE + c)];
			const float *u = &v->pos[3 * (r1 * BT_SIZE + c)];
			double tx[3], ty[3], n[3], len;
			for (int q = 0; q < 3; q++)
				tx[q] = bb[q] - a[q], ty[q] = d[q] - u[q];
			n[0] = tx[1] * ty[2] - tx[2] * ty[1];
			n[1] = tx[2] * ty[0] - tx[0] * ty[2];
			n[2] = tx[0] * ty[1] - tx[1] * ty[0];
			len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
			for (int q = 0; q < 3; q++)
				v->nrm[3 * (r * BT_SIZE + c) + q] =
				    (float)(len > 0 ? n[q] / len : q == 2);
		}
}

/* Skirt floors: under each border vertex, at the world's floor, shaded
 * as the vertex above. */
static void
floors(const world *w, mesh_verts *v)
{
	for (int side = 0; side < 4; side++)
		for (int t = 0; t < BT_SIZE; t++) {
			int c = side < 2 ? t : side == 2 ? 0 : BT_CELLS;
			int r = side >= 2 ? t : side == 0 ? 0 : BT_CELLS;
			int k = r * BT_SIZE + c, f = (int)floor_of(side, t);
			memcpy(&v->pos[3 * f], &v->pos[3 * k], 3 * sizeof(float));
			v->pos[3 * f + 2] = (float)(w->base - v->origin[2]);
			memcpy(&v->nrm[3 * f], &v->nrm[3 * k], 3 * sizeof(float));
			v->val[2 * f] = v->val[2 * k];
			v->val[2 * f + 1] = v->val[2 * k + 1];
		}
}

int
mesh_verts_build(const world *w, const pyramid_block *b, mesh_verts *v,
    tl_err *e)
{
	memset(v, 0, sizeof *v);
	v->pos = tl_alloc(MESH_NV * 3, sizeof *v->pos, e);
	v->nrm = tl_alloc(MESH_NV * 3, sizeof *v->nrm, e);
	v->val = tl_alloc(MESH_NV * 2, sizeof *v->val, e);
	if (!v->pos || !v->nrm || !v->val) {
		mesh_verts_free(v);
		return -1;
	}
	place(w, b, v);
	normals(v);
	floors(w, v);
	return 0;
}

void
mesh_verts_free(mesh_verts *v)
{
	free(v->pos), free(v->nrm), free(v->val);
	v->pos = v->nrm = v->val = NULL;
}

typedef struct {
	const pyramid_block *b;
	double tau;
	int skirts;
	mesh_tris *t;
	int failed;
} sel;

static int
push(mesh_tris *t, uint32_t a, uint32_t b, uint32_t c)
{
	if (t->n + 3 > t->cap) {
		size_t cap = t->cap ? 2 * t->cap : 3 * 4096;
		uint32_t *p = realloc(t->idx, cap * sizeof *p);
		if (p == NULL)
			return -1;
		t->idx = p, t->cap = cap;
	}
	t->idx[t->n++] = a, t->idx[t->n++] = b, t->idx[t->n++] = c;
	return 0;
}

static int
split(void *ctx, int c, int r)
{
	const sel *s = ctx;

	return s->tau < 0 || s->b->e[r * BT_SIZE + c] > s->tau;
}

/* The side both ends of an edge lie on, or -1. */
static int
side_of(const int a[2], const int b[2])
{
	if (a[1] == 0 && b[1] == 0)
		return 0;
	if (a[1] == BT_CELLS && b[1] == BT_CELLS)
		return 1;
	if (a[0] == 0 && b[0] == 0)
		return 2;
	if (a[0] == BT_CELLS && b[0] == BT_CELLS)
		return 3;
	return -1;
}

static void
emit(void *ctx, const int t[3][2])
{
	sel *s = ctx;
	uint32_t k[3];

	for (int q = 0; q < 3; q++)
		k[q] = (uint32_t)(t[q][1] * BT_SIZE + t[q][0]);
	if (push(s->t, k[0], k[1], k[2]) < 0)
		s->failed = 1;
	s->t->tris++;
	for (int q = 0; s->skirts && q < 3; q++) {
		const int *a = t[q], *b = t[(q + 1) % 3];
		int side = side_of(a, b), ta, tb;
		if (side < 0)
			continue;
		ta = side < 2 ? a[0] : a[1], tb = side < 2 ? b[0] : b[1];
		if (push(s->t, k[q], k[(q + 1) % 3], floor_of(side, tb)) < 0 ||
		    push(s->t, k[q], floor_of(side, tb), floor_of(side, ta)) < 0)
			s->failed = 1;
		s->t->skirts += 2;
	}
}

int
mesh_tris_build(const pyramid_block *b, double tau, int skirts, mesh_tris *t,
    tl_err *e)
{
	sel s = { b, tau, skirts, t, 0 };

	t->n = 0, t->tris = 0, t->skirts = 0;
	/* block-local coordinates: the bintree is the same in every block */
	bt_select(0, 0, split, &s, emit, &s);
	if (s.failed)
		return tl_fail(e, "block %d/%d_%d: out of memory for its "
		    "triangles", b->level, b->bj, b->bi);
	return 0;
}

void
mesh_tris_free(mesh_tris *t)
{
	free(t->idx);
	t->idx = NULL;
	t->n = t->cap = 0;
}
