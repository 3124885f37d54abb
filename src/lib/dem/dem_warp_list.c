/* dem_warp_list.c - dem2rgb(1)'s input as one GDAL dataset (dem_gdal.h,
 * dem_warp_open): what GDAL opens, or a list of DEM files made the very
 * VRT that the reader reads for dem2vgis(1) and dem2fqm(1) (dem_list.c
 * gives its entries, dem_mosaic.c its checks and its VRT), so that the
 * warp, the extent and the error pass's reading (dem_open) see one DEM. */
#include <stdlib.h>
#include <string.h>

#include "dem/dem_gdal.h"

GDALDatasetH
dem_warp_open(const char *path, const dem_opts *o, int samples, tl_err *e)
{
	char **paths = NULL, name[DEM_NAME];
	GDALDatasetH ds;
	dem_gdal_msg m;
	dem_tiles dt;
	int n = 0, r;

	dem_gdal_init();
	/* GDAL's refusal of a list is no failure: kept from the caller's
	 * messages, which its warp's flush is judged by */
	dem_gdal_catch(&m);
	ds = dem_gdal_open(path);
	if (ds == NULL && (r = dem_list_paths(path, &paths, &n, e)) == 0)
		ds = dem_mosaic_vrt(paths, n, o, samples, dem_name(path, name),
		    &dt, e);
	else if (ds == NULL && r > 0)
		tl_fail(e, "%s: %s (dem2rgb reads a raster GDAL opens, or a "
		    "list of DEM files)", path, m.msg[0] ? m.msg :
		    "GDAL cannot open it");
	dem_gdal_release();
	for (int k = 0; k < n; k++)
		free(paths[k]);
	free(paths);
	return ds;
}
