"""mkbad.py DIR - small GeoTIFF fixtures for tests/t_badinput.sh, with GDAL.

Run with Debian's /usr/bin/python3 (python3-gdal, python3-numpy).
"""
import os
import sys

import numpy as np
from osgeo import gdal, osr

gdal.UseExceptions()
gdal.SetConfigOption("GDAL_PAM_ENABLED", "NO")


def write(path, z, nodata=None, dy=30):
    h, w = z.shape
    ds = gdal.GetDriverByName("GTiff").Create(path, w, h, 1, gdal.GDT_Float32)
    ds.SetGeoTransform((500000, 30, 0, 5200000, 0, -dy))
    s = osr.SpatialReference()
    s.ImportFromEPSG(32632)
    ds.SetProjection(s.ExportToWkt())
    b = ds.GetRasterBand(1)
    if nodata is not None:
        b.SetNoDataValue(nodata)
    b.WriteArray(z)
    ds = None


def main(d):
    i, j = np.meshgrid(np.arange(64.0), np.arange(48.0))
    hills = (500 + 40 * np.sin(i / 5) * np.cos(j / 7)).astype(np.float32)
    write(f"{d}/one.tif", np.full((1, 1), 100, np.float32))
    write(f"{d}/two.tif", np.full((2, 2), 100, np.float32))
    write(f"{d}/allvoid.tif", np.full((20, 30), -9999, np.float32), -9999)
    write(f"{d}/allnan.tif", np.full((20, 30), np.nan, np.float32))
    nan = hills.copy()
    nan[10:20, 30:50] = np.nan      # 200 NaN voids
    write(f"{d}/somenan.tif", nan)
    write(f"{d}/hills.tif", hills)
    # A tilted plane, exact in float32, cells 30 m x 20 m, 301 x 203.
    i, j = np.meshgrid(np.arange(301.0), np.arange(203.0))
    write(f"{d}/plane.tif", (1000 + 0.375 * i - 1.25 * j).astype(np.float32),
          dy=20)
    # One block: zero but a 10 m spike at its centre (col 64, row 64);
    # and a tilted plane.
    spike = np.zeros((129, 129), np.float32)
    spike[64, 64] = 10
    write(f"{d}/spike.tif", spike)
    i, j = np.meshgrid(np.arange(129.0), np.arange(129.0))
    write(f"{d}/tilt.tif", (200 + 0.5 * i + 0.25 * j).astype(np.float32))


if __name__ == "__main__":
    main(sys.argv[1])
