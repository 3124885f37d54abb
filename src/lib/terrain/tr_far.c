/* tr_far.c - a projected DEM's selection spared the triangles that add
 * nothing to a tile. Every block of level p that meets a tile is walked
 * whole (bt_select), and at a deep level most of its triangles lie far
 * from the tile: tr_rim_sel (tr_cut.c) drops each, at the cost of
 * visiting it. A split vertex (c, r) of the bintree, k the lowest bit of
 * c | r, has its two triangles and all they hold within the square of
 * half-side k around it; when that square lies inside the DEM's grid
 * (no cut, no band) and the longitude, latitude box of its vertices
 * misses the tile beyond keep_grid's margin, every triangle under it
 * adds nothing, so it is not split: the one emitted in its place adds
 * nothing either, and the selection over the tile is the same. The
 * boxes: per block, of its aligned squares of side 4 to 128 cells. */
#include <math.h>
#include <stdlib.h>

#include "terrain/tr_impl.h"

#define K0 TR_FAR_K0
#define NL 6                      /* sides 4 .. 128 */
#define NBOX (32 * 32 + 16 * 16 + 8 * 8 + 4 * 4 + 2 * 2 + 1)

/* Level l's first box (side K0 << l, BT_CELLS / (K0 << l) a row). */
static int
first(int l)
{
	int o = 0;

	for (int i = 0, n = BT_CELLS / K0; i < l; i++, n /= 2)
		o += n * n;
	return o;
}

/* The boxes come from the vertices every SK cells of the block, the
 * lattice L (5 x 5, its 4 x 4 cells), not from all the vertices of the
 * squares: a tile's selection reads few of a block's vertices (through
 * PROJ as they are read: tr_ll_need), and the corners of every 4-cell
 * square were more conversions than the selection's own. */
#define SK 32
#define SN (BT_CELLS / SK + 1)

/* The bend of a (a vertex's longitude or latitude) over a cell of L:
 * within it, a is L's bilinear interpolant plus a rest of at most
 * (h^2 / 8) (sup |a_xx| + sup |a_yy|), h the step of L (linear
 * interpolation along x errs by h^2 / 8 sup |a_xx|, and the
 * interpolant in x of the errors along y, a convex mean of them, by no
 * more). A second difference of a along L, a(i-1) - 2 a(i) + a(i+1), is
 * h^2 a_xx at some place within a step of i (the mean value theorem):
 * the bend is the largest second difference of each direction over L,
 * their sum over 8, times 4 for a_xx's change from the places sampled to
 * any in the block, a step away at most (a map's second derivatives
 * change by their own size over thousands of kilometres; a step is 32
 * cells of level p: 1 km of N48W125's UTM warp at level 0, 60 km at
 * level 6), plus 1e-9 degrees (0.1 mm) for PROJ's rounding of each
 * vertex and the interpolant's. On that warp the bend is at most 6e-7
 * degrees at level 0 and 2.4e-3 at level 6 (its top), far within
 * tr_far's twentieth of a tile (5e-4 degrees at level 14, 0.14 at level
 * 6), and each vertex's distance past the interpolant at most a quarter
 * of it. */
static double
bend(const double *a)
{
	double d[2] = { 0, 0 };
	int x = SK, y = SK * BT_SIZE; /* a step along L's rows, columns */

	for (int j = 0; j < SN; j++)
		for (int i = 0; i < SN; i++) {
			const double *o = a + j * y + i * x;
			if (i > 0 && i < SN - 1)
				d[0] = fmax(d[0], fabs(o[-x] - 2 * o[0] + o[x]));
			if (j > 0 && j < SN - 1)
				d[1] = fmax(d[1], fabs(o[-y] - 2 * o[0] + o[y]));
		}
	return 4 * (d[0] + d[1]) / 8 + 1e-9;
}

/* L's interpolant at vertex (c, r) in its cell (i, j). */
static double
lerp(const double *a, int i, int j, int c, int r)
{
	const double *o = a + SK * (j * BT_SIZE + i);
	double s = (double)(c - SK * i) / SK, t = (double)(r - SK * j) / SK;

	return (1 - t) * ((1 - s) * o[0] + s * o[SK]) + t * ((1 - s) *
	    o[SK * BT_SIZE] + s * o[SK * BT_SIZE + SK]);
}

