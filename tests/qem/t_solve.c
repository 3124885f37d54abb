/* t_solve - placing a level's vertices (solve.h): mode names, the vertex
 * map's header and row encoding, the pass-through modes, QEM-1D on a
 * plane and on a vertex without planes, the cell test, and QEM-3D's
 * streaming fold fix checked by brute force on whole levels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/pool.h"
#include "qem/solve.h"
#include "tap.h"
#include "urand.h"

#define DX 30.0
#define DY 20.0

static void
test_modes(void)
{
	static const char *const names[] = { "qem1d", "qem3d", "filtered",
		"subsample" };
	enum solve_mode m;
	int bad = 0;

	for (int k = 0; k < 4; k++) {
		bad += solve_mode_parse(names[k], &m) != 0;
		bad += strcmp(solve_mode_name(m), names[k]) != 0;
	}
	ok(bad == 0, "solve_mode_parse and solve_mode_name round-trip the "
	    "four modes");
	m = SOLVE_QEM3D;
	ok(solve_mode_parse("qem2d", &m) < 0 && solve_mode_parse("QEM1D",
	    &m) < 0 && m == SOLVE_QEM3D, "an unknown mode is refused, the "
	    "mode left as it was");
}

/* The vertex map's header keeps the FQM's attributes and says what it
 * is; solve_encode puts each field in its channel. */
static void
test_header(void)
{
	rs_header fqm, oh;
	solve_vertex v[2] = { { 1.5, -2, 3, 1 }, { 7, 0.25, -0.5, 0 } };
	float row[4 * 2];
	int x, y, z, vv;

	rs_header_init(&fqm, 2, 1);
	rs_add_channel(&fqm, "Q.a11", NULL);
	rs_add_channel(&fqm, "S", NULL);
	rs_set_int(&fqm, FQM_ATTR_LEVEL, 3, NULL);
	rs_set_string(&fqm, FQM_ATTR_KIND, "fqm", NULL);
	ok(solve_header(&oh, &fqm, SOLVE_QEM1D, NULL) == 0 && oh.nch == 2 &&
	    rs_channel(&oh, "Z") >= 0 && rs_channel(&oh, "V") >= 0 &&
	    rs_channel(&oh, "S") < 0, "QEM-1D map: channels V Z only");
	rs_header_free(&oh);
	ok(solve_header(&oh, &fqm, SOLVE_QEM3D, NULL) == 0 && oh.nch == 4 &&
	    strcmp(rs_get_string(&oh, FQM_ATTR_KIND), "vertices") == 0 &&
	    strcmp(rs_get_string(&oh, FQM_ATTR_MODE), "qem3d") == 0 &&
	    rs_get_int(&oh, FQM_ATTR_LEVEL, &x) == 0 && x == 3,
	    "QEM-3D map: V X Y Z, kind vertices, mode qem3d, fqm:level kept");
	solve_encode(&oh, v, row);
	x = rs_channel(&oh, "X"), y = rs_channel(&oh, "Y");
	z = rs_channel(&oh, "Z"), vv = rs_channel(&oh, "V");
	ok(row[z * 2] == 1.5f && row[z * 2 + 1] == 7 && row[x * 2] == -2 &&
	    row[x * 2 + 1] == 0.25f && row[y * 2] == 3 &&
	    row[y * 2 + 1] == -0.5f && row[vv * 2] == 1 && row[vv * 2 + 1] == 0,
	    "solve_encode: each field in its channel, channel-planar");
	rs_header_free(&oh);
	rs_header_free(&fqm);
}

/* One row of three vertices through a mode. */
static void
solve_one(enum solve_mode mode, const fqm_vertex *in, solve_vertex *out)
{
	geo_ground m;
	solve_state s;

	geo_ground_const(&m, 8, DX, DY, NULL);
	solve_init(&s, mode, 0, 3, 3, &m, NULL);
	solve_row(&s, in, out);
	solve_free(&s);
	geo_ground_free(&m);
}

