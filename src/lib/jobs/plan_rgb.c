/* plan_rgb.c - dem2rgb's plan on disk (plan_rgb.h): the Makefile of the
 * parts and the gather, the job wrapper, the list of the parts'
 * targets, the scripts for GNU parallel and Slurm, and the DEM's
 * stamp. */
#include "jobs/plan_rgb.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"
#include "base/paths.h"
#include "base/stamp.h"
#include "jobs/plan_impl.h"

/* The plan with its paths made absolute. */
typedef struct {
	const plan_rgb_opts *o;
	char dir[4096], dem[4096], out[4096], bin[4096];
} ctx;

static void
put_makefile(FILE *f, const void *arg)
{
	const ctx *c = arg;
	const plan_rgb_opts *o = c->o;
	const char *const dem = c->dem, *const out = c->out, *bin = c->bin;

	fprintf(f, "# Made by %s --plan: the raster-dem %s %s\n# of the DEM "
	    "%s.\n# Run: make -C THIS-DIRECTORY -j N, and again after a "
	    "failure or a kill:\n# it goes on where it stopped. Each job is "
	    "a step of vgis-job(1):\n# done/warp (the DEM on the deepest "
	    "zoom's grid, its voids filled,\n# into work.grid/), done/p-K "
	    "(part K of N: its tiles into work/), done/gather\n# (work/ "
	    "becomes the %s).\n", o->prog, o->archive ? "archive" : "tree",
	    c->out, c->dem, o->archive ? "archive" : "tree");
	fputs("SHELL = /bin/sh\nB =", f);
	plan_words(f, &bin, 1, 1);
	fputs("\nJOB = sh job $(B)\nDEM =", f);
	plan_words(f, &dem, 1, 1);
	fputs("\nOUT =", f);
	plan_words(f, &out, 1, 1);
	plan_make_sweep(f, o->opt, o->nopt, o->jobs);
	fputs("PARTS =", f);
	for (int k = 0; k < o->nparts; k++)
		fprintf(f, " done/p-%d", k);
	fputs("\n\n", f);
	fputs("done/warp:\n\t$(JOB) $@ $(B)/vgis-job rgb-warp $(JOBOPTS) "
	    "$(OPTS) $(DEM) work\n\n", f);
	for (int k = 0; k < o->nparts; k++)
		fprintf(f, "done/p-%d: done/warp\n\t$(JOB) $@ $(B)/vgis-job "
		    "rgb-part $(JOBOPTS) $(OPTS) %d:%d $(DEM) work\n\n", k, k,
		    o->nparts);
	fprintf(f, "done/gather: $(PARTS)\n\t$(JOB) $@ $(B)/vgis-job "
	    "rgb-gather $(OPTS) %s\n", o->archive ? "-o $(OUT) $(DEM) work" :
	    "$(DEM) work $(OUT)");
}

static void
put_job(FILE *f, const void *arg)
{
	(void)arg;
	fputs("#!/bin/sh\n"
	    "# job B TARGET CMD...: the plan's job TARGET (done/NAME, made when "
	    "CMD\n# succeeds; B: the programs' directory). Run once however "
	    "many runners\n# ask for it at once: under an flock(1) of "
	    "done/.lock-NAME, and not when\n# TARGET was made meanwhile. "
	    "First the DEM's files are checked as the\n# plan recorded them "
	    "(dem.stamp).\n"
	    "# job B --sweep: the markers of the warp whose grid (work.grid/) "
	    "and of\n# parts whose records (work.parts/), tiles (work/) or "
	    "pieces\n# (work.grid/K) are gone removed, so that make runs them "
	    "again; none\n# once the gather is done.\n", f);
	plan_job_head(f);
	fputs("\tif [ -e done/warp ] && [ ! -d work.grid ]; then\n"
	    "\t\trm -f done/warp; gone=\"$gone warp\"\n"
	    "\tfi\n"
	    "\tfor m in done/p-*; do # p-K: work.parts/K\n"
	    "\t\t[ -e \"$m\" ] || continue\n"
	    "\t\tk=${m#done/p-}\n"
	    "\t\t[ -d work ] && [ -e \"work.parts/$k\" ] &&\n"
	    "\t\t    { [ -d \"work.grid/$k\" ] || [ ! -d work.grid/. ] ||\n"
	    "\t\t    [ ! -e work.grid/seg0.filled ]; } && continue\n"
	    "\t\trm -f \"$m\"; gone=\"$gone ${m#done/}\"\n"
	    "\tdone\n", f);
	plan_job_tail(f, "records", "dem.stamp");
}

