/* t_level - the errors of a level's blocks (level.h), through its
 * callbacks: E derived by hand for a spike (as t_tilepack.sh has them
 * through the programs), the same E on a displaced level with zero
 * offsets, a tilted plane's E and base errors 0 on levels 0 and 1, every
 * block handed out once in row order with shared borders identical and
 * padding copied, rows asked for in order once each, and a failing
 * callback's error passed on; on rough terrain with holes, levels 0 to
 * 2, the undisplaced levels' integer scan (undisplaced_scan.c) gives
 * every E and base error bit for bit as the general test
 * (exact_error.c's tri_row) does on the same level displaced by zero
 * offsets. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "qem/fqm.h"
#include "pack/level.h"
#include "tap.h"
#include "tmpdir.h"
#include "tiff.h"
#include "urand.h"

static char tmp[PATH_MAX - 64];

/* The level's rows, row-major w x h (offsets 0 on displaced levels, or
 * up to 0.45 of a cell given jitter > 0: the level's step in metres). */
typedef struct {
	const float *z;
	int w, h;
	int next, bad_order, bad_cols; /* bad_cols: a span past the row */
	int fail_at; /* a row whose read fails, or -1 */
	double jitter;
} rows;

static int
row_fn(void *ctx, int r, int c0, int n, float *z, float *x, float *y,
    tl_err *e)
{
	rows *R = ctx;

	R->bad_order += r != R->next++;
	R->bad_cols += c0 < 0 || n < 1 || c0 + n > R->w;
	if (r == R->fail_at)
		return tl_fail(e, "row %d: cannot", r);
	memcpy(z, R->z + (size_t)r * R->w + c0, (size_t)n * sizeof *z);
	if (x != NULL) {
		memset(x, 0, (size_t)n * sizeof *x);
		memset(y, 0, (size_t)n * sizeof *y);
		for (int i = 0; R->jitter > 0 && i < n; i++) {
			x[i] = rough_offset(R->jitter, c0 + i, r, 7);
			y[i] = rough_offset(R->jitter, c0 + i, r, 8);
		}
	}
	return 0;
}

/* The blocks handed out: E and Z gathered on the level's padded grid. */
typedef struct {
	int bx, by, gw;
	float *z, *e;         /* gw x (128 by + 1) */
	int *seen;            /* per block */
	double *base, *emax, *zmin, *zmax;
	int last, bad_order;  /* blocks in row order */
	int bad_border;       /* a shared vertex that differs */
	int fail_at;          /* a block whose write fails, or -1 */
	pthread_mutex_t mu;
} sink;

static int
block_fn(void *ctx, const pyramid_block *b, tl_err *e)
{
	sink *s = ctx;
	int k = b->bj * s->bx + b->bi;

	if (k == s->fail_at)
		return tl_fail(e, "block %d: cannot", k);
	pthread_mutex_lock(&s->mu); /* threads: blocks of a row at once */
	s->bad_order += k != s->last + 1;
	s->last = k;
	s->seen[k]++;
	s->base[k] = b->base, s->emax[k] = b->emax;
	s->zmin[k] = b->zmin, s->zmax[k] = b->zmax;
	for (int r = 0; r < BT_SIZE; r++)
		for (int c = 0; c < BT_SIZE; c++) {
			size_t g = (size_t)(b->bj * BT_CELLS + r) * s->gw +
			    b->bi * BT_CELLS + c;
			int q = r * BT_SIZE + c;
			int shared = (r == 0 && b->bj > 0) ||
			    (c == 0 && b->bi > 0);
			if (shared &&
			    (s->z[g] != b->z[q] || s->e[g] != b->e[q]))
				s->bad_border++;
			s->z[g] = b->z[q], s->e[g] = b->e[q];
		}
	pthread_mutex_unlock(&s->mu);
	return 0;
}

typedef struct {
	level_stats st;
	sink s;
	rows R;
	int r;
	tl_err e;
} run;

/* A piece's local errors, the maximum over its parts (level_run_part):
 * level columns lo .. hi-1 of every row of the padded level. */
