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

#include "core/outfile.h"
#include "core/progress.h"
#include "jobs/graph.h"
#include "jobs/pipeline.h"
#include "jobs/plan.h"
#include "jobs/scratch.h"

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

	if (strcmp(label, "dem2fqm") == 0)
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
	char base[256], dir[PATHMAX], buf[1 << 16];
	long long off = 0;
	ssize_t r;
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
	while ((r = read(0, buf, sizeof buf)) != 0) {
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0 ? tl_failsys(e, "stdin") < 0 :
		    tl_pwrite(fd, buf, (size_t)r, off, path, e) < 0) {
			close(fd);
			return -1;
		}
		off += r;
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

/* The level count from the reader itself ("dem2fqm -I"); its message is
 * ours if it cannot read the DEM. */
static int
level_count(const pipeline_opts *o, const char *dem, int *levels,
    int *status, tl_err *e)
{
	char info[4096], *p;
	words a = { 0 };
	int in = -1, r;

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
	for (p = info; p != NULL && *p; p = strchr(p, '\n'), p = p ? p + 1 : p)
		if (sscanf(p, "levels %d", levels) == 1 && *levels >= 1 &&
		    *levels <= MAXLEVELS)
			return 0;
	*status = 1;
	return tl_fail(e, "%s: %s: dem2fqm -I gave no level count", o->prog,
	    dem);
}

/* The filter chain and one solver per level, all at once. */
static int
quadrics(const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, meter *m, int *status, tl_err *e)
{
	graph *g = graph_new(o->prog, o->bindir, e);
	words a = { 0 };
	int up[2], r = -1;

	if (g == NULL || graph_pipe(g, up, e) < 0)
		goto done;
	graph_progress(g, on_progress, m);
	say(&a, "dem2fqm");
	say_demopts(&a, o);
	if (o->name != NULL && strcmp(o->dem, "-") != 0)
		say(&a, "-n"), say(&a, o->name);
	say(&a, dem), say(&a, "-");
	if (graph_exec(g, (char *const *)a.w, -1, up[1], e) < 0)
		goto done;
	for (int l = 0; l < levels; l++) {
		int q[2], f[2], v;
		if (graph_pipe(g, q, e) < 0 ||
		    (v = graph_open(g, vpath[l], O_WRONLY | O_CREAT | O_EXCL,
		    0600, e)) < 0)
			goto done;
		a.n = 0;
		say(&a, "fqmsolve"), say(&a, "-m"), say(&a, o->mode);
		if (o->cut != NULL)
			say(&a, "-r"), say(&a, o->cut);
		say(&a, "-"), say(&a, "-");
		if (graph_exec(g, (char *const *)a.w, q[0], v, e) < 0)
			goto done;
		if (l == levels - 1) { /* the top: no filter above it */
			if (graph_tee(g, up[0], q[1], -1, e) < 0)
				goto done;
			break;
		}
		if (graph_pipe(g, f, e) < 0 ||
		    graph_tee(g, up[0], q[1], f[1], e) < 0)
			goto done;
		a.n = 0;
		say(&a, "fqmfilter"), say(&a, "-k"), say(&a, o->kernel);
		say(&a, "-"), say(&a, "-");
		if (graph_pipe(g, up, e) < 0 ||
		    graph_exec(g, (char *const *)a.w, f[0], up[1], e) < 0)
			goto done;
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

/* -M: the quadric chain only, its vertex maps into the directory o->out,
 * made atomically (an earlier one replaced): a plan's first job. */
static int
vmaps_only(const pipeline_opts *o, const char *dem, int levels,
    vpath_t *vpath, meter *m, int *status, tl_err *e)
{
	tl_outfile d;
	int r;

	if (tl_outdir_begin(&d, o->out, e) < 0)
		return ours(o, e);
	for (int l = 0; l < levels; l++)
		snprintf(vpath[l], sizeof vpath[l], "%s/v%d.fqm", d.tmp, l);
	tl_progress_start(&m->bar, o->prog, 1000);
	if ((r = quadrics(o, dem, levels, vpath, m, status, e)) == 0 &&
	    (r = tl_outdir_commit(&d, e)) < 0)
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
	return snprintf(buf, n, "%s/%s", cwd, p) < (int)n ? 0 :
	    tl_fail(e, "%s: name too long", p);
}

/* --plan: the job graph (plan.h), each job one of the stages with the
 * options given here. */
static int
plan(const pipeline_opts *o, const char *dem, int levels, int *status,
    tl_err *e)
{
	const char *chain[PIPELINE_MAXOPTS + 8], *dopt[PIPELINE_MAXOPTS + 2];
	char adem[PATHMAX], aout[PATHMAX], abin[PATHMAX];
	plan_opts p = { .prog = o->prog, .levels = levels, .force = o->force };
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
	if (absolute(o->out, aout, sizeof aout, e) < 0 ||
	    absolute(o->bindir != NULL ? o->bindir : ".", abin, sizeof abin,
	    e) < 0 || (o->ndem <= 1 && absolute(dem, adem, sizeof adem, e) < 0))
		return ours(o, e);
	p.dem = adem, p.out = aout, p.bindir = abin;
	p.dems = o->ndem > 1 ? (const char *const *)o->dems : NULL;
	p.ndem = o->ndem > 1 ? o->ndem : 0;
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
	int levels, r;

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
	if (level_count(o, dem, &levels, status, e) < 0)
		return -1;
	if (o->plan != NULL)
		return plan(o, dem, levels, status, e);
	if (o->vmaps)
		return vmaps_only(o, dem, levels, vpath, &m, status, e);
	for (int l = 0; l < levels; l++)
		snprintf(vpath[l], sizeof vpath[l], "%s/v%d.fqm", s->path, l);
	tl_progress_start(&m.bar, o->prog, 1000);
	r = quadrics(o, dem, levels, vpath, &m, status, e);
	if (r == 0)
		r = pack(o, dem, levels, vpath, &m, status, e);
	if (r == 0)
		tl_progress_end(&m.bar);
	else if (m.bar.on && m.bar.last >= 0)
		fputs("\r\033[K", stderr); /* the message goes where it was */
	return r;
}

int
pipeline_run(const pipeline_opts *o, int *status, tl_err *e)
{
	vpath_t *vpath;
	scratch s;
	int r;

	if (precheck(o, status, e) < 0)
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
