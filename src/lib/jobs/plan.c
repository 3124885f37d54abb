/* plan.c - a DEM-to-pyramid build as a job graph on disk (plan.h): the
 * plan directory, its checks and its lists of jobs; each consumer's file
 * (make, the job wrapper, GNU parallel, Slurm) is written by a backend of
 * the table below, one file each (plan_impl.h). */
#include "jobs/plan_impl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"

/* The consumers' files, in the order they are written. */
static const plan_backend backends[] = {
	{ "Makefile", 0, plan_makefile },
	{ "mkpieces", 1, plan_mkpieces },
	{ "job", 1, plan_job },
	{ "parallel.sh", 1, plan_parallel },
	{ "slurm.sh", 1, plan_slurm },
};

/* A backend's file, through put. */
typedef struct {
	const plan_backend *b;
	const plan_ctx *c;
} backend_call;

static void
put_backend(FILE *f, const void *arg)
{
	const backend_call *bc = arg;

	bc->b->write(f, bc->c);
}

/* Every consumer's file into dir: the table walked in order. */
static int
put_backends(const char *dir, const plan_ctx *c, tl_err *e)
{
	for (size_t i = 0; i < sizeof backends / sizeof backends[0]; i++) {
		backend_call bc = { &backends[i], c };

		if (plan_put(dir, backends[i].name, backends[i].exec,
		    put_backend, &bc, e) < 0)
			return -1;
	}
	return 0;
}

/* A list of jobs, a line each, for GNU parallel and Slurm's arrays:
 * done/PREFIX-0 .. done/PREFIX-(n-1) (bands/targets: the band jobs;
 * bands/fill1, fill2: the fill's passes). */
typedef struct {
	const char *prefix;
	int n;
} joblist;

static void
put_targets(FILE *f, const void *arg)
{
	const joblist *j = arg;

	for (int k = 0; k < j->n; k++)
		fprintf(f, "done/%s-%d\n", j->prefix, k);
}

/* A band list (fqm(5)) of the bands' file name in their directories. */
typedef struct {
	const plan_opts *o;
	const char *name;
} bandlist;

static void
put_bandlist(FILE *f, const void *arg)
{
	const bandlist *b = arg;

	fputs("fqm-bands 1\n", f);
	for (int k = 0; k < b->o->nbands; k++)
		fprintf(f, "%d/%s\n", k, b->name);
}

/* bands/: the lists of every banded level's vertex maps and of the top
 * FQMs, and the band jobs' targets. */
static int
put_bands(const char *dir, const plan_opts *o, tl_err *e)
{
	joblist bands = { "b", o->nbands }, f1 = { "f1", o->nfill };
	joblist f2 = { "f2", o->nfill };
	char sub[4200], name[32], list[48];

	if (o->nbands == 0)
		return 0;
	snprintf(sub, sizeof sub, "%s/bands", dir);
	if (mkdir(sub, 0777) != 0)
		return tl_failsys(e, "%s", sub);
	for (int l = 0; l <= o->band_levels; l++) {
		bandlist b = { o, name };
		if (l < o->band_levels)
			snprintf(name, sizeof name, "v%d.fqm", l),
			    snprintf(list, sizeof list, "v%d.bands", l);
		else
			snprintf(name, sizeof name, "f.fqm"),
			    snprintf(list, sizeof list, "f.bands");
		if (plan_put(sub, list, 0, put_bandlist, &b, e) < 0)
			return -1;
	}
	return plan_put(sub, "targets", 0, put_targets, &bands, e) < 0 ||
	    (o->nfill > 0 &&
	    (plan_put(sub, "fill1", 0, put_targets, &f1, e) < 0 ||
	    plan_put(sub, "fill2", 0, put_targets, &f2, e) < 0)) ? -1 : 0;
}

/* The mosaic's files as a list, absolute paths (cwd for relative). */
static void
put_list(FILE *f, const void *arg)
{
	const plan_opts *o = arg;
	char cwd[4096];

	if (getcwd(cwd, sizeof cwd) == NULL)
		cwd[0] = '\0';
	for (int k = 0; k < o->ndem; k++)
		fprintf(f, "%s%s%s\n", o->dems[k][0] == '/' ? "" : cwd,
		    o->dems[k][0] == '/' ? "" : "/", o->dems[k]);
}

