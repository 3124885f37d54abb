/* t_far_boxes.c - a projected block's vertices through PROJ as they are
 * read (tr_ll_need, terrain/tr_grid.c) and the boxes of its squares
 * (tr_far_boxes, tr_far.c), made from a 5 x 5 lattice of its vertices
 * widened by the map's bend: on blocks of four CRSs (UTM, LAEA, Lambert
 * conformal, polar stereographic), at level 0 and at a coarse level, the
 * boxes read the 25 vertices of the lattice and no other; each box holds
 * every vertex of its square (tr_far's test and the measure's skip are
 * conservative only so); and the vertices converted a few at a time, a
 * vertex listed twice among them, are the doubles the whole block
 * through PROJ at once gives (what the scratch file and the output rely
 * on). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tap.h"
#include "terrain/tr_impl.h"

/* Block (0, 0) of level l of a north-up grid of step s metres whose
 * corner is (x0, y0) in crs. */
static void
check(const char *crs, int epsg, double x0, double y0, double s, int l)
{
	static tr_work w;
	static pyramid_index ix;
	static double x[PYRAMID_N], y[PYRAMID_N];
	tr_grid g = { 0 };
	tl_err e = { "" };
	const double *bx;
	int n = BT_CELLS / TR_FAR_K0, out = 0, same = 1, three[3];

	memset(&w, 0, sizeof w), memset(&ix, 0, sizeof ix);
	ix.geo.model = GEO_PROJECTED, ix.geo.epsg = epsg;
	snprintf(ix.geo.crs, sizeof ix.geo.crs, "%s", crs);
	ix.geo.origin[0] = x0, ix.geo.origin[1] = y0;
	ix.geo.step[0] = s, ix.geo.step[1] = -s, ix.geo.unit = 1;
	g.projected = 1, g.w0 = g.h0 = BT_SIZE << l;
	w.ix = &ix, w.g = &g, w.ncache = 1;
	if (!ok(geo_proj_open(&w.proj, &ix.geo, &e) == 0, "%s: PROJ (%s)",
	    crs, e.msg))
		return;
	w.clon[0] = malloc(2 * PYRAMID_N * sizeof *w.clon[0]);
	w.clat[0] = w.clon[0] + PYRAMID_N;
	for (int v = 0; v < 2 * PYRAMID_N; v++)
		w.clon[0][v] = NAN;
	w.cused[0] = 1, w.ckey[0][0] = l;
	bx = tr_far_boxes(&w, &w.cache[0], w.clon[0], w.clat[0]);
	ok(bx != NULL && w.cnll[0] == 25, "%s level %d: the boxes converted "
	    "%d vertices", crs, l, w.cnll[0]);
	/* the rest a few at a time, each vertex twice */
	for (int v = 0; v < PYRAMID_N; v++) {
		three[0] = v, three[1] = v + 1 < PYRAMID_N ? v + 1 : v;
		three[2] = v;
		if (tr_ll_need(&w, &w.cache[0], three, 3, &e) < 0)
			same = 0;
	}
	ok(same && w.cnll[0] == PYRAMID_N, "%s level %d: every vertex "
	    "converted once (%d)", crs, l, w.cnll[0]);
	for (int v = 0; v < PYRAMID_N; v++)
		x[v] = (double)(v % BT_SIZE << l), y[v] = (double)(v / BT_SIZE <<
		    l);
	same = tr_lonlat(&g, &w.proj, &ix.geo, x, y, PYRAMID_N, &e) == 0 &&
	    memcmp(x, w.clon[0], sizeof x) == 0 &&
	    memcmp(y, w.clat[0], sizeof y) == 0;
	ok(same, "%s level %d: the doubles of the whole block at once", crs,
	    l);
	for (int j = 0; bx && j < n; j++)
		for (int i = 0; i < n; i++) {
			const double *o = bx + 4 * (j * n + i);
			for (int r = TR_FAR_K0 * j; r <= TR_FAR_K0 * (j + 1); r++)
				for (int c = TR_FAR_K0 * i; c <= TR_FAR_K0 * (i + 1);
				    c++) {
					double a = w.clon[0][r * BT_SIZE + c];
					double b = w.clat[0][r * BT_SIZE + c];
					out += !(a >= o[0] && a <= o[2] && b >= o[1] &&
					    b <= o[3]);
				}
		}
	ok(bx && out == 0, "%s level %d: every vertex within its square's "
	    "box (%d outside)", crs, l, out);
	free(w.clon[0]), free(w.cbox[0]);
	geo_proj_close(&w.proj);
}

int
main(void)
{
	/* N48W125's UTM zone; Catalonia in LAEA Europe; France's Lambert
	 * 93; Greenland's polar stereographic */
	check("EPSG:32610", 32610, 400000, 5450000, 30, 0);
	check("EPSG:32610", 32610, 400000, 5450000, 30, 6);
	check("EPSG:3035", 3035, 3600000, 2250000, 80, 0);
	check("EPSG:3035", 3035, 3600000, 2250000, 80, 5);
	check("EPSG:2154", 2154, 550000, 6300000, 25, 0);
	check("EPSG:2154", 2154, 550000, 6300000, 25, 7);
	check("EPSG:3413", 3413, -300000, -1000000, 100, 0);
	check("EPSG:3413", 3413, -300000, -1000000, 100, 6);
	return tap_done();
}
