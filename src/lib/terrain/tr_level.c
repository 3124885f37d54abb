/* tr_level.c - the export's unit (tr_export.h): a range of one level's
 * tiles at one try, on a pool of threads (each tile's bytes depend on
 * its level's choice alone, so any thread count writes the same files),
 * the level's choice of pyramid level and tau, its directories, and the
 * settling of a level's tries. The run in one process (tr_run.c) and a
 * plan's jobs (tr_plan.c) make the same units. */
#include <assert.h>
#include <errno.h>
#include <limits.h>
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

/* The switch VGIS2TERRAIN_MEASURE=all: every tile measured, each of
 * its samples checked against its triangle's bound (tr_bound). */
static int
measure_all(void)
{
	const char *s = getenv("VGIS2TERRAIN_MEASURE");

	return s && strcmp(s, "all") == 0;
}

/* Tile (x, y) kept and measured against its triangles' bounds. */
static int
measure_checked(tr_work *w, int z, int x, int y, float lo, float hi,
    double d[2], tl_err *e)
{
	double *b = malloc((size_t)(w->m.nt ? w->m.nt : 1) * sizeof *b);
	tr_kept *k = NULL;
	int r = -1;

	double band;

	d[0] = d[1] = 0;
	if (b == NULL)
		return tl_fail(e, "tile: out of memory");
	tr_bound(w, z, x, y, lo, hi, INFINITY, b, &band);
	if (tr_keep(w, z, x, y, &k, e) == 0)
		r = k == NULL ? 0 : tr_kept_check(k, b, w->m.nt, band, e) < 0 ?
		    -1 : tr_kept_walk(w, k, d, e);
	tr_kept_free(k), free(b);
	return r;
}

/* Tile (x, y)'s distances d, or, while tiles are kept for one pass
 * (tr_batch), d 0 and the tile kept, measured at once past x->keep.
 * Where the tile's bound (tr_bound) fits c's budget, E_L - max(tau,
 * base), the tile is not measured: d[0] is the bound, d[1] 0, and the
 * level holds or not as the measure would have it (its d[0] is within
 * the bound); *m 0. A projected tile's samples that the bound leaves
 * out (those its triangles past the footprint or in the band may draw,
 * near the grid's sides) are measured: d the larger of both. */
static int
measure(tr_export *j, tr_work *w, const tr_choice *c, int x, int y,
    float lo, float hi, double d[2], int *m, tl_err *e)
{
	int z = c->z, r;
	double band;
	tr_kept *k;

	*m = 1;
	if (measure_all())
		return measure_checked(w, z, x, y, lo, hi, d, e);
	d[0] = tr_bound(w, z, x, y, lo, hi, c->el - fmax(c->tau, c->base),
	    NULL, &band), d[1] = 0;
	if (fmax(c->tau, c->base) + d[0] <= c->el) {
		double dm[2];
		*m = 0;
		if (band < 0)
			return 0;
		if (j->keep == 0) {
			if (tr_measure_band(w, z, x, y, band, dm, e) < 0)
				return -1;
			d[0] = fmax(d[0], dm[0]), d[1] = dm[1];
			return 0;
		}
	} else
		band = INFINITY;
	if (j->keep == 0)
		return tr_measure(w, z, x, y, d, e);
	if (band == INFINITY)
		d[0] = d[1] = 0; /* else the bound, the band's added later */
	if (tr_keep(w, z, x, y, &k, e) < 0)
		return -1;
	if (k == NULL)
		return 0;
	tr_kept_band(k, band);
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
		w->kept[w->nkept].k = k, w->kept[w->nkept++].z = z;
		return 0;
	}
	r = tr_kept_walk(w, k, d, e);
	tr_kept_free(k);
	return r;
}

/* Tile (x, y) of level c->z at c's try. */
static int
one_tile(tr_export *j, const tr_choice *c, tr_work *w, int x, int y,
    tl_err *e)
{
	char path[4096];
	float lo, hi;
	double d[2];
	int m;

	if (tr_mesh_tile(w, c, x, y, e) < 0 ||
	    tr_quantise(w, c->z, x, y, &lo, &hi, e) < 0 ||
	    measure(j, w, c, x, y, lo, hi, d, &m, e) < 0 ||
	    (j->t3 ? t3t_glb(w, j->t3, c->z, x, y, lo, hi, e) :
	    qm_encode(w, lo, hi, j->a->gzip, e)) < 0)
		return -1;
	w->err = fmax(w->err, d[0]), w->direct = fmax(w->direct, d[1]);
	w->nsamp += tr_tile_samples(w->g, c->z, x, y);
	w->nmeas += m ? tr_tile_samples(w->g, c->z, x, y) : 0;
	w->tiles++, w->tris += w->m.nt, w->bytes += (long long)w->nbuf;
	snprintf(path, sizeof path, "%s/%d/%d/%d.terrain", j->tmp, c->z, x,
	    y);
	if (j->t3)
		t3t_path(path, sizeof path, j->tmp, c->z, x, y);
	return write_file(path, w, e);
}

