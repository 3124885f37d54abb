/* t3c_seam.c - same-level neighbours of the 3D Tiles terrain profile
 * meet without a crack: along the edge two tiles share (east, across the
 * antimeridian and between the two roots too; north), the same vertices
 * at the same places (1/100 of a 0..32767 step) and there the same
 * heights up to each tile's height quantisation (half a step of its
 * TILE_* height range, what quantized-mesh allows) and the positions'
 * rounding, + 1 mm. Vertices at a pole, whose longitude is lost, are
 * left out. */
#include "verify/t3c.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
	double at, h;
} ev;

typedef struct {
	t3c_tile t;
	double *uv, *h;
	unsigned char *pole;
	const t3c_meta *m;
} placed;

static int
cmpev(const void *a, const void *b)
{
	const ev *x = a, *y = b;

	return x->at < y->at ? -1 : x->at > y->at;
}

static void
unplace(placed *p)
{
	t3c_free(&p->t);
	free(p->uv), free(p->h), free(p->pole);
	memset(p, 0, sizeof *p);
}

/* Tile k decoded, placed, its vertices inside its rectangle. */
static int
place(const char *dir, const t3c_set *T, qm_key k, placed *p)
{
	char path[4096];
	tl_err e;
	size_t n;

	memset(p, 0, sizeof *p);
	t3c_path(dir, T, QM_KZ(k), QM_KX(k), QM_KY(k), path, sizeof path);
	if ((p->m = t3c_set_meta(T, k)) == NULL ||
	    t3c_read(path, &p->t, &e) < 0)
		return -1;
	n = p->t.n;
	p->uv = malloc((2 * n + 1) * sizeof *p->uv);
	p->h = malloc((n + 1) * sizeof *p->h);
	p->pole = malloc(n + 1);
	if (p->uv == NULL || p->h == NULL || p->pole == NULL)
		return -1;
	t3c_place(&p->t, QM_KZ(k), QM_KX(k), QM_KY(k), p->uv, p->h, p->pole);
	for (size_t i = 0; i < 2 * n; i++)
		if (p->uv[i] < 0 || p->uv[i] > QM_MAXQ)
			return -1;
	return 0;
}

/* The vertices of p on side s, by place along it. */
static ev *
side(const placed *p, int s, long *n)
{
	ev *e = malloc(((size_t)p->t.n + 1) * sizeof *e);
	int across = s == QM_WEST || s == QM_EAST ? 0 : 1;
	double want = s == QM_WEST || s == QM_SOUTH ? 0 : QM_MAXQ;

	*n = 0;
	if (e == NULL)
		return NULL;
	for (uint32_t i = 0; i < p->t.n; i++)
		if (p->uv[2 * i + across] == want && !p->pole[i]) {
			e[*n].at = p->uv[2 * i + !across];
			e[(*n)++].h = p->h[i];
		}
	qsort(e, (size_t)*n, sizeof *e, cmpev);
	return e;
}

static void
meet(const placed *a, const placed *b, int s, qm_key ka, qm_key kb,
    qm_report *r)
{
	long na, nb, i = 0, j = 0;
	ev *ea = side(a, s, &na), *eb = side(b, s == QM_EAST ? QM_WEST :
	    QM_SOUTH, &nb);
	double tol = 0.5 * (a->m->hmax - a->m->hmin) / QM_MAXQ +
	    0.5 * (b->m->hmax - b->m->hmin) / QM_MAXQ + a->t.noise +
	    b->t.noise + 1e-3;
	int z = QM_KZ(ka), x = QM_KX(ka), y = QM_KY(ka);
	const char *dir = s == QM_EAST ? "east" : "north";

	if (ea == NULL || eb == NULL)
		goto done;
	for (; i < na || j < nb; i++, j++) {
		if (i == na || j == nb || fabs(ea[i].at - eb[j].at) > 0.01) {
			qm_issue_add(r, QM_SEAM, z, x, y, "%s edge: %ld "
			    "vertices, %ld in its neighbour %d/%d/%d; first "
			    "apart at %.2f (a T-junction)", dir, na, nb, z,
			    QM_KX(kb), QM_KY(kb), i < na ? ea[i].at :
			    eb[j].at);
			break;
		}
		if (fabs(ea[i].h - eb[j].h) > tol) {
			qm_issue_add(r, QM_SEAM, z, x, y, "%s edge at %.2f: "
			    "height %.4f m, %.4f m in its neighbour %d/%d/%d "
			    "(a crack over the quantisation's %.4g m)", dir,
			    ea[i].at, ea[i].h, eb[j].h, z, QM_KX(kb),
			    QM_KY(kb), tol);
			break;
		}
	}
done:
	free(ea), free(eb);
}

void
t3c_seam_check(const char *dir, const t3c_set *T, qm_report *r)
{
	const qm_set *s = &T->s;

	for (long k = 0; k < s->n; k++) {
		int z = QM_KZ(s->key[k]), x = QM_KX(s->key[k]);
		int y = QM_KY(s->key[k]);
		qm_key nb[2];
		placed a, b;

		nb[0] = QM_KEY(z, (x + 1) % (2 << z), y);
		nb[1] = QM_KEY(z, x, y + 1);
		if (place(dir, T, s->key[k], &a) < 0) {
			unplace(&a);
			continue;
		}
		for (int d = 0; d < 2; d++) {
			if ((d == 1 && y + 1 >= (1 << z)) || nb[d] == s->key[k]
			    || !qm_set_has(s, nb[d]))
				continue;
			if (place(dir, T, nb[d], &b) == 0)
				meet(&a, &b, d ? QM_NORTH : QM_EAST, s->key[k],
				    nb[d], r);
			unplace(&b);
		}
		unplace(&a);
	}
}
