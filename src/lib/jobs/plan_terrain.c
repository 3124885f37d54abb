/* plan_terrain.c - the terrain export's plan on disk (plan_terrain.h):
 * the Makefile of the rounds and the gather, the job wrapper, the lists
 * of each round's targets, the scripts for GNU parallel and Slurm, and
 * the pyramid's stamp. */
#include "jobs/plan_terrain.h"

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
	const plan_terrain_opts *o;
	char dir[4096], pyr[4096], out[4096], bin[4096];
} ctx;

static void
make_range(FILE *f, const int *r, int round)
{
	fprintf(f, "done/t%d-%d-%d-%d:", round, r[0], r[1], r[2]);
	if (round == 2)
		fprintf(f, " $(L%d)", r[0]);
	fprintf(f, "\n\t$(JOB) $@ $(B)/vgis-job terrain-part%s $(JOBOPTS) "
	    "$(OPTS) %d:%d:%d $(PYR) work\n\n", round == 2 ? " --settle" : "",
	    r[0], r[1], r[2]);
}

static void
put_makefile(FILE *f, const void *arg)
{
	const ctx *c = arg;
	const plan_terrain_opts *o = c->o;
	const char *const pyr = c->pyr, *const out = c->out, *bin = c->bin;

	fprintf(f, "# Made by %s --plan: the terrain %s\n# of the pyramid %s.\n"
	    "# Run: make -C THIS-DIRECTORY -j N, and again after a failure "
	    "or a kill:\n# it goes on where it stopped. Each job is a step "
	    "of vgis-job(1):\n# done/t1-Z-I0-I1 (round 1: tiles I0..I1-1 of "
	    "level Z into work/, at the\n# first try at which they hold), "
	    "done/t2-Z-I0-I1 (round 2, once level Z's\n# round 1 is done: "
	    "from the level's largest try), done/gather (work/\n# becomes "
	    "the terrain).\n", o->prog, c->out, c->pyr);
	fputs("SHELL = /bin/sh\nB =", f);
	plan_words(f, &bin, 1, 1);
	fputs("\nJOB = sh job $(B)\nPYR =", f);
	plan_words(f, &pyr, 1, 1);
	fputs("\nOUT =", f);
	plan_words(f, &out, 1, 1);
	plan_make_sweep(f, o->opt, o->nopt, o->jobs);
	for (int k = 0; k < o->nrange; k++) {
		const int *r = o->range[k];
		if (k == 0 || r[0] != o->range[k - 1][0])
			fprintf(f, "%sL%d =", k ? "\n" : "", r[0]);
		fprintf(f, " done/t1-%d-%d-%d", r[0], r[1], r[2]);
	}
	fputs("\nT2 =", f);
	for (int k = 0; k < o->nrange; k++)
		fprintf(f, " done/t2-%d-%d-%d", o->range[k][0], o->range[k][1],
		    o->range[k][2]);
	fputs("\n\n", f);
	for (int k = 0; k < o->nrange; k++)
		make_range(f, o->range[k], 1), make_range(f, o->range[k], 2);
	fputs("done/gather: $(T2)\n"
	    "\t$(JOB) $@ $(B)/vgis-job terrain-gather $(OPTS) $(PYR) work "
	    "$(OUT)\n", f);
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
	    "First the pyramid is checked as the plan\n# recorded it "
	    "(pyramid.stamp).\n"
	    "# job B --sweep: the markers of ranges whose records "
	    "(work.ranges/) or\n# tiles (work/) are gone removed, so that make "
	    "runs them again; none once\n# the gather is done.\n", f);
	plan_job_head(f);
	fputs("\tfor m in done/t1-* done/t2-*; do # tR-Z-I0-I1: "
	    "work.ranges/Z-I0.R\n"
	    "\t\t[ -e \"$m\" ] || continue\n"
	    "\t\tn=${m#done/t} n=${n%%-*} r=${m#done/t?-} r=${r%-*}\n"
	    "\t\t[ -d work ] && [ -e \"work.ranges/$r.$n\" ] && continue\n"
	    "\t\trm -f \"$m\"; gone=\"$gone ${m#done/}\"\n"
	    "\tdone\n", f);
	plan_job_tail(f, "records", "pyramid.stamp");
}