static void
test_rows(void)
{
	fqm_vertex in[3];
	solve_vertex out[3];
	double n[3] = { 0, 0.6, 0.8 };
	int bad = 0;

	memset(in, 0, sizeof in);
	for (int i = 0; i < 3; i++) {
		in[i].z = 100 + i, in[i].s = 50 - i, in[i].v = i != 1;
		/* the plane 0.6 y + 0.8 z - 4 = 0: z = 5 at x = y = 0 */
		quadric_add_plane(&in[i].q, n, -4, 1 + i);
	}
	quadric_zero(&in[2].q); /* a void: no plane at all */
	solve_one(SOLVE_FILTERED, in, out);
	for (int i = 0; i < 3; i++)
		bad += out[i].z != in[i].z || out[i].v != in[i].v ||
		    out[i].x != 0 || out[i].y != 0;
	solve_one(SOLVE_SUBSAMPLE, in, out);
	for (int i = 0; i < 3; i++)
		bad += out[i].z != in[i].s || out[i].v != in[i].v;
	ok(bad == 0, "filtered and subsample: Z and S passed through, V "
	    "too, no offsets");
	solve_one(SOLVE_QEM1D, in, out);
	ok(fabs(out[0].z - 105) < 1e-12 && fabs(out[1].z - 106) < 1e-12 &&
	    out[2].z == 102 && out[1].v == 0, "QEM-1D: the reference height "
	    "plus the quadric's z (%g %g), the reference height where no "
	    "plane constrains z (%g)", out[0].z, out[1].z, out[2].z);
}

static void
test_cell(void)
{
	double g[4][2] = { { 0, 0 }, { 30, 0 }, { 30, 20 }, { 0, 20 } };
	double p[4][2], f[4][2];

	memcpy(p, g, sizeof p);
	ok(solve_cell_ok(p, g, 1) && solve_cell_ok(p, g, 0.05),
	    "solve_cell_ok: the grid cell itself passes, even at min 1");
	p[2][0] = 5, p[2][1] = 2; /* corner 2 pulled near corner 0 */
	ok(!solve_cell_ok(p, g, 0.05), "solve_cell_ok: a corner pulled "
	    "across the other diagonal fails");
	memcpy(f, g, sizeof f);
	f[1][0] = -30; /* mirrored: every triangle flips */
	ok(!solve_cell_ok(f, g, 0), "solve_cell_ok: a folded cell fails");
}

/* QEM-3D on quadrics pulling each vertex up to a cell away in a random
 * direction: every cell of the result is convex with its triangles at
 * least `shrink` of their grid area, boundary vertices on their boundary,
 * offsets within half a cell. Checked by brute force on the whole level. */
