"""mkdem.py DIR - write the DEM fixtures of tests/t_dem.c into DIR with GDAL.

Run with Debian's /usr/bin/python3 (python3-gdal, python3-numpy). Every
value follows a formula that t_dem.c knows; i is the column, j the row.
"""
import os
import sys

import numpy as np
from osgeo import gdal, osr

gdal.UseExceptions()
os.environ["GDAL_PAM_ENABLED"] = "NO"  # no .aux.xml sidecars
gdal.SetConfigOption("GDAL_PAM_ENABLED", "NO")


def grid(w, h):
    return np.meshgrid(np.arange(w, dtype=np.float64),
                       np.arange(h, dtype=np.float64))


def srs(text):
    s = osr.SpatialReference()
    s.SetFromUserInput(text)
    return s.ExportToWkt()


def write(path, bands, gdt, opts=(), gt=None, crs=None, nodata=None,
          meta=None, driver="GTiff"):
    h, w = bands[0].shape
    mem = gdal.GetDriverByName("MEM").Create("", w, h, len(bands), gdt)
    for k, b in enumerate(bands):
        mem.GetRasterBand(k + 1).WriteArray(b)
        if nodata is not None:
            mem.GetRasterBand(k + 1).SetNoDataValue(nodata)
    if gt is not None:
        mem.SetGeoTransform(gt)
    if crs is not None:
        mem.SetProjection(srs(crs))
    if meta:
        mem.SetMetadata(meta)
    gdal.GetDriverByName(driver).CreateCopy(path, mem, options=list(opts))


