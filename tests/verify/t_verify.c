/* t_verify - the pyramid checker (verify.h) on hand-built pyramids
 * (handmade.h) that must pass, then one corruption at a time that must
 * be caught, and tilecheck(1) printing its report and exit statuses. The
 * checker's bintree is t_verify_tree, its index reader t_verify_index,
 * its report t_verify_report. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "handmade.h"
#include "verify/verify.h"
#include "tap.h"
#include "tmpdir.h"

static char tmp[PATH_MAX - 64];

/* --- running the checker -------------------------------------------- */

static vf_report rep;

static int
check(const world *w, const char *dir, int with_dem)
{
	vf_opts o;
	tl_err e;

	vf_report_free(&rep);
	vf_opts_init(&o);
	if (vf_check(dir, with_dem ? w->dem : NULL, &w->dopt, &o, &rep,
	    &e) < 0) {
		printf("# vf_check: %s\n", e.msg);
		return -1;
	}
	return 0;
}

static void
show(int kind)
{
	for (int k = 0; k < rep.nissue; k++)
		if (kind < 0 || rep.issue[k].kind == kind) {
			printf("#   level %d block (%d,%d) vertex (%d,%d): %s: %s\n",
			    rep.issue[k].level, rep.issue[k].block[0],
			    rep.issue[k].block[1], rep.issue[k].vertex[0],
			    rep.issue[k].vertex[1],
			    vf_kind_name(rep.issue[k].kind), rep.issue[k].text);
			if (kind < 0 && k > 10)
				break;
		}
}

static void
counts(char *buf, size_t n)
{
	size_t len = 0;

	buf[0] = '\0';
	for (int k = 0; k < VF_NKIND && len < n; k++)
		if (rep.count[k])
			len += snprintf(buf + len, n - len, " %s %lld",
			    vf_kind_name(k), rep.count[k]);
}

static void
passes(const world *w, const char *dir)
{
	long long ntri = 0;
	double tight = 0;
	char c[256];

	if (check(w, dir, 1) < 0) {
		ok(0, "%s: the checker ran", w->name);
		return;
	}
	counts(c, sizeof c);
	ok(rep.total == 0, "%s: %d levels pass every check with the DEM "
	    "(%lld violations:%s)", w->name, rep.nlevels, rep.total, c);
	if (rep.total)
		show(-1);
	for (int l = 0; l < rep.nlevels; l++) {
		const vf_level *L = &rep.lev[l];
		ntri += L->tau[0].triangles;
		if (!isnan(L->tight))
			tight = fmax(tight, L->tight);
		printf("# level %d: %d taus, %lld triangles at tau 0, max "
		    "error %.4g at tau %g, tightness %.3f, base %.4g "
		    "(real %.4g), %lld samples\n", l, L->ntau,
		    L->tau[0].triangles, L->tau[L->ntau - 1].maxerr,
		    L->tau[L->ntau - 1].tau, L->tight, L->base, L->base_real,
		    L->samples);
	}
	ok(rep.dem && ntri > 0 && tight <= 1 && rep.lev[0].base_real == 0,
	    "%s: triangles counted, tightness %.3f <= 1, level 0 "
	    "reproduces every sample", w->name, tight);
	ok(check(w, dir, 0) == 0 && rep.total == 0 && !rep.dem &&
	    isnan(rep.lev[0].tau[0].maxerr), "%s: passes without the DEM",
	    w->name);
}

/* --- corruptions ---------------------------------------------------- */

static int
edit_block(const world *w, const char *dir, int l, int bi, int bj,
    void (*fn)(pyramid_block *, void *), void *arg)
{
	char path[PATH_MAX];
	pyramid_block b;
	rs_header h;
	tl_err e;
	int r;

	if (pyramid_block_alloc(&b, w->disp[l], &e) < 0)
		return -1;
	b.level = l, b.bi = bi, b.bj = bj;
	pyramid_block_path(path, sizeof path, dir, l, bi, bj);
	if (pyramid_block_read(path, &b, &e) < 0 ||
	    attrs(w, l, mode_of(w, l), &h) < 0) {
		printf("# %s\n", e.msg);
		pyramid_block_free(&b);
		return -1;
	}
	fn(&b, arg);
	r = pyramid_block_write(path, &b, &h, &e);
	rs_header_free(&h);
	pyramid_block_free(&b);
	return r;
}

static void
bump_z(pyramid_block *b, void *arg)
{
	int k = *(int *)arg;

	b->z[k] += 0.25f;
}

static void
lower_parent(pyramid_block *b, void *arg)
{
	/* the block's centre (scale 64), below its children on the axes */
	int m = 64 * BT_SIZE + 64;
	float c = fmaxf(fmaxf(b->e[64], b->e[128 * BT_SIZE + 64]),
	    fmaxf(b->e[64 * BT_SIZE], b->e[64 * BT_SIZE + 128]));

	(void)arg;
	b->e[m] = c / 2;
}

