/* plan_make.c - the plan for make: the Makefile, which holds the job
 * graph (the chain, the fill, the bands, the pieces, the gather), and
 * mkpieces, which adds the pieces' rules once the chain has run. */
#include "jobs/plan_impl.h"

/* The vertex maps tilepack reads: the bands' lists below band_levels. */
static void
vmaps(FILE *f, const plan_opts *o)
{
	fputs("\nV =", f);
	for (int l = 0; l < o->levels; l++)
		if (l < o->band_levels)
			fprintf(f, " bands/v%d.bands", l);
		else
			fprintf(f, " vmaps/v%d.fqm", l);
}

/* A part of the fill: vgis-job fill's pass PASS (filled(5)), its scratch
 * here beside fill.dem, not in one machine's TMPDIR. */
static void
fill_part(FILE *f, const plan_opts *o, const char *pass, int k)
{
	fprintf(f, "\t$(JOB) $@ env TMPDIR=. $(B)/vgis-job fill --pass %s ",
	    pass);
	if (k >= 0) {
		int y1 = (k + 1) * o->fillrows;
		fprintf(f, "--rows %d,%d", k * o->fillrows,
		    y1 < o->height ? y1 : o->height);
	} else
		fprintf(f, "--band-rows %d", o->fillrows);
	fputs(" $(DEMOPTS) $(DEM) fill.dem\n\n", f);
}

/* The DEM converted and its voids filled once (the fill reaches across
 * it), as one job or in row bands: a void's neighbours along its row
 * are in its band, and across rows a band needs only each column's
 * nearest valid samples above and below it, which the join finds. */
static void
fill(FILE *f, const plan_opts *o)
{
	if (o->nfill == 0) {
		fputs("done/fill:\n"
		    "\t$(JOB) $@ env TMPDIR=. $(B)/vgis-job fill $(DEMOPTS) "
		    "$(DEM) fill.dem\n\n", f);
		return;
	}
	for (int pass = 1; pass <= 2; pass++) {
		fprintf(f, "F%d =", pass);
		for (int k = 0; k < o->nfill; k++)
			fprintf(f, " done/f%d-%d", pass, k);
		fputc('\n', f);
	}
	fputc('\n', f);
	for (int k = 0; k < o->nfill; k++) {
		fprintf(f, "done/f1-%d:\n", k);
		fill_part(f, o, "1", k);
	}
	fputs("done/fill-join: $(F1)\n", f);
	fill_part(f, o, "join", -1);
	for (int k = 0; k < o->nfill; k++) {
		fprintf(f, "done/f2-%d: done/fill-join\n", k);
		fill_part(f, o, "2", k);
	}
	fputs("done/fill: $(F2)\n", f);
	fill_part(f, o, "commit", -1);
}

/* The chain as one job, or as the fill, the bands and the rest. */
static void
chain(FILE *f, const plan_opts *o)
{
	if (o->nbands == 0) {
		fputs("done/chain:\n"
		    "\t$(JOB) $@ $(B)/vgis-job chain $(CHAINOPTS) $(DEM) vmaps\n\n",
		    f);
		return;
	}
	fputs("BANDS =", f);
	for (int k = 0; k < o->nbands; k++)
		fprintf(f, " done/b-%d", k);
	fputs("\n\n", f);
	fill(f, o);
	for (int k = 0; k < o->nbands; k++) {
		int a = k * o->bandw;
		int b = k == o->nbands - 1 ? o->width : a + o->bandw;
		fprintf(f, "done/b-%d: done/fill\n"
		    "\t$(JOB) $@ $(B)/vgis-job chain --band %d,%d --band-levels %d "
		    "--fill fill.dem $(CHAINOPTS) $(DEM) bands/%d\n\n", k, a, b,
		    o->band_levels, k);
	}
	fprintf(f, "done/chain: $(BANDS)\n"
	    "\t$(JOB) $@ $(B)/vgis-job chain --from bands/f.bands $(CHAINOPTS) "
	    "$(DEM) vmaps\n\n");
}

