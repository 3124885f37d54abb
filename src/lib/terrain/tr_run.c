/* tr_run.c - vgis2terrain's work (terrain.h, tr_export.h): the run in
 * one process, the levels one after the other, each as one range of
 * tr_level.c's units (the first, small levels measured together in one
 * pass over level 0: tr_batch.c), into a tree built under a temporary
 * name and renamed when complete (outfile.h). A level whose
 * bound (the selection's max(tau, base) plus the largest measured
 * distance of the drawn surface from the selection) passes E_L is made
 * again with a tighter choice. A plan's jobs make the same units
 * (tr_plan.c). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/outfile.h"
#include "base/paths.h"
#include "geo/vdatum.h"
#include "terrain/tr_export.h"

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
int
tr_check_out(const char *out, tl_err *e)
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

int
tr_finish(tr_export *x, const char *dir, tl_err *e)
{
	const char *datum = x->ix.geo.vdatum[0] ? x->ix.geo.vdatum :
	    "vertical datum not declared, taken as ellipsoidal";

	return x->t3 ? t3t_finish(x->t3, dir, x->a, datum, e) :
	    tr_layer_write(dir, x->a, x->maxz, (const int (*)[4])x->av,
	    datum, e);
}

/* The run in one process: each level one range, from try 0 (the rule of
 * a plan's jobs, with one job a level: tr_plan.c). */
static int
export(tr_export *x, tr_report *rep, tl_err *e)
{
	tl_outfile od = { 0 };
	tr_part p, pb[TR_MAXZ + 1];
	int r = -1, z1 = tr_batch_depth(x), zs = tr_sweep_level(x);

	if (tr_check_out(x->a->out, e) < 0 || tl_outdir_begin(&od, x->a->out,
	    e) < 0)
		return -1;
	if (x->a->format && (x->t3 = t3t_new(x->maxz,
	    (const int (*)[4])x->av, e)) == NULL)
		goto done;
	/* the first levels batched, the deep ones swept (zs >= 1), those
	 * between level by level */
	z1 = z1 < zs - 1 ? z1 : zs - 1;
	if (tr_batch(x, od.tmp, z1, pb, e) < 0)
		goto done;
	for (int z = 0; z <= z1; z++)
		tr_report_level(x, z, &pb[z], rep);
	for (int z = z1 + 1; z < zs; z++) {
		if (tr_dirs(x, od.tmp, z, e) < 0 || tr_settle(x, od.tmp, z, 0,
		    (int)tr_count(x, z), 0, &p, e) < 0)
			goto done;
		tr_report_level(x, z, &p, rep);
	}
	if (zs <= x->maxz && tr_sweep(x, od.tmp, zs, pb, e) < 0)
		goto done;
	for (int z = zs; z <= x->maxz; z++)
		tr_report_level(x, z, &pb[z], rep);
	if (tr_finish(x, od.tmp, e) < 0)
		goto done;
	r = tl_outdir_commit(&od, e);
done:
	if (r < 0)
		tl_outdir_abort(&od);
	t3t_free(x->t3);
	x->t3 = NULL;
	return r;
}

static void
work_free(tr_work *w)
{
	for (int s = 0; s < TR_CACHE; s++)
		if (w->cused[s]) {
			pyramid_block_free(&w->cache[s]);
			free(w->clon[s]); /* clat within it */
		}
	for (int s = 0; s < TR_CACHE; s++)
		free(w->cbox[s]);
	if (w->g->projected)
		geo_proj_close(&w->proj);
	tr_mesh_free(&w->m);
	for (int i = 0; i < w->nkept; i++)
		tr_kept_free(w->kept[i].k);
	free(w->kept);
	free(w->sel), free(w->gsel), free(w->fu), free(w->fok), free(w->row);
	free(w->u);
	free(w->v);
	free(w->q), free(w->pos), free(w->order), free(w->tmp), free(w->buf);
	free(w->zrec);
}

/* The threads' state, each with its PROJ for a projected DEM. */
static int
workers(tr_export *x, tl_err *e)
{
	int ready = 0;

	x->w = tl_alloc(x->nt, sizeof *x->w, e);
	x->err = x->w ? tl_alloc(x->nt, sizeof *x->err, e) : NULL;
	x->failed = x->err ? tl_alloc(x->nt, sizeof *x->failed, e) : NULL;
	for (; x->failed && ready < x->nt; ready++) {
		x->w[ready].ix = &x->ix, x->w[ready].dir = x->a->dir;
		x->w[ready].g = &x->g;
		x->w[ready].ncache = x->g.projected ? TR_CACHE_PROJ : TR_CACHE;
		if (x->g.projected && geo_proj_open(&x->w[ready].proj,
		    &x->ix.geo, e) < 0)
			break;
	}
	if (x->failed == NULL || ready < x->nt) {
		for (int k = 0; k < ready; k++)
			work_free(&x->w[k]);
		free(x->w), free(x->err), free(x->failed);
		x->w = NULL, x->err = NULL, x->failed = NULL;
		return -1;
	}
	return (x->pool = tl_pool_new(x->nt, e)) == NULL ? -1 : 0;
}

int
tr_open(tr_export *x, const tr_args *a, tl_err *e)
{
	geo_proj p0 = { 0 };
	int ok;

	memset(x, 0, sizeof *x);
	x->a = a;
	x->nt = a->jobs < 1 ? 1 : a->jobs > TR_MAXJOBS ? TR_MAXJOBS : a->jobs;
	/* OUTDIR kept off the pyramid before any work (paths.h) */
	if (tl_path_check(a->out, a->dir, "pyramid", TL_PATH_TREE, e) < 0 ||
	    pyramid_index_read(a->dir, &x->ix, e) < 0)
		return -1;
	if (pyramid_levels_probe(a->dir, &x->ix, e) < 0 ||
	    check_pyramid(a, &x->ix, e) < 0) {
		pyramid_index_free(&x->ix);
		return -1;
	}
	x->g.projected = x->ix.geo.model != GEO_GEOGRAPHIC;
	if ((x->g.projected && geo_proj_open(&p0, &x->ix.geo, e) < 0)) {
		pyramid_index_free(&x->ix);
		return -1;
	}
	ok = tr_grid_init(&x->g, &x->ix, &p0, e) == 0;
	if (x->g.projected)
		geo_proj_close(&p0);
	if (ok && workers(x, e) == 0) {
		plan(&x->g, &x->maxz, x->av);
		return 0;
	}
	tr_close(x);
	return -1;
}

void
tr_close(tr_export *x)
{
	if (x->pool)
		tl_pool_free(x->pool);
	for (int k = 0; x->w != NULL && k < x->nt; k++)
		work_free(&x->w[k]);
	free(x->w), free(x->err), free(x->failed);
	t3t_free(x->t3);
	tr_grid_free(&x->g, x->ix.nlevels);
	pyramid_index_free(&x->ix);
	memset(x, 0, sizeof *x);
}

int
tr_run(const tr_args *a, tr_report *rep, tl_err *e)
{
	tr_export x;
	int r;

	memset(rep, 0, sizeof *rep);
	if (tr_open(&x, a, e) < 0)
		return -1;
	rep->maxzoom = x.maxz;
	r = export(&x, rep, e);
	tr_close(&x);
	return r;
}
