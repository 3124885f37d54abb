/* pipeline.c - DEM to pyramid as supervised stages (pipeline.h). */
#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "qem/fqm.h"
#include "base/outfile.h"
#include "base/paths.h"
#include "base/progress.h"
#include "jobs/graph.h"
#include "jobs/pipeline.h"
#include "jobs/plan.h"
#include "base/scratch.h"

#define MAXLEVELS 32 /* levels of a DEM of 2^31 x 2^31 samples: 25 */
#define MAXWORDS (PIPELINE_MAXOPTS + MAXLEVELS + 16)
#define PATHMAX 4200

typedef char vpath_t[PATHMAX];

/* The whole pipeline's one progress line, from what the stages report:
 * the quadric chain runs at dem2fqm's pace, then tilepack's pieces of
 * every level. The weights are the two phases' shares of the time
 * (scripts/bench-pyramid). */
#define QUADRIC_SHARE 0.35

typedef struct {
	tl_progress bar;
	double quad, pack; /* fractions done */
} meter;

static void
on_progress(void *ctx, const char *label, long long done, long long total)
{
	meter *m = ctx;
	double f = total > 0 ? (double)done / (double)total : 0;

	if (strcmp(label, "dem2fqm") == 0 ||
	    strcmp(label, "vgis-job level0") == 0)
		m->quad = f;
	else if (strcmp(label, "tilepack") == 0)
		m->pack = f;
	else
		return;
	f = QUADRIC_SHARE * m->quad + (1 - QUADRIC_SHARE) * m->pack;
	tl_progress_step(&m->bar, (long long)(1000 * f));
}

/* An argv under construction; the words are not copied (graph_exec
 * copies the whole argv). */
typedef struct {
	const char *w[MAXWORDS + 1];
	int n;
} words;

static void
say(words *a, const char *w)
{
	assert(a->n < MAXWORDS);
	a->w[a->n++] = w;
	a->w[a->n] = NULL;
}

static void
say_demopts(words *a, const pipeline_opts *o)
{
	for (int i = 0; i < o->ndemopt; i++)
		say(a, o->demopt[i]);
}

/* Runs one stage alone: its usage error (exit 2) is returned as -1 with
 * status 2; other failures only when fatal is set. */
static int
alone(const pipeline_opts *o, words *a, int in, int fatal, char *cap,
    size_t ncap, int *status, tl_err *e)
{
	graph *g = graph_new(o->prog, o->bindir, e);
	int k, r = -1, st = 1;

	if (g == NULL)
		goto done;
	if ((k = graph_exec(g, (char *const *)a->w, in, -1, e)) < 0 ||
	    (cap != NULL && graph_capture(g, k, cap, ncap, e) < 0))
		goto done;
	r = graph_run(g, &st, e);
	if (r < 0 && !fatal && st == 1)
		r = 0; /* not a usage error: the real run will say */
done:
	graph_free(g);
	*status = r < 0 ? st : 0;
	return r;
}

/* The options passed on, tried before any work: each stage on no input. */
static int
precheck(const pipeline_opts *o, int *status, tl_err *e)
{
	words a = { 0 };

	say(&a, "fqmsolve"), say(&a, "-m"), say(&a, o->mode);
	if (o->cut != NULL)
		say(&a, "-r"), say(&a, o->cut);
	say(&a, "-"), say(&a, "-");
	if (alone(o, &a, -1, 0, NULL, 0, status, e) < 0)
		return -1;
	a.n = 0;
	say(&a, "fqmfilter"), say(&a, "-k"), say(&a, o->kernel);
	say(&a, "-"), say(&a, "-");
	return alone(o, &a, -1, 0, NULL, 0, status, e);
}

/* A DEM on stdin is read twice (quadrics, then errors): a copy in
 * scratch, under the name -n gives, which GDAL may need (N44W072.hgt). */
static int
spool_stdin(const pipeline_opts *o, const scratch *s, char *path, size_t n,
    tl_err *e)
{
	char base[256], dir[PATHMAX];
	int fd;

	snprintf(base, sizeof base, "%s", o->name ? o->name : "stdin");
	snprintf(dir, sizeof dir, "%s/in", s->path);
	if (mkdir(dir, 0700) < 0)
		return tl_failsys(e, "%s", dir);
	if (snprintf(path, n, "%s/%s", dir, basename(base)) >= (int)n)
		return tl_fail(e, "%s: name too long", base);
	if ((fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC,
	    0600)) < 0)
		return tl_failsys(e, "%s", path);
	if (tl_copy_fd(0, "stdin", fd, 0, path, e) < 0) {
		close(fd);
		return -1;
	}
	return close(fd) < 0 ? tl_failsys(e, "%s", path) : 0;
}

