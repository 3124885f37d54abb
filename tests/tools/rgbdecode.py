#!/usr/bin/python3
"""rgbdecode - the tests' own decoder of raster-dem tiles (Terrarium and
Mapbox Terrain-RGB, PNG or WebP, read with GDAL), sharing no code with the
encoder, and the surface MapLibre GL JS draws from them.

Where MapLibre puts a pixel's height (maplibre-gl 6.17.0, the version
tests/js pins; the sources are in its dist/*.map):
- src/data/dem_data.ts, DEMData: a 'dim' px tile is decoded into a
  (dim+4)^2 array with 2 px of border; the constructor fills the border
  with the tile's own nearest edge pixel, backfillBorder(neighbour, dx, dy)
  then copies the 2 px next to the edge from each of the 8 neighbours that
  loaded (raster_dem_tile_source / terrain_tile_manager); a neighbour that
  never loads leaves the clamped copy. sampleBilinear(x, y) is bilinear
  between the 4 pixels around (x, y) in pixel index units.
- src/render/terrain_coverage.ts, _createElevationSampler (what
  map.queryTerrainElevation -> Terrain.getElevationForLngLat reads):
  DEM_CELL_CENTER_OFFSET = -0.5: "DEM pixel i describes the cell centred
  at tile coordinate (i + 0.5) / dim"; the shader agrees
  (_prelude.vertex.glsl get_elevation: coord = tilecoord * dim + 1.5 in
  the 2 px padded texture, 4 texelFetch, mix). So the surface is bilinear
  between pixel centres, across tile borders through the backfilled
  neighbours. (MapLibre draws it on a 128 x 128 mesh per terrain tile,
  src/render/terrain.ts getTerrainMesh, meshSize; the height at a vertex
  is this surface's.) Older MapLibre (before the coverage sampler) put
  pixel i at i / dim; this file follows the pinned version.
- Raster-dem tiles are loaded deltaZoom = 1 below the terrain tile, whose
  tileSize is the source's times 2 (src/tile/terrain_tile_manager.ts).

As a library: read_tree, decode, surface, tile_set_check, dem_samples.
As a program:
  rgbdecode.py check TREE [DEM]        tiles vs tiles.json (and the DEM's
                                       valid samples); per zoom range
  rgbdecode.py error TREE DEM [-n N]   per zoom: n, max, rms of the
                                       surface minus the DEM at N (default
                                       all) valid DEM samples
  rgbdecode.py at TREE FILE            per line "lon lat ..." of FILE: the
                                       surface's height at every zoom
  rgbdecode.py declared TREE           per zoom the error tiles.json
                                       declares (max rms), if any
  rgbdecode.py claim TREE DEM          the measured error against the
                                       declared: fails where either
                                       exceeds the declared by 5 % + a step
Exit 0, 1 on a failed check, 2 on usage.
"""
import glob
import json
import math
import os
import re
import sys

import numpy as np
from osgeo import gdal

gdal.UseExceptions()


def read_tree(tree):
    """tiles.json of TREE and its tiles on disk: {(z, x, y): path}; the
    tiles' template is the path after the last '/' before '{z}'."""
    with open(os.path.join(tree, "tiles.json")) as f:
        tj = json.load(f)
    t = tj["tiles"][0]
    m = re.search(r"([^/]*)\{z\}/\{x\}/\{y\}(\.\w+)", t)
    if not m:
        raise ValueError("tiles.json: tiles %r: no {z}/{x}/{y}" % t)
    ext = m.group(2)
    tiles = {}
    for p in glob.glob(os.path.join(tree, "*", "*", "*" + ext)):
        z, x, y = p[len(tree):].strip("/").split("/")
        y = y[:-len(ext)]
        if z.isdigit() and x.isdigit() and y.isdigit():
            tiles[(int(z), int(x), int(y))] = p
    return tj, tiles