static void
corner_e(pyramid_block *b, void *arg)
{
	(void)arg;
	b->e[0] = 1000;
}

static void
scale_e(pyramid_block *b, void *arg)
{
	for (int k = 0; k < PYRAMID_N; k++)
		if (b->e[k] < FLT_MAX)
			b->e[k] *= *(float *)arg;
}

static void
move_x(pyramid_block *b, void *arg)
{
	int *a = arg; /* vertex, level cells, metres per cell */

	b->x[a[0]] += (float)a[1] * (float)a[2];
}

typedef int (*corrupt_fn)(const world *, const char *);

static int
c_border(const world *w, const char *d)
{
	int k = 40 * BT_SIZE + BT_CELLS; /* right edge of block (0,0) */

	return edit_block(w, d, 0, 0, 0, bump_z, &k);
}

static int
c_saturation(const world *w, const char *d)
{
	return edit_block(w, d, 0, 0, 0, lower_parent, NULL);
}

static int
c_missing(const world *w, const char *d)
{
	char p[PATH_MAX];

	(void)w;
	pyramid_block_path(p, sizeof p, d, 0, 1, 0);
	return unlink(p);
}

static int
c_truncated(const world *w, const char *d)
{
	char p[PATH_MAX];
	struct stat st;

	(void)w;
	pyramid_block_path(p, sizeof p, d, 0, 0, 1);
	if (stat(p, &st) < 0)
		return -1;
	return truncate(p, st.st_size / 2);
}

static int
c_corner(const world *w, const char *d)
{
	return edit_block(w, d, 0, 1, 1, corner_e, NULL);
}

static int
c_zrange(const world *w, const char *d)
{
	pyramid_index ix;
	tl_err e;
	int r;

	(void)w;
	if (pyramid_index_read(d, &ix, &e) < 0)
		return -1;
	ix.lev[0].zmin[1] -= 1;
	ix.lev[0].zmax[1] += 1;
	r = pyramid_index_write(d, &ix, &e);
	pyramid_index_free(&ix);
	return r;
}

/* Every E of level 1 (a displaced one) scaled down: saturation, index
 * and matching still hold, the errors do not. */
static int
c_small_e(const world *w, const char *d)
{
	pyramid_index ix;
	tl_err e;
	float f = 0.02f;
	int r = 0;

	if (pyramid_index_read(d, &ix, &e) < 0)
		return -1;
	for (int bj = 0; bj < ix.lev[1].blocks[1] && r == 0; bj++)
		for (int bi = 0; bi < ix.lev[1].blocks[0] && r == 0; bi++) {
			r = edit_block(w, d, 1, bi, bj, scale_e, &f);
			ix.lev[1].emax[bj * ix.lev[1].blocks[0] + bi] =
			    (float)ix.lev[1].emax[bj * ix.lev[1].blocks[0] + bi] *
			    f;
		}
	if (r == 0)
		r = pyramid_index_write(d, &ix, &e);
	pyramid_index_free(&ix);
	return r;
}

static int
c_stray(const world *w, const char *d)
{
	char p[PATH_MAX];
	FILE *f;

	(void)w;
	snprintf(p, sizeof p, "%s/0/.0_0.exr.tmp", d);
	if ((f = fopen(p, "w")) == NULL)
		return -1;
	return fclose(f);
}

static int
c_padding(const world *w, const char *d)
{
	/* level 0 is 300 wide: block column 2 holds 256..384 */
	int k = 10 * BT_SIZE + 100;

	return edit_block(w, d, 0, 2, 0, bump_z, &k);
}

static int
c_fold(const world *w, const char *d)
{
	/* level 1 (s = 2, 2 m cells): 3 cells right */
	int a[3] = { 30 * BT_SIZE + 30, 3, 4 };

	return edit_block(w, d, 1, 0, 0, move_x, a);
}

static int
c_hole(const world *w, const char *d)
{
	/* a left-edge vertex of level 1 moved half a cell (2 m) inwards */
	int a[3] = { 50 * BT_SIZE, 1, 2 };

	return edit_block(w, d, 1, 0, 0, move_x, a);
}