/* A name the list could not give back as it is: entries lose the blanks
 * around them, and a line ends at a newline. */
static int
listable(const char *dem)
{
	size_t n = strlen(dem);

	return n > 0 && strchr(dem, '\n') == NULL &&
	    strchr(" \t\r\f\v", dem[n - 1]) == NULL;
}

/* Several DEMs: the list file the stages read as one mosaic, in dir
 * (scratch, or a plan), one absolute path a line (a relative entry would
 * be relative to the list's directory). Each is checked here first, so
 * that a missing one is named as the user gave it. */
static int
write_list(const pipeline_opts *o, const char *dir, char *path, size_t n,
    tl_err *e)
{
	char cwd[PATHMAX];
	FILE *f;
	int r = 0;

	if (getcwd(cwd, sizeof cwd) == NULL)
		return tl_failsys(e, "current directory");
	for (int k = 0; k < o->ndem; k++) {
		if (access(o->dems[k], F_OK) < 0)
			return tl_failsys(e, "%s", o->dems[k]);
		if (!listable(o->dems[k]))
			return tl_fail(e, "%s: a name holding a newline or "
			    "ending in a blank cannot go in a list of DEMs",
			    o->dems[k]);
	}
	if (snprintf(path, n, "%s/dems.txt", dir) >= (int)n)
		return tl_fail(e, "%s/dems.txt: name too long", dir);
	if ((f = fopen(path, "wx")) == NULL)
		return tl_failsys(e, "%s", path);
	for (int k = 0; k < o->ndem; k++) {
		const char *d = o->dems[k];
		fprintf(f, "%s%s%s\n", d[0] == '/' ? "" : cwd,
		    d[0] == '/' ? "" : "/", d);
	}
	if (ferror(f))
		r = tl_failsys(e, "%s", path);
	if (fclose(f) != 0 && r == 0)
		r = tl_failsys(e, "%s", path);
	return r;
}

/* Our own failure (not a stage's, which names itself): "prog: what". */
static int
ours(const pipeline_opts *o, tl_err *e)
{
	char m[sizeof e->msg];

	snprintf(m, sizeof m, "%s", e->msg);
	return tl_fail(e, "%s: %s", o->prog, m);
}

/* The level count and the width from the reader itself ("dem2fqm -I");
 * its message is ours if it cannot read the DEM. */
static int
level_count(const pipeline_opts *o, const char *dem, int *levels,
    int *width, int *height, int *status, tl_err *e)
{
	char info[4096], *p;
	words a = { 0 };
	int in = -1, r;

	/* the reader keeps the outputs off the DEM's files (a list's
	 * entries, a VRT's sources), which it alone can tell */
	say(&a, "vgis-job"), say(&a, "guard"), say(&a, "--"), say(&a, dem);
	say(&a, o->out);
	if (o->plan != NULL)
		say(&a, o->plan);
	if (alone(o, &a, -1, 1, NULL, 0, status, e) < 0)
		return -1;
	a.n = 0;
	say(&a, "dem2fqm");
	say_demopts(&a, o);
	if (o->name != NULL && strcmp(o->dem, "-") != 0)
		say(&a, "-n"), say(&a, o->name);
	say(&a, "-I");
	if (strcmp(o->dem, "-") == 0 && o->name == NULL) {
		/* its messages say stdin, as the user gave it */
		say(&a, "-");
		if ((in = open(dem, O_RDONLY | O_CLOEXEC)) < 0)
			return tl_failsys(e, "%s: %s", o->prog, dem);
	} else
		say(&a, dem);
	r = alone(o, &a, in, 1, info, sizeof info, status, e);
	if (in >= 0)
		close(in);
	if (r < 0)
		return -1;
	*levels = *width = *height = 0;
	for (p = info; p != NULL && *p; p = strchr(p, '\n'), p = p ? p + 1 : p)
		if (sscanf(p, "levels %d", levels) != 1)
			(void)sscanf(p, "size %d %d", width, height);
	if (*levels >= 1 && *levels <= MAXLEVELS && *width >= 1 &&
	    *height >= 1)
		return 0;
	*status = 1;
	return tl_fail(e, "%s: %s: dem2fqm -I gave no level count or size",
	    o->prog, dem);
}

/* A band's columns of level l (-C a,b), of a DEM w columns wide. */
static void
band_cols(const pipeline_opts *o, int w, int l, char *buf, size_t n)
{
	int b = o->band[1] >= w ? geo_level_size(w, l) : o->band[1] >> l;

	snprintf(buf, n, "%d,%d", o->band[0] >> l, b);
}

