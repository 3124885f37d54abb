/* tr_run.c - vgis2terrain's work (terrain.h): the levels of the global
 * quadtree one after the other, the tiles of a level on a pool of
 * threads (each tile's bytes depend on its level's choice alone, so any
 * thread count writes the same files), into a tree built under a
 * temporary name and renamed when complete (outfile.h). A level whose
 * bound (the selection's max(tau, base) plus the largest measured
 * distance of the drawn surface from the selection) passes E_L is made
 * again with a tighter choice. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/outfile.h"
#include "base/paths.h"
#include "base/pool.h"
#include "geo/vdatum.h"
#include "terrain/t3t.h"
#include "terrain/tr_impl.h"

#define TRIES 8
#define RMIN 6335439.0 /* m: WGS 84's least radius of curvature */

typedef struct {
	const tr_args *a;
	tr_work *w;
	tl_err *err;
	int *failed;
	const char *tmp;
	tr_choice c;
	int x0, y0, nx, ny;
	t3t_set *t3;      /* -f 3dtiles, else NULL */
} job;

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

static int
one_tile(job *j, tr_work *w, int x, int y, tl_err *e)
{
	char path[4096];
	float lo, hi;
	double d[2];

	if (tr_mesh_tile(w, &j->c, x, y, e) < 0 ||
	    tr_quantise(w, j->c.z, x, y, &lo, &hi, e) < 0 ||
	    tr_measure(w, j->c.z, x, y, d, e) < 0 ||
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
	job *j = arg;

	for (int i = i0; i < i1 && !j->failed[k]; i++) {
		int x, y;
		tr_tile_at(j->w[k].g, j->c.z, j->nx, j->ny, i, &x, &y);
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
static void
choose(const pyramid_index *ix, int z, int t, tr_choice *c)
{
	double el = ldexp(TR_E0, -z), wm = ldexp(180, -z) * 111320.0;
	int n = 1;

	while (wm / n > sqrt(RMIN * el / 2) && n < 1024)
		n *= 2;
	c->z = z, c->el = el, c->tau = ldexp(el, -(t + 1));
	c->n = n << (t / 2) > 4096 ? 4096 : n << (t / 2);
	c->p = pick_level(ix, c->tau, &c->base);
	/* the last try: every vertex of level 0, so that no sample the
	 * saturated errors leave out (voids the pyramid filled) is missed */
	if (t == TRIES - 1)
		c->tau = -1, c->p = 0, c->base = 0;
}

static int
level_dirs(const char *tmp, int z, const int av[4], tl_err *e)
{
	char p[4096];

	snprintf(p, sizeof p, "%s/%d", tmp, z);
	if (mkdir(p, 0777) < 0)
		return tl_failsys(e, "%s", p);
	for (int x = av[0]; x <= av[2]; x++) {
		snprintf(p, sizeof p, "%s/%d/%d", tmp, z, x);
		if (mkdir(p, 0777) < 0)
			return tl_failsys(e, "%s", p);
	}
	return 0;
}

static int
do_level(job *j, tl_pool *pool, int nt, int z, const int av[4],
    tr_report *rep, tl_err *e)
{
	int n = (av[2] - av[0] + 1) * (av[3] - av[1] + 1);

	j->x0 = av[0], j->y0 = av[1], j->nx = av[2] - av[0] + 1;
	j->ny = av[3] - av[1] + 1;
	for (int t = 0; t < TRIES; t++) {
		double err = 0, direct = 0;
		choose(j->w[0].ix, z, t, &j->c);
		for (int k = 0; k < nt; k++)
			j->w[k].err = j->w[k].direct = 0,
			j->w[k].tiles = j->w[k].tris =
			    j->w[k].bytes = 0;
		tl_pool_for(pool, n, run_range, j);
		for (int k = 0; k < nt; k++)
			if (j->failed[k]) {
				*e = j->err[k];
				return -1;
			}
		rep->tiles[z] = rep->tris[z] = rep->bytes[z] = 0;
		for (int k = 0; k < nt; k++) {
			err = fmax(err, j->w[k].err);
			direct = fmax(direct, j->w[k].direct);
			rep->tiles[z] += j->w[k].tiles;
			rep->tris[z] += j->w[k].tris;
			rep->bytes[z] += j->w[k].bytes;
		}
		/* the selection within max(tau, base) of the valid samples
		 * (vgis(5)), the drawn surface within err of the selection */
		rep->err[z] = fmax(j->c.tau, j->c.base) + err;
		rep->direct[z] = direct, rep->plevel[z] = j->c.p;
		rep->tau[z] = j->c.tau, rep->tries[z] = t + 1;
		if (rep->err[z] <= j->c.el)
			return 0;
	}
	return tl_fail(e, "level %d: the bound %.3f m passes E_L = %.3f m "
	    "after %d refinements: not written", z, rep->err[z], j->c.el,
	    TRIES);
}

/* Refuses what cannot go on the globe as ellipsoidal heights, as
 * vgis2tiles does; a projected DEM is not exported yet. */
static int
check_pyramid(const tr_args *a, const pyramid_index *ix, tl_err *e)
{
	const georef *g = &ix->geo;

	if (g->model == GEO_NONE)
		return tl_fail(e, "%s: the pyramid has no CRS: it cannot be "
		    "placed on the globe (rebuild it from a georeferenced DEM)",
		    a->dir);
	if (g->vdatum[0] != '\0' && !vdatum_is_ellipsoid(g->vdatum))
		return tl_fail(e, "%s: heights are in %s, not ellipsoidal: "
		    "rebuild the pyramid with dem2vgis -H ellipsoid DEM DIR",
		    a->dir, g->vdatum);
	if (ix->lev[0].displaced)
		return tl_fail(e, "%s: level 0 is displaced: not exported",
		    a->dir);
	if (g->vdatum[0] == '\0' && a->prog != NULL && !a->quiet)
		fprintf(stderr, "%s: %s: vertical datum unknown: heights taken "
		    "as ellipsoidal (if they are not, rebuild with dem2vgis "
		    "-D datum -H ellipsoid)\n", a->prog, a->dir);
	return 0;
}

/* The deepest level and the tiles of each level: those the terrain's
 * rectangle covers with some area (a projected DEM's: the box of its
 * footprint widened by the level's band, tr_rim_band), and both roots. */
static void
plan(const tr_grid *g, int *maxz, int (*av)[4])
{
	double res = g->projected ? g->cell / 111320.0 :
	    fmax(fabs(g->bx), fabs(g->by));

	/* the first level whose tile holds 64 DEM cells or fewer */
	for (*maxz = 0; *maxz < TR_MAXZ && ldexp(180, -*maxz) / 64 > res;)
		++*maxz;
	av[0][0] = 0, av[0][1] = 0, av[0][2] = 1, av[0][3] = 0;
	for (int z = 1; z <= *maxz; z++) {
		double w = ldexp(180, -z), r[4] = { g->r[0], g->r[1], g->r[2],
			g->r[3] };
		int nx = 2 << z, ny = 1 << z;
		if (g->projected) {
			double m = (tr_rim_band(g, z) + 0.01) * g->cell / 111000.0;
			double c = cos(fmin(89, fmax(fabs(g->fp[1]),
			    fabs(g->fp[3]))) * M_PI / 180);
			r[0] = g->fp[0] - m / c, r[2] = g->fp[2] + m / c;
			r[1] = g->fp[1] - m, r[3] = g->fp[3] + m;
		}
		av[z][0] = (int)floor((r[0] + 180) / w);
		av[z][2] = (int)ceil((r[2] + 180) / w) - 1;
		av[z][1] = (int)floor((r[1] + 90) / w);
		av[z][3] = (int)ceil((r[3] + 90) / w) - 1;
		for (int k = 0; k < 2; k++) {
			int m = k ? ny : nx;
			av[z][k] = av[z][k] < 0 ? 0 : av[z][k] >= m ? m - 1 :
			    av[z][k];
			av[z][k + 2] = av[z][k + 2] < av[z][k] ? av[z][k] :
			    av[z][k + 2] >= m ? m - 1 : av[z][k + 2];
		}
	}
}

/* An existing OUTDIR is replaced only when it is a terrain tileset. */
static int
check_out(const char *out, tl_err *e)
{
	char p[4096];
	struct stat st;

	if (stat(out, &st) < 0)
		return errno == ENOENT ? 0 : tl_failsys(e, "%s", out);
	snprintf(p, sizeof p, "%s/layer.json", out);
	if (!S_ISDIR(st.st_mode) || (stat(p, &st) < 0 &&
	    (snprintf(p, sizeof p, "%s/r0/0/0/0.subtree", out),
	    stat(p, &st) < 0)))
		return tl_fail(e, "%s: exists and is not a terrain tileset: "
		    "not replaced", out);
	return 0;
}

static int
export(job *j, const pyramid_index *ix, int nt, tr_report *rep, tl_err *e)
{
	int av[TR_MAXZ + 1][4];
	tl_outfile od = { 0 };
	tl_pool *pool = NULL;
	const char *datum = ix->geo.vdatum[0] ? ix->geo.vdatum :
	    "vertical datum not declared, taken as ellipsoidal";
	int r = -1;

	plan(j->w[0].g, &rep->maxzoom, av);
	if (check_out(j->a->out, e) < 0 || tl_outdir_begin(&od, j->a->out,
	    e) < 0)
		return -1;
	j->tmp = od.tmp;
	if (j->a->format && (j->t3 = t3t_new(rep->maxzoom,
	    (const int (*)[4])av, e)) == NULL)
		goto done;
	if ((pool = tl_pool_new(nt, e)) == NULL)
		goto done;
	for (int z = 0; z <= rep->maxzoom; z++)
		if ((j->t3 ? t3t_dirs(od.tmp, z, av[z], e) :
		    level_dirs(od.tmp, z, av[z], e)) < 0 ||
		    do_level(j, pool, nt, z, av[z], rep, e) < 0)
			goto done;
	if (j->t3 ? t3t_finish(j->t3, od.tmp, j->a, datum, e) < 0 :
	    tr_layer_write(od.tmp, j->a, rep->maxzoom,
	    (const int (*)[4])av, datum, e) < 0)
		goto done;
	r = tl_outdir_commit(&od, e);
done:
	if (r < 0)
		tl_outdir_abort(&od);
	if (pool)
		tl_pool_free(pool);
	t3t_free(j->t3);
	return r;
}

static void
work_free(tr_work *w)
{
	for (int s = 0; s < TR_CACHE; s++)
		if (w->cused[s]) {
			pyramid_block_free(&w->cache[s]);
			free(w->clon[s]), free(w->clat[s]);
		}
	if (w->g->projected)
		geo_proj_close(&w->proj);
	tr_mesh_free(&w->m);
	free(w->sel), free(w->row), free(w->u), free(w->v), free(w->q), free(w->pos);
	free(w->order), free(w->tmp), free(w->buf);
}

int
tr_run(const tr_args *a, tr_report *rep, tl_err *e)
{
	pyramid_index ix = { 0 };
	tr_grid g = { 0 };
	geo_proj p0 = { 0 };
	job j = { .a = a };
	int nt = a->jobs < 1 ? 1 : a->jobs > TR_MAXJOBS ? TR_MAXJOBS : a->jobs;
	int r = -1;

	memset(rep, 0, sizeof *rep);
	/* OUTDIR kept off the pyramid before any work (paths.h) */
	if (tl_path_check(a->out, a->dir, "pyramid", TL_PATH_TREE, e) < 0 ||
	    pyramid_index_read(a->dir, &ix, e) < 0)
		return -1;
	if (pyramid_levels_probe(a->dir, &ix, e) < 0 ||
	    check_pyramid(a, &ix, e) < 0) {
		pyramid_index_free(&ix);
		return -1;
	}
	g.projected = ix.geo.model != GEO_GEOGRAPHIC;
	if ((g.projected && geo_proj_open(&p0, &ix.geo, e) < 0)) {
		pyramid_index_free(&ix);
		return -1;
	}
	int ok = tr_grid_init(&g, &ix, &p0, e) == 0, ready = 0;
	if (g.projected)
		geo_proj_close(&p0);
	j.w = ok ? tl_alloc(nt, sizeof *j.w, e) : NULL;
	j.err = j.w ? tl_alloc(nt, sizeof *j.err, e) : NULL;
	j.failed = j.err ? tl_alloc(nt, sizeof *j.failed, e) : NULL;
	for (; j.failed && ready < nt; ready++) {
		j.w[ready].ix = &ix, j.w[ready].dir = a->dir, j.w[ready].g = &g;
		if (g.projected && geo_proj_open(&j.w[ready].proj, &ix.geo,
		    e) < 0)
			break;
	}
	if (j.failed && ready == nt)
		r = export(&j, &ix, nt, rep, e);
	for (int k = 0; k < ready; k++)
		work_free(&j.w[k]);
	free(j.w), free(j.err), free(j.failed);
	tr_grid_free(&g, ix.nlevels);
	pyramid_index_free(&ix);
	return r;
}
