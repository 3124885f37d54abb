/* plan_impl.h - the plan's insides, shared by plan*.c: what each
 * consumer's writer is given, the writers plan.c's table names (one file
 * each: plan_make.c, plan_job.c, plan_parallel.c, plan_slurm.c), the
 * quoting they share (plan_word.c, a leaf) and the files every plan
 * writes (plan_file.c, a leaf). Calls go one way: plan.c to the
 * writers, the writers to plan_word.c. */
#ifndef TL_PLAN_IMPL_H
#define TL_PLAN_IMPL_H

#include <stdio.h>

#include "jobs/plan.h"
#include "base/util.h"

/* What a writer is given: the plan's options (dem: dems.txt's absolute
 * path for a mosaic) and the plan's final absolute path. */
typedef struct {
	const plan_opts *o;
	const char *dir;
} plan_ctx;

/* One consumer's file of the plan: its name, whether executable, and
 * the function writing it. plan.c walks a table of them. */
typedef struct {
	const char *name;
	int exec;
	void (*write)(FILE *, const plan_ctx *);
} plan_backend;

/* The writers (the graph made concrete for each consumer). */
void plan_makefile(FILE *, const plan_ctx *);  /* make: Makefile */
void plan_mkpieces(FILE *, const plan_ctx *);  /* make: the pieces' rules */
void plan_job(FILE *, const plan_ctx *);       /* every job's wrapper */
void plan_parallel(FILE *, const plan_ctx *);  /* GNU parallel */
void plan_slurm(FILE *, const plan_ctx *);     /* Slurm */
/* Every job wrapper's lock and sweep start, and its end (plan_job.c):
 * WHAT the sweep reports gone ("records"), STAMP the file checked. */
void plan_job_head(FILE *);
void plan_job_tail(FILE *, const char *what, const char *stamp);
/* A ranges-and-gather Makefile's OPTS, JOBOPTS, goal and sweep
 * (plan_job.c; dem2rgb's and vgis2terrain's plans). */
void plan_make_sweep(FILE *, const char *const *opt, int nopt, int jobs);
/* Slurm's shell functions job and array (plan_slurm.c), for every plan. */
void plan_slurm_funcs(FILE *);

/* GNU parallel running make targets of the plan "$P". -q: parallel runs
 * its command through a shell, which would split "$P" at blanks and run
 * what it holds; quoted, it is one word whatever it holds (the targets,
 * from ::: and ::::, are always quoted). */
#define PLAN_PAR "parallel -q --will-cite --halt now,fail=1 make -C \"$P\" "

/* A word for the shell, single-quoted; make: also as make reads a
 * variable's value. plan_words: n of them, each after a blank. */
void plan_word(FILE *, const char *w, int make);
void plan_words(FILE *, const char *const *w, int n, int make);

/* File name in dir, written whole by fn(f, arg), executable or not. */
int plan_put(const char *dir, const char *name, int exec,
    void (*fn)(FILE *, const void *), const void *arg, tl_err *e);
/* p made absolute into full (n bytes); a newline, which no Makefile
 * carries, refused (what names p). */
int plan_absolute(const char *what, const char *p, char *full, size_t n,
    tl_err *e);

#endif