/* The chain's first stage: dem2fqm writing level 0 into a pipe, whose
 * end to read is *up; a band reads its window (-w) of the filled DEM
 * (-F), a plan's step (vgis-job level0). */
static int
level0(const pipeline_opts *o, graph *g, const char *dem, int w, char *win,
    size_t nwin, int *up, tl_err *e)
{
	words a = { 0 };
	int p[2];

	if (graph_pipe(g, p, e) < 0)
		return -1;
	if (o->fill != NULL || o->band[1] > 0)
		say(&a, "vgis-job"), say(&a, "level0");
	else
		say(&a, "dem2fqm");
	say_demopts(&a, o);
	if (o->name != NULL && strcmp(o->dem, "-") != 0)
		say(&a, "-n"), say(&a, o->name);
	if (o->fill != NULL)
		say(&a, "-F"), say(&a, o->fill);
	if (o->band[1] > 0) {
		long h = pipeline_halo(o->band_levels);
		long x0 = o->band[0] - h, x1 = o->band[1] + h;
		snprintf(win, nwin, "%ld,%ld", x0 < 0 ? 0 : x0, x1 > w ? w : x1);
		say(&a, "-w"), say(&a, win);
	}
	say(&a, dem), say(&a, "-");
	*up = p[0];
	return graph_exec(g, (char *const *)a.w, -1, p[1], e);
}

/* The filter chain and one solver per level, all at once: levels first
 * .. levels-1, from the DEM (first 0) or from the FQM o->from; a band's
 * top filter writes level `levels`' FQM to fpath. */
static int
quadrics(const pipeline_opts *o, const char *dem, int first, int levels,
    int w, vpath_t *vpath, const char *fpath, meter *m, int *status,
    tl_err *e)
{
	graph *g = graph_new(o->prog, o->bindir, e);
	char cut[MAXLEVELS + 1][32], win[64];
	int band = o->band[1] > 0, up = -1, r = -1;
	words a = { 0 };

	if (g == NULL)
		goto done;
	graph_progress(g, on_progress, m);
	if (o->from == NULL && level0(o, g, dem, w, win, sizeof win, &up,
	    e) < 0)
		goto done;
	for (int l = first; l < levels; l++) {
		/* the level's FQM: the pipe up, or the file o->from */
		const char *src = up < 0 ? o->from : "-";
		int q[2] = { -1, -1 }, f[2] = { -1, -1 }, v, top = l == levels - 1;
		if ((up >= 0 && graph_pipe(g, q, e) < 0) ||
		    (v = graph_open(g, vpath[l], O_WRONLY | O_CREAT | O_EXCL,
		    0600, e)) < 0)
			goto done;
		a.n = 0;
		/* a band's columns (-C): a plan's step */
		if (band)
			say(&a, "vgis-job"), say(&a, "solve");
		else
			say(&a, "fqmsolve");
		say(&a, "-m"), say(&a, o->mode);
		if (o->cut != NULL)
			say(&a, "-r"), say(&a, o->cut);
		if (band)
			band_cols(o, w, l, cut[l], sizeof cut[l]),
			    say(&a, "-C"), say(&a, cut[l]);
		say(&a, src), say(&a, "-");
		if (graph_exec(g, (char *const *)a.w, q[0], v, e) < 0)
			goto done;
		if (top && !band) { /* the top: no filter above it */
			if (up >= 0 && graph_tee(g, up, q[1], -1, e) < 0)
				goto done;
			break;
		}
		if (up >= 0 && (graph_pipe(g, f, e) < 0 ||
		    graph_tee(g, up, q[1], f[1], e) < 0))
			goto done;
		a.n = 0;
		if (top)
			say(&a, "vgis-job"), say(&a, "filter");
		else
			say(&a, "fqmfilter");
		say(&a, "-k"), say(&a, o->kernel);
		if (top)
			band_cols(o, w, l + 1, cut[l + 1], sizeof cut[l + 1]),
			    say(&a, "-C"), say(&a, cut[l + 1]);
		say(&a, src), say(&a, "-");
		if (top) {
			if ((v = graph_open(g, fpath, O_WRONLY | O_CREAT | O_EXCL,
			    0600, e)) < 0 ||
			    graph_exec(g, (char *const *)a.w, f[0], v, e) < 0)
				goto done;
			break;
		}
		if (graph_pipe(g, q, e) < 0 ||
		    graph_exec(g, (char *const *)a.w, f[0], q[1], e) < 0)
			goto done;
		up = q[0];
	}
	r = graph_run(g, status, e);
done:
	if (r < 0 && *status == 0)
		*status = 1;
	graph_free(g);
	return r;
}

