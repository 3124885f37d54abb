/* tr_level.c - the export's unit (tr_export.h): a range of one level's
 * tiles at one try, on a pool of threads (each tile's bytes depend on
 * its level's choice alone, so any thread count writes the same files),
 * the level's choice of pyramid level and tau, its directories, and the
 * settling of a level's tries. The run in one process (tr_run.c) and a
 * plan's jobs (tr_plan.c) make the same units. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "terrain/tr_export.h"

static int
write_file(const char *path, const tr_work *w, tl_err *e)
{
	FILE *f = fopen(path, "wb");

	if (f == NULL)
		return tl_failsys(e, "%s", path);
	if (fwrite(w->buf, 1, w->nbuf, f) != w->nbuf) {
		fclose(f);
		return tl_failsys(e, "%s", path);
	}
	if (fclose(f) != 0)
		return tl_failsys(e, "%s", path);
	return 0;
}

/* Tile (x, y)'s distances d, or, while tiles are kept for one pass
 * (tr_batch), d 0 and the tile kept, measured at once past x->keep. */
static int
measure(tr_export *j, tr_work *w, int x, int y, double d[2], tl_err *e)
{
	tr_kept *k;
	int r;

	if (j->keep == 0)
		return tr_measure(w, j->c.z, x, y, d, e);
	d[0] = d[1] = 0;
	if (tr_keep(w, j->c.z, x, y, &k, e) < 0)
		return -1;
	if (k == NULL)
		return 0;
	if (w->kbytes + tr_kept_bytes(k) <= j->keep) {
		if (w->nkept == w->ckept) {
			int n = w->ckept ? 2 * w->ckept : 16;
			struct tr_keptz *p = realloc(w->kept, n * sizeof *p);
			if (p == NULL) {
				tr_kept_free(k);
				return tl_fail(e, "tile: out of memory");
			}
			w->kept = p, w->ckept = n;
		}
		w->kbytes += tr_kept_bytes(k);
		w->kept[w->nkept].k = k, w->kept[w->nkept++].z = j->c.z;
		return 0;
	}
	r = tr_kept_walk(w, k, d, e);
	tr_kept_free(k);
	return r;
}

static int
one_tile(tr_export *j, tr_work *w, int x, int y, tl_err *e)
{
	char path[4096];
	float lo, hi;
	double d[2];

	if (tr_mesh_tile(w, &j->c, x, y, e) < 0 ||
	    tr_quantise(w, j->c.z, x, y, &lo, &hi, e) < 0 ||
	    measure(j, w, x, y, d, e) < 0 ||
	    (j->t3 ? t3t_glb(w, j->t3, j->c.z, x, y, lo, hi, e) :
	    qm_encode(w, lo, hi, j->a->gzip, e)) < 0)
		return -1;
	w->err = fmax(w->err, d[0]), w->direct = fmax(w->direct, d[1]);
	w->tiles++, w->tris += w->m.nt, w->bytes += (long long)w->nbuf;
	snprintf(path, sizeof path, "%s/%d/%d/%d.terrain", j->tmp, j->c.z, x,
	    y);
	if (j->t3)
		t3t_path(path, sizeof path, j->tmp, j->c.z, x, y);
	return write_file(path, w, e);
}

static void
run_range(void *arg, int k, int i0, int i1)
{
	tr_export *j = arg;

	for (int i = i0; i < i1 && !j->failed[k]; i++) {
		int x, y;
		/* whole rows: in strips (tr_tile_at), else row by row */
		if (j->ny > 0) {
			tr_tile_at(j->w[k].g, j->c.z, j->nx, j->ny, i, &x, &y);
			y += j->i0 / j->nx;
		} else
			x = (j->i0 + i) % j->nx, y = (j->i0 + i) / j->nx;
		if (one_tile(j, &j->w[k], j->x0 + x, j->y0 + y, &j->err[k]) < 0)
			j->failed[k] = 1;
	}
}

/* The pyramid level for tolerance tau: the coarsest undisplaced one
 * whose finest triangles are within tau of the DEM everywhere. */
static int
pick_level(const pyramid_index *ix, double tau, double *base)
{
	int p = 0;

	*base = 0;

	for (int l = 1; l < ix->nlevels; l++) {
		const pyramid_level *L = &ix->lev[l];
		double b = 0;
		if (L->displaced)
			continue;
		for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++)
			b = fmax(b, L->base[k]);
		if (b <= tau)
			p = l, *base = b;
	}
	return p;
}