typedef struct {
	const level_part *q;
	int lo, n, next, bad_order;
	float *acc;
} merged;

static int
part_out(void *ctx, int g, float *err, tl_err *e)
{
	merged *m = ctx;

	m->bad_order += g != m->next++;
	for (int i = 0; i < m->n; i++) {
		float *a = &m->acc[(size_t)g * m->n + i];
		*a = err[i] > *a ? err[i] : *a;
	}
	return 0;
}

static int
part_in(void *ctx, int g, float *err, tl_err *e)
{
	merged *m = ctx;

	m->bad_order += g != m->next++;
	memcpy(err, &m->acc[(size_t)g * m->n], (size_t)m->n * sizeof *err);
	return 0;
}

/* Piece p's local errors (m->acc, Q rows of level columns lo .. hi-1)
 * and base errors (base, (b1 - b0) x block rows) as the maxima over its
 * parts of nrows DEM rows, each reading its own window of the DEM
 * (dem_open_window) and asking for level rows from its own first one;
 * the samples counted, summed. Checks the rows given out and read. */
static int
parts_merge(const level_args *L, const level_piece *p, const char *path,
    int nrows, rows *R, merged *m, double *base, long long *samples,
    tl_err *e)
{
	static const dem_opts none;
	int Q = pyramid_nblocks(L->size[1]) * BT_CELLS + 1;
	int nb = (p->b1 - p->b0) * pyramid_nblocks(L->size[1]), r = 0, bad = 0;
	double *pb = calloc(nb, sizeof *pb);
	level_window win;
	level_part q;

	level_piece_window(L, L->m->width, p, &win);
	level_part_window(L, p, 0, 1, &q);
	memset(m, 0, sizeof *m);
	m->lo = q.lo, m->n = q.hi - q.lo;
	m->acc = calloc((size_t)Q * m->n, sizeof *m->acc);
	*samples = 0;
	for (int y0 = 0; r == 0 && y0 < L->m->height; y0 += nrows) {
		int y1 = y0 + nrows < L->m->height ? y0 + nrows :
		    L->m->height;
		level_stats ps;
		dem *d;
		level_part_window(L, p, y0, y1, &q);
		if ((d = dem_open_window(path, &none, (int)win.d0, (int)win.d1,
		    y0, y1, e)) == NULL) {
			r = -1;
			break;
		}
		m->q = &q, m->next = q.g0;
		R->next = q.r0;
		r = level_run_part(L, p, &q, d, part_out, m, pb, &ps, e);
		dem_close(d);
		if (m->next != q.g1 || R->next != (q.r1 < L->size[1] ? q.r1 :
		    L->size[1]))
			printf("# part %d..%d: errors to row %d of %d, rows read "
			    "to %d of %d\n", y0, y1, m->next, q.g1, R->next,
			    q.r1), bad++;
		for (int k = 0; k < nb; k++)
			base[k] = pb[k] > base[k] ? pb[k] : base[k];
		*samples += ps.samples;
	}
	free(pb);
	if (r == 0 && (bad || m->bad_order))
		r = tl_fail(e, "parts: local errors given out in another "
		    "order, or rows asked for beyond the part's");
	return r;
}

/* Piece p in parts of nrows DEM rows, merged (level_run_merged); its
 * stats to st. */
static int
run_parts(const level_args *L, const level_piece *p, const char *path,
    int nrows, rows *R, level_stats *st, tl_err *e)
{
	int Q = pyramid_nblocks(L->size[1]) * BT_CELLS + 1;
	int nb = (p->b1 - p->b0) * pyramid_nblocks(L->size[1]), r;
	double *base = calloc(nb, sizeof *base);
	long long samples;
	merged m;

	r = parts_merge(L, p, path, nrows, R, &m, base, &samples, e);
	m.next = 0, R->next = 0;
	if (r == 0)
		r = level_run_merged(L, p, L->m->width, part_in, &m, base, st,
		    e);
	st->samples = samples;
	if (r == 0 && (m.bad_order || m.next != Q))
		r = tl_fail(e, "merged: local errors read out of order, or "
		    "to row %d of %d", m.next, Q);
	free(m.acc), free(base);
	return r;
}

