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

static void
build(double *bx, const double *lon, const double *lat)
{
	int n = BT_CELLS / K0;

	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			double *o = bx + 4 * (j * n + i);
			o[0] = o[1] = INFINITY, o[2] = o[3] = -INFINITY;
			for (int r = K0 * j; r <= K0 * (j + 1); r++)
				for (int c = K0 * i; c <= K0 * (i + 1); c++) {
					int v = r * BT_SIZE + c;
					o[0] = dmin(o[0], lon[v]), o[2] = dmax(o[2], lon[v]);
					o[1] = dmin(o[1], lat[v]), o[3] = dmax(o[3], lat[v]);
				}
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
	int s = (int)(b - w->cache);

	if (w->cboxok[s])
		return w->cbox[s];
	if (w->cbox[s] == NULL &&
	    (w->cbox[s] = malloc(4 * NBOX * sizeof *w->cbox[s])) == NULL)
		return NULL; /* no memory: every triangle visited */
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
