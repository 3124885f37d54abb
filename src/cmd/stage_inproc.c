/* stage_inproc.c - the stages' work for dem2vgis's threads
 * (stage_inproc.h): the options its command lines would carry, and the
 * message each program would print on failure. */
#include <assert.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/pool.h"
#include "qem/fqm.h"
#include "stage_inproc.h"

/* A failure in its program's words, as cli_exit prints them. */
static int
said(const cli *c, int r, tl_err *e)
{
	static const int limits[] = { EMFILE, EFBIG };
	char m[sizeof e->msg];
	const char *hint = "";

	if (r >= 0)
		return r;
	for (int k = 0; k < 2; k++)
		if (strstr(e->msg, strerror(limits[k])) != NULL &&
		    strstr(e->msg, tl_errno_hint(limits[k])) == NULL)
			hint = tl_errno_hint(limits[k]);
	snprintf(m, sizeof m, "%s", e->msg);
	return tl_fail(e, "%s: %s%s", c->prog, m, hint);
}

/* pipeline_work's count: vgis-job guard's check, then dem2fqm -I's
 * header read (stage_dem2fqm with -I), in this process: two processes
 * that each load GDAL were a tenth of N48W125's run on two cores, all
 * of it before the work could start. */
static int
count(void *ctx, const char *path, const char *const *outs, int nout,
    int *levels, int *w, int *h, tl_err *e)
{
	stage_inproc *p = ctx;
	const georef *g;
	char m[sizeof e->msg];
	dem *d;

	if (stage_guard(path, NULL, outs, nout, e) < 0) {
		snprintf(m, sizeof m, "%s", e->msg);
		return tl_fail(e, "vgis-job guard: %s", m);
	}
	if ((d = dem_open_info(path, &p->c[0].dem, e)) == NULL)
		return said(&p->c[0], -1, e);
	g = dem_georef(d);
	*w = g->width, *h = g->height;
	*levels = geo_levels(g->width, g->height);
	dem_close(d);
	return 0;
}

/* stage_level0's open: the DEM converted, once (a second call, after a
 * failure: its answer again). */
static dem *
dem_get(void *ctx, tl_err *e)
{
	stage_inproc *p = ctx;
	stage_dem *sd = &p->dem;

	/* written only here, before the threads (dem_begin): the chain's
	 * call reads it while tilepack's work does */
	if (!sd->done) {
		sd->d = dem_open_streamed(sd->path, &p->c[0].dem, &sd->err);
		sd->done = 1;
	}
	if (sd->d == NULL)
		*e = sd->err;
	return sd->d;
}

/* pipeline_work's open: the DEM the chain and tilepack's work share,
 * converted now, so that tilepack's work can start with the chain (a
 * failure is dem2fqm's, said when its work asks for the DEM). */
static int
dem_begin(void *ctx, const char *path)
{
	stage_dem *sd = &((stage_inproc *)ctx)->dem;
	tl_err e;

	assert(!sd->named && !sd->done);
	/* too long a name: each stage converts it, as before */
	sd->named = (size_t)snprintf(sd->path, sizeof sd->path, "%s", path) <
	    sizeof sd->path;
	return sd->named && dem_get(ctx, &e) != NULL;
}

static void
dem_end(void *ctx)
{
	stage_dem *sd = &((stage_inproc *)ctx)->dem;

	dem_close(sd->d);
	memset(sd, 0, sizeof *sd);
}

static int
level0(void *ctx, const char *path, tl_err *e)
{
	stage_inproc *p = ctx;
	stage_level0 o = p->l0;

	o.in = path;
	if (p->dem.named && strcmp(path, p->dem.path) == 0)
		o.open = dem_get, o.open_ctx = p;
	return said(&p->c[0], stage_dem2fqm(&p->c[0], &o, e), e);
}

static int
filter(void *ctx, tl_err *e)
{
	stage_inproc *p = ctx;

	return said(&p->c[1], stage_fqmfilter(&p->c[1], &p->f, e), e);
}

static int
solve(void *ctx, const char *out, tl_err *e)
{
	stage_inproc *p = ctx;
	stage_solve o = p->s;

	o.out = out;
	return said(&p->c[2], stage_fqmsolve(&p->c[2], &o, e), e);
}

/* Level 0's vertex map's header, as dem2fqm's and fqmsolve's work
 * make it for the DEM d (stage_level0.c, stage_solve.c): the pack's
 * known level 0 (pack.h, known0). */
static int
level0_header(rs_header *oh, dem *d, enum solve_mode mode, tl_err *e)
{
	fqm_info fi = { .geo = *dem_georef(d) };
	rs_header h;
	int r;

	fi.size0[0] = fi.geo.width, fi.size0[1] = fi.geo.height;
	rs_header_init(&h, 0, 0);
	r = fqm_header(&h, &fi, "none", e) == 0 &&
	    solve_header(oh, &h, mode, e) == 0 ? 0 : -1;
	rs_header_free(&h);
	return r;
}