/* Level `level` (w x h, z row-major) of the DEM at path, its columns
 * shared among threads, as a whole or (cols > 0) in pieces of cols block
 * columns, one after another, (rows > 0) each in parts of that many DEM
 * rows; displaced levels get offsets when jitter; row fail_row and block
 * fail_block (-1: none) fail. */
static void
run_level_in(run *u, const char *path, int level, int w, int h,
    const float *z, int displaced, int fail_row, int fail_block, int threads,
    int cols, int jitter, int nrows)
{
	static const dem_opts none;
	level_args L = { 0 };
	geo_ground m = { 0 };
	size_t nb, ng;
	dem *d;

	memset(u, 0, sizeof *u);
	u->r = -1;
	u->R.z = z, u->R.w = w, u->R.h = h, u->R.fail_at = fail_row;
	u->R.jitter = jitter ? (double)(1 << level) : 0;
	u->s.bx = pyramid_nblocks(w), u->s.by = pyramid_nblocks(h);
	u->s.gw = u->s.bx * BT_CELLS + 1;
	u->s.last = -1, u->s.fail_at = fail_block;
	pthread_mutex_init(&u->s.mu, NULL);
	nb = (size_t)u->s.bx * u->s.by;
	ng = (size_t)u->s.gw * (u->s.by * BT_CELLS + 1);
	u->s.z = calloc(ng, sizeof *u->s.z);
	u->s.e = calloc(ng, sizeof *u->s.e);
	u->s.seen = calloc(nb, sizeof *u->s.seen);
	u->s.base = calloc(nb, sizeof *u->s.base);
	u->s.emax = calloc(nb, sizeof *u->s.emax);
	u->s.zmin = calloc(nb, sizeof *u->s.zmin);
	u->s.zmax = calloc(nb, sizeof *u->s.zmax);
	if ((d = dem_open(path, &none, &u->e)) == NULL ||
	    geo_ground_init(&m, dem_georef(d), &u->e) < 0)
		goto done;
	L.level = level, L.size[0] = w, L.size[1] = h;
	L.displaced = displaced, L.m = &m, L.threads = threads;
	L.row = row_fn, L.row_ctx = &u->R;
	L.block = block_fn, L.block_ctx = &u->s;
	if (cols == 0) {
		u->r = level_run(&L, d, &u->st, &u->e);
		goto done;
	}
	level_piece p[64];
	int n = level_pieces(&L, cols, p, 64);
	u->r = 0;
	for (int k = 0; k < n && u->r == 0; k++) {
		level_stats st;
		u->R.next = 0; /* each piece reads every row */
		u->r = nrows > 0 ? run_parts(&L, &p[k], path, nrows, &u->R,
		    &st, &u->e) : level_run_piece(&L, &p[k], d, &st, &u->e);
		u->st.max_e = st.max_e > u->st.max_e ? st.max_e : u->st.max_e;
		u->st.max_base = st.max_base > u->st.max_base ? st.max_base :
		    u->st.max_base;
		u->st.samples += st.samples;
	}
	u->s.bad_order = 0; /* row order holds within each piece only */
done:
	if (d != NULL)
		dem_close(d);
	geo_ground_free(&m);
}

static void
run_level_as(run *u, const char *path, int level, int w, int h,
    const float *z, int displaced, int fail_row, int fail_block, int threads,
    int cols, int jitter)
{
	run_level_in(u, path, level, w, h, z, displaced, fail_row, fail_block,
	    threads, cols, jitter, 0);
}

static void
run_level(run *u, const char *path, int level, int w, int h,
    const float *z, int displaced, int fail_row, int fail_block, int threads)
{
	run_level_as(u, path, level, w, h, z, displaced, fail_row, fail_block,
	    threads, 0, 0);
}

