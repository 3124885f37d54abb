/* fz_dem - the DEM input adapter (GDAL for every raster format, the EXR
 * plugin, void filling): the first byte picks the file name's extension,
 * since GDAL and the reader go by it for .hgt and .asc; then every row. */
#include <stdlib.h>

#include "dem/dem.h"
#include "fuzz.h"

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char *const names[] = { "d.tif", "d.png", "d.asc",
		"N44W072.hgt", "d.exr", "d.vrt", "d" };
	const char *path;
	dem_opts o = { 0 };
	const georef *g;
	float *z;
	unsigned char *v;
	tl_err e;
	dem *d;

	if (size < 1)
		return 0;
	path = fuzz_file(names[data[0] % 7], data + 1, size - 1);
	if (path == NULL || (d = dem_open(path, &o, &e)) == NULL)
		return 0;
	g = dem_georef(d);
	z = malloc((size_t)g->width * sizeof *z);
	v = malloc((size_t)g->width);
	for (int j = 0; z != NULL && v != NULL && j < g->height; j++)
		if (dem_read_row(d, j, z, v, &e) < 0)
			break;
	free(z), free(v);
	dem_close(d);
	return 0;
}