static void
corruptions(const world *w)
{
	static const struct {
		const char *what;
		corrupt_fn fn;
		int kind, kind2;
	} t[] = {
		{ "Z changed on one side of a border", c_border, VF_BORDER, -1 },
		{ "E lowered below its child's", c_saturation, VF_SATURATION,
		    -1 },
		{ "a missing block", c_missing, VF_INDEX, VF_COVERAGE },
		{ "a truncated block file", c_truncated, VF_INDEX, -1 },
		{ "a corner's E not FLT_MAX", c_corner, VF_SATURATION, -1 },
		{ "index zmin/zmax that lie", c_zrange, VF_INDEX, -1 },
		{ "E too small for the DEM", c_small_e, VF_ERROR, VF_LOCAL },
		{ "a stray file in a level directory", c_stray, VF_INDEX, -1 },
		{ "a padding vertex that is no copy", c_padding, VF_PADDING,
		    -1 },
		{ "a displaced vertex moved 3 cells", c_fold, VF_FOLD, -1 },
		{ "an edge vertex moved inwards", c_hole, VF_COVERAGE, -1 },
	};
	char dir[PATH_MAX], c[256];
	size_t q;
	int st;

	for (q = 0; q < sizeof t / sizeof t[0]; q++) {
		snprintf(dir, sizeof dir, "%s/bad%zu", tmp, q);
		if (build(w, dir) < 0 || t[q].fn(w, dir) < 0 ||
		    check(w, dir, 1) < 0) {
			ok(0, "corruption: %s: set up", t[q].what);
			continue;
		}
		counts(c, sizeof c);
		ok(rep.count[t[q].kind] > 0 && (t[q].kind2 < 0 ||
		    rep.count[t[q].kind2] > 0), "caught: %s (%s%s%s:%s)",
		    t[q].what, vf_kind_name(t[q].kind),
		    t[q].kind2 >= 0 ? ", " : "",
		    t[q].kind2 >= 0 ? vf_kind_name(t[q].kind2) : "", c);
		show(t[q].kind);
	}
	/* the small E pass the structural checks: only the DEM sees them */
	snprintf(dir, sizeof dir, "%s/bad6", tmp);
	st = check(w, dir, 0);
	ok(st == 0 && rep.total == 0, "E too small: invisible without the "
	    "DEM (%lld violations)", rep.total);
}

/* --- the program ---------------------------------------------------- */

static int
run(const char *cmd)
{
	int s = system(cmd);

	return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
}

/* tilecheck of the build under test (TL_BUILD, as tests/lib.sh has it). */
static void
program(const world *w, const char *good)
{
	const char *b = getenv("TL_BUILD") ? getenv("TL_BUILD") : "build";
	char cmd[8 * PATH_MAX], prog[PATH_MAX];

	snprintf(prog, sizeof prog, "%s/tilecheck", b);
	if (access(prog, X_OK) != 0) {
		printf("ok %d - # SKIP %s not built\n", ++tap_n, prog);
		return;
	}
	snprintf(cmd, sizeof cmd, "%s --dem %s -s 2,3 -N %g --tau 0.5,2,8 %s "
	    ">%s/out 2>&1 && grep -q '^result: pass' %s/out && grep -Eq "
	    "'^ +8 +[0-9]+ +[0-9.e+-]+$' %s/out", prog, w->dem, NODATA, good,
	    tmp, tmp, tmp);
	ok(run(cmd) == 0, "tilecheck --dem --tau: exit 0, \"result: pass\", "
	    "a row per tau");
	snprintf(cmd, sizeof cmd, "%s %s/bad0 >%s/out 2>&1", prog, tmp, tmp);
	ok(run(cmd) == 1, "tilecheck on a broken pyramid: exit 1");
	snprintf(cmd, sizeof cmd, "grep -q '^result: FAIL, [0-9]* violations:"
	    " border' %s/out && grep -q 'border: Z' %s/out", tmp, tmp);
	ok(run(cmd) == 0, "... the summary and the border violation printed");
	snprintf(cmd, sizeof cmd, "%s %s/nosuch >/dev/null 2>%s/err; s=$?; "
	    "grep -q '^tilecheck: .*nosuch/index.json: ' %s/err && exit $s",
	    prog, tmp, tmp, tmp);
	ok(run(cmd) == 3, "tilecheck on no pyramid: exit 3 (cannot check), "
	    "message");
}

/* A world of W x H samples, its pyramid in tmp/name, checked. */
static void
one(const char *name, int W, int H, const int *disp, int nlev, int more)
{
	char dir[PATH_MAX];
	world w;

	if (make_world(&w, tmp, name, W, H) < 0) {
		ok(0, "%s: the DEM", name);
		return;
	}
	for (int l = 0; disp != NULL && l < w.nlev; l++)
		w.disp[l] = disp[l];
	snprintf(dir, sizeof dir, "%s/%s", tmp, name);
	ok(build(&w, dir) == 0 && w.nlev == nlev, "%s: built", name);
	passes(&w, dir);
	if (more) {
		corruptions(&w);
		program(&w, dir);
	}
	free_world(&w);
}

int
main(void)
{
	static const int exact[] = { 0, 1 }, padded[] = { 0, 1, 1 };

	if (tmpdir_make(tmp, sizeof tmp, "tlverify") < 0) {
		ok(0, "set up");
		return tap_done();
	}
	/* one block, one level, 1D */
	one("small", 100, 90, NULL, 1, 0);
	/* 2x2 blocks without padding, then a displaced 1x1 */
	one("exact", 257, 257, exact, 2, 0);
	/* 3x2 blocks with padding, displaced levels 1 and 2 */
	one("padded", 300, 200, padded, 3, 1);
	vf_report_free(&rep);
	tmpdir_done(tmp);
	return tap_done();
}
