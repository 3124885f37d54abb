/* qm_seam.c - same-level neighbours meet without a crack: along the edge
 * two tiles share (east with the next tile east, across the antimeridian
 * too; north with the next tile north), both have vertices at the same
 * places and, there, the same heights up to the two tiles' height
 * quantisation. A vertex on one side only is a T-junction: the surfaces
 * part there unless the other side's edge passes through it. */
#include "verify/qm.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
	int32_t at;   /* v along an east or west edge, u along north, south */
	double h, hi; /* metres: the lowest and highest vertex there (two
	               * vertices at one place are qm_tile_check's) */
} ev;

static int
cmpev(const void *a, const void *b)
{
	const ev *x = a, *y = b;

	if (x->at != y->at)
		return x->at < y->at ? -1 : 1;
	return x->h < y->h ? -1 : x->h > y->h;
}

static double
metres(const qm_tile *t, uint32_t i)
{
	double q = (double)t->h[i] / QM_MAXQ;

	return (1 - q) * t->hmin + q * (double)t->hmax;
}

/* The vertices of t on its side (QM_EAST ...), by place, each place once;
 * NULL when out of memory. */
static ev *
side(const qm_tile *t, int s, long *n)
{
	ev *e = malloc(((size_t)t->n + 1) * sizeof *e);
	long m = 0;

	if (e == NULL)
		return NULL;
	for (uint32_t i = 0; i < t->n; i++) {
		int32_t q = s == QM_WEST || s == QM_EAST ? t->u[i] : t->v[i];

		if (q != (s == QM_WEST || s == QM_SOUTH ? 0 : QM_MAXQ))
			continue;
		e[m].at = s == QM_WEST || s == QM_EAST ? t->v[i] : t->u[i];
		e[m].h = e[m].hi = metres(t, i);
		m++;
	}
	qsort(e, (size_t)m, sizeof *e, cmpev);
	*n = 0;
	for (long i = 0; i < m; i++)
		if (*n == 0 || e[i].at != e[*n - 1].at)
			e[(*n)++] = e[i];
		else
			e[*n - 1].hi = e[i].h;
	return e;
}

static void
meet(const qm_tile *a, const qm_tile *b, int s, int z, int x, int y,
    int bx, int by, qm_report *r)
{
	long na, nb, i = 0, j = 0;
	ev *ea = side(a, s, &na), *eb = side(b, s == QM_EAST ? QM_WEST :
	    QM_SOUTH, &nb);
	double tol = 0.5 * ((double)a->hmax - a->hmin) / QM_MAXQ +
	    0.5 * ((double)b->hmax - b->hmin) / QM_MAXQ + 1e-3;
	const char *dir = s == QM_EAST ? "east" : "north";

	if (ea == NULL || eb == NULL) {
		free(ea), free(eb);
		return;
	}
	while (i < na || j < nb) {
		if (j == nb || (i < na && ea[i].at < eb[j].at)) {
			qm_issue_add(r, QM_SEAM, z, x, y, "%s edge: a vertex at "
			    "%d that %d/%d/%d lacks (a T-junction)", dir,
			    ea[i].at, z, bx, by);
			break;
		}
		if (i == na || eb[j].at < ea[i].at) {
			qm_issue_add(r, QM_SEAM, z, x, y, "%s edge: %d/%d/%d "
			    "has a vertex at %d this tile lacks (a T-junction)",
			    dir, z, bx, by, eb[j].at);
			break;
		}
		if (ea[i].h - eb[j].hi > tol || eb[j].h - ea[i].hi > tol) {
			qm_issue_add(r, QM_SEAM, z, x, y, "%s edge at %d: "
			    "height %.4f m, %.4f m in %d/%d/%d (a crack "
			    "over the quantisation's %.4g m)", dir, ea[i].at,
			    ea[i].h, eb[j].h, z, bx, by, tol);
			break;
		}
		i++, j++;
	}
	free(ea), free(eb);
}

void
qm_seam_check(const char *dir, const qm_set *s, qm_report *r)
{
	char path[4096];

	for (long k = 0; k < s->n; k++) {
		int z = QM_KZ(s->key[k]), x = QM_KX(s->key[k]);
		int y = QM_KY(s->key[k]), nb[2][2];
		qm_tile a, b;
		tl_err e;

		nb[0][0] = (x + 1) % (2 << z), nb[0][1] = y; /* east */
		nb[1][0] = x, nb[1][1] = y + 1;               /* north */
		snprintf(path, sizeof path, "%s/%d/%d/%d.terrain", dir, z, x,
		    y);
		if (qm_read(path, &a, &e) < 0 || !qm_tile_sane(&a)) {
			qm_free(&a);
			continue;
		}
		for (int d = 0; d < 2; d++) {
			if (nb[d][1] >= (1 << z) || (nb[d][0] == x && d == 0) ||
			    !qm_set_has(s, QM_KEY(z, nb[d][0], nb[d][1])))
				continue;
			snprintf(path, sizeof path, "%s/%d/%d/%d.terrain", dir,
			    z, nb[d][0], nb[d][1]);
			if (qm_read(path, &b, &e) == 0 && qm_tile_sane(&b))
				meet(&a, &b, d ? QM_NORTH : QM_EAST, z, x, y,
				    nb[d][0], nb[d][1], r);
			qm_free(&b);
		}
		qm_free(&a);
	}
}
