/* plan_slurm.c - the plan for Slurm: slurm.sh, the Makefile's targets
 * submitted as jobs and arrays chained by dependencies. */
#include "jobs/plan_impl.h"

/* The script's shell functions job and array, for every plan's Slurm
 * script (the pyramid's here, the terrain's: plan_terrain.c). */
void
plan_slurm_funcs(FILE *f)
{
	fputs(
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
	    "}\n", f);
}

void
plan_slurm(FILE *f, const plan_ctx *c)
{
	const plan_opts *o = c->o;

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
	plan_word(f, c->dir, 0);
	fputs("\n", f);
	plan_slurm_funcs(f);
	fputs("if [ \"${1:-}\" != --pieces ]; then\n", f);
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
