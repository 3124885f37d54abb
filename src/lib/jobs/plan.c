/* plan.c - a DEM-to-pyramid build as a job graph on disk (plan.h). */
#include "jobs/plan.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/outfile.h"

/* A word for the shell, single-quoted; for a Makefile, $ doubled as make
 * wants. */
static void
word(FILE *f, const char *w, int make)
{
	fputc('\'', f);
	for (const char *p = w; *p; p++)
		if (*p == '\'')
			fputs("'\\''", f);
		else if (*p == '$' && make)
			fputs("$$", f);
		else
			fputc(*p, f);
	fputc('\'', f);
}

static void
words(FILE *f, const char *const *w, int n, int make)
{
	for (int i = 0; i < n; i++) {
		fputc(' ', f);
		word(f, w[i], make);
	}
}

static void
makefile(FILE *f, const plan_opts *o)
{
	fprintf(f, "# Made by %s --plan: builds the pyramid %s\n# from %s.\n"
	    "# Run: make -C THIS-DIRECTORY -j N, and again after a failure "
	    "or a kill:\n# it goes on where it stopped. The jobs: "
	    "done/chain (the quadric chain,\n# every level's vertex map into "
	    "vmaps/), done/p-L-B0-B1 (tilepack -p: one\n# piece into work/), "
	    "done/gather (tilepack -g: work/ becomes the pyramid).\n",
	    o->prog, o->out, o->dem);
	fputs("SHELL = /bin/sh\nB =", f);
	words(f, &o->bindir, 1, 1);
	fputs("\nDEM =", f);
	words(f, &o->dem, 1, 1);
	fputs("\nOUT =", f);
	words(f, &o->out, 1, 1);
	fputs("\nDEMOPTS =", f);
	words(f, o->demopt, o->ndemopt, 1);
	fputs("\nCHAINOPTS =", f);
	words(f, o->chainopt, o->nchainopt, 1);
	fputs("\nV =", f);
	for (int l = 0; l < o->levels; l++)
		fprintf(f, " vmaps/v%d.fqm", l);
	fprintf(f, "\n\n"
	    "all: done/gather\n\n"
	    "done/chain:\n"
	    "\tmkdir -p done\n"
	    "\t$(B)/dem2vgis -M $(CHAINOPTS) $(DEM) vmaps\n"
	    "\ttouch $@\n\n"
	    "# the pieces, known once the vertex maps are: a rule each\n"
	    "done/pieces.mk: done/chain\n"
	    "\t$(B)/tilepack -l $(DEMOPTS) $(DEM) - $(V) >done/pieces.tmp\n"
	    "\tsed 's/:/-/g; s|^|done/p-|' done/pieces.tmp >done/targets\n"
	    "\tsh mkpieces done/pieces.tmp >$@.tmp\n"
	    "\tmv $@.tmp $@\n\n"
	    "-include done/pieces.mk\n\n"
	    "done/gather: done/pieces.mk $(PIECES)\n"
	    "\t$(B)/tilepack -q%s -g work $(DEMOPTS) $(DEM) $(OUT) $(V)\n"
	    "\ttouch $@\n", o->force ? " -f" : "");
}

static void
mkpieces(FILE *f)
{
	fputs("#!/bin/sh\n"
	    "# mkpieces LIST: the Makefile's rules for the pieces (tilepack "
	    "-l's lines)\n"
	    "printf 'PIECES ='\n"
	    "while read -r p; do printf ' done/p-%s' \"$(echo \"$p\" | tr : -)\"; "
	    "done <\"$1\"\n"
	    "echo\n"
	    "while read -r p; do\n"
	    "\tt=done/p-$(echo \"$p\" | tr : -)\n"
	    "\tprintf '%s: done/chain\\n\\t$(B)/tilepack -j 1 -p %s "
	    "$(DEMOPTS) $(DEM) work $(V)\\n\\ttouch $@\\n' \"$t\" \"$p\"\n"
	    "done <\"$1\"\n", f);
}

static void
parallel(FILE *f, const char *dir)
{
	fputs("#!/bin/sh\n"
	    "# GNU parallel, stage by stage: the chain, the pieces, the "
	    "gather. Each job is\n# a make target of this directory, so a run "
	    "again skips what is done. Its\n# options come from PARALLEL, e.g. "
	    "PARALLEL='--sshloginfile hosts -j 4' for\n# machines that share "
	    "this file system (same paths).\nset -e\nP=", f);
	word(f, dir, 0);
	fputs("\nparallel --will-cite --halt now,fail=1 make -C \"$P\" ::: done/pieces.mk\n"
	    "parallel --will-cite --halt now,fail=1 make -C \"$P\" :::: \"$P/done/targets\"\n"
	    "parallel --will-cite --halt now,fail=1 make -C \"$P\" ::: done/gather\n", f);
}

