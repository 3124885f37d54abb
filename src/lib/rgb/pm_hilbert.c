/* pm_hilbert.c - PMTiles tile ids: z/x/y to its place on the series of
 * Hilbert curves, one a zoom, and back (pmtiles.h; PMTiles v3
 * specification, protomaps/PMTiles spec/v3/spec.md, 4.1 TileID). The
 * arithmetic is the reference implementation's (its rotate, in unsigned
 * integers: only the bits below the current one matter after a turn). */
#include "rgb/pmtiles.h"

#include <assert.h>

/* The tiles of the zooms above z: (4^z - 1) / 3; z = 32 too, the first
 * id past the last zoom ((2^64 - 1) / 3). */
static uint64_t
zoom_base(int z)
{
	return z == 32 ? UINT64_MAX / 3 : ((UINT64_C(1) << (2 * z)) - 1) / 3;
}

/* The quadrant turned so that the curve's sub-square reads as the
 * whole: a reflection when ry is 0 and rx is not, then a transpose. */
static void
rotate(uint64_t n, uint64_t *x, uint64_t *y, uint64_t rx, uint64_t ry)
{
	uint64_t t;

	if (ry != 0)
		return;
	if (rx != 0) {
		*x = n - 1 - *x;
		*y = n - 1 - *y;
	}
	t = *x, *x = *y, *y = t;
}

uint64_t
pm_tileid(int z, uint32_t x, uint32_t y)
{
	uint64_t acc = zoom_base(z), tx = x, ty = y;

	assert(z >= 0 && z <= PM_MAXZOOM);
	assert((uint64_t)x < (UINT64_C(1) << z) &&
	    (uint64_t)y < (UINT64_C(1) << z));
	for (int a = z - 1; a >= 0; a--) {
		uint64_t s = UINT64_C(1) << a, rx = tx & s, ry = ty & s;

		acc += (uint64_t)((3 * (rx != 0)) ^ (ry != 0)) << (2 * a);
		rotate(s, &tx, &ty, rx, ry);
	}
	return acc;
}

int
pm_tile_zxy(uint64_t id, int *z, uint32_t *x, uint32_t *y)
{
	uint64_t pos, tx = 0, ty = 0, n;
	int k = 0;

	if (id >= zoom_base(PM_MAXZOOM + 1))
		return -1;
	while (zoom_base(k + 1) <= id)
		k++;
	pos = id - zoom_base(k);
	n = UINT64_C(1) << k;
	for (uint64_t s = 1; s < n; s <<= 1) {
		uint64_t rx = s & (pos / 2), ry = s & (pos ^ rx);

		rotate(s, &tx, &ty, rx, ry);
		tx += rx, ty += ry;
		pos >>= 1;
	}
	*z = k, *x = (uint32_t)tx, *y = (uint32_t)ty;
	return 0;
}
