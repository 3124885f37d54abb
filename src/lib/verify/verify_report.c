/* verify_report.c - the checker's report and its programs' entry:
 * tilecheck(1) and tileplay --verify both parse their options into a
 * vf_args and call vf_run. */
#include "verify/verify.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int
vf_parse_taus(vf_args *a, const char *s)
{
	char buf[1024], *tok, *save;

	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	a->ntau = 0;
	for (tok = strtok_r(buf, ",", &save); tok != NULL;
	    tok = strtok_r(NULL, ",", &save)) {
		if (a->ntau == VF_MAXTAU ||
		    tl_parse_double(tok, &a->tau[a->ntau]) < 0 ||
		    a->tau[a->ntau] < 0)
			return -1;
		a->ntau++;
	}
	return a->ntau > 0 ? 0 : -1;
}

/* Kinds that ran on this level: fold on displaced levels, the DEM ones
 * with a DEM. */
static int
ran(const vf_report *r, const vf_level *L, int k)
{
	if (k == VF_FOLD)
		return L->displaced;
	if (k == VF_ERROR || k == VF_BASE || k == VF_LOCAL ||
	    k == VF_COVERAGE)
		return r->dem;
	return 1;
}

static void
print_level(FILE *f, const vf_report *r, const vf_level *L)
{
	fprintf(f, "level %d: %dx%d vertices, %dx%d blocks (%lld read), %s\n",
	    L->level, L->size[0], L->size[1], L->blocks[0], L->blocks[1],
	    L->blocks_read, L->displaced ? "displaced (X Y)" : "1D");
	fprintf(f, "  violations:");
	for (int k = 0; k < VF_NKIND; k++) {
		if (ran(r, L, k))
			fprintf(f, " %s %lld", vf_kind_name(k), L->count[k]);
		else
			fprintf(f, " %s -", vf_kind_name(k));
	}
	fprintf(f, "\n  largest E %.6g m, base error %.6g m", L->emax,
	    L->base);
	if (r->dem)
		fprintf(f, " (finest triangles: %.6g m), largest local error "
		    "%.6g m, %lld valid samples", L->base_real, L->local_max,
		    L->samples);
	fprintf(f, "\n  %12s %12s %12s\n", "tau", "triangles",
	    r->dem ? "max error" : "");
	for (int t = 0; t < L->ntau; t++) {
		fprintf(f, "  %12.6g %12lld", L->tau[t].tau,
		    L->tau[t].triangles);
		if (r->dem)
			fprintf(f, " %12.6g", L->tau[t].maxerr);
		fputc('\n', f);
	}
	if (r->dem && !isnan(L->tight))
		fprintf(f, "  tightness: max error / tau %.4f at tau %.6g in "
		    "block (%d,%d)\n", L->tight, L->tight_tau,
		    L->tight_block[0], L->tight_block[1]);
}

static void
print_issue(FILE *f, const vf_issue *s)
{
	if (s->level >= 0)
		fprintf(f, "  level %d", s->level);
	else
		fprintf(f, "  pyramid");
	if (s->block[0] >= 0)
		fprintf(f, " block (%d,%d)", s->block[0], s->block[1]);
	if (s->vertex[0] >= 0)
		fprintf(f, " vertex (%d,%d)", s->vertex[0], s->vertex[1]);
	if (!isnan(s->tau))
		fprintf(f, " tau %.6g", s->tau);
	fprintf(f, ": %s: %s\n", vf_kind_name(s->kind), s->text);
}

void
vf_report_print(FILE *f, const vf_report *r, const char *dir,
    const char *dem_path, int max_issues)
{
	fprintf(f, "pyramid %s: %d levels, level 0 %dx%d; ", dir, r->nlevels,
	    r->size0[0], r->size0[1]);
	if (r->dem)
		fprintf(f, "DEM %s\n", dem_path);
	else
		fprintf(f, "no DEM: error, base, local, coverage not "
		    "checked\n");
	for (int l = 0; l < r->nlevels; l++)
		print_level(f, r, &r->lev[l]);
	if (r->nissue > 0) {
		fprintf(f, "violations (at most %d of each kind per level):\n",
		    max_issues);
		for (int k = 0; k < r->nissue; k++)
			print_issue(f, &r->issue[k]);
	}
	if (r->total == 0) {
		fprintf(f, "result: pass\n");
		return;
	}
	fprintf(f, "result: FAIL, %lld violations:", r->total);
	for (int k = 0; k < VF_NKIND; k++)
		if (r->count[k] > 0)
			fprintf(f, " %s %lld", vf_kind_name(k), r->count[k]);
	fputc('\n', f);
}

int
vf_run(const vf_args *a, const char *prog)
{
	vf_opts vo;
	vf_report r;
	tl_err e;
	int failed;

	vf_opts_init(&vo);
	if (a->ntau > 0) {
		vo.tau = a->tau;
		vo.ntau = a->ntau;
	}
	if (vf_check(a->dir, a->dem_path, &a->dem, &vo, &r, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		vf_report_free(&r);
		return -1;
	}
	vf_report_print(stdout, &r, a->dir, a->dem_path, vo.max_issues);
	failed = r.total > 0;
	vf_report_free(&r);
	return failed;
}