static void
slurm(FILE *f, const char *dir)
{
	/* The jobs run in the plan (-D), so that their commands (--wrap, a
	 * line of sh) need not name it: any name, quotes included. A job
	 * whose dependency failed is cancelled (--kill-on-invalid-dep),
	 * not left pending for ever. */
	fputs("#!/bin/sh\n"
	    "# Slurm: the chain, then a job submitting the pieces as an array "
	    "and the\n# gather after them (the pieces are known once the "
	    "chain has run). Each job\n# is a make target of this directory: "
	    "submitted again, it skips what is done.\n# A failed job cancels "
	    "those after it. sbatch options (partition, account,\n# time) "
	    "come from SBATCH_OPTS.\n"
	    "set -e\nP=", f);
	word(f, dir, 0);
	fputs("\nif [ \"${1:-}\" != --pieces ]; then\n"
	    "\tc=$(sbatch --parsable $SBATCH_OPTS -J chain -D \"$P\" "
	    "--wrap 'make done/pieces.mk')\n"
	    "\tsbatch --parsable $SBATCH_OPTS -J submit -D \"$P\" "
	    "--dependency=afterok:$c --kill-on-invalid-dep=yes "
	    "--wrap 'sh slurm.sh --pieces'\n"
	    "\texit 0\nfi\n"
	    "n=$(wc -l <\"$P/done/targets\")\n"
	    "a=$(sbatch --parsable $SBATCH_OPTS -J pieces -D \"$P\" "
	    "--array=1-$n --wrap 'make \"$(sed -n \"${SLURM_ARRAY_TASK_ID}p\" "
	    "done/targets)\"')\n"
	    "sbatch --parsable $SBATCH_OPTS -J gather -D \"$P\" "
	    "--dependency=afterok:$a --kill-on-invalid-dep=yes "
	    "--wrap 'make done/gather'\n", f);
}

/* File name in dir, written by fn, executable or not. */
static int
put(const char *dir, const char *name, int exec,
    void (*fn)(FILE *, const void *), const void *arg, tl_err *e)
{
	char path[4096];
	FILE *f;

	snprintf(path, sizeof path, "%s/%s", dir, name);
	if ((f = fopen(path, "w")) == NULL)
		return tl_failsys(e, "%s", path);
	fn(f, arg);
	if (fclose(f) != 0)
		return tl_failsys(e, "%s", path);
	if (exec && chmod(path, 0755) != 0)
		return tl_failsys(e, "%s", path);
	return 0;
}

static void
put_makefile(FILE *f, const void *o)
{
	makefile(f, o);
}

static void
put_mkpieces(FILE *f, const void *o)
{
	(void)o;
	mkpieces(f);
}

static void
put_parallel(FILE *f, const void *dir)
{
	parallel(f, dir);
}

static void
put_slurm(FILE *f, const void *dir)
{
	slurm(f, dir);
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

int
plan_write(const plan_opts *o, const char *dir, tl_err *e)
{
	char full[4096], list[4200], cwd[4096];
	plan_opts q = *o;
	struct stat st;
	tl_outfile d;

	if (!o->force && stat(dir, &st) == 0)
		return tl_fail(e, "%s: exists; use -f to replace it", dir);
	/* the scripts name the plan by its final absolute path */
	if (dir[0] != '/' && getcwd(cwd, sizeof cwd) == NULL)
		return tl_failsys(e, "current directory");
	if (snprintf(full, sizeof full, "%s%s%s", dir[0] == '/' ? "" : cwd,
	    dir[0] == '/' ? "" : "/", dir) >= (int)sizeof full)
		return tl_fail(e, "%s: name too long", dir);
	snprintf(list, sizeof list, "%s/dems.txt", full);
	if (o->ndem > 0)
		q.dem = list;
	if (tl_outdir_begin(&d, dir, e) < 0)
		return -1;
	if ((o->ndem > 0 && put(d.tmp, "dems.txt", 0, put_list, o, e) < 0) ||
	    put(d.tmp, "Makefile", 0, put_makefile, &q, e) < 0 ||
	    put(d.tmp, "mkpieces", 1, put_mkpieces, o, e) < 0 ||
	    put(d.tmp, "parallel.sh", 1, put_parallel, full, e) < 0 ||
	    put(d.tmp, "slurm.sh", 1, put_slurm, full, e) < 0) {
		tl_outdir_abort(&d);
		return -1;
	}
	return tl_outdir_commit(&d, e);
}