int
tr_take(tr_export *x, int n, int chunk, int *i0, int *i1)
{
	int c = __atomic_fetch_add(&x->next, 1, __ATOMIC_RELAXED);

	if ((long long)c * chunk >= n)
		return 0;
	*i0 = c * chunk, *i1 = n - *i0 < chunk ? n : *i0 + chunk;
	return 1;
}

static void
run_range(void *arg, int k, int r0, int r1)
{
	tr_export *j = arg;
	/* about 8 chunks a thread, each a run of neighbouring tiles (their
	 * blocks shared through the thread's cache) */
	int n = j->count, chunk = n / (8 * j->nt), i0, i1;

	(void)r0, (void)r1;
	while (!j->failed[k] && tr_take(j, n, chunk > 0 ? chunk : 1, &i0, &i1))
		for (int i = i0; i < i1 && !j->failed[k]; i++) {
			int x, y;
			/* whole rows: in strips (tr_tile_at), else row by row */
			if (j->ny > 0) {
				tr_tile_at(j->w[k].g, j->c.z, j->nx, j->ny, i, &x,
				    &y);
				y += j->i0 / j->nx;
			} else
				x = (j->i0 + i) % j->nx, y = (j->i0 + i) / j->nx;
			if (one_tile(j, &j->c, &j->w[k], j->x0 + x, j->y0 + y,
			    &j->err[k]) < 0)
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
		x->w[k].nsamp = x->w[k].nmeas = 0,
		x->w[k].tiles = x->w[k].tris = x->w[k].bytes = 0;
	x->count = i1 - i0, x->next = 0;
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
		p->nsamp += x->w[k].nsamp, p->nmeas += x->w[k].nmeas;
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
	rep->measured[z] = p->nsamp > 0 ? (double)p->nmeas / p->nsamp : -1;
	rep->tau[z] = c.tau, rep->tries[z] = p->t + 1;
}

/* --- the deep levels in one sweep (tr_sweep) ----------------------- */

/* Levels g .. x->maxz at try 0, tile (z, x, y) with its ancestor
 * (x, y) >> (z - g) at level g: the ancestors' rows from the south,
 * every second one east to west, and each ancestor's tiles level by
 * level, row by row. An ancestor's blocks fit the thread's cache
 * (tr_sweep_level), so its tiles of every level read each of them once
 * and the next ancestor finds the blocks they share still cached. */
typedef struct {
	tr_export *x;
	int g, nx;              /* first level; ancestors in a row */
	int d;                  /* tiles an ancestor spans, all levels */
	tr_choice c[TR_MAXZ + 1];
	tr_part *p;             /* per thread, per level */
} sweep;

/* Place i of the sweep: 1 and its tile, or 0 where the ancestor's
 * square of level z reaches past av[z]. */
static int
sweep_tile(const sweep *s, int i, int *z, int *x, int *y)
{
	const int (*av)[4] = (const int (*)[4])s->x->av;
	int a = i / s->d, l = i % s->d, row = a / s->nx, col = a % s->nx;
	int k = 0, n = 1;

	if (row % 2)
		col = s->nx - 1 - col;
	while (l >= n)
		l -= n, n *= 4, k++;
	*z = s->g + k;
	*x = ((av[s->g][0] + col) << k) + l % (1 << k);
	*y = ((av[s->g][1] + row) << k) + l / (1 << k);
	return *x >= av[*z][0] && *x <= av[*z][2] && *y >= av[*z][1] &&
	    *y <= av[*z][3];
}

/* An ancestor's places at a time (tr_take), in their order: its tiles of
 * every level share its blocks through the thread's cache. */
static void
sweep_range(void *arg, int k, int r0, int r1)
{
	sweep *s = arg;
	tr_export *j = s->x;
	tr_work *w = &j->w[k];
	int i0, i1;

	(void)r0, (void)r1;
	while (!j->failed[k] && tr_take(j, j->count, s->d, &i0, &i1)) {
		for (int i = i0; i < i1 && !j->failed[k]; i++) {
			int z, x, y;
			if (!sweep_tile(s, i, &z, &x, &y))
				continue;
			tr_part *p = &s->p[(size_t)k * (TR_MAXZ + 1) + z];
			w->err = w->direct = 0, w->tiles = w->tris = w->bytes = 0;
			w->nsamp = w->nmeas = 0;
			if (one_tile(j, &s->c[z], w, x, y, &j->err[k]) < 0) {
				j->failed[k] = 1;
				break;
			}
			p->err = fmax(p->err, w->err);
			p->direct = fmax(p->direct, w->direct);
			p->tiles += w->tiles, p->tris += w->tris;
			p->bytes += w->bytes;
			p->nsamp += w->nsamp, p->nmeas += w->nmeas;
		}
		/* its kept tiles (a projected DEM's) measured together */
		if (!j->failed[k] && tr_batch_own(j, k, s->p + (size_t)k *
		    (TR_MAXZ + 1), &j->err[k]) < 0)
			j->failed[k] = 1;
	}
}

/* Sweep places of levels g .. maxz, or -1 when the levels' rectangles
 * are not within their ancestors' at g or the count passes an int. */
static long long
sweep_size(const tr_export *x, int g, int *d)
{
	long long n = 0;

	*d = 0;
	for (int z = g; z <= x->maxz; z++) {
		const int *a = x->av[z], *b = x->av[g], k = z - g;
		if (a[0] >> k < b[0] || a[2] >> k > b[2] || a[1] >> k < b[1] ||
		    a[3] >> k > b[3] || k > 12)
			return -1;
		*d += 1 << 2 * k;
	}
	n = tr_count(x, g) * *d;
	return n > 0 && n <= INT_MAX ? n : -1;
}

int
tr_sweep_level(const tr_export *x)
{
	const tr_grid *g = &x->g;
	double res = g->projected ? g->cell / 111320.0 : fmax(fabs(g->bx),
	    fabs(g->by));
	int z = 1, d;

	/* the first level whose tile, with a block either side, spans no
	 * more blocks than a thread's cache holds */
	while (z <= x->maxz) {
		double b = ldexp(180, -z) / (BT_CELLS * res) + 2;
		if (b * b <= x->w[0].ncache)
			break;
		z++;
	}
	return z <= x->maxz && sweep_size(x, z, &d) > 0 ? z : x->maxz + 1;
}

int
tr_sweep(tr_export *x, const char *tmp, int g, tr_part *p, tl_err *e)
{
	sweep s = { .x = x, .g = g };
	int n = (int)sweep_size(x, g, &s.d), r = -1;

	assert(n > 0);
	s.nx = x->av[g][2] - x->av[g][0] + 1;
	if ((s.p = tl_alloc((size_t)x->nt * (TR_MAXZ + 1), sizeof *s.p,
	    e)) == NULL)
		return -1;
	for (int z = g; z <= x->maxz; z++) {
		memset(&p[z], 0, sizeof p[z]);
		tr_choose(&x->ix, z, 0, &s.c[z]);
		if (tr_dirs(x, tmp, z, e) < 0)
			goto done;
	}
	x->tmp = tmp, x->count = n, x->next = 0;
	/* a projected DEM's tiles kept, an ancestor's at a time, for one
	 * pass over the blocks under it (tr_batch_own) */
	x->keep = x->g.projected ? TR_KEEP / (size_t)x->nt : 0;
	tl_pool_for(x->pool, n, sweep_range, &s);
	x->keep = 0;
	for (int k = 0; k < x->nt; k++) {
		tr_work *w = &x->w[k];
		for (int i = 0; i < w->nkept; i++) /* left by a failure */
			tr_kept_free(w->kept[i].k);
		w->nkept = 0, w->kbytes = 0;
	}
	for (int k = 0; k < x->nt; k++)
		if (x->failed[k]) {
			*e = x->err[k];
			goto done;
		}
	for (int z = g; z <= x->maxz; z++) {
		for (int k = 0; k < x->nt; k++) {
			const tr_part *q = &s.p[(size_t)k * (TR_MAXZ + 1) + z];
			p[z].err = fmax(p[z].err, q->err);
			p[z].direct = fmax(p[z].direct, q->direct);
			p[z].tiles += q->tiles, p[z].tris += q->tris;
			p[z].nsamp += q->nsamp, p[z].nmeas += q->nmeas;
			p[z].bytes += q->bytes;
		}
		/* tr_try's test; a level that does not hold is made again
		 * from try 1, as tr_settle would */
		p[z].held = fmax(s.c[z].tau, s.c[z].base) + p[z].err <=
		    s.c[z].el;
		if (!p[z].held && tr_settle(x, tmp, z, 0, (int)tr_count(x, z),
		    1, &p[z], e) < 0)
			goto done;
	}
	r = 0;
done:
	free(s.p);
	return r;
}