static void
test_folds(int level, int W, int H, double reach)
{
	geo_ground m;
	int n = (W > H ? W : H) << (level + 1);
	fqm_vertex *in = calloc(W, sizeof *in);
	solve_vertex *lev = calloc((size_t)W * H, sizeof *lev);
	solve_state s;
	unsigned seed = 99;
	long bad = 0, moved = 0, outside = 0;
	double sx, sy;

	geo_ground_const(&m, n, DX, DY, NULL);
	sx = DX * (1 << level), sy = DY * (1 << level);
	solve_init(&s, SOLVE_QEM3D, level, W, H, &m, NULL);
	for (int j = 0; j < H; j++) {
		for (int i = 0; i < W; i++) {
			/* three planes through a random point: full rank */
			double p[3] = { reach * sx * urand(&seed),
				reach * sy * urand(&seed), 3 * urand(&seed) };
			double ns[3][3] = { { 0.3, 0, 1 }, { -0.2, 0.4, 1 },
				{ 0, -0.5, 1 } };
			quadric_zero(&in[i].q);
			for (int k = 0; k < 3; k++) {
				double *nn = ns[k], l = sqrt(nn[0] * nn[0] +
				    nn[1] * nn[1] + 1);
				double u[3] = { nn[0] / l, nn[1] / l, 1 / l };
				quadric_add_plane(&in[i].q, u, -(u[0] * p[0] +
				    u[1] * p[1] + u[2] * p[2]), 1);
			}
			in[i].z = 100, in[i].v = 1;
		}
		solve_row(&s, in, lev + (size_t)j * W);
	}
	for (int j = 0; j < H; j++)
		for (int i = 0; i < W; i++) {
			solve_vertex *v = &lev[(size_t)j * W + i];
			moved += v->x != 0 || v->y != 0;
			if (fabs(v->x) > sx / 2 || fabs(v->y) > sy / 2 ||
			    ((i == 0 || i == W - 1) && v->x != 0) ||
			    ((j == 0 || j == H - 1) && v->y != 0))
				outside++;
			/* the two-cell triangles of a scale-1 edge vertex */
			int kind = (i & 1) && !(j & 1) ? 0 : !(i & 1) && (j & 1) ?
			    1 : -1;
			static const int et[2][2][3][2] = {
				{ { { -1, 0 }, { 1, 0 }, { 0, -1 } },
				  { { -1, 0 }, { 1, 0 }, { 0, 1 } } },
				{ { { 0, -1 }, { 0, 1 }, { -1, 0 } },
				  { { 0, -1 }, { 0, 1 }, { 1, 0 } } },
			};
			for (int t = 0; kind >= 0 && t < 2; t++) {
				double g3[3][2], p3[3][2], ga, pa;
				int inside = 1;
				for (int k = 0; k < 3; k++) {
					int ii = i + et[kind][t][k][0];
					int jj = j + et[kind][t][k][1];
					if (ii < 0 || jj < 0 || ii >= W || jj >= H)
						inside = 0;
					else {
						solve_vertex *u = &lev[(size_t)jj * W + ii];
						g3[k][0] = ii * sx, g3[k][1] = jj * sy;
						p3[k][0] = g3[k][0] + u->x;
						p3[k][1] = g3[k][1] + u->y;
					}
				}
				if (!inside)
					continue;
				ga = (g3[1][0] - g3[0][0]) * (g3[2][1] - g3[0][1]) -
				    (g3[1][1] - g3[0][1]) * (g3[2][0] - g3[0][0]);
				pa = (p3[1][0] - p3[0][0]) * (p3[2][1] - p3[0][1]) -
				    (p3[1][1] - p3[0][1]) * (p3[2][0] - p3[0][0]);
				bad += ga > 0 ? pa < s.shrink * ga : pa > s.shrink * ga;
			}
			if (i + 1 == W || j + 1 == H)
				continue;
			double g[4][2] = { { 0, 0 }, { sx, 0 }, { sx, sy },
				{ 0, sy } }, p[4][2];
			solve_vertex *c[4] = { v, v + 1, v + 1 + W, v + W };
			for (int k = 0; k < 4; k++)
				p[k][0] = g[k][0] + c[k]->x,
				p[k][1] = g[k][1] + c[k]->y;
			bad += !solve_cell_ok(p, g, s.shrink);
		}
	ok(bad == 0 && outside == 0 && moved > W * H / 2,
	    "QEM-3D %dx%d level %d, targets up to %.1f cell away: %ld "
	    "folded cell or two-cell triangles, %ld offsets out of bounds, "
	    "%ld of %d vertices "
	    "moved, fold fix reduced %lld (zeroed %lld)", W, H, level, reach,
	    bad, outside, moved, W * H, s.reduced, s.zeroed);
	solve_free(&s);
	free(in), free(lev);
	geo_ground_free(&m);
}


/* solve_row_direct (fqmsolve's path: the FQM's channels in, the map's
 * out) gives the bits of solve_row and solve_encode, for every mode but
 * QEM-3D, on random rows: zeros of both signs in Z and the quadric,
 * a33 zero or negative (no plane), widths not a multiple of 4. */
static void
test_direct(void)
{
	static const char *const qch[10] = { "Q.a11", "Q.a12", "Q.a13",
		"Q.a22", "Q.a23", "Q.a33", "Q.b1", "Q.b2", "Q.b3", "Q.c" };
	static const enum solve_mode modes[3] = { SOLVE_QEM1D, SOLVE_FILTERED,
		SOLVE_SUBSAMPLE };
	unsigned seed = 5;
	int bad = 0, n = 0;

	for (int w = 1; w <= 13; w += 3)
		for (int mi = 0; mi < 3; mi++) {
			rs_header fqm, oh;
			fqm_layout L;
			geo_ground m;
			solve_state s, t;
			int h = 64;
			float *in = malloc((size_t)w * 13 * sizeof *in);
			float *a = malloc((size_t)w * 2 * sizeof *a);
			float *b = malloc((size_t)w * 2 * sizeof *b);
			fqm_vertex *v = malloc((size_t)w * sizeof *v);
			solve_vertex *sv = malloc((size_t)w * sizeof *sv);
			rs_header_init(&fqm, w, h);
			for (int k = 0; k < 10; k++)
				rs_add_channel(&fqm, qch[k], NULL);
			rs_add_channel(&fqm, "Z", NULL);
			rs_add_channel(&fqm, "S", NULL);
			rs_add_channel(&fqm, "V", NULL);
			fqm_layout_of(&fqm, &L, "t", NULL);
			solve_header(&oh, &fqm, modes[mi], NULL);
			geo_ground_const(&m, 64, DX, DY, NULL);
			solve_init(&s, modes[mi], 2, w, h, &m, NULL);
			solve_init(&t, modes[mi], 2, w, h, &m, NULL);
			for (int y = 0; y < h; y++, n++) {
				for (int i = 0; i < w * 13; i++)
					in[i] = any_float(&seed);
				fqm_decode(&L, in, w, v);
				solve_row(&s, v, sv);
				solve_encode(&oh, sv, a);
				solve_row_direct(&t, &L, in, &oh, b);
				bad += memcmp(a, b, (size_t)w * 2 *
				    sizeof *a) != 0;
			}
			solve_free(&s), solve_free(&t);
			geo_ground_free(&m);
			rs_header_free(&oh), rs_header_free(&fqm);
			free(in), free(a), free(b), free(v), free(sv);
		}
	ok(bad == 0, "solve_row_direct: the bits of solve_row + "
	    "solve_encode (QEM-1D, filtered, sub-sampled; %d random rows "
	    "of 1 to 13 vertices, zeros of both signs, no-plane vertices)",
	    n - bad);
}