def main(d):
    # Tiled float32, DEFLATE + floating-point predictor, voids of every
    # kind: a NaN block (i 100..139, j 50..69), +Inf at (299,199), -Inf
    # at (0,0), 2e6 (beyond 1e6 m) at (5,5): 803 voids.
    i, j = grid(300, 200)
    z = (100 + 0.5 * i + 0.25 * j).astype(np.float32)
    z[50:70, 100:140] = np.nan
    z[199, 299] = np.inf
    z[0, 0] = -np.inf
    z[5, 5] = 2e6
    write(f"{d}/tiled_f32.tif", [z], gdal.GDT_Float32,
          ["TILED=YES", "BLOCKXSIZE=64", "BLOCKYSIZE=64", "COMPRESS=DEFLATE",
           "PREDICTOR=3"], (500000, 30, 0, 5200000, 0, -30), "EPSG:32632")

    # uint16, big-endian, nodata 0: zero at (0,0) and along row 10: 51
    # voids; 65535 at (49,39) to catch a signed misreading.
    i, j = grid(50, 40)
    z = (i * 1000 + j * 7).astype(np.uint16)
    z[10, :] = 0
    z[39, 49] = 65535
    write(f"{d}/u16_be.tif", [z], gdal.GDT_UInt16, ["ENDIANNESS=BIG"],
          (10, 0.01, 0, 50, 0, -0.01), "EPSG:4326", nodata=0)

    # 16-bit grey PNG: i * 1000 + j.
    i, j = grid(64, 48)
    write(f"{d}/grey16.png", [(i * 1000 + j).astype(np.uint16)],
          gdal.GDT_UInt16, driver="PNG")

    # Terrain-RGB as 8-bit RGB TIFF and PNG: R = 1, G = i, B = j.
    i, j = grid(40, 30)
    rgb = [np.ones_like(i, dtype=np.uint8), i.astype(np.uint8),
           j.astype(np.uint8)]
    write(f"{d}/trgb.tif", rgb, gdal.GDT_Byte, ["PHOTOMETRIC=RGB"])
    write(f"{d}/trgb.png", rgb, gdal.GDT_Byte, driver="PNG")

    # 1 x 1 float32 of 42.5; an all-void int16; planar int32 (band 1 is
    # i - 100 j, band 2 is 999); float64 big-endian 0.001 i + j; half
    # floats 0.5 i + j; signed bytes i - 16.
    write(f"{d}/one.tif", [np.full((1, 1), 42.5, np.float32)],
          gdal.GDT_Float32, gt=(0, 1, 0, 0, 0, -1), crs="EPSG:32632")
    write(f"{d}/allvoid.tif", [np.full((3, 4), -9999, np.int16)],
          gdal.GDT_Int16, nodata=-9999)
    i, j = grid(33, 21)
    write(f"{d}/planar_i32.tif", [(i - 100 * j).astype(np.int32),
          np.full(i.shape, 999, np.int32)], gdal.GDT_Int32,
          ["INTERLEAVE=BAND"])
    write(f"{d}/f64_be.tif", [0.001 * i + j], gdal.GDT_Float64,
          ["ENDIANNESS=BIG"])
    write(f"{d}/half.tif", [(0.5 * i + j).astype(np.float32)],
          gdal.GDT_Float32, ["NBITS=16"])
    write(f"{d}/i8.tif", [(i - 16).astype(np.int8).view(np.uint8)],
          gdal.GDT_Byte, ["PIXELTYPE=SIGNEDBYTE"])

    # Void filling: a cross of void row 2 and void column 3 over
    # 10 i + j (the crossing has no valid sample in its row or column);
    # and a small non-linear case whose weights t_dem.c spells out.
    i, j = grid(7, 5)
    z = (10 * i + j).astype(np.float32)
    z[2, :] = np.nan
    z[:, 3] = np.nan
    write(f"{d}/cross.tif", [z], gdal.GDT_Float32)
    z = np.array([[0, 0, 0, 0], [8, -1, -1, 2], [0, 4, 0, 0]], np.float32)
    write(f"{d}/idw.tif", [z], gdal.GDT_Float32, nodata=-1)

    # Georeferencing cases: rotated (must fail), a compound CRS with a
    # vertical part, a user-defined projection, PixelIsPoint projected.
    z = np.zeros((4, 5), np.float32)
    write(f"{d}/rotated.tif", [z], gdal.GDT_Float32,
          gt=(0, 1, 0.1, 0, 0.1, -1), crs="EPSG:32632")
    write(f"{d}/compound.tif", [z], gdal.GDT_Float32,
          gt=(1, 0.5, 0, 2, 0, -0.5), crs="EPSG:4326+5773")
    write(f"{d}/userdef.tif", [z], gdal.GDT_Float32,
          gt=(1000, 2, 0, 9000, 0, -2),
          crs="+proj=tmerc +lat_0=0 +lon_0=13.5 +k=0.9999 +x_0=400000 "
              "+y_0=0 +ellps=GRS80 +units=m +no_defs")
    write(f"{d}/point.tif", [z], gdal.GDT_Float32,
          gt=(699985, 30, 0, 5100015, 0, -30), crs="EPSG:32633",
          meta={"AREA_OR_POINT": "Point"})

    # Width 2^26 + 1 (sparse: no strip is written).
    gdal.GetDriverByName("GTiff").Create(f"{d}/huge.tif", (1 << 26) + 1, 1,
                                         1, gdal.GDT_Byte, ["SPARSE_OK=YES"])

    # A truncated DEFLATE TIFF: the header and strip table survive, the
    # pixel data stops at 60 %.
    i, j = grid(256, 256)
    write(f"{d}/whole.tif", [(np.sin(i * 0.3) * 1000 + j).astype(np.int16)],
          gdal.GDT_Int16, ["COMPRESS=DEFLATE"], (0, 1, 0, 0, 0, -1),
          "EPSG:32632")
    with open(f"{d}/whole.tif", "rb") as f:
        data = f.read()
    with open(f"{d}/trunc.tif", "wb") as f:
        f.write(data[: len(data) * 6 // 10])
    with open(f"{d}/notraster.txt", "w") as f:
        f.write("this is not a raster, just some text.\n" * 10)


if __name__ == "__main__":
    main(sys.argv[1])
