/* tileplay - the VGIS pyramid's player. For now its checker only:
 * --verify runs verify.h's brute-force checks, with no display and no GL;
 * the interactive viewer will join this file. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dem.h"
#include "util.h"
#include "verify.h"

static const char *prog = "tileplay";

#define MAXTAU 64

static void
usage(FILE *f)
{
	fprintf(f, "usage: %s --verify dir [--dem dem] [--tau t,...] "
	    "[-e encoding] [-N nodata]\n"
	    "                [-n name] [-s dx[,dy]]\n"
	    "  --verify dir    check the pyramid in dir: index, blocks, "
	    "borders, saturation,\n"
	    "                  triangulations at a sweep of tolerances\n"
	    "  --dem dem       the DEM it was made from: check its errors "
	    "too\n"
	    "  --tau t,...     tolerances in metres instead of each level's "
	    "sweep\n"
	    "  -e, -N, -n, -s  how to read the DEM, as for dem2fqm(1)\n",
	    prog);
}

typedef struct {
	dem_opts dem;
	const char *verify, *dem_path;
	double tau[MAXTAU];
	int ntau;
} options;

/* --- the report ----------------------------------------------------- */

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
print_level(const vf_report *r, const vf_level *L)
{
	printf("level %d: %dx%d vertices, %dx%d blocks (%lld read), %s\n",
	    L->level, L->size[0], L->size[1], L->blocks[0], L->blocks[1],
	    L->blocks_read, L->displaced ? "displaced (X Y)" : "1D");
	printf("  violations:");
	for (int k = 0; k < VF_NKIND; k++) {
		if (ran(r, L, k))
			printf(" %s %lld", vf_kind_name(k), L->count[k]);
		else
			printf(" %s -", vf_kind_name(k));
	}
	printf("\n  largest E %.6g m, base error %.6g m", L->emax, L->base);
	if (r->dem)
		printf(" (finest triangles: %.6g m), largest local error "
		    "%.6g m, %lld valid samples", L->base_real, L->local_max,
		    L->samples);
	printf("\n  %12s %12s %12s\n", "tau", "triangles",
	    r->dem ? "max error" : "");
	for (int t = 0; t < L->ntau; t++) {
		printf("  %12.6g %12lld", L->tau[t].tau, L->tau[t].triangles);
		if (r->dem)
			printf(" %12.6g", L->tau[t].maxerr);
		putchar('\n');
	}
	if (r->dem && !isnan(L->tight))
		printf("  tightness: max error / tau %.4f at tau %.6g in block "
		    "(%d,%d)\n", L->tight, L->tight_tau, L->tight_block[0],
		    L->tight_block[1]);
}

static void
print_issue(const vf_issue *s)
{
	if (s->level >= 0)
		printf("  level %d", s->level);
	else
		printf("  pyramid");
	if (s->block[0] >= 0)
		printf(" block (%d,%d)", s->block[0], s->block[1]);
	if (s->vertex[0] >= 0)
		printf(" vertex (%d,%d)", s->vertex[0], s->vertex[1]);
	if (!isnan(s->tau))
		printf(" tau %.6g", s->tau);
	printf(": %s: %s\n", vf_kind_name(s->kind), s->text);
}

static void
print_report(const char *dir, const options *o, const vf_report *r,
    int max_issues)
{
	printf("pyramid %s: %d levels, level 0 %dx%d; ", dir, r->nlevels,
	    r->size0[0], r->size0[1]);
	if (r->dem)
		printf("DEM %s\n", o->dem_path);
	else
		printf("no DEM: error, base, local, coverage not checked\n");
	for (int l = 0; l < r->nlevels; l++)
		print_level(r, &r->lev[l]);
	if (r->nissue > 0) {
		printf("violations (at most %d of each kind per level):\n",
		    max_issues);
		for (int k = 0; k < r->nissue; k++)
			print_issue(&r->issue[k]);
	}
	if (r->total == 0) {
		printf("result: pass\n");
		return;
	}
	printf("result: FAIL, %lld violations:", r->total);
	for (int k = 0; k < VF_NKIND; k++)
		if (r->count[k] > 0)
			printf(" %s %lld", vf_kind_name(k), r->count[k]);
	putchar('\n');
}