/* QEM-3D rows solved on a pool of n threads (placements and fold checks
 * cut in ranges), for the test below: targets up to `reach` cells away
 * force folds to fix. */
static void
solve_on(int n, int level, int W, int H, double reach, solve_vertex *lev,
    long long counts[2])
{
	geo_ground m;
	fqm_vertex *in = calloc(W, sizeof *in);
	tl_pool *p = n > 1 ? tl_pool_new(n, NULL) : NULL;
	solve_state s;
	unsigned seed = 7;
	double sx = DX * (1 << level), sy = DY * (1 << level);

	geo_ground_const(&m, (W > H ? W : H) << (level + 1), DX, DY, NULL);
	solve_init(&s, SOLVE_QEM3D, level, W, H, &m, NULL);
	solve_pool(&s, p, NULL);
	for (int j = 0; j < H; j++) {
		for (int i = 0; i < W; i++) {
			double c[3] = { reach * sx * urand(&seed),
				reach * sy * urand(&seed), 3 * urand(&seed) };
			double ns[3][3] = { { 0.3, 0, 1 },
				{ -0.2 + 0.1 * urand(&seed), 0.4, 1 }, { 0, -0.5, 1 } };
			quadric_zero(&in[i].q);
			for (int k = 0; k < 3; k++) {
				double *nn = ns[k], l = sqrt(nn[0] * nn[0] +
				    nn[1] * nn[1] + 1);
				double u[3] = { nn[0] / l, nn[1] / l, 1 / l };
				quadric_add_plane(&in[i].q, u, -(u[0] * c[0] +
				    u[1] * c[1] + u[2] * c[2]), 1);
			}
			in[i].z = 100, in[i].v = 1;
		}
		solve_row(&s, in, lev + (size_t)j * W);
	}
	counts[0] = s.reduced, counts[1] = s.zeroed;
	solve_free(&s);
	tl_pool_free(p);
	geo_ground_free(&m);
	free(in);
}

/* The same level on 1, 2 and 5 threads: the same vertices bit for bit,
 * the same fold fix counts (each vertex placed alone; a mark is a set). */
static void
test_pool(void)
{
	int W = 203, H = 37;
	size_t n = (size_t)W * H;
	solve_vertex *a = calloc(n, sizeof *a), *b = calloc(n, sizeof *b);
	long long ca[2], cb[2];

	solve_on(1, 1, W, H, 2.0, a, ca);
	for (int t = 2; t <= 5; t += 3) {
		solve_on(t, 1, W, H, 2.0, b, cb);
		ok(memcmp(a, b, n * sizeof *a) == 0 && ca[0] == cb[0] &&
		    ca[1] == cb[1] && ca[0] > 0,
		    "QEM-3D %dx%d on %d threads: every vertex and the fold "
		    "fix's counts (%lld reduced, %lld zeroed) those of one "
		    "thread, bit for bit", W, H, t, ca[0], ca[1]);
	}
	free(a), free(b);
}

int
main(void)
{
	test_modes();
	test_header();
	test_rows();
	test_direct();
	test_cell();
	test_folds(0, 60, 40, 0.3);
	test_folds(2, 60, 40, 1.0);
	test_folds(3, 129, 129, 3.0);
	test_pool();
	return tap_done();
}
