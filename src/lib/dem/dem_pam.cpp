// dem_pam.cpp - GDAL datasets opened for reading only, sidecars included:
// GDAL's auxiliary metadata (PAM, NAME.aux.xml: the CRS and geotransform
// gdal_translate gives a PNG, AREA_OR_POINT, nodata, ...) is read, but a
// dataset GDAL thinks changed would write one on close beside the user's
// file, so saving is turned off on every dataset the reader opens
// (dem_gdal.h). No exception leaves it.
#include <gdal_pam.h>

// declared in dem_gdal.h, a C header
extern "C" GDALDatasetH dem_gdal_open(const char *path);

GDALDatasetH
dem_gdal_open(const char *path)
{
	GDALDatasetH h = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY,
	    nullptr, nullptr, nullptr);
	GDALPamDataset *p;

	if (h == nullptr)
		return nullptr;
	p = dynamic_cast<GDALPamDataset *>(GDALDataset::FromHandle(h));
	if (p != nullptr)
		p->SetPamFlags(p->GetPamFlags() | GPF_NOSAVE);
	return h;
}