static void
run_free(run *u)
{
	free(u->s.z), free(u->s.e), free(u->s.seen);
	free(u->s.base), free(u->s.emax), free(u->s.zmin), free(u->s.zmax);
	pthread_mutex_destroy(&u->s.mu);
}

static float
E(const run *u, int i, int j)
{
	return u->s.e[(size_t)j * u->s.gw + i];
}

/* Every block handed out once, in row order, borders identical. */
static int
blocks_ok(const run *u)
{
	int once = 1;

	for (int k = 0; k < u->s.bx * u->s.by; k++)
		once &= u->s.seen[k] == 1;
	return u->r == 0 && once && !u->s.bad_order && !u->s.bad_border &&
	    !u->R.bad_order && !u->R.bad_cols && u->R.next == u->R.h;
}

/* Run p made the blocks of run u, a whole level, bit for bit: E, Z,
 * base errors and stats, every block once and rows read in order. */
static int
same_level(const run *u, const run *p)
{
	size_t ng = (size_t)u->s.gw * (u->s.by * BT_CELLS + 1);
	size_t nb = (size_t)u->s.bx * u->s.by;

	return u->r == 0 && p->r == 0 && blocks_ok(p) &&
	    memcmp(u->s.e, p->s.e, ng * sizeof *u->s.e) == 0 &&
	    memcmp(u->s.z, p->s.z, ng * sizeof *u->s.z) == 0 &&
	    memcmp(u->s.base, p->s.base, nb * sizeof *u->s.base) == 0 &&
	    u->st.max_e == p->st.max_e && u->st.max_base == p->st.max_base &&
	    u->st.samples == p->st.samples;
}

/* A DEM of w x h samples from z, as a TIFF in tmp. */
static int
dem_file(char *path, size_t n, const char *name, int w, int h,
    const float *z)
{
	snprintf(path, n, "%s/%s.tif", tmp, name);
	return write_tiff(path, w, h, z);
}

/* The spike: one 129x129 block, height 0 but 10 m at s = (64,64). E by
 * hand (t_tilepack.sh derives each): (64,64)'s diamond is the roots,
 * whose corners are 0: 10. (64,0) (hypotenuse (0,0)-(128,0), apex s):
 * the weight of s at samples (63..65, 63) is 63/64: 9.84375; likewise
 * (0,64), (128,64), (64,128) and the square (96,96). (65,64), a leaf
 * between s and (66,64): 5. (1,0), (127,127): nothing nonzero in reach,
 * 0. Corners FLT_MAX. */
static void
test_spike(void)
{
	static const struct {
		int i, j;
		float e;
	} want[] = {
		{ 64, 64, 10 }, { 64, 0, 9.84375f }, { 0, 64, 9.84375f },
		{ 128, 64, 9.84375f }, { 64, 128, 9.84375f },
		{ 96, 96, 9.84375f }, { 65, 64, 5 }, { 1, 0, 0 },
		{ 127, 127, 0 }, { 0, 0, FLT_MAX }, { 128, 128, FLT_MAX },
	};
	static float z[BT_SIZE * BT_SIZE];
	char path[PATH_MAX];
	run u, v;
	int bad = 0;

	z[64 * BT_SIZE + 64] = 10;
	if (dem_file(path, sizeof path, "spike", BT_SIZE, BT_SIZE, z) < 0) {
		ok(0, "spike: the DEM");
		return;
	}
	run_level(&u, path, 0, BT_SIZE, BT_SIZE, z, 0, -1, -1, 1);
	ok(blocks_ok(&u) && u.s.bx == 1 && u.s.by == 1, "spike: one block, "
	    "every row read once in order (%s)", u.r ? u.e.msg : "ok");
	for (size_t q = 0; q < sizeof want / sizeof want[0]; q++)
		if (E(&u, want[q].i, want[q].j) != want[q].e && bad++ < 4)
			printf("# E(%d,%d) = %.9g, not %.9g\n", want[q].i,
			    want[q].j, E(&u, want[q].i, want[q].j), want[q].e);
	ok(bad == 0, "spike: E as derived by hand at 11 vertices");
	ok(u.s.zmin[0] == 0 && u.s.zmax[0] == 10 && u.s.base[0] == 0 &&
	    u.s.emax[0] == 10, "spike: the block's z range 0..10, base error "
	    "0, largest finite E 10");
	ok(u.st.max_e == 10 && u.st.max_base == 0 &&
	    u.st.samples == BT_SIZE * BT_SIZE, "spike: stats: max E 10, "
	    "max base 0, %lld samples", u.st.samples);
	run_level(&v, path, 0, BT_SIZE, BT_SIZE, z, 1, -1, -1, 1);
	ok(blocks_ok(&v) && memcmp(u.s.e, v.s.e, (size_t)u.s.gw * BT_SIZE *
	    sizeof *u.s.e) == 0, "spike: a displaced level with zero offsets "
	    "has the same E");
	run_free(&v);
	run_level(&v, path, 0, BT_SIZE, BT_SIZE, z, 0, 70, -1, 1);
	ok(v.r < 0 && strstr(v.e.msg, "row 70: cannot") != NULL, "a row "
	    "that cannot be read: failed with its message (%s)", v.e.msg);
	run_free(&v);
	run_level(&v, path, 0, BT_SIZE, BT_SIZE, z, 0, -1, 0, 1);
	ok(v.r < 0 && strstr(v.e.msg, "block 0: cannot") != NULL, "a block "
	    "that cannot be written: failed with its message (%s)", v.e.msg);
	run_free(&v);
	run_free(&u);
}

