/* t_verify_report - the checker's programs' side (verify_report.c): --tau
 * parsing, kind names, the report printed for a report made by hand
 * (without and with the DEM, passing and failing, every kind of issue
 * line), vf_run on no pyramid. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "verify/verify.h"
#include "tap.h"

static void
test_taus(void)
{
	char many[1024] = "0";
	vf_args a = { 0 };

	ok(vf_parse_taus(&a, "0.5,2,8") == 0 && a.ntau == 3 &&
	    a.tau[0] == 0.5 && a.tau[1] == 2 && a.tau[2] == 8,
	    "--tau 0.5,2,8: three taus");
	ok(vf_parse_taus(&a, "1,x") < 0 && vf_parse_taus(&a, "-1") < 0 &&
	    vf_parse_taus(&a, "") < 0 && vf_parse_taus(&a, "1e400") < 0,
	    "--tau refuses 1,x, -1, nothing, an overflow");
	for (int k = 1; k < VF_MAXTAU; k++)
		strcat(many, ",1");
	ok(vf_parse_taus(&a, many) == 0 && a.ntau == VF_MAXTAU,
	    "--tau takes %d taus", VF_MAXTAU);
	strcat(many, ",2");
	ok(vf_parse_taus(&a, many) < 0, "--tau refuses %d", VF_MAXTAU + 1);
}

static void
test_kinds(void)
{
	ok(strcmp(vf_kind_name(VF_INDEX), "index") == 0 &&
	    strcmp(vf_kind_name(VF_COVERAGE), "coverage") == 0 &&
	    strcmp(vf_kind_name(VF_NKIND), "?") == 0 &&
	    strcmp(vf_kind_name(-1), "?") == 0, "kind names, ? past them");
}

/* On failure, the text as TAP comments. */
static void
comment(const char *s)
{
	for (; s != NULL && *s != '\0'; s = strchr(s, '\n') + 1) {
		printf("# %.*s\n", (int)strcspn(s, "\n"), s);
		if (strchr(s, '\n') == NULL)
			break;
	}
}

/* The report of r, printed. */
static char *
printed(const vf_report *r, const char *dem_path)
{
	char *buf = NULL;
	size_t n = 0;
	FILE *f = open_memstream(&buf, &n);

	if (f == NULL)
		return NULL;
	vf_report_print(f, r, "d", dem_path, 20);
	fclose(f);
	return buf;
}

static const char pass_text[] =
    "pyramid d: 1 levels, level 0 100x90; no DEM: error, base, local, "
    "coverage not checked\n"
    "level 0: 100x90 vertices, 1x1 blocks (1 read), 1D\n"
    "  violations: index 0 border 0 padding 0 saturation 0 matching 0 "
    "fold - error - base - local - coverage -\n"
    "  largest E 3.5 m, base error 0 m\n"
    "           tau    triangles             \n"
    "             0          100\n"
    "           1.5           40\n"
    "result: pass\n";

static void
one_level(vf_level *L, vf_taustat *ts)
{
	memset(L, 0, sizeof *L);
	L->size[0] = 100, L->size[1] = 90;
	L->blocks[0] = L->blocks[1] = 1;
	L->blocks_read = 1;
	L->ntau = 2, L->tau = ts;
	ts[0].tau = 0, ts[0].triangles = 100, ts[0].maxerr = NAN;
	ts[1].tau = 1.5, ts[1].triangles = 40, ts[1].maxerr = NAN;
	L->emax = 3.5;
	L->tight = L->base_real = L->local_max = NAN;
}

static void
issue(vf_report *r, int kind, int level, int bi, int gi, double tau,
    const char *text)
{
	vf_issue *s = &r->issue[r->nissue++];

	s->kind = kind, s->level = level;
	s->block[0] = s->block[1] = bi;
	s->vertex[0] = gi, s->vertex[1] = gi < 0 ? -1 : gi + 1;
	s->tau = tau;
	snprintf(s->text, sizeof s->text, "%s", text);
	r->count[kind]++, r->total++;
	if (level >= 0)
		r->lev[level].count[kind]++;
}

static void
test_print(void)
{
	vf_taustat ts[2];
	vf_issue is[3];
	vf_level L;
	vf_report r = { 0 };
	char *s;

	r.size0[0] = 100, r.size0[1] = 90;
	r.nlevels = 1, r.lev = &L;
	one_level(&L, ts);
	s = printed(&r, NULL);
	if (!ok(s != NULL && strcmp(s, pass_text) == 0, "a passing report "
	    "without the DEM, as printed"))
		comment(s);
	free(s);
	r.dem = 1, L.displaced = 1;
	ts[0].maxerr = 0.125, ts[1].maxerr = 1.47;
	L.base_real = 0.25, L.local_max = 3.5, L.samples = 9000;
	L.tight = 0.98, L.tight_tau = 1.5;
	r.issue = is, r.capissue = 3;
	issue(&r, VF_BORDER, 0, 0, 128, NAN, "Z 1 vs 2 in block (1,0)");
	issue(&r, VF_INDEX, -1, -1, -1, NAN, "x/y: not a level directory");
	issue(&r, VF_ERROR, 0, 0, 3, 1.5, "t");
	s = printed(&r, "dem.tif");
	ok(s != NULL && strstr(s, "pyramid d: 1 levels, level 0 100x90; DEM "
	    "dem.tif\nlevel 0: 100x90 vertices, 1x1 blocks (1 read), "
	    "displaced (X Y)\n") != NULL, "with the DEM: named; a displaced "
	    "level");
	ok(s != NULL && strstr(s, "  violations: index 0 border 1 padding 0 "
	    "saturation 0 matching 0 fold 0 error 1 base 0 local 0 coverage "
	    "0\n  largest E 3.5 m, base error 0 m (finest triangles: 0.25 m), "
	    "largest local error 3.5 m, 9000 valid samples\n") != NULL,
	    "... every kind counted, the DEM's figures");
	ok(s != NULL && strstr(s, "           tau    triangles    max error\n"
	    "             0          100        0.125\n           1.5"
	    "           40         1.47\n  tightness: max error / tau 0.9800 "
	    "at tau 1.5 in block (0,0)\n") != NULL, "... a max error per tau, "
	    "the tightness");
	ok(s != NULL && strstr(s, "violations (at most 20 of each kind per "
	    "level):\n  level 0 block (0,0) vertex (128,129): border: Z 1 vs "
	    "2 in block (1,0)\n  pyramid: index: x/y: not a level directory\n"
	    "  level 0 block (0,0) vertex (3,4) tau 1.5: error: t\n"
	    "result: FAIL, 3 violations: index 1 border 1 error 1\n") != NULL,
	    "... the issues, each with what applies, and the summary");
	if (tap_failed)
		comment(s);
	free(s);
}

int
main(void)
{
	vf_args a = { 0 };

	test_taus();
	test_kinds();
	test_print();
	a.dir = "/nonexistent";
	ok(vf_run(&a, "t_verify_report") < 0, "vf_run on no pyramid: -1, "
	    "the reason on stderr");
	return tap_done();
}