/* Level 0's pieces at once beside the chain: at most want, as many as
 * keep the whole run under 128 MiB by dem2vgis(1)'s MEMORY formula
 * (the chain's rings grow with the DEM's width w; a piece is 14 MiB, 18
 * in QEM-3D); 0: level 0 waits for the chain, as the other levels do. */
static int
beside_jobs(int want, int w, int mode3d)
{
	long long mib = 1 << 20, budget = 128 * mib;
	long long chain = mode3d ? 57 * mib + 2900LL * w : 56 * mib + 2400LL * w;
	long long piece = (mode3d ? 18 : 14) * mib;
	long long fit = chain < budget ? (budget - chain) / piece : 0;

	return fit < want ? (int)fit : want;
}

/* tilepack's pack (tilepack.c): the guard, the run, its report. Beside
 * the chain (g), level 0 from the DEM (its known vertex map), and the
 * chain's failure the run's: this one's then unsaid. */
static int
pack(void *ctx, const char *path, const char *out, char *const *vmaps, int n,
    const pipeline_gate *g, tl_err *e)
{
	stage_inproc *p = ctx;
	pack_args a = p->pk;
	pack_gate pg;
	pack_level *lev;
	rs_header h0;
	int r = -1;

	rs_header_init(&h0, 0, 0);
	a.dem_path = path, a.dir = out, a.levels = vmaps, a.nlevels = n;
	/* the chain's DEM, converted once (its options: the same cli) */
	if (p->dem.done && p->dem.d != NULL && strcmp(path, p->dem.path) == 0)
		a.opened = p->dem.d;
	if (g != NULL) {
		pg = (pack_gate){ g->ctx, g->ended, g->stopped };
		a.gate = &pg;
		if (a.opened != NULL)
			a.gate_jobs = beside_jobs(a.gate_jobs,
			    dem_georef(a.opened)->width, p->mode3d);
		if (a.opened != NULL &&
		    level0_header(&h0, a.opened, p->s.mode, e) < 0)
			goto done;
		a.known0 = a.opened != NULL ? &h0 : NULL;
	}
	if (stage_pack_guard(&a, NULL, e) < 0)
		goto done;
	if ((lev = tl_alloc((size_t)n, sizeof *lev, e)) == NULL)
		goto done;
	r = pack_run(&a, lev, e);
	if (r == 0 && !p->quiet)
		pack_report(stderr, p->c[3].prog, lev, n);
	free(lev);
done:
	rs_header_free(&h0);
	return said(&p->c[3], r, e);
}

int
stage_inproc_init(stage_inproc *p, const cli *c, const pipeline_opts *o,
    tl_err *e)
{
	static const char *const progs[4] = { "dem2fqm", "fqmfilter",
	    "fqmsolve", "tilepack" };
	int jobs = cli_jobs();

	memset(p, 0, sizeof *p);
	for (int k = 0; k < 4; k++) {
		p->c[k] = *c;
		p->c[k].prog = progs[k];
		p->c[k].comp = RS_ZIP;
		/* -n names a DEM file; a DEM from stdin is spooled under
		 * that name (pipeline_spool_stdin) and given no -n */
		if (strcmp(o->dem, "-") == 0)
			p->c[k].dem.hgt_name = NULL;
	}
	p->l0.out = "-";
	p->f.in = p->f.out = "-";
	if ((p->f.kernel = filter_find(o->kernel)) == NULL)
		return tl_fail(e, "-k %s: unknown kernel", o->kernel);
	p->s.in = "-";
	p->s.rel = o->cut != NULL ? strtod(o->cut, NULL) : 1e-3;
	p->s.jobs = jobs > TL_POOL_MAXTHREADS ? TL_POOL_MAXTHREADS : jobs;
	if (solve_mode_parse(o->mode, &p->s.mode) < 0)
		return tl_fail(e, "-m %s: unknown mode", o->mode);
	p->pk.dem = p->c[3].dem;
	p->pk.jobs = o->jobs != NULL ? atoi(o->jobs) : jobs;
	p->pk.jobs = p->pk.jobs > PACK_MAXJOBS ? PACK_MAXJOBS : p->pk.jobs;
	/* beside the chain, which keeps a core busy (QEM-3D's solvers
	 * more), one job less takes level 0's pieces: the cores busy, and a
	 * piece less in memory while the chain's rings are (dem2vgis(1),
	 * MEMORY) */
	p->pk.gate_jobs = p->pk.jobs > 1 ? p->pk.jobs - 1 : 1;
	p->mode3d = p->s.mode == SOLVE_QEM3D;
	p->pk.force = o->force;
	p->pk.part_samples = 1LL << 30;
	p->pk.prog = p->c[3].prog;
	p->quiet = o->quiet;
	p->w = (pipeline_work){ .ctx = p, .count = count,
	    .open = dem_begin, .close = dem_end,
	    .level0 = level0, .filter = filter, .solve = solve, .pack = pack };
	return 0;
}