/* A tilted plane, exact in float32 at every grid point and midpoint:
 * every triangle interpolates it, so where no padding is in reach (a
 * level of whole blocks) E and the base errors are 0; padding copies the
 * last real row and column. */
static double
plane(double I, double J)
{
	return 100 + 0.5 * I - 0.25 * J;
}

static void
test_plane_level(const char *path, int W, int H, int level)
{
	int w = geo_level_size(W, level), h = geo_level_size(H, level);
	float *z = malloc((size_t)w * h * sizeof *z);
	int nonzero = 0, pad = 0;
	double base = 0;
	run u;

	for (int j = 0; j < h; j++)
		for (int i = 0; i < w; i++)
			z[(size_t)j * w + i] = (float)plane((double)i *
			    (1 << level), (double)j * (1 << level));
	run_level(&u, path, level, w, h, z, 0, -1, -1, 1);
	for (int j = 0; j <= u.s.by * BT_CELLS; j++)
		for (int i = 0; i < u.s.gw; i++) {
			int corner = i % BT_CELLS == 0 && j % BT_CELLS == 0;
			int ri = i < w ? i : w - 1, rj = j < h ? j : h - 1;
			nonzero += !corner && E(&u, i, j) != 0;
			pad += u.s.z[(size_t)j * u.s.gw + i] !=
			    z[(size_t)rj * w + ri];
		}
	for (int k = 0; k < u.s.bx * u.s.by; k++)
		base = fmax(base, u.s.base[k]);
	ok(blocks_ok(&u), "plane level %d: %dx%d blocks, each once in row "
	    "order, shared borders identical", level, u.s.bx, u.s.by);
	if ((w - 1) % BT_CELLS == 0 && (h - 1) % BT_CELLS == 0)
		ok(nonzero == 0 && base == 0 && u.st.max_e == 0, "plane level "
		    "%d, no padding: E 0 but at corners (%d not), base errors "
		    "0 (%g)", level, nonzero, base);
	ok(pad == 0, "plane level %d: Z of every vertex, padding the last "
	    "real one (%d differ)", level, pad);
	run_free(&u);
	free(z);
}

static void
test_plane(int W, int H)
{
	float *z = malloc((size_t)W * H * sizeof *z);
	char path[PATH_MAX], name[32];

	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++)
			z[(size_t)j * W + i] = (float)plane(i, j);
	snprintf(name, sizeof name, "plane%dx%d", W, H);
	if (dem_file(path, sizeof path, name, W, H, z) < 0) {
		ok(0, "plane: the DEM");
		free(z);
		return;
	}
	free(z);
	test_plane_level(path, W, H, 0);
	test_plane_level(path, W, H, 1);
}

