"""spike.py SRC DST ROW COL - a copy of the DEM SRC with a spike at
(ROW, COL): 5500 m added there and 2750 m on the sample below, so that
no tile-aligned grid holds it at the first try (the terrain tests'
levels made again). Run with Debian's python3 (python3-gdal, numpy)."""
import sys

from osgeo import gdal

gdal.UseExceptions()
src, dst, row, col = sys.argv[1], sys.argv[2], int(sys.argv[3]), \
    int(sys.argv[4])
s = gdal.Open(src)
a = s.GetRasterBand(1).ReadAsArray().astype("float32")
d = gdal.GetDriverByName("GTiff").CreateCopy(dst, s)
a[row, col] += 5500
a[row + 1, col] += 2750
d.GetRasterBand(1).WriteArray(a)
