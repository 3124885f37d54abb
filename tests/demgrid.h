/* demgrid.h - small DEMs with voids where a test wants them, as Esri ASCII
 * grids (GDAL reads them): the fixtures of the filled-DEM tests. */
#ifndef T_DEMGRID_H
#define T_DEMGRID_H

#include <stdio.h>

/* path: w x h samples z(i, j), nodata -9999 where isvoid(i, j). */
static inline void
demgrid_write(const char *path, int w, int h, double (*z)(int, int),
    int (*isvoid)(int, int))
{
	FILE *f = fopen(path, "w");

	if (f == NULL)
		return; /* the test that opens it says so */
	fprintf(f, "ncols %d\nnrows %d\nxllcorner 1000\nyllcorner 2000\n"
	    "cellsize 10\nNODATA_value -9999\n", w, h);
	for (int j = 0; j < h; j++)
		for (int i = 0; i < w; i++)
			fprintf(f, "%.4f%c", isvoid(i, j) ? -9999 : z(i, j),
			    i == w - 1 ? '\n' : ' ');
	fclose(f);
}

/* exact in the grid's decimals and in float32 */
static inline double z_wave(int i, int j) { return 100 + 0.25 * i +
    0.5 * j * j + (i * 7 + j * 3) % 11 * 0.125; }
/* row 3 and column 4 void across the whole grid (an orphan where they
 * meet), and a corner */
static inline int v_cross(int i, int j) { return j == 3 || i == 4 ||
    (i == 8 && j == 6); }
/* voids in rows of every 64-row word (the rank table), whole row 70,
 * the last row; the first and last column */
static inline int v_tall(int i, int j) { return j == 70 || j == 129 ||
    (j % 5 == 0 && i == j % 3) || (j == 64 && i == 2) || (j == 63 && i == 0); }
static inline int v_none(int i, int j) { return 0; }
/* only the first and last columns, whole (300 wide) */
static inline int v_edges(int i, int j) { return i == 0 || i == 299; }
/* whole rows 7 and 13 (a 7-row band's first and last), whole columns 0,
 * 5 and 19 (orphans where they meet), scattered voids, the last row but
 * one sample */
static inline int v_bands(int i, int j) { return j == 7 || j == 13 ||
    i == 0 || i == 5 || i == 19 || (j % 4 == 1 && i == j * 3 % 20) ||
    (j == 20 && i != 11); }

#endif