def decode(path, encoding):
    """The heights of one tile, float64, rows from the north."""
    d = gdal.Open(path)
    if d.RasterCount < 3 or d.RasterXSize != d.RasterYSize:
        raise ValueError("%s: not a square RGB tile" % path)
    r, g, b = (d.GetRasterBand(i + 1).ReadAsArray().astype(np.float64)
        for i in range(3))
    if encoding == "terrarium":
        return r * 256 + g + b / 256 - 32768
    if encoding == "mapbox":
        return -10000 + (r * 65536 + g * 256 + b) * 0.1
    raise ValueError("encoding %r" % encoding)


def step(encoding):
    return 1 / 256 if encoding == "terrarium" else 0.1


def merc(lon, lat):
    """lon, lat (degrees) to world coordinates in [0, 1), rows from the
    north, as MapLibre's MercatorCoordinate."""
    lon, lat = np.asarray(lon, float), np.asarray(lat, float)
    x = (180 + lon) / 360
    y = (180 - np.degrees(np.log(np.tan(np.pi / 4 + np.radians(lat) / 2)))) / 360
    return x, y


class Zoom:
    """One zoom's decoded tiles, looked up by tile."""

    def __init__(self, z, tiles, encoding):
        self.z, self.h, self.dim = z, {}, None
        for (tz, x, y), p in tiles.items():
            if tz != z:
                continue
            self.h[(x, y)] = decode(p, encoding)
            if self.dim is None:
                self.dim = self.h[(x, y)].shape[0]
            elif self.h[(x, y)].shape[0] != self.dim:
                raise ValueError("%s: not %d px" % (p, self.dim))

    def pixel(self, tx, ty, i, j):
        """DEMData's value at pixel (i, j) of tile (tx, ty), i and j in
        -1..dim: a neighbour's pixel (backfillBorder), else the tile's
        own clamped (the constructor's border)."""
        d = self.dim
        nx, ny = tx + (i >= d) - (i < 0), ty + (j >= d) - (j < 0)
        if (nx, ny) in self.h:
            return self.h[(nx, ny)][j % d, i % d]
        return self.h[(tx, ty)][min(max(j, 0), d - 1), min(max(i, 0), d - 1)]

    def surface(self, wx, wy):
        """The height at world coordinates (wx, wy), as
        terrain_coverage.ts samples it; NaN where no tile is."""
        n = 1 << self.z
        tx, ty = int(math.floor(wx * n)), int(math.floor(wy * n))
        if (tx, ty) not in self.h:
            return math.nan
        u = (wx * n - tx) * self.dim - 0.5
        v = (wy * n - ty) * self.dim - 0.5
        i, j = int(math.floor(u)), int(math.floor(v))
        fu, fv = u - i, v - j
        p = self.pixel
        return (p(tx, ty, i, j) * (1 - fu) * (1 - fv) +
            p(tx, ty, i + 1, j) * fu * (1 - fv) +
            p(tx, ty, i, j + 1) * (1 - fu) * fv +
            p(tx, ty, i + 1, j + 1) * fu * fv)

    def surface_many(self, wx, wy):
        """surface at arrays of points, vectorised per tile."""
        out = np.full(len(wx), np.nan)
        n, d = 1 << self.z, self.dim
        tx, ty = np.floor(wx * n).astype(int), np.floor(wy * n).astype(int)
        for (x, y), h in self.h.items():
            k = np.nonzero((tx == x) & (ty == y))[0]
            if not len(k):
                continue
            # the tile with its 1 px border as DEMData has it
            pad = np.empty((d + 2, d + 2))
            pad[1:-1, 1:-1] = h
            for j in (-1, d):
                for i in range(-1, d + 1):
                    pad[j + 1, i + 1] = self.pixel(x, y, i, j)
            for i in (-1, d):
                col = [self.pixel(x, y, i, j) for j in range(d)]
                pad[1:-1, i + 1] = col
            u = (wx[k] * n - x) * d - 0.5
            v = (wy[k] * n - y) * d - 0.5
            i, j = np.floor(u).astype(int), np.floor(v).astype(int)
            fu, fv = u - i, v - j
            i, j = i + 1, j + 1
            out[k] = (pad[j, i] * (1 - fu) * (1 - fv) +
                pad[j, i + 1] * fu * (1 - fv) +
                pad[j + 1, i] * (1 - fu) * fv +
                pad[j + 1, i + 1] * fu * fv)
        return out