static int
pack(const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, meter *m, int *status, tl_err *e)
{
	graph *g = graph_new(o->prog, o->bindir, e);
	words a = { 0 };
	int r = -1;

	if (g != NULL)
		graph_progress(g, on_progress, m);
	say(&a, "tilepack");
	if (o->force)
		say(&a, "-f");
	if (o->quiet)
		say(&a, "-q");
	if (o->jobs != NULL)
		say(&a, "-j"), say(&a, o->jobs);
	say_demopts(&a, o);
	if (o->name != NULL && strcmp(o->dem, "-") != 0)
		say(&a, "-n"), say(&a, o->name);
	say(&a, dem), say(&a, o->out);
	for (int l = 0; l < levels; l++)
		say(&a, vpath[l]);
	if (g != NULL && graph_exec(g, (char *const *)a.w, -1, -1, e) >= 0)
		r = graph_run(g, status, e);
	else
		*status = 1;
	graph_free(g);
	return r;
}

/* The level of the FQM the chain starts from (--from), 0 from a DEM:
 * its header's (read by the raster layer alone: the supervisor links no
 * georeferencing; the stages check the rest). */
static int
first_level(const pipeline_opts *o, int *first, tl_err *e)
{
	rs_reader *r;
	int x0 = 0, ok;

	*first = 0;
	if (o->from == NULL)
		return 0;
	if ((r = rs_open(o->from, e)) == NULL)
		return -1;
	ok = rs_get_int(rs_header_of(r), FQM_ATTR_LEVEL, first) == 0 &&
	    *first >= 0 && *first < MAXLEVELS;
	(void)rs_get_int(rs_header_of(r), RS_ATTR_X0, &x0);
	rs_close(r);
	if (!ok)
		return tl_fail(e, "%s: no fqm:level", o->from);
	return x0 == 0 ? 0 : tl_fail(e, "%s: a band from column %d, not a "
	    "whole level (give the band list)", o->from, x0);
}

/* -M: the quadric chain only, its vertex maps into the directory o->out,
 * made atomically (an earlier one replaced): a plan's job. A band's
 * directory also gets f.fqm, its columns of level band_levels' FQM. */
static int
vmaps_only(const pipeline_opts *o, const char *dem, int levels, int w,
    vpath_t *vpath, meter *m, int *status, tl_err *e)
{
	char fpath[PATHMAX];
	tl_outfile d;
	int first, r;

	if (o->band[1] > 0 && (o->band_levels >= levels || o->band[1] > w)) {
		*status = 2;
		return tl_fail(e, "%s: --band %d,%d --band-levels %d: the DEM "
		    "has %d columns and %d levels", o->prog, o->band[0],
		    o->band[1], o->band_levels, w, levels);
	}
	if (o->band[1] > 0)
		levels = o->band_levels;
	if (first_level(o, &first, e) < 0)
		return ours(o, e);
	if (first >= levels || tl_outdir_begin(&d, o->out, e) < 0)
		return first >= levels ? tl_fail(e, "%s: %s: level %d, the "
		    "DEM has %d", o->prog, o->from, first, levels) : ours(o, e);
	for (int l = first; l < levels; l++)
		snprintf(vpath[l], sizeof vpath[l], "%s/v%d.fqm", d.tmp, l);
	snprintf(fpath, sizeof fpath, "%s/f.fqm", d.tmp);
	tl_progress_start(&m->bar, o->prog, 1000);
	if ((r = quadrics(o, dem, first, levels, w, vpath, fpath, m, status,
	    e)) == 0 && (r = tl_outdir_commit(&d, e)) < 0)
		return ours(o, e);
	if (r < 0)
		tl_outdir_abort(&d);
	else
		tl_progress_end(&m->bar);
	return r;
}

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
	r = alone(o, &a, in, 1, NULL, 0, status, e);
	if (in >= 0)
		close(in);
	return r;
}

/* --plan: the job graph (plan.h), each job one of the stages with the
 * options given here. */
static int
plan(const pipeline_opts *o, const char *dem, const scratch *s, int levels,
    int w, int h, int *status, tl_err *e)
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
		return ours(o, e);
	p.dem = adem, p.out = aout, p.bindir = abin;
	p.dems = o->ndem > 1 ? (const char *const *)o->dems : NULL;
	p.ndem = o->ndem > 1 ? o->ndem : 0;
	if (plan_check(&p, o->plan, e) < 0)
		return ours(o, e);
	if (plan_stamp(o, dem, s, stamp, sizeof stamp, status, e) < 0)
		return -1;
	if (plan_write(&p, o->plan, e) < 0)
		return ours(o, e);
	*status = 0;
	return 0;
}