/* Attempt t's choice for level z: tolerance E_L / 2^(t+1), cells small
 * enough that a flat chord across one sags E_L / 8 at most, halved
 * every second attempt; the last, the whole of level 0. */
void
tr_choose(const pyramid_index *ix, int z, int t, tr_choice *c)
{
	double el = ldexp(TR_E0, -z), wm = ldexp(180, -z) * 111320.0;
	int n = 1;

	while (wm / n > sqrt(TR_RMIN * el / 2) && n < 1024)
		n *= 2;
	c->z = z, c->el = el, c->tau = ldexp(el, -(t + 1));
	c->n = n << (t / 2) > 4096 ? 4096 : n << (t / 2);
	c->p = pick_level(ix, c->tau, &c->base);
	/* the last try: every vertex of level 0, so that no sample the
	 * saturated errors leave out (voids the pyramid filled) is missed */
	if (t == TR_TRIES - 1)
		c->tau = -1, c->p = 0, c->base = 0;
}

static int
mk(const char *p, tl_err *e)
{
	if (mkdir(p, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", p);
	return 0;
}

int
tr_dirs(const tr_export *x, const char *tmp, int z, tl_err *e)
{
	const int *av = x->av[z];
	char p[4096];

	if (x->t3)
		return t3t_dirs(tmp, z, av, e);
	snprintf(p, sizeof p, "%s/%d", tmp, z);
	if (mk(p, e) < 0)
		return -1;
	for (int i = av[0]; i <= av[2]; i++) {
		snprintf(p, sizeof p, "%s/%d/%d", tmp, z, i);
		if (mk(p, e) < 0)
			return -1;
	}
	return 0;
}

long long
tr_count(const tr_export *x, int z)
{
	const int *av = x->av[z];

	return (long long)(av[2] - av[0] + 1) * (av[3] - av[1] + 1);
}

int
tr_try(tr_export *x, const char *tmp, int z, int i0, int i1, int t,
    tr_part *p, tl_err *e)
{
	memset(p, 0, sizeof *p);
	tr_choose(&x->ix, z, t, &x->c);
	x->tmp = tmp, x->i0 = i0;
	x->x0 = x->av[z][0], x->y0 = x->av[z][1];
	x->nx = x->av[z][2] - x->av[z][0] + 1;
	x->ny = i0 % x->nx == 0 && i1 % x->nx == 0 ? (i1 - i0) / x->nx : 0;
	for (int k = 0; k < x->nt; k++)
		x->w[k].err = x->w[k].direct = 0,
		x->w[k].tiles = x->w[k].tris = x->w[k].bytes = 0;
	tl_pool_for(x->pool, i1 - i0, run_range, x);
	for (int k = 0; k < x->nt; k++)
		if (x->failed[k]) {
			*e = x->err[k];
			return -1;
		}
	for (int k = 0; k < x->nt; k++) {
		p->err = fmax(p->err, x->w[k].err);
		p->direct = fmax(p->direct, x->w[k].direct);
		p->tiles += x->w[k].tiles;
		p->tris += x->w[k].tris;
		p->bytes += x->w[k].bytes;
	}
	/* the selection within max(tau, base) of the valid samples
	 * (vgis(5)), the drawn surface within err of the selection */
	p->t = t;
	p->held = fmax(x->c.tau, x->c.base) + p->err <= x->c.el;
	return 0;
}

int
tr_settle(tr_export *x, const char *tmp, int z, int i0, int i1, int from,
    tr_part *p, tl_err *e)
{
	for (int t = from; t < TR_TRIES; t++)
		if (tr_try(x, tmp, z, i0, i1, t, p, e) < 0)
			return -1;
		else if (p->held)
			return 0;
	return tl_fail(e, "level %d: the bound %.3f m passes E_L = %.3f m "
	    "after %d refinements: not written", z, fmax(x->c.tau,
	    x->c.base) + p->err, x->c.el, TR_TRIES);
}

void
tr_report_level(const tr_export *x, int z, const tr_part *p,
    tr_report *rep)
{
	tr_choice c;

	tr_choose(&x->ix, z, p->t, &c);
	rep->tiles[z] = p->tiles, rep->tris[z] = p->tris;
	rep->bytes[z] = p->bytes;
	rep->err[z] = fmax(c.tau, c.base) + p->err;
	rep->direct[z] = p->direct, rep->plevel[z] = c.p;
	rep->tau[z] = c.tau, rep->tries[z] = p->t + 1;
}
