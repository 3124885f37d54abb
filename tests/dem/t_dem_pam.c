/* t_dem_pam.c - the DEM reader's GDAL datasets (dem_gdal_open) read an
 * .aux.xml sidecar and never write one, even when GDAL thinks a dataset
 * changed (its metadata set): the same change on a dataset GDAL opens
 * itself writes NAME.aux.xml, so the check can fail. */
#include <gdal.h>
#include <unistd.h>

#include "tap.h"
#include "tmpdir.h"
#include "dem/dem_gdal.h"

/* A 4 x 4 GeoTIFF at path; 0 when made. */
static int
make_tif(const char *path)
{
	GDALDriverH drv = GDALGetDriverByName("GTiff");
	GDALDatasetH ds = drv ? GDALCreate(drv, path, 4, 4, 1, GDT_Float32,
	    NULL) : NULL;
	double gt[6] = { 10, 1, 0, 20, 0, -1 };

	if (ds == NULL)
		return -1;
	GDALSetGeoTransform(ds, gt);
	GDALClose(ds);
	return 0;
}

/* Opens path with open, marks it changed, closes: whether a sidecar
 * appeared. */
static int
dirty_close(GDALDatasetH ds, const char *aux)
{
	if (ds == NULL)
		return -1;
	GDALSetMetadataItem(ds, "TL_TEST", "changed", NULL);
	GDALClose(ds);
	return access(aux, F_OK) == 0;
}

int
main(void)
{
	char dir[PATH_MAX - 64];
	const char *tif, *aux;
	GDALDatasetH ds;

	dem_gdal_init();
	if (!ok(tmpdir_make(dir, sizeof dir, "t_dem_pam") == 0, "scratch"))
		return tap_done();
	tif = tmpdir_join(dir, "a.tif"), aux = tmpdir_join(dir, "a.tif.aux.xml");
	ok(make_tif(tif) == 0, "a GeoTIFF");
	ok(dirty_close(dem_gdal_open(tif), aux) == 0,
	    "dem_gdal_open: a changed dataset writes no .aux.xml");
	ok(tmpdir_entries(dir, "") == 1, "nothing else beside it");
	ok(dirty_close(GDALOpenEx(tif, GDAL_OF_RASTER | GDAL_OF_READONLY,
	    NULL, NULL, NULL), aux) == 1,
	    "control: GDAL's own open writes one (so the check can fail)");
	ds = dem_gdal_open(tif);
	ok(ds != NULL && GDALGetMetadataItem(ds, "TL_TEST", NULL) != NULL,
	    "dem_gdal_open reads the sidecar");
	if (ds != NULL)
		GDALClose(ds);
	if (tap_failed == 0)
		tmpdir_done(dir);
	return tap_done();
}