static int
stages(const pipeline_opts *o, const scratch *s, vpath_t *vpath,
    int *status, tl_err *e)
{
	char spool[PATHMAX];
	const char *dem = o->dem;
	meter m = { 0 };
	int levels, w, h, r;

	*status = 1;
	if (o->ndem > 1) {
		if (write_list(o, s->path, spool, sizeof spool, e) < 0)
			return ours(o, e);
		dem = spool;
	} else if (strcmp(dem, "-") == 0) {
		if (spool_stdin(o, s, spool, sizeof spool, e) < 0)
			return ours(o, e);
		dem = spool;
	} else if (access(dem, F_OK) < 0)
		return tl_failsys(e, "%s: %s", o->prog, dem);
	if (level_count(o, dem, &levels, &w, &h, status, e) < 0)
		return -1;
	if (o->plan != NULL)
		return plan(o, dem, s, levels, w, h, status, e);
	if (o->vmaps)
		return vmaps_only(o, dem, levels, w, vpath, &m, status, e);
	for (int l = 0; l < levels; l++)
		snprintf(vpath[l], sizeof vpath[l], "%s/v%d.fqm", s->path, l);
	tl_progress_start(&m.bar, o->prog, 1000);
	r = quadrics(o, dem, 0, levels, w, vpath, NULL, &m, status, e);
	if (r == 0)
		r = pack(o, dem, levels, vpath, &m, status, e);
	if (r == 0)
		tl_progress_end(&m.bar);
	else if (m.bar.on && m.bar.last >= 0)
		fputs("\r\033[K", stderr); /* the message goes where it was */
	return r;
}

/* The outputs (OUT, the plan) kept off the inputs given here and off
 * each other, before any work (paths.h); level_count has the reader
 * check what the DEM is read from. */
static int
guard(const pipeline_opts *o, tl_err *e)
{
	const char *plan = o->plan;
	char *const *dem = o->ndem > 1 ? o->dems : (char *const *)&o->dem;
	tl_paths s = { 0 };
	int r = 0;

	for (int k = 0; r == 0 && k < (o->ndem > 1 ? o->ndem : 1); k++)
		r = tl_paths_add(&s, dem[k], 0, e, "the input DEM %s", dem[k]);
	if (r == 0 && o->fill != NULL)
		r = tl_paths_add(&s, o->fill, 0, e, "the input filled DEM %s",
		    o->fill);
	if (r == 0 && o->from != NULL)
		r = tl_paths_add_raster(&s, o->from, "FQM", e);
	if (r == 0)
		r = tl_paths_check(&s, o->out, e);
	if (r == 0 && plan != NULL && (r = tl_paths_check(&s, plan, e)) == 0)
		r = tl_paths_add(&s, o->out, TL_PATH_OUT, e, "the output "
		    "directory %s", o->out);
	if (r == 0 && plan != NULL)
		r = tl_paths_check(&s, plan, e);
	tl_paths_free(&s);
	return r < 0 ? ours(o, e) : 0;
}

/* A relative name beginning with '-' would be an option to the stages
 * it is given to: "./" before it. */
static const char *
undashed(const char *p, char *buf, size_t n)
{
	if (p[0] != '-' || p[1] == '\0' || (size_t)snprintf(buf, n, "./%s",
	    p) >= n)
		return p;
	return buf;
}

int
pipeline_run(const pipeline_opts *opts, int *status, tl_err *e)
{
	char dem[PATHMAX], out[PATHMAX];
	pipeline_opts q = *opts;
	const pipeline_opts *o = &q;
	vpath_t *vpath;
	scratch s;
	int r;

	q.dem = undashed(opts->dem, dem, sizeof dem);
	q.out = undashed(opts->out, out, sizeof out);

	*status = 1;
	if (guard(o, e) < 0 || precheck(o, status, e) < 0)
		return -1;
	*status = 1;
	if ((vpath = tl_alloc(MAXLEVELS, sizeof *vpath, e)) == NULL)
		return ours(o, e);
	if (scratch_begin(&s, o->prog, e) < 0) {
		free(vpath);
		return ours(o, e);
	}
	r = stages(o, &s, vpath, status, e);
	scratch_end(&s);
	free(vpath);
	if (graph_signal() && r == 0) {
		*status = 128 + graph_signal();
		r = tl_fail(e, "%s: stopped by signal %d", o->prog,
		    graph_signal());
	}
	return r;
}