static void
put_parallel(FILE *f, const void *arg)
{
	const ctx *c = arg;
	fputs("#!/bin/sh\n"
	    "# GNU parallel, stage by stage: the warp, every part, then the "
	    "gather. Each\n# job is a make target of this directory, so a run again skips "
	    "what is done. Its\n# options come from PARALLEL, e.g. "
	    "PARALLEL='--sshloginfile hosts -j 4' for\n# machines that share "
	    "this file system (same paths).\nset -e\nP=", f);
	plan_word(f, c->dir, 0);
	fputs("\n" PLAN_PAR "::: done/warp\n"
	    PLAN_PAR ":::: \"$P/targets1\"\n"
	    PLAN_PAR "::: done/gather\n", f);
}

static void
put_slurm(FILE *f, const void *arg)
{
	const ctx *c = arg;
	fputs("#!/bin/sh\n"
	    "# Slurm: the warp, the parts as job arrays after it, the gather "
	    "after them.\n# Each job is a make target of this directory: submitted again, it skips "
	    "what is done. A failed\n# job cancels the gather. sbatch options "
	    "(partition, account, time) come\n# from SBATCH_OPTS; arrays have "
	    "at most TL_SLURM_ARRAY tasks (default 1000:\n# Slurm's default "
	    "MaxArraySize is 1001), more make several.\nset -e\nP=", f);
	plan_word(f, c->dir, 0);
	fputs("\n", f);
	plan_slurm_funcs(f);
	fputs("w=$(job warp \"\" 'make done/warp')\n"
	    "a=$(array parts \"$w\" targets1)\n"
	    "job gather \"$a\" 'make done/gather'\n", f);
}

static void
put_targets(FILE *f, const void *arg)
{
	const ctx *c = arg;
	for (int k = 0; k < c->o->nparts; k++)
		fprintf(f, "done/p-%d\n", k);
}

/* The plan directory apart from the output ("DIR: contains the output
 * OUT"). */
static int
off_out(const char *dir, const plan_rgb_opts *o, tl_err *e)
{
	tl_paths s = { 0 };
	int r = tl_paths_add(&s, o->out, TL_PATH_OUT, e, "the output %s",
	    o->out);

	if (r == 0)
		r = tl_paths_check(&s, dir, e);
	tl_paths_free(&s);
	return r;
}

int
plan_rgb_write(const plan_rgb_opts *o, const char *dir, tl_err *e)
{
	ctx c = { o, "", "", "", "" };
	char stamp[4400], *dems[1] = { c.dem };
	struct stat st;
	tl_outfile d;

	if (plan_absolute("the plan directory", dir, c.dir, sizeof c.dir,
	    e) < 0 ||
	    plan_absolute("the DEM", o->dem, c.dem, sizeof c.dem, e) < 0 ||
	    plan_absolute("the output", o->out, c.out, sizeof c.out, e) < 0 ||
	    plan_absolute("the programs' directory",
	    o->bindir ? o->bindir : ".", c.bin, sizeof c.bin, e) < 0)
		return -1;
	for (int k = 0; k < o->nopt; k++)
		if (strchr(o->opt[k], '\n') != NULL)
			return tl_fail(e, "an option holds a newline: it "
			    "cannot go into a plan");
	/* the plan kept off the DEM and off the output */
	if (tl_path_check(dir, o->dem, "DEM", 0, e) < 0 ||
	    off_out(dir, o, e) < 0)
		return -1;
	if (stat(dir, &st) == 0)
		return tl_fail(e, "%s: exists: remove it first", dir);
	if (tl_outdir_begin(&d, dir, e) < 0)
		return -1;
	snprintf(stamp, sizeof stamp, "%s/dem.stamp", d.tmp);
	if (plan_put(d.tmp, "Makefile", 0, put_makefile, &c, e) < 0 ||
	    plan_put(d.tmp, "job", 1, put_job, &c, e) < 0 ||
	    plan_put(d.tmp, "parallel.sh", 1, put_parallel, &c, e) < 0 ||
	    plan_put(d.tmp, "slurm.sh", 1, put_slurm, &c, e) < 0 ||
	    plan_put(d.tmp, "targets1", 0, put_targets, &c, e) < 0 ||
	    dem_stamp(stamp, dems, 1, e) < 0) {
		tl_outdir_abort(&d);
		return -1;
	}
	return tl_outdir_commit(&d, e);
}
