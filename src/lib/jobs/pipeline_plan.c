/* pipeline_plan.c - --plan: dem2vgis's options turned into the plan's
 * (plan.h): its column and row bands, absolute paths, the DEM's stamp. */
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "jobs/pipeline_impl.h"
#include "jobs/plan.h"

/* An absolute path for p, from the current directory. */
static int
absolute(const char *p, char *buf, size_t n, tl_err *e)
{
	char cwd[PATHMAX];

	if (p[0] == '/')
		return snprintf(buf, n, "%s", p) < (int)n ? 0 :
		    tl_fail(e, "%s: name too long", p);
	if (getcwd(cwd, sizeof cwd) == NULL)
		return tl_failsys(e, "current directory");
	while (p[0] == '.' && p[1] == '/') /* ./-x (undashed), ./x */
		p += 2;
	return snprintf(buf, n, "%s/%s", cwd, p) < (int)n ? 0 :
	    tl_fail(e, "%s: name too long", p);
}

/* The chain's split into column bands (plan.h): bands of a multiple of
 * 2^T columns, T levels banded (the rest is 4^T times smaller). Not for
 * QEM-3D: its fold fix carries each row's moves into the next rows with
 * no bound on how far they travel along a row, so a band's vertices
 * could depend on columns any distance away (dem2vgis(1)). */
#define PLAN_BAND_LEVELS 4
#define PLAN_BAND_WIDTH 4096
#define PLAN_FILL_ROWS 4096

/* The fill in row bands, when it has two or more: a void's neighbours
 * along its row are in the band, and across rows a band needs only each
 * column's nearest valid samples above and below it (dem2fqm(1)). */
static void
plan_fill(const pipeline_opts *o, int h, plan_opts *p)
{
	long rows = o->fillplan > 0 ? o->fillplan : PLAN_FILL_ROWS;

	p->height = h;
	if (p->nbands == 0 || o->fillplan < 0 || rows * 2 > h)
		return;
	p->fillrows = (int)rows;
	p->nfill = (int)((h + rows - 1) / rows);
}

static void
plan_bands(const pipeline_opts *o, int levels, int w, plan_opts *p)
{
	int t = levels - 1 < PLAN_BAND_LEVELS ? levels - 1 : PLAN_BAND_LEVELS;
	long bw = o->bandplan > 0 ? o->bandplan : PLAN_BAND_WIDTH;

	p->width = w;
	if (o->bandplan < 0 || t < 1 || strcmp(o->mode, "qem3d") == 0)
		return;
	bw = (bw + (1L << t) - 1) >> t << t;
	if (bw * 2 > w) /* one band would do */
		return;
	p->band_levels = t, p->bandw = (int)bw;
	p->nbands = (int)((w + bw - 1) / bw);
	/* a last band narrower than a halo joins the one before it */
	if (w - (long)(p->nbands - 1) * bw < pipeline_halo(t))
		p->nbands--;
}

/* What identifies the DEM's files, recorded by vgis-job stamp into
 * path in the scratch (stamp.h); a mosaic's list (in the scratch too)
 * on its stdin, so that its entries are recorded, not it. */
static int
plan_stamp(const pipeline_opts *o, const char *dem, const scratch *s,
    char *path, size_t n, int *status, tl_err *e)
{
	words a = { 0 };
	int in = -1, r;

	if ((size_t)snprintf(path, n, "%s/dem.stamp", s->path) >= n)
		return tl_fail(e, "%s: %s/dem.stamp: name too long", o->prog,
		    s->path);
	say(&a, "vgis-job"), say(&a, "stamp"), say(&a, path);
	if (o->ndem > 1) {
		say(&a, "-");
		if ((in = open(dem, O_RDONLY | O_CLOEXEC)) < 0)
			return tl_failsys(e, "%s: %s", o->prog, dem);
	} else
		say(&a, dem);
	r = pipeline_alone(o, &a, in, 1, NULL, 0, status, e);
	if (in >= 0)
		close(in);
	return r;
}

/* --plan: the job graph (plan.h), each job one of the stages with the
 * options given here. */
int
pipeline_plan(const pipeline_opts *o, const char *dem, const scratch *s,
    int levels, int w, int h, int *status, tl_err *e)
{
	const char *chain[PIPELINE_MAXOPTS + 8], *dopt[PIPELINE_MAXOPTS + 2];
	char adem[PATHMAX], aout[PATHMAX], abin[PATHMAX], stamp[PATHMAX];
	plan_opts p = { .prog = o->prog, .levels = levels, .force = o->force,
	    .part_samples = o->partplan, .stamp = stamp };
	int nc = 0, nd = 0;

	if (strcmp(o->mode, "qem3d") == 0)
		chain[nc++] = "-3";
	chain[nc++] = "-k", chain[nc++] = o->kernel;
	if (o->cut != NULL)
		chain[nc++] = "-r", chain[nc++] = o->cut;
	for (int i = 0; i < o->ndemopt; i++)
		chain[nc++] = dopt[nd++] = o->demopt[i];
	if (o->name != NULL) {
		chain[nc++] = dopt[nd++] = "-n";
		chain[nc++] = dopt[nd++] = o->name;
	}
	p.chainopt = chain, p.nchainopt = nc;
	p.demopt = dopt, p.ndemopt = nd;
	plan_bands(o, levels, w, &p);
	plan_fill(o, h, &p);
	if (absolute(o->out, aout, sizeof aout, e) < 0 ||
	    absolute(o->bindir != NULL ? o->bindir : ".", abin, sizeof abin,
	    e) < 0 || (o->ndem <= 1 && absolute(dem, adem, sizeof adem, e) < 0))
		return pipeline_ours(o, e);
	p.dem = adem, p.out = aout, p.bindir = abin;
	p.dems = o->ndem > 1 ? (const char *const *)o->dems : NULL;
	p.ndem = o->ndem > 1 ? o->ndem : 0;
	if (plan_check(&p, o->plan, e) < 0)
		return pipeline_ours(o, e);
	if (plan_stamp(o, dem, s, stamp, sizeof stamp, status, e) < 0)
		return -1;
	if (plan_write(&p, o->plan, e) < 0)
		return pipeline_ours(o, e);
	*status = 0;
	return 0;
}
