#!/usr/bin/python3
"""ellipsoidal.py SRC DST: a geographic DEM of EGM96 heights (SRTM) as a
float32 GeoTIFF of WGS 84 ellipsoidal heights, converted sample by sample
by PROJ (pyproj), voids NaN, CRS EPSG:4326 with no vertical datum."""
import sys
import numpy as np
from osgeo import gdal
from pyproj import Transformer
src, dst = sys.argv[1], sys.argv[2]
ds = gdal.Open(src)
z = ds.GetRasterBand(1).ReadAsArray().astype(np.float64)
nd = ds.GetRasterBand(1).GetNoDataValue()
gt = ds.GetGeoTransform()
h, w = z.shape
jj, ii = np.mgrid[0:h, 0:w]
lon = gt[0] + (ii + 0.5) * gt[1]
lat = gt[3] + (jj + 0.5) * gt[5]
t = Transformer.from_crs('EPSG:4326+5773', 'EPSG:4979', always_xy=True)
_, _, e = t.transform(lon, lat, np.where(z == nd, 0, z))
e = np.where(z == nd, np.nan, e).astype(np.float32)
out = gdal.GetDriverByName('GTiff').Create(dst, w, h, 1, gdal.GDT_Float32)
out.SetGeoTransform(gt)
from osgeo import osr
sr = osr.SpatialReference()
sr.ImportFromEPSG(4326)
out.SetProjection(sr.ExportToWkt())
out.GetRasterBand(1).SetNoDataValue(float('nan'))
out.GetRasterBand(1).WriteArray(e)
out = None