/* Each square's box: the interpolant's over it, that of its values at
 * the square's corners (it is linear along each side), widened by the
 * bend; so it holds every vertex of the square. */
static void
build(double *bx, const double *lon, const double *lat)
{
	int n = BT_CELLS / K0;
	double mx = bend(lon), my = bend(lat);

	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			double *o = bx + 4 * (j * n + i);
			int ci = K0 * i / SK, cj = K0 * j / SK;
			o[0] = o[1] = INFINITY, o[2] = o[3] = -INFINITY;
			for (int q = 0; q < 4; q++) {
				int c = K0 * (i + q % 2), r = K0 * (j + q / 2);
				double x = lerp(lon, ci, cj, c, r);
				double y = lerp(lat, ci, cj, c, r);
				o[0] = dmin(o[0], x), o[2] = dmax(o[2], x);
				o[1] = dmin(o[1], y), o[3] = dmax(o[3], y);
			}
			o[0] -= mx, o[2] += mx, o[1] -= my, o[3] += my;
		}
	for (int l = 1; l < NL; l++) {
		const double *a = bx + 4 * first(l - 1);
		double *b = bx + 4 * first(l);
		int m = n;
		n /= 2;
		for (int j = 0; j < n; j++)
			for (int i = 0; i < n; i++) {
				double *o = b + 4 * (j * n + i);
				o[0] = o[1] = INFINITY, o[2] = o[3] = -INFINITY;
				for (int q = 0; q < 4; q++) {
					const double *s = a + 4 * ((2 * j + q / 2) * m +
					    2 * i + q % 2);
					o[0] = dmin(o[0], s[0]), o[1] = dmin(o[1], s[1]);
					o[2] = dmax(o[2], s[2]), o[3] = dmax(o[3], s[3]);
				}
			}
	}
}

const double *
tr_far_boxes(tr_work *w, const pyramid_block *b, const double *lon,
    const double *lat)
{
	int s = (int)(b - w->cache), v[SN * SN];
	tl_err ignored;

	if (w->cboxok[s])
		return w->cbox[s];
	for (int j = 0; j < SN; j++)
		for (int i = 0; i < SN; i++)
			v[j * SN + i] = SK * (j * BT_SIZE + i);
	/* no memory, or PROJ failing on L (the selection will say): every
	 * triangle visited */
	if (tr_ll_need(w, b, v, SN * SN, &ignored) < 0 || (w->cbox[s] ==
	    NULL && (w->cbox[s] = malloc(4 * NBOX * sizeof *w->cbox[s])) ==
	    NULL))
		return NULL;
	build(w->cbox[s], lon, lat);
	w->cboxok[s] = 1;
	return w->cbox[s];
}

int
tr_far(const tr_grid *g, const double *bx, int p, int bi, int bj, int c,
    int r, int z, const double t[4])
{
	int k = (c | r) & -(c | r), l = 0;
	double W = g->w0 - 1, H = g->h0 - 1, m = ldexp(180, -z) / 20;
	double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY,
		-INFINITY };

	if (k < K0 || k > BT_CELLS / 2)
		return 0;
	/* inside the grid: the places tr_rim_sel gives its vertices */
	if (!((double)(bi * BT_CELLS + c - k) * (1 << p) > 0 &&
	    (double)(bi * BT_CELLS + c + k) * (1 << p) < W &&
	    (double)(bj * BT_CELLS + r - k) * (1 << p) > 0 &&
	    (double)(bj * BT_CELLS + r + k) * (1 << p) < H))
		return 0;
	while ((K0 << l) < k)
		l++;
	int n = BT_CELLS / k;
	const double *o = bx + 4 * first(l);
	/* the square c - k .. c + k: the aligned ones each side of c, r
	 * (those past the block hold no triangle of it) */
	for (int j = r / k - 1; j <= r / k; j++)
		for (int i = c / k - 1; i <= c / k; i++) {
			if (i < 0 || j < 0 || i >= n || j >= n)
				continue;
			const double *s = o + 4 * (j * n + i);
			lo[0] = dmin(lo[0], s[0]), lo[1] = dmin(lo[1], s[1]);
			hi[0] = dmax(hi[0], s[2]), hi[1] = dmax(hi[1], s[3]);
		}
	return hi[0] < t[0] - m || lo[0] > t[2] + m || hi[1] < t[1] - m ||
	    lo[1] > t[3] + m;
}