static void
put_parallel(FILE *f, const void *arg)
{
	const ctx *c = arg;
	fputs("#!/bin/sh\n"
	    "# GNU parallel, stage by stage: round 1 of every range, round 2, "
	    "the gather.\n# Each job is a make target of this directory, so a "
	    "run again skips what is\n# done. Its options come from PARALLEL, "
	    "e.g. PARALLEL='--sshloginfile hosts\n# -j 4' for machines that "
	    "share this file system (same paths).\nset -e\nP=", f);
	plan_word(f, c->dir, 0);
	fputs("\n" PLAN_PAR ":::: \"$P/targets1\"\n"
	    PLAN_PAR ":::: \"$P/targets2\"\n"
	    PLAN_PAR "::: done/gather\n", f);
}

static void
put_slurm(FILE *f, const void *arg)
{
	const ctx *c = arg;
	fputs("#!/bin/sh\n"
	    "# Slurm: round 1 of every range as job arrays, round 2 as arrays "
	    "after\n# them, the gather after those. Each job is a make target "
	    "of this\n# directory: submitted again, it skips what is done. A "
	    "failed job cancels\n# those after it. sbatch options (partition, "
	    "account, time) come from\n# SBATCH_OPTS; arrays have at most "
	    "TL_SLURM_ARRAY tasks (default 1000:\n# Slurm's default "
	    "MaxArraySize is 1001), more make several.\nset -e\nP=", f);
	plan_word(f, c->dir, 0);
	fputs("\n", f);
	plan_slurm_funcs(f);
	fputs("a=$(array round1 \"\" targets1)\n"
	    "b=$(array round2 \"$a\" targets2)\n"
	    "job gather \"$b\" 'make done/gather'\n", f);
}

static void
put_targets(FILE *f, const ctx *c, int round)
{
	for (int k = 0; k < c->o->nrange; k++)
		fprintf(f, "done/t%d-%d-%d-%d\n", round, c->o->range[k][0],
		    c->o->range[k][1], c->o->range[k][2]);
}

static void
put_targets1(FILE *f, const void *arg)
{
	put_targets(f, arg, 1);
}

static void
put_targets2(FILE *f, const void *arg)
{
	put_targets(f, arg, 2);
}

int
plan_terrain_write(const plan_terrain_opts *o, const char *dir, tl_err *e)
{
	ctx c = { o, "", "", "", "" };
	char index[4200], stamp[4400], *files[1] = { index };
	struct stat st;
	tl_outfile d;

	if (plan_absolute("the plan directory", dir, c.dir, sizeof c.dir,
	    e) < 0 ||
	    plan_absolute("the pyramid", o->pyr, c.pyr, sizeof c.pyr, e) < 0 ||
	    plan_absolute("the terrain", o->out, c.out, sizeof c.out, e) < 0 ||
	    plan_absolute("the programs' directory",
	    o->bindir ? o->bindir : ".", c.bin, sizeof c.bin, e) < 0)
		return -1;
	for (int k = 0; k < o->nopt; k++)
		if (strchr(o->opt[k], '\n') != NULL)
			return tl_fail(e, "an option holds a newline: it "
			    "cannot go into a plan");
	/* the plan kept off the pyramid, as OUTDIR is (paths.h) */
	if (tl_path_check(dir, o->pyr, "pyramid", TL_PATH_TREE, e) < 0)
		return -1;
	if (stat(dir, &st) == 0)
		return tl_fail(e, "%s: exists: remove it first", dir);
	snprintf(index, sizeof index, "%s/index.json", c.pyr);
	if (tl_outdir_begin(&d, dir, e) < 0)
		return -1;
	snprintf(stamp, sizeof stamp, "%s/pyramid.stamp", d.tmp);
	if (plan_put(d.tmp, "Makefile", 0, put_makefile, &c, e) < 0 ||
	    plan_put(d.tmp, "job", 1, put_job, &c, e) < 0 ||
	    plan_put(d.tmp, "parallel.sh", 1, put_parallel, &c, e) < 0 ||
	    plan_put(d.tmp, "slurm.sh", 1, put_slurm, &c, e) < 0 ||
	    plan_put(d.tmp, "targets1", 0, put_targets1, &c, e) < 0 ||
	    plan_put(d.tmp, "targets2", 0, put_targets2, &c, e) < 0 ||
	    stamp_write(stamp, files, 1, e) < 0) {
		tl_outdir_abort(&d);
		return -1;
	}
	return tl_outdir_commit(&d, e);
}