/* The file src copied to dir/name. */
static int
copy(const char *dir, const char *name, const char *src, tl_err *e)
{
	char path[4400], buf[8192];
	FILE *in, *out;
	size_t n;
	int r = 0;

	snprintf(path, sizeof path, "%s/%s", dir, name);
	if ((in = fopen(src, "r")) == NULL)
		return tl_failsys(e, "%s", src);
	if ((out = fopen(path, "w")) == NULL) {
		fclose(in);
		return tl_failsys(e, "%s", path);
	}
	while ((n = fread(buf, 1, sizeof buf, in)) > 0)
		if (fwrite(buf, 1, n, out) != n)
			break;
	if (ferror(in))
		r = tl_failsys(e, "%s", src);
	if (ferror(out) && r == 0)
		r = tl_failsys(e, "%s", path);
	if (fclose(out) != 0 && r == 0)
		r = tl_failsys(e, "%s", path);
	fclose(in);
	return r;
}

/* What a plan cannot carry: make reads a recipe a line at a time, so a
 * newline in a path or an option would end the job's command there (and
 * a list of DEMs has a path a line). Every other byte is quoted for each
 * consumer: make, sh, GNU parallel (plan_word, PAR) and sbatch
 * (plan_slurm). The
 * name is shown with its newlines as \n, cut at 200 bytes. */
static int
carriable(const char *what, const char *s, tl_err *e)
{
	char shown[208];
	size_t n = 0;

	if (strchr(s, '\n') == NULL)
		return 0;
	for (; *s != '\0' && n < 200; s++)
		if (*s == '\n')
			shown[n++] = '\\', shown[n++] = 'n';
		else
			shown[n++] = *s;
	shown[n] = '\0';
	return tl_fail(e, "%s %s%s: a newline cannot go into a plan (make "
	    "reads its jobs' commands a line at a time): rename it", what,
	    shown, *s != '\0' ? "..." : "");
}

/* Every path and option the plan's jobs are given, carriable. */
static int
check_words(const plan_opts *o, const char *dir, const char *cwd,
    tl_err *e)
{
	if (carriable("the plan directory", dir, e) < 0 ||
	    carriable("the pyramid", o->out, e) < 0 ||
	    carriable("the programs' directory", o->bindir, e) < 0 ||
	    (o->ndem == 0 && carriable("the DEM", o->dem, e) < 0))
		return -1;
	for (int k = 0; k < o->ndem; k++)
		if (carriable("the DEM", o->dems[k], e) < 0 ||
		    (o->dems[k][0] != '/' &&
		    carriable("the current directory", cwd, e) < 0))
			return -1;
	for (int k = 0; k < o->nchainopt; k++)
		if (carriable("the option", o->chainopt[k], e) < 0)
			return -1;
	return 0;
}

/* The plan's final absolute path (the scripts name it so) into full,
 * and the current directory into cwd (or ""). */
static int
plan_path(const char *dir, char *full, char *cwd, size_t n, tl_err *e)
{
	if (getcwd(cwd, n) == NULL) {
		if (dir[0] != '/')
			return tl_failsys(e, "current directory");
		cwd[0] = '\0';
	}
	if ((size_t)snprintf(full, n, "%s%s%s", dir[0] == '/' ? "" : cwd,
	    dir[0] == '/' ? "" : "/", dir) >= n)
		return tl_fail(e, "%s: name too long", dir);
	return 0;
}

int
plan_check(const plan_opts *o, const char *dir, tl_err *e)
{
	char full[4096], cwd[4096];

	return plan_path(dir, full, cwd, sizeof full, e) < 0 ? -1 :
	    check_words(o, full, cwd, e);
}

int
plan_write(const plan_opts *o, const char *dir, tl_err *e)
{
	char full[4096], list[4200], cwd[4096];
	plan_opts q = *o;
	plan_ctx c = { &q, full };
	struct stat st;
	tl_outfile d;

	if (plan_path(dir, full, cwd, sizeof full, e) < 0 ||
	    check_words(o, full, cwd, e) < 0)
		return -1;
	if (!o->force && stat(dir, &st) == 0)
		return tl_fail(e, "%s: exists; use -f to replace it", dir);
	snprintf(list, sizeof list, "%s/dems.txt", full);
	if (o->ndem > 0)
		q.dem = list;
	if (tl_outdir_begin(&d, dir, e) < 0)
		return -1;
	if ((o->ndem > 0 &&
	    plan_put(d.tmp, "dems.txt", 0, put_list, o, e) < 0) ||
	    put_backends(d.tmp, &c, e) < 0 ||
	    copy(d.tmp, "dem.stamp", o->stamp, e) < 0 ||
	    put_bands(d.tmp, o, e) < 0) {
		tl_outdir_abort(&d);
		return -1;
	}
	return tl_outdir_commit(&d, e);
}
