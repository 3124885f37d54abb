/* plan_parallel.c - the plan for GNU parallel: parallel.sh, the
 * Makefile's targets stage by stage. */
#include "jobs/plan_impl.h"

#define PAR PLAN_PAR

void
plan_parallel(FILE *f, const plan_ctx *c)
{
	const plan_opts *o = c->o;

	fputs("#!/bin/sh\n"
	    "# GNU parallel, stage by stage: the chain (the fill, the bands, "
	    "the rest, when\n# split), the pieces' parts, the pieces, the "
	    "gather. Each job is "
	    "a make target of this directory,\n# so a run again skips what "
	    "is done. Its options come from PARALLEL, e.g.\n"
	    "# PARALLEL='--sshloginfile hosts -j 4' for machines that share "
	    "this file\n# system (same paths).\nset -e\nP=", f);
	plan_word(f, c->dir, 0);
	if (o->nfill > 0)
		fputs("\n" PAR ":::: \"$P/bands/fill1\"\n"
		    PAR "::: done/fill-join\n"
		    PAR ":::: \"$P/bands/fill2\"", f);
	if (o->nbands > 0)
		fputs("\n" PAR "::: done/fill\n"
		    PAR ":::: \"$P/bands/targets\"", f);
	fputs("\n" PAR "::: done/pieces.mk\n"
	    PAR ":::: \"$P/done/parts\"\n"
	    PAR ":::: \"$P/done/targets\"\n"
	    PAR "::: done/gather\n", f);
}
