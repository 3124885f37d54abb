"""mkgdal.py CMD ARGS - fixtures and expected values for tests/t_gdal.sh.

Run with Debian's /usr/bin/python3 (python3-gdal, python3-numpy). Every
fixture is made from a crop of a real DEM (SRC); every expected value is
read back from the fixture with GDAL and numpy, never with our code.

  raw SRC OUT        UInt16 raw = (h - 100) / 0.1, no nodata (the test
                     then assigns -a_scale 0.1 -a_offset 100)
  feet SRC OUT       Float32 h * 3937 / 1200 (US survey feet), nodata kept
  mask SRC OUT       Int16, -32768 in a region marked invalid by an
                     internal per-dataset mask band, no nodata value
  nan SRC OUT        Float32 with NaN samples, nodata nan
  southup SRC OUT    rows flipped, geotransform with a positive y step
  rotated SRC OUT    a rotation term in the geotransform
  flipped SRC OUT    Float32, rows and columns flipped (positive y step,
                     negative x step), NaN voids: region's, a block
                     across the middle column and one sample in 50
  sparse SRC OUT     the top-right 128x128 tile set to SRC's nodata
  stat FILE          "voids N min X max Y count C": voids = nodata, NaN
                     or masked samples; min/max of the others, scale and
                     offset applied
  sparse_tiles FILE  how many of band 1's tiles are absent (offset 0)
  vals FILE i j ...  scaled values of samples (column i, row j)
"""
import os
import sys

import numpy as np
from osgeo import gdal

gdal.UseExceptions()
os.environ["GDAL_PAM_ENABLED"] = "NO"  # no .aux.xml sidecars
gdal.SetConfigOption("GDAL_PAM_ENABLED", "NO")


def load(path):
    ds = gdal.Open(path)
    return ds, ds.GetRasterBand(1).ReadAsArray().astype(np.float64)


def write(path, src, z, gdt, gt=None, nodata=None, opts=(), mask=None):
    """z as the single band of a GTiff with src's CRS and metadata."""
    h, w = z.shape
    ds = gdal.GetDriverByName("GTiff").Create(path, w, h, 1, gdt,
                                              options=list(opts))
    ds.SetGeoTransform(gt if gt is not None else src.GetGeoTransform())
    if src.GetProjection():
        ds.SetProjection(src.GetProjection())
    ds.SetMetadata(src.GetMetadata())  # AREA_OR_POINT
    b = ds.GetRasterBand(1)
    if nodata is not None:
        b.SetNoDataValue(nodata)
    b.WriteArray(z)
    if mask is not None:
        ds.CreateMaskBand(gdal.GMF_PER_DATASET)
        b.GetMaskBand().WriteArray(mask)
    ds.FlushCache()
    ds = None


def region(z):
    """A block and a diagonal line of samples: what the voids are."""
    r = np.zeros(z.shape, dtype=bool)
    r[40:70, 50:110] = True
    k = np.arange(min(z.shape))
    r[k, k] = True
    return r


def cmd_raw(src, out):
    ds, z = load(src)
    write(out, ds, np.round((z - 100) / 0.1).astype(np.uint16),
          gdal.GDT_UInt16)


def cmd_feet(src, out):
    ds, z = load(src)
    write(out, ds, (z * 3937 / 1200).astype(np.float32), gdal.GDT_Float32,
          nodata=ds.GetRasterBand(1).GetNoDataValue())


def cmd_mask(src, out):
    gdal.SetConfigOption("GDAL_TIFF_INTERNAL_MASK", "YES")
    ds, z = load(src)
    r = region(z)
    z[r] = -32768
    write(out, ds, z.astype(np.int16), gdal.GDT_Int16,
          mask=np.where(r, 0, 255).astype(np.uint8))


def cmd_nan(src, out):
    ds, z = load(src)
    z = z.astype(np.float32)
    z[region(z)] = np.nan
    write(out, ds, z, gdal.GDT_Float32, nodata=float("nan"))


def cmd_southup(src, out):
    ds, z = load(src)
    x0, dx, _, y0, _, dy = ds.GetGeoTransform()
    h = z.shape[0]
    write(out, ds, np.flipud(z).astype(np.int16), gdal.GDT_Int16,
          gt=(x0, dx, 0, y0 + h * dy, 0, -dy),
          nodata=ds.GetRasterBand(1).GetNoDataValue())


def cmd_flipped(src, out):
    ds, z = load(src)
    x0, dx, _, y0, _, dy = ds.GetGeoTransform()
    h, w = z.shape
    z = z.astype(np.float32)
    r = region(z)
    r[h // 4:h // 2, w // 2 - 200:w // 2 + 200] = True
    r |= np.random.default_rng(7).random(z.shape) < 0.02
    z[r] = np.nan
    write(out, ds, np.flipud(np.fliplr(z)), gdal.GDT_Float32,
          gt=(x0 + w * dx, -dx, 0, y0 + h * dy, 0, -dy), nodata=float("nan"))


def cmd_rotated(src, out):
    ds, z = load(src)
    x0, dx, _, y0, _, dy = ds.GetGeoTransform()
    write(out, ds, z.astype(np.int16), gdal.GDT_Int16,
          gt=(x0, dx * 0.98, dx * 0.2, y0, dy * 0.2, dy * 0.98))


def cmd_sparse(src, out):
    ds, z = load(src)
    nd = ds.GetRasterBand(1).GetNoDataValue()
    z[0:128, 128:256] = nd
    write(out, ds, z.astype(np.int16), gdal.GDT_Int16, nodata=nd)


def cmd_stat(path):
    ds = gdal.Open(path)
    b = ds.GetRasterBand(1)
    z = b.ReadAsArray().astype(np.float64)
    void = np.isnan(z)
    nd = b.GetNoDataValue()
    if nd is not None and not np.isnan(nd):
        void |= z == nd
    flags = b.GetMaskFlags()
    if not flags & (gdal.GMF_ALL_VALID | gdal.GMF_NODATA):
        void |= b.GetMaskBand().ReadAsArray() == 0
    z = z * (b.GetScale() or 1) + (b.GetOffset() or 0)
    ok = z[~void]
    print("voids %d min %.17g max %.17g count %d" %
          (void.sum(), ok.min(), ok.max(), z.size))


def cmd_sparse_tiles(path):
    ds = gdal.Open(path)  # kept: a band outliving its dataset crashes
    b = ds.GetRasterBand(1)
    bx, by = b.GetBlockSize()
    nx = (b.XSize + bx - 1) // bx
    ny = (b.YSize + by - 1) // by
    n = 0
    for j in range(ny):
        for i in range(nx):
            off = b.GetMetadataItem("BLOCK_OFFSET_%d_%d" % (i, j), "TIFF")
            n += off is None or int(off) == 0
    print(n)


def cmd_vals(path, *ij):
    ds = gdal.Open(path)
    b = ds.GetRasterBand(1)
    z = b.ReadAsArray().astype(np.float64)
    z = z * (b.GetScale() or 1) + (b.GetOffset() or 0)
    for k in range(0, len(ij), 2):
        print("%.17g" % z[int(ij[k + 1]), int(ij[k])])


if __name__ == "__main__":
    if len(sys.argv) < 2 or "cmd_" + sys.argv[1] not in globals():
        sys.exit(__doc__)
    globals()["cmd_" + sys.argv[1]](*sys.argv[2:])
