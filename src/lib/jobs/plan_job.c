/* plan_job.c - the plan's script job, the wrapper every job of every
 * consumer runs through (plan.h), and its sweep of stale markers. */
#include "jobs/plan_impl.h"

/* The wrapper of every job (plan.h): the DEM checked, a lock, the
 * marker; and the sweep of stale markers. */
void
plan_job(FILE *f, const plan_ctx *c)
{
	(void)c;
	fputs("#!/bin/sh\n"
	    "# job B TARGET CMD...: the plan's job TARGET (done/NAME, made when "
	    "CMD\n"
	    "# succeeds; B: the programs' directory). Run once however many "
	    "runners\n"
	    "# ask for it at once (two makes, make and GNU parallel...): under "
	    "an\n"
	    "# flock(1) of done/.lock-NAME, and not when TARGET was made "
	    "meanwhile.\n"
	    "# First the DEM's files are checked as the plan recorded them "
	    "(dem.stamp).\n"
	    "# job B --sweep: the markers of jobs whose outputs are gone (work/ "
	    "or\n"
	    "# vmaps/ removed...) removed, so that make runs those jobs again; "
	    "none\n"
	    "# once the gather is done.\n", f);
	plan_job_head(f);
	fputs("\tstale() { rm -f \"$1\"; gone=\"$gone ${1#done/}\"; }\n"
	    "\tfor m in done/p-*; do\n"
	    "\t\t[ ! -e \"$m\" ] || [ -e \"work/.pieces/${m#done/p-}\" ] ||\n"
	    "\t\t    stale \"$m\"\n"
	    "\tdone\n"
	    "\tfor m in done/q-*; do # q-L-B0-B1-Y0-Y1: .parts/L-B0-B1-Y0\n"
	    "\t\tp=${m#done/q-} p=${p%-*-*} y=${m%-*} y=${y##*-}\n"
	    "\t\t[ ! -e \"$m\" ] || [ -e \"work/.parts/$p-$y\" ] ||\n"
	    "\t\t    [ -e \"work/.pieces/$p\" ] || stale \"$m\"\n"
	    "\tdone\n"
	    "\tfor m in done/b-*; do\n"
	    "\t\t[ ! -e \"$m\" ] || [ -d \"bands/${m#done/b-}\" ] || stale \"$m\"\n"
	    "\tdone\n"
	    "\t[ ! -e done/chain ] || [ -d vmaps ] || stale done/chain\n"
	    "\tif [ -e done/fill ] && [ ! -e fill.dem ] && [ -e bands/targets ]\n"
	    "\tthen\n"
	    "\t\twhile read -r m; do\n"
	    "\t\t\t[ -e \"$m\" ] || { stale done/fill; break; }\n"
	    "\t\tdone <bands/targets\n"
	    "\tfi\n", f);
	plan_job_tail(f, "outputs", "dem.stamp");
}

/* Every plan's wrapper, after its comment: the lock, and the sweep's
 * start (a sweep once the gather is done does nothing). */
void
plan_job_head(FILE *f)
{
	fputs("set -e\n"
	    "b=$1 t=$2\n"
	    "shift 2\n"
	    "mkdir -p done\n"
	    "lock() {\n"
	    "\texec 9>>\"done/.lock-$1\"\n"
	    "\tif command -v flock >/dev/null; then flock 9; fi\n"
	    "}\n"
	    "if [ \"$t\" = --sweep ]; then\n"
	    "\tlock gather\n"
	    "\t[ ! -e done/gather ] || exit 0\n"
	    "\tgone=\n", f);
}

/* ... and its end: the sweep's report of the WHAT gone, then the job
 * under its lock, after the check of the plan's STAMP. */
void
plan_job_tail(FILE *f, const char *what, const char *stamp)
{
	fprintf(f, "\t[ -z \"$gone\" ] || echo \"job: %s gone, their jobs "
	    "to be\" \\\n"
	    "\t    \"run again (done/ markers removed):$gone\" >&2\n"
	    "\texit 0\n"
	    "fi\n"
	    "lock \"${t#done/}\"\n"
	    "[ ! -e \"$t\" ] || exit 0\n"
	    "\"$b/vgis-job\" check-stamp %s\n"
	    "\"$@\" 9>&-\n"
	    "touch \"$t\"\n", what, stamp);
}

/* The end of the head of a Makefile of ranges and a gather (dem2rgb's,
 * vgis2terrain's plans): OPTS, JOBOPTS, the goal, and the sweep of
 * stale markers before a whole run or the gather. */
void
plan_make_sweep(FILE *f, const char *const *opt, int nopt, int jobs)
{
	fputs("\nOPTS =", f);
	plan_words(f, opt, nopt, 1);
	fputs("\nJOBOPTS =", f);
	if (jobs > 1)
		fprintf(f, " -j %d", jobs);
	fputs("\n\nall: done/gather\n\n"
	    "# done/ markers whose records are gone (work/ removed...) removed "
	    "first,\n# to be made again: for the whole run or the gather, not "
	    "for each job\n# that GNU parallel and Slurm run, nor for make -n "
	    "or -q\n"
	    "ifneq ($(filter all done/gather,$(or $(MAKECMDGOALS),all)),)\n"
	    "ifeq ($(findstring n,$(firstword -$(MAKEFLAGS)))$(findstring q,"
	    "$(firstword -$(MAKEFLAGS))),)\n"
	    "SWEPT := $(shell $(JOB) --sweep)\nendif\nendif\n\n", f);
}
