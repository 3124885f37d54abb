/* dem_mosaic_tile.c - a mosaic's tile opened by GDAL (dem_mosaic.h): a
 * leaf, which the checks and the overlaps both open tiles with. */
#include <string.h>

#include "dem/dem_mosaic.h"

GDALDatasetH
dem_mosaic_open(const char *path, tl_err *e)
{
	GDALDatasetH ds;
	dem_gdal_msg c;
	char name[DEM_NAME];

	dem_name(path, name);
	dem_gdal_catch(&c);
	ds = dem_gdal_open(path);
	dem_gdal_release();
	if (ds == NULL && (c.msg[0] == '\0' || strstr(c.msg,
	    "not recognized") != NULL))
		tl_fail(e, "%s: not a raster GDAL reads (a mosaic's tiles are "
		    "read by GDAL)", name);
	else if (ds == NULL)
		tl_fail(e, "%s: truncated or corrupt: %s", name, c.msg);
	else if (GDALGetRasterCount(ds) < 1) {
		GDALClose(ds);
		ds = NULL;
		tl_fail(e, "%s: no raster band", name);
	}
	return ds;
}