static void
test_scan(void)
{
	int W = 300, H = 200;
	float *z = malloc((size_t)W * H * sizeof *z);
	char path[PATH_MAX];

	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++)
			z[(size_t)j * W + i] = (i / 7 + j / 5) % 11 == 3 ?
			    NAN : rough(i, j, 0);
	if (dem_file(path, sizeof path, "rough", W, H, z) < 0) {
		ok(0, "rough: the DEM");
		free(z);
		return;
	}
	for (int level = 0; level <= 2; level++) {
		int w = geo_level_size(W, level), h = geo_level_size(H, level);
		float *v = malloc((size_t)w * h * sizeof *v);
		size_t ng, nb;
		run u, d;
		for (int j = 0; j < h; j++)
			for (int i = 0; i < w; i++)
				v[(size_t)j * w + i] = rough(i, j, 1 + level);
		run_level(&u, path, level, w, h, v, 0, -1, -1, 1);
		run_level(&d, path, level, w, h, v, 1, -1, -1, 1);
		ng = (size_t)u.s.gw * (u.s.by * BT_CELLS + 1);
		nb = (size_t)u.s.bx * u.s.by;
		ok(blocks_ok(&u) && blocks_ok(&d) && u.st.max_e > 0 &&
		    memcmp(u.s.e, d.s.e, ng * sizeof *u.s.e) == 0 &&
		    memcmp(u.s.base, d.s.base, nb * sizeof *u.s.base) == 0 &&
		    u.st.samples == d.st.samples && u.st.samples < W * H,
		    "rough level %d with holes: the integer scan's E and base "
		    "errors are the general test's, bit for bit (max E %g)",
		    level, u.st.max_e);
		/* the plain copies of the hot loops, not the AVX2 ones */
		{
			run up, dp;
			setenv("TL_NO_AVX2", "1", 1);
			run_level(&up, path, level, w, h, v, 0, -1, -1, 1);
			run_level_as(&dp, path, level, w, h, v, 1, -1, -1, 1, 0,
			    1);
			unsetenv("TL_NO_AVX2");
			run dj;
			run_level_as(&dj, path, level, w, h, v, 1, -1, -1, 1, 0,
			    1);
			ok(up.r == 0 && dp.r == 0 && dj.r == 0 &&
			    memcmp(u.s.e, up.s.e, ng * sizeof *u.s.e) == 0 &&
			    memcmp(u.s.base, up.s.base, nb * sizeof *u.s.base) == 0 &&
			    memcmp(dj.s.e, dp.s.e, ng * sizeof *dj.s.e) == 0 &&
			    memcmp(dj.s.base, dp.s.base, nb * sizeof *dj.s.base) == 0,
			    "rough level %d: without the AVX2 copies (TL_NO_AVX2) "
			    "the same bits, integer scan and displaced with "
			    "offsets", level);
			run_free(&up), run_free(&dp), run_free(&dj);
		}
		/* the columns in shares on threads: the same bits */
		for (int t = 2; t <= 7; t += 5) {
			run ut, dt;
			run_level(&ut, path, level, w, h, v, 0, -1, -1, t);
			run_level(&dt, path, level, w, h, v, 1, -1, -1, t);
			ok(ut.r == 0 && dt.r == 0 &&
			    memcmp(u.s.e, ut.s.e, ng * sizeof *u.s.e) == 0 &&
			    memcmp(u.s.z, ut.s.z, ng * sizeof *u.s.z) == 0 &&
			    memcmp(u.s.base, ut.s.base, nb * sizeof *u.s.base) == 0 &&
			    memcmp(d.s.e, dt.s.e, ng * sizeof *d.s.e) == 0 &&
			    memcmp(d.s.base, dt.s.base, nb * sizeof *d.s.base) == 0 &&
			    ut.st.samples == u.st.samples,
			    "rough level %d on %d threads: E, Z and base errors "
			    "those of one thread, bit for bit (both tests)",
			    level, t);
			run_free(&ut), run_free(&dt);
		}
		run_free(&u), run_free(&d);
		free(v);
	}
	free(z);
}