def tile_range(bounds, z):
    """The tiles of zoom z that the bounds (W, S, E, N) meet."""
    n = 1 << z
    x0, y1 = merc(bounds[0], bounds[1])
    x1, y0 = merc(bounds[2], bounds[3])
    f = lambda v: min(max(int(math.floor(v * n)), 0), n - 1)
    # a bound on a tile edge meets no tile past it
    g = lambda v: min(max(int(math.ceil(v * n)) - 1, 0), n - 1)
    return f(x0), f(y0), g(x1), g(y1)


def dem_samples(dem, n=0, seed=24):
    """lon, lat, height of the DEM's valid samples (all, or n at random
    with a fixed seed), at the samples' positions (GDAL's geotransform:
    the cell centres); the DEM in EPSG:4326."""
    d = gdal.Open(dem)
    b = d.GetRasterBand(1)
    z = b.ReadAsArray().astype(np.float64)
    nd = b.GetNoDataValue()
    ok = np.isfinite(z) if nd is None else np.isfinite(z) & (z != nd)
    jj, ii = np.nonzero(ok)
    if n and n < len(jj):
        k = np.random.RandomState(seed).choice(len(jj), n, replace=False)
        jj, ii = jj[k], ii[k]
    g = d.GetGeoTransform()
    return (g[0] + (ii + .5) * g[1], g[3] + (jj + .5) * g[5], z[jj, ii])


def tile_set_check(tj, tiles, dem=None):
    """The failures (strings) of the tiles present against tiles.json:
    zooms minzoom..maxzoom, each tile inside the bounds' tile range; with
    the DEM, every tile holding a valid sample present and the bounds
    holding every valid sample."""
    bad = []
    z0, z1, bd = tj["minzoom"], tj["maxzoom"], tj["bounds"]
    for key in ("tilejson", "tiles", "minzoom", "maxzoom", "bounds",
        "center", "encoding", "tileSize"):
        if key not in tj:
            bad.append("tiles.json: no %s" % key)
    for (z, x, y) in sorted(tiles):
        x0, y0, x1, y1 = tile_range(bd, z)
        if not (z0 <= z <= z1 and x0 <= x <= x1 and y0 <= y <= y1):
            bad.append("tile %d/%d/%d outside tiles.json's zooms or bounds"
                % (z, x, y))
    if dem is not None:
        lon, lat, _ = dem_samples(dem)
        if (lon.min() < bd[0] or lon.max() > bd[2] or lat.min() < bd[1] or
            lat.max() > bd[3]):
            bad.append("bounds %s miss valid DEM samples (%.6f %.6f %.6f %.6f)"
                % (bd, lon.min(), lat.min(), lon.max(), lat.max()))
        wx, wy = merc(lon, lat)
        for z in range(z0, z1 + 1):
            n = 1 << z
            need = set(zip(np.floor(wx * n).astype(int).tolist(),
                np.floor(wy * n).astype(int).tolist()))
            for x, y in sorted(need - {(x, y) for (q, x, y) in tiles if q == z}):
                bad.append("tile %d/%d/%d holds valid DEM samples: missing"
                    % (z, x, y))
    for z in range(z0, z1 + 1):
        if not any(q == z for (q, _, _) in tiles):
            bad.append("no tile at zoom %d" % z)
    return bad


def zooms(tj, tiles):
    return {z: Zoom(z, tiles, tj["encoding"])
        for z in range(tj["minzoom"], tj["maxzoom"] + 1)}