void
plan_makefile(FILE *f, const plan_ctx *c)
{
	const plan_opts *o = c->o;

	fprintf(f, "# Made by %s --plan: builds the pyramid %s\n# from %s.\n"
	    "# Run: make -C THIS-DIRECTORY -j N, and again after a failure "
	    "or a kill:\n# it goes on where it stopped. Each job is a step "
	    "of vgis-job(1): done/chain\n# (the quadric chain, every level's "
	    "vertex map into vmaps/), done/p-L-B0-B1\n# (one piece into "
	    "work/; a piece whose window of the DEM holds more samples\n"
	    "# than -b allows after its parts done/q-L-B0-B1-Y0-Y1, each "
	    "scanning DEM rows\n# Y0..Y1-1), done/gather (work/ becomes the "
	    "pyramid).\n", o->prog, o->out, o->dem);
	if (o->nbands > 0)
		fprintf(f, "# The chain is split into %d column bands: done/fill "
		    "(the DEM, its voids\n# filled), done/b-K (levels 0..%d "
		    "of band K into bands/K), then done/chain\n# (levels %d.. "
		    "from the bands' FQMs of level %d).\n", o->nbands,
		    o->band_levels - 1, o->band_levels, o->band_levels);
	fputs("SHELL = /bin/sh\nB =", f);
	plan_words(f, &o->bindir, 1, 1);
	fputs("\nJOB = sh job $(B)", f);
	fputs("\nDEM =", f);
	plan_words(f, &o->dem, 1, 1);
	fputs("\nOUT =", f);
	plan_words(f, &o->out, 1, 1);
	fputs("\nDEMOPTS =", f);
	plan_words(f, o->demopt, o->ndemopt, 1);
	fputs("\nCHAINOPTS =", f);
	plan_words(f, o->chainopt, o->nchainopt, 1);
	fputs("\nPARTOPTS =", f);
	if (o->part_samples >= 0)
		fprintf(f, " -b %lld", o->part_samples);
	vmaps(f, o);
	fputs("\n\nall: done/gather\n\n"
	    "# done/ markers whose outputs are gone (work/ removed...) removed "
	    "first,\n# to be made again: for the whole build or the gather, "
	    "not for each\n# job that GNU parallel and Slurm run, nor for "
	    "make -n or -q\n"
	    "ifneq ($(filter all done/gather,$(or $(MAKECMDGOALS),all)),)\n"
	    "ifeq ($(findstring n,$(firstword -$(MAKEFLAGS)))$(findstring q,"
	    "$(firstword -$(MAKEFLAGS))),)\n"
	    "SWEPT := $(shell $(JOB) --sweep)\nendif\nendif\n\n", f);
	chain(f, o);
	fprintf(f, "# the pieces, known once the vertex maps are: a rule each\n"
	    "done/pieces.mk: done/chain\n"
	    "\t$(JOB) $@ sh mkpieces $(B)/vgis-job pieces $(PARTOPTS) "
	    "$(DEMOPTS) $(DEM) $(V)\n\n"
	    "# made (and read again) for any goal but the chain's band stages\n"
	    "# alone, which GNU parallel and Slurm run before it\n"
	    "ifneq ($(filter-out done/fill done/fill-join done/f1-%% "
	    "done/f2-%% done/b-%%,$(or $(MAKECMDGOALS),all)),)\n"
	    "-include done/pieces.mk\n"
	    "endif\n\n"
	    "done/gather: done/pieces.mk $(PIECES)\n"
	    "\t$(JOB) $@ $(B)/vgis-job gather%s $(DEMOPTS) work $(DEM) $(OUT) "
	    "$(V)\n", o->force ? " -f" : "");
}

void
plan_mkpieces(FILE *f, const plan_ctx *c)
{
	(void)c;
	fputs("#!/bin/sh\n"
	    "# mkpieces CMD...: CMD, vgis-job pieces, lists the pieces into\n"
	    "# done/pieces.tmp (level:b0:b1 a piece, level:b0:b1:y0:y1 a part of\n"
	    "# one, before it); then the Makefile's rules for their jobs into\n"
	    "# done/pieces.mk, the parts' targets into done/parts, the pieces'\n"
	    "# into done/targets, a line each\n"
	    "set -e\n"
	    "\"$@\" >done/pieces.tmp\n"
	    ": >done/parts\n"
	    ": >done/targets\n"
	    "tr : - <done/pieces.tmp | awk '\n"
	    "BEGIN { FS = \"-\" }\n"
	    "NF == 5 {\n"
	    "\tq = \"done/q-\" $0\n"
	    "\tprint q >\"done/parts\"\n"
	    "\tdeps[$1 \"-\" $2 \"-\" $3] = deps[$1 \"-\" $2 \"-\" $3] \" \" q\n"
	    "\tprintf \"%s: done/chain\\n\\t$(JOB) $@ $(B)/vgis-job part \" \\\n"
	    "\t    \"$(PARTOPTS) $(DEMOPTS) %s:%s:%s:%s:%s $(DEM) work \" \\\n"
	    "\t    \"$(V)\\n\", q, $1, $2, $3, $4, $5\n"
	    "}\n"
	    "NF == 3 {\n"
	    "\tp = \"done/p-\" $0\n"
	    "\tprint p >\"done/targets\"\n"
	    "\tlist = list \" \" p\n"
	    "\tprintf \"%s: done/chain%s\\n\\t$(JOB) $@ $(B)/vgis-job piece \" \\\n"
	    "\t    \"$(PARTOPTS) $(DEMOPTS) %s:%s:%s $(DEM) work $(V)\\n\", \\\n"
	    "\t    p, deps[$0], $1, $2, $3\n"
	    "}\n"
	    "END { print \"PIECES =\" list }\n"
	    "' >done/pieces.mk.tmp\n"
	    "mv done/pieces.mk.tmp done/pieces.mk\n", f);
}