/* A level in pieces of 1, 2 and 5 block columns (windows with edges
 * inside the level, 1D and displaced with offsets, 1 and 3 threads per
 * piece): every block the whole level's, bit for bit. Two DEMs: a rough
 * one with holes, and a flat one (vertices flat too) with spikes of
 * distinct heights within 128 columns of block edges, where a window too
 * narrow would lose the one spike that sets an E. */
static void
test_pieces(int spiky, int W, int H, int parts_only)
{
	float *z = malloc((size_t)W * H * sizeof *z);
	char path[PATH_MAX];

	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++) {
			int m = i % BT_CELLS, k = (i + 7 * j) % 29;
			float *p = &z[(size_t)j * W + i];
			if (!spiky)
				*p = (i / 9 + j / 4) % 13 == 5 ? NAN :
				    rough(i, j, 3);
			else
				*p = (m <= 3 || m >= 120) && k == 0 ?
				    1 + rough(i, j, 5) : 0;
		}
	if (dem_file(path, sizeof path, spiky ? "spiky" : W > H ? "wide" :
	    "tall", W, H,
	    z) < 0) {
		ok(0, "wide: the DEM");
		free(z);
		return;
	}
	for (int level = 0; level <= 1; level++) {
		int w = geo_level_size(W, level), h = geo_level_size(H, level);
		float *v = malloc((size_t)w * h * sizeof *v);
		for (int j = 0; j < h; j++)
			for (int i = 0; i < w; i++)
				v[(size_t)j * w + i] = spiky ? 0 :
				    rough(i, j, 11 + level);
		for (int disp = 0; disp <= 1; disp++) {
			run u;
			run_level_as(&u, path, level, w, h, v, disp, -1, -1, 1,
			    0, 1);
			for (int cols = 1; !parts_only && cols <= 5;
			    cols += cols < 2 ? 1 : 3) {
				run p;
				int th = cols == 2 ? 3 : 1;
				run_level_as(&p, path, level, w, h, v, disp, -1,
				    -1, th, cols, 1);
				/* (blocks of a row on threads come in any
				 * order: the border check needs them in order) */
				p.s.bad_border *= th == 1;
				ok(same_level(&u, &p),
				    "%s level %d (%d blocks wide), %s, in pieces "
				    "of %d block columns on %d thread(s): E, Z, "
				    "base errors and samples the whole level's, "
				    "bit for bit", spiky ? "spiky" : "rough",
				    level, u.s.bx, disp ? "displaced" : "1D",
				    cols, th);
				run_free(&p);
			}
			/* parts of rows: a few, odd, and more than a
			 * ring's worth of level rows */
			for (int k = 0; k < 3; k++) {
				/* (tall: a part longer than the rings) */
				const int nr[] = { 37, 100, H > W ? 700 : 230 };
				int cols = k == 1 ? 2 : 3, th = k == 2 ? 2 : 1;
				run p;
				run_level_in(&p, path, level, w, h, v, disp, -1,
				    -1, th, cols, 1, nr[k] << level);
				p.s.bad_border *= th == 1;
				ok(same_level(&u, &p),
				    "%s level %d, %s, pieces of %d block columns "
				    "in parts of %d DEM rows merged, on %d "
				    "thread(s): E, Z, base errors and stats the "
				    "whole level's, bit for bit (%s)",
				    spiky ? "spiky" : "rough", level,
				    disp ? "displaced" : "1D", cols,
				    nr[k] << level, th, p.r ? p.e.msg : "ok");
				run_free(&p);
			}
			run_free(&u);
		}
		free(v);
	}
	free(z);
}