def errors(tj, tiles, dem, n=0):
    """Per zoom: (count, max, rms) of the surface minus the DEM at its
    valid samples."""
    lon, lat, h = dem_samples(dem, n)
    wx, wy = merc(lon, lat)
    out = {}
    for z, zm in zooms(tj, tiles).items():
        e = zm.surface_many(wx, wy) - h
        e = e[np.isfinite(e)]
        out[z] = (len(e), float(np.abs(e).max()) if len(e) else math.nan,
            float(np.sqrt(np.mean(e * e))) if len(e) else math.nan)
    return out


def declared(tj):
    """The per-zoom error tiles.json declares, {z: (max, rms)}: any
    top-level key with 'error' in its name holding per zoom entries
    {max, rms} (or [max, rms]), keyed by zoom or listed with 'zoom'/'z'."""
    out = {}
    for k, v in tj.items():
        if "error" not in k.lower() or not isinstance(v, (dict, list)):
            continue
        items = v.items() if isinstance(v, dict) else \
            [(e.get("zoom", e.get("z")), e) for e in v if isinstance(e, dict)]
        for z, e in items:
            try:
                z = int(z)
            except (TypeError, ValueError):
                continue
            if isinstance(e, dict) and "max" in e and "rms" in e:
                out[z] = (float(e["max"]), float(e["rms"]))
            elif isinstance(e, list) and len(e) == 2:
                out[z] = (float(e[0]), float(e[1]))
    return out


def main(a):
    if len(a) < 2 or a[0] not in ("check", "error", "at", "declared", "claim"):
        print(__doc__.split("As a program:")[1], file=sys.stderr)
        return 2
    tj, tiles = read_tree(a[1])
    if a[0] == "check":
        bad = tile_set_check(tj, tiles, a[2] if len(a) > 2 else None)
        for b in bad:
            print("rgbdecode: %s" % b, file=sys.stderr)
        zs = zooms(tj, tiles)
        for z, zm in zs.items():
            v = np.concatenate([h.ravel() for h in zm.h.values()])
            print("zoom %d tiles %d dim %s min %.4f max %.4f" %
                (z, len(zm.h), zm.dim, v.min(), v.max()))
        print("tiles %d" % len(tiles))
        return 1 if bad else 0
    if a[0] == "error":
        n = int(a[4]) if len(a) > 4 and a[3] == "-n" else 0
        for z, (k, mx, rms) in errors(tj, tiles, a[2], n).items():
            print("zoom %d n %d max %.4f rms %.4f" % (z, k, mx, rms))
        return 0
    if a[0] == "claim":
        d, bad = declared(tj), 0
        if not d:
            print("rgbdecode: tiles.json declares no error per zoom",
                file=sys.stderr)
            return 1
        st = step(tj["encoding"])
        for z, (k, mx, rms) in errors(tj, tiles, a[2]).items():
            dm, dr = d.get(z, (math.nan, math.nan))
            ok = mx <= dm * 1.05 + st and rms <= dr * 1.05 + st
            print("zoom %d measured max %.4f rms %.4f declared max %.4f "
                "rms %.4f%s" % (z, mx, rms, dm, dr, "" if ok else " EXCEEDED"))
            bad += not ok
        if bad:
            print("rgbdecode: the error exceeds the declared at %d zooms"
                % bad, file=sys.stderr)
        return 1 if bad else 0
    if a[0] == "declared":
        for z, (mx, rms) in sorted(declared(tj).items()):
            print("zoom %d max %.4f rms %.4f" % (z, mx, rms))
        return 0
    pts = np.loadtxt(a[2], ndmin=2, usecols=(0, 1))
    wx, wy = merc(pts[:, 0], pts[:, 1])
    zs = zooms(tj, tiles)
    hs = [zs[z].surface_many(wx, wy) for z in sorted(zs)]
    for k in range(len(pts)):
        print(" ".join("%d:%.4f" % (z, hs[i][k])
            for i, z in enumerate(sorted(zs))))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
