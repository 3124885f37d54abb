/* plan.c - a DEM-to-pyramid build as a job graph on disk (plan.h). */
#include "jobs/plan.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"

/* A word for the shell, single-quoted; for a Makefile also as make
 * reads a variable's value: $ doubled, and a '#' (a comment) escaped by a
 * backslash, the n backslashes before it doubled (make halves them, and
 * takes the rest literally). A newline no Makefile carries: plan_write
 * refuses it first (carriable). */
static void
word(FILE *f, const char *w, int make)
{
	int bs = 0;

	fputc('\'', f);
	for (const char *p = w; *p; p++) {
		if (*p == '\\' && make) {
			bs++;
			continue;
		}
		for (int k = 0; k < (*p == '#' && make ? 2 * bs + 1 : bs); k++)
			fputc('\\', f);
		bs = 0;
		if (*p == '\'')
			fputs("'\\''", f);
		else if (*p == '$' && make)
			fputs("$$", f);
		else
			fputc(*p, f);
	}
	while (bs-- > 0)
		fputc('\\', f);
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

static void
makefile(FILE *f, const plan_opts *o)
{
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
	words(f, &o->bindir, 1, 1);
	fputs("\nJOB = sh job $(B)", f);
	fputs("\nDEM =", f);
	words(f, &o->dem, 1, 1);
	fputs("\nOUT =", f);
	words(f, &o->out, 1, 1);
	fputs("\nDEMOPTS =", f);
	words(f, o->demopt, o->ndemopt, 1);
	fputs("\nCHAINOPTS =", f);
	words(f, o->chainopt, o->nchainopt, 1);
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

static void
mkpieces(FILE *f)
{
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

/* The wrapper of every job (plan.h): the DEM checked, a lock, the
 * marker; and the sweep of stale markers. */
static void
job(FILE *f)
{
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
	    "# once the gather is done.\n"
	    "set -e\n"
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
	    "\tgone=\n"
	    "\tstale() { rm -f \"$1\"; gone=\"$gone ${1#done/}\"; }\n"
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
	    "\tfi\n"
	    "\t[ -z \"$gone\" ] || echo \"job: outputs gone, their jobs to be\" \\\n"
	    "\t    \"run again (done/ markers removed):$gone\" >&2\n"
	    "\texit 0\n"
	    "fi\n"
	    "lock \"${t#done/}\"\n"
	    "[ ! -e \"$t\" ] || exit 0\n"
	    "\"$b/vgis-job\" check-stamp dem.stamp\n"
	    "\"$@\" 9>&-\n"
	    "touch \"$t\"\n", f);
}

/* -q: parallel runs its command through a shell, which would split "$P"
 * at blanks and run what it holds; quoted, it is one word whatever it
 * holds (the targets, from ::: and ::::, are always quoted). */
#define PAR "parallel -q --will-cite --halt now,fail=1 make -C \"$P\" "

static void
parallel(FILE *f, const plan_opts *o, const char *dir)
{
	fputs("#!/bin/sh\n"
	    "# GNU parallel, stage by stage: the chain (the fill, the bands, "
	    "the rest, when\n# split), the pieces' parts, the pieces, the "
	    "gather. Each job is "
	    "a make target of this directory,\n# so a run again skips what "
	    "is done. Its options come from PARALLEL, e.g.\n"
	    "# PARALLEL='--sshloginfile hosts -j 4' for machines that share "
	    "this file\n# system (same paths).\nset -e\nP=", f);
	word(f, dir, 0);
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

static void
slurm(FILE *f, const plan_opts *o, const char *dir)
{
	/* The jobs run in the plan (-D), so that their commands (--wrap, a
	 * line of sh) need not name it: any name, quotes included. A job
	 * whose dependency failed is cancelled (--kill-on-invalid-dep),
	 * not left pending for ever. */
	fputs("#!/bin/sh\n"
	    "# Slurm: the chain (split: the fill, the bands as an array, the rest),\n"
	    "# then a job submitting the pieces' parts and the pieces as arrays and\n"
	    "# the gather after them (they are known once the chain has run). Each\n"
	    "# job is a make target of this directory: submitted again, it skips what\n"
	    "# is done. A failed job cancels those after it. sbatch options\n"
	    "# (partition, account, time) come from SBATCH_OPTS; arrays have at most\n"
	    "# TL_SLURM_ARRAY tasks (default 1000: Slurm's default MaxArraySize is\n"
	    "# 1001), more make several.\n"
	    "set -e\n", f);
	fputs("P=", f);
	word(f, dir, 0);
	fputs("\n"
	    "# job NAME DEP CMD [OPTION...]: a job running CMD (a line of sh) in the\n"
	    "# plan after the jobs DEP (ids a:b:..., or none); prints its id\n"
	    "job() {\n"
	    "\tj=$1 d=$2 c=$3; shift 3\n"
	    "\tsbatch --parsable $SBATCH_OPTS -J \"$j\" -D \"$P\" \"$@\" \\\n"
	    "\t    ${d:+--dependency=afterok:$d --kill-on-invalid-dep=yes} --wrap \"$c\"\n"
	    "}\n"
	    "# array NAME DEP LIST: the make targets of LIST (a line each) as job\n"
	    "# arrays after the jobs DEP; prints their ids joined by ':'\n"
	    "array() {\n"
	    "\tn=$(wc -l <\"$P/$3\") m=${TL_SLURM_ARRAY:-1000} o=0 ids=\n"
	    "\twhile [ \"$o\" -lt \"$n\" ]; do\n"
	    "\t\tk=$((n - o < m ? n - o : m))\n"
	    "\t\tw=\"make \\\"\\$(sed -n \\$((SLURM_ARRAY_TASK_ID + $o))p $3)\\\"\"\n"
	    "\t\tid=$(job \"$1\" \"$2\" \"$w\" --array=1-$k)\n"
	    "\t\tids=${ids:+$ids:}$id o=$((o + k))\n"
	    "\tdone\n"
	    "\techo \"$ids\"\n"
	    "}\n"
	    "if [ \"${1:-}\" != --pieces ]; then\n", f);
	if (o->nfill > 0)
		fputs("\tf=$(array fill1 \"\" bands/fill1)\n"
		    "\tf=$(job join \"$f\" 'make done/fill-join')\n"
		    "\tf=$(array fill2 \"$f\" bands/fill2)\n"
		    "\tf=$(job fill \"$f\" 'make done/fill')\n", f);
	else if (o->nbands > 0)
		fputs("\tf=$(job fill \"\" 'make done/fill')\n", f);
	fputs(o->nbands > 0 ?
	    "\tb=$(array bands \"$f\" bands/targets)\n"
	    "\tc=$(job chain \"$b\" 'make done/pieces.mk')\n" :
	    "\tc=$(job chain \"\" 'make done/pieces.mk')\n", f);
	fputs("\tjob submit \"$c\" 'sh slurm.sh --pieces'\n"
	    "\texit 0\n"
	    "fi\n"
	    "q=$(array parts \"\" done/parts)\n"
	    "a=$(array pieces \"$q\" done/targets)\n"
	    "job gather \"$a\" 'make done/gather'\n", f);
}

/* File name in dir, written by fn, executable or not. */
static int
put(const char *dir, const char *name, int exec,
    void (*fn)(FILE *, const void *), const void *arg, tl_err *e)
{
	char path[4400];
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
put_job(FILE *f, const void *o)
{
	(void)o;
	job(f);
}

/* The scripts need the plan's options and its final path. */
typedef struct {
	const plan_opts *o;
	const char *dir;
} script;

static void
put_parallel(FILE *f, const void *arg)
{
	const script *s = arg;

	parallel(f, s->o, s->dir);
}

static void
put_slurm(FILE *f, const void *arg)
{
	const script *s = arg;

	slurm(f, s->o, s->dir);
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
		if (put(sub, list, 0, put_bandlist, &b, e) < 0)
			return -1;
	}
	return put(sub, "targets", 0, put_targets, &bands, e) < 0 ||
	    (o->nfill > 0 && (put(sub, "fill1", 0, put_targets, &f1, e) < 0 ||
	    put(sub, "fill2", 0, put_targets, &f2, e) < 0)) ? -1 : 0;
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
 * consumer: make, sh, GNU parallel (word, PAR) and sbatch (slurm). The
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
	script sc = { o, full };
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
	if ((o->ndem > 0 && put(d.tmp, "dems.txt", 0, put_list, o, e) < 0) ||
	    put(d.tmp, "Makefile", 0, put_makefile, &q, e) < 0 ||
	    put(d.tmp, "mkpieces", 1, put_mkpieces, o, e) < 0 ||
	    put(d.tmp, "job", 1, put_job, o, e) < 0 ||
	    copy(d.tmp, "dem.stamp", o->stamp, e) < 0 ||
	    put(d.tmp, "parallel.sh", 1, put_parallel, &sc, e) < 0 ||
	    put(d.tmp, "slurm.sh", 1, put_slurm, &sc, e) < 0 ||
	    put_bands(d.tmp, o, e) < 0) {
		tl_outdir_abort(&d);
		return -1;
	}
	return tl_outdir_commit(&d, e);
}