/* Local errors, before saturation hides most of them: a piece's, merged
 * from parts of 37, 100 and 700 DEM rows, are those of one part of every
 * row, bit for bit (rows a part gives out too early, or a part's rows of
 * centres cut too short, lose maxima that only the merged local errors
 * show); levels 0 and 1 of a flat level over a tall valley with holes,
 * 1D and displaced. */
static void
test_part_errors(void)
{
	static const dem_opts none;
	int W = 300, H = 1500;
	float *z = malloc((size_t)W * H * sizeof *z);
	char path[PATH_MAX];
	geo_ground gm = { 0 };
	tl_err e;
	dem *d = NULL;

	/* a rough valley with holes, rising away from its middle row: a
	 * diamond on a flat level has its largest local error at its top
	 * tip above the middle, at its bottom tip below it, where a part's
	 * first or last rows cut it */
	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++)
			z[(size_t)j * W + i] = (i / 7 + j / 5) % 17 == 3 ? NAN :
			    abs(j - H / 2) + rough(i, j, 21) / 1000;
	if (dem_file(path, sizeof path, "parts", W, H, z) < 0 ||
	    (d = dem_open(path, &none, &e)) == NULL ||
	    geo_ground_init(&gm, dem_georef(d), &e) < 0) {
		ok(0, "part errors: the DEM");
		goto done;
	}
	for (int level = 0; level <= 1; level++)
		for (int disp = 0; disp <= 1; disp++) {
			int w = geo_level_size(W, level), h = geo_level_size(H,
			    level), Q = pyramid_nblocks(h) * BT_CELLS + 1;
			float *v = malloc((size_t)w * h * sizeof *v);
			level_args L = { 0 };
			level_piece p[8];
			rows R = { 0 };
			memset(v, 0, (size_t)w * h * sizeof *v);
			R.z = v, R.w = w, R.h = h, R.fail_at = -1;
			R.jitter = disp ? (double)(1 << level) : 0;
			L.level = level, L.size[0] = w, L.size[1] = h;
			L.displaced = disp, L.m = &gm, L.threads = 1;
			L.row = row_fn, L.row_ctx = &R;
			level_pieces(&L, 1, p, 8);
			/* the second piece: halos on both sides */
			int nb = pyramid_nblocks(h), same = 1, r;
			double *b1 = calloc(nb, sizeof *b1), *b2 = calloc(nb,
			    sizeof *b2);
			long long s1, s2;
			merged one, m;
			r = parts_merge(&L, &p[1], path, H, &R, &one, b1, &s1, &e);
			for (int k = 0; r == 0 && k < 3; k++) {
				static const int nr[] = { 37, 100, 700 };
				memset(b2, 0, nb * sizeof *b2);
				r = parts_merge(&L, &p[1], path, nr[k] << level,
				    &R, &m, b2, &s2, &e);
				same &= r == 0 && memcmp(one.acc, m.acc,
				    (size_t)Q * m.n * sizeof *m.acc) == 0 &&
				    memcmp(b1, b2, nb * sizeof *b1) == 0 &&
				    s1 == s2;
				free(m.acc);
			}
			ok(r == 0 && same, "level %d, %s, a piece's local and "
			    "base errors and samples from parts of 37, 100 and "
			    "700 rows: one part's, bit for bit (%s)", level,
			    disp ? "displaced" : "1D", r ? e.msg : "ok");
			free(one.acc), free(b1), free(b2), free(v);
		}
done:
	if (d != NULL)
		dem_close(d);
	geo_ground_free(&gm);
	free(z);
}

int
main(void)
{
	if (tmpdir_make(tmp, sizeof tmp, "tltiles") < 0) {
		ok(0, "set up");
		return tap_done();
	}
	test_spike();
	test_plane(300, 200); /* 3x2 blocks, padded */
	test_plane(257, 257); /* 2x2 blocks, then 1 */
	test_scan();
	test_pieces(0, 1500, 300, 0);
	test_pieces(1, 1500, 300, 0);
	/* parts of a level taller than the rings */
	test_pieces(0, 300, 1500, 1);
	test_part_errors();
	tmpdir_done(tmp);
	return tap_done();
}
