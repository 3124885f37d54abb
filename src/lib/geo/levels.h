/* levels.h - the level-size rule of the pyramid, which the DEM reader,
 * the FQM format, the packer, the checker and the exporters all share:
 * level l of a grid of n0 samples has ceil((n0-1)/2^l)+1 of them (every
 * other vertex kept, the last one always), down to the first level that
 * fits one block of GEO_LEVEL_BLOCK x GEO_LEVEL_BLOCK vertices (vgis(5)).
 * Header only: the supervisor (dem2vgis) needs it and links no
 * georeferencing. */
#ifndef TL_GEO_LEVELS_H
#define TL_GEO_LEVELS_H

#define GEO_LEVEL_BLOCK 129

/* Columns (or rows) of level l for a level-0 extent of n0. */
static inline int
geo_level_size(int n0, int level)
{
	long long span = n0 - 1, step = 1LL << level;

	return (int)((span + step - 1) / step) + 1;
}

/* The pyramid's level count: levels 0 .. the first that fits one block. */
static inline int
geo_levels(int w0, int h0)
{
	int l = 0;

	while (geo_level_size(w0, l) > GEO_LEVEL_BLOCK ||
	    geo_level_size(h0, l) > GEO_LEVEL_BLOCK)
		l++;
	return l + 1;
}

#endif