static int
verify(const options *o)
{
	vf_opts vo;
	vf_report r;
	tl_err e;
	int failed;

	vf_opts_init(&vo);
	if (o->ntau > 0) {
		vo.tau = o->tau;
		vo.ntau = o->ntau;
	}
	if (vf_check(o->verify, o->dem_path, &o->dem, &vo, &r, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		vf_report_free(&r);
		return 1;
	}
	print_report(o->verify, o, &r, vo.max_issues);
	failed = r.total > 0;
	vf_report_free(&r);
	return failed;
}

/* --- options -------------------------------------------------------- */

static int
parse_cell(const char *s, double cell[2])
{
	char buf[64], *comma;

	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	if ((comma = strchr(buf, ',')) != NULL)
		*comma++ = '\0';
	if (tl_parse_double(buf, &cell[0]) < 0 || cell[0] <= 0)
		return -1;
	cell[1] = cell[0];
	if (comma != NULL && (tl_parse_double(comma, &cell[1]) < 0 ||
	    cell[1] <= 0))
		return -1;
	return 0;
}

static int
parse_taus(const char *s, options *o)
{
	char buf[1024], *tok, *save;

	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	o->ntau = 0;
	for (tok = strtok_r(buf, ",", &save); tok != NULL;
	    tok = strtok_r(NULL, ",", &save)) {
		if (o->ntau == MAXTAU ||
		    tl_parse_double(tok, &o->tau[o->ntau]) < 0 ||
		    o->tau[o->ntau] < 0)
			return -1;
		o->ntau++;
	}
	return o->ntau > 0 ? 0 : -1;
}

static int
parse_encoding(const char *s, enum dem_encoding *enc)
{
	static const struct {
		const char *name;
		enum dem_encoding enc;
	} t[] = {
		{ "auto", DEM_ENC_AUTO }, { "grey", DEM_ENC_GREY },
		{ "gray", DEM_ENC_GREY }, { "terrainrgb", DEM_ENC_TERRAINRGB },
		{ "terrarium", DEM_ENC_TERRARIUM },
	};

	for (size_t k = 0; k < sizeof t / sizeof t[0]; k++)
		if (strcmp(s, t[k].name) == 0) {
			*enc = t[k].enc;
			return 0;
		}
	return -1;
}

enum { OPT_VERIFY = 256, OPT_DEM, OPT_TAU };

/* 0: go on; else the exit status + 1. */
static int
option(int c, const char *arg, options *o)
{
	switch (c) {
	case OPT_VERIFY:
		o->verify = arg;
		return 0;
	case OPT_DEM:
		o->dem_path = arg;
		return 0;
	case OPT_TAU:
		if (parse_taus(arg, o) == 0)
			return 0;
		tl_warn(prog, "--tau %s: expected up to %d numbers >= 0, "
		    "comma-separated", arg, MAXTAU);
		return 3;
	case 'e':
		if (parse_encoding(arg, &o->dem.encoding) == 0)
			return 0;
		tl_warn(prog, "-e %s: unknown encoding", arg);
		return 3;
	case 'h':
		usage(stdout);
		return 1;
	case 'N':
		if (tl_parse_double(arg, &o->dem.nodata) < 0) {
			tl_warn(prog, "-N %s: not a number", arg);
			return 3;
		}
		o->dem.has_nodata = 1;
		return 0;
	case 'n':
		o->dem.hgt_name = arg;
		return 0;
	case 's':
		if (parse_cell(arg, o->dem.cell) == 0)
			return 0;
		tl_warn(prog, "-s %s: expected dx or dx,dy in metres, > 0", arg);
		return 3;
	case 'V':
		printf("%s %s\n", prog, TL_VERSION);
		return 1;
	}
	usage(stderr);
	return 3;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "verify", required_argument, NULL, OPT_VERIFY },
		{ "dem", required_argument, NULL, OPT_DEM },
		{ "tau", required_argument, NULL, OPT_TAU },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	options o;
	int c, r;

	memset(&o, 0, sizeof o);
	while ((c = getopt_long(argc, argv, "e:hN:n:s:V", longopts, NULL)) !=
	    -1)
		if ((r = option(c, optarg, &o)) != 0)
			return r - 1;
	if (optind < argc) {
		usage(stderr);
		return 2;
	}
	if (o.verify == NULL) {
		tl_warn(prog, "the viewer is not built yet; use --verify");
		return 2;
	}
	return verify(&o);
}
