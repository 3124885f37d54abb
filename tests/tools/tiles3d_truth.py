#!/usr/bin/python3
"""tiles3d_truth.py - check a 3D Tiles tileset from vgis2tiles against its
DEM, sharing no code with the writer.

usage: tiles3d_truth.py DEM TILESET_DIR

Walks tileset.json (composing the tiles' transforms), decodes every glb
(GLB chunks, accessors), turns glTF's y-up into z-up as 3D Tiles does,
takes ECEF (EPSG:4978) back to the DEM's CRS with ellipsoidal heights
(pyproj), drops skirts (vertices under another one at the same grid
position) and measures, for every valid DEM sample under each terrain
triangle, the height of the triangle as drawn (the flat ECEF triangle met
by the ellipsoid's normal through the sample) minus the sample's height.
Prints one line per failed check and a summary; exit 0 when:
  - every tile's content exists, errors never grow from parent to child;
  - every measured distance is <= its tile's geometricError + TOL;
  - some tile measures more than half its geometricError (not vacuous);
  - every valid sample of the DEM is under some tile's triangles.
"""
import json
import os
import struct
import sys

import numpy as np
from osgeo import gdal
from pyproj import CRS, Transformer

TOL = 1e-3  # metres: PROJ vs pyproj, and the writer's quadratic bound
# Barycentric slack: float32 vertices come back ~1e-6 of a triangle off
# their grid places, and samples on the DEM's edge lie on triangle edges
EPS = 1e-5


def glb_read(path):
    """Positions (float32, n x 3) and triangle indices (m x 3)."""
    data = open(path, 'rb').read()
    magic, version, length = struct.unpack_from('<III', data, 0)
    assert magic == 0x46546C67 and version == 2 and length == len(data)
    jlen, jtype = struct.unpack_from('<II', data, 12)
    assert jtype == 0x4E4F534A
    gl = json.loads(data[20:20 + jlen])
    blen, btype = struct.unpack_from('<II', data, 20 + jlen)
    assert btype == 0x004E4942
    binc = data[28 + jlen:28 + jlen + blen]
    prim = gl['meshes'][0]['primitives'][0]
    assert prim.get('mode', 4) == 4

    def accessor(k):
        a = gl['accessors'][k]
        v = gl['bufferViews'][a['bufferView']]
        dt = {5126: '<f4', 5123: '<u2', 5125: '<u4'}[a['componentType']]
        n = {'SCALAR': 1, 'VEC3': 3}[a['type']]
        off = v.get('byteOffset', 0) + a.get('byteOffset', 0)
        stride = v.get('byteStride', 0)
        size = np.dtype(dt).itemsize * n
        assert stride in (0, size)
        arr = np.frombuffer(binc, dt, a['count'] * n, off)
        return arr.reshape(-1, n) if n > 1 else arr
    pos = accessor(prim['attributes']['POSITION']).astype(np.float64)
    idx = accessor(prim['indices']).astype(np.int64).reshape(-1, 3)
    return pos, idx


def walk(tile, parent, out, up_error, problems, root):
    m = np.array(tile.get('transform', np.eye(4).T.ravel()),
                 np.float64).reshape(4, 4).T
    m = parent @ m
    ge = tile['geometricError']
    if ge > up_error:
        problems.append('error grows: %s %g > parent %g' % (
            tile['content']['uri'], ge, up_error))
    uri = os.path.join(root, tile['content']['uri'])
    if not os.path.exists(uri):
        problems.append('missing content ' + uri)
    else:
        out.append((uri, m, ge))
    for c in tile.get('children', []):
        walk(c, m, out, ge, problems, root)


class Dem:
    def __init__(self, path):
        ds = gdal.Open(path)
        b = ds.GetRasterBand(1)
        self.z = b.ReadAsArray().astype(np.float64)
        nd = b.GetNoDataValue()
        self.valid = np.isfinite(self.z)
        if nd is not None:
            self.valid &= self.z != nd
        self.gt = ds.GetGeoTransform()
        crs = CRS.from_wkt(ds.GetProjection())
        self.crs3d = crs.to_3d()
        h, w = self.z.shape
        jj, ii = np.mgrid[0:h, 0:w]
        x = self.gt[0] + (ii + 0.5) * self.gt[1]
        y = self.gt[3] + (jj + 0.5) * self.gt[5]
        t = Transformer.from_crs(self.crs3d, CRS.from_epsg(4978),
                                 always_xy=True)
        p0 = np.stack(t.transform(x, y, np.zeros_like(x)), -1)
        p1 = np.stack(t.transform(x, y, np.ones_like(x)), -1)
        self.s0, self.n = p0, p1 - p0  # ellipsoid point, unit normal
        self.back = Transformer.from_crs(CRS.from_epsg(4978), self.crs3d,
                                         always_xy=True)

    def grid(self, ecef):
        x, y, h = self.back.transform(ecef[:, 0], ecef[:, 1], ecef[:, 2])
        col = (np.asarray(x) - self.gt[0]) / self.gt[1] - 0.5
        row = (np.asarray(y) - self.gt[3]) / self.gt[5] - 0.5
        return col, row, np.asarray(h)


def terrain(col, row, h, idx):
    """Triangles without skirt vertices (under a vertex at the same grid
    position)."""
    key = np.round(col * 64).astype(np.int64) * (1 << 32) + \
        np.round(row * 64).astype(np.int64)
    order = np.lexsort((-h, key))
    first = np.ones(len(key), bool)
    first[order[1:]] = key[order[1:]] != key[order[:-1]]
    return idx[first[idx].all(1)]


def measure(dem, ecef, col, row, tris, covered):
    worst = 0.0
    H, W = dem.z.shape
    for t in tris:
        c, r = col[t], row[t]
        i0, i1 = max(int(np.floor(c.min() - 1e-6)), 0), \
            min(int(np.ceil(c.max() + 1e-6)), W - 1)
        j0, j1 = max(int(np.floor(r.min() - 1e-6)), 0), \
            min(int(np.ceil(r.max() + 1e-6)), H - 1)
        if i1 < i0 or j1 < j0:
            continue
        jj, ii = np.mgrid[j0:j1 + 1, i0:i1 + 1]
        d = (c[1] - c[0]) * (r[2] - r[0]) - (c[2] - c[0]) * (r[1] - r[0])
        if abs(d) < 1e-12:
            continue
        l1 = ((ii - c[0]) * (r[2] - r[0]) - (c[2] - c[0]) * (jj - r[0])) / d
        l2 = ((c[1] - c[0]) * (jj - r[0]) - (ii - c[0]) * (r[1] - r[0])) / d
        inside = (l1 >= -EPS) & (l2 >= -EPS) & (l1 + l2 <= 1 + EPS)
        inside &= dem.valid[j0:j1 + 1, i0:i1 + 1]
        if not inside.any():
            continue
        covered[j0:j1 + 1, i0:i1 + 1] |= inside
        a, b, cc = ecef[t[0]], ecef[t[1]], ecef[t[2]]
        nrm = np.cross(b - a, cc - a)
        s0 = dem.s0[j0:j1 + 1, i0:i1 + 1][inside]
        un = dem.n[j0:j1 + 1, i0:i1 + 1][inside]
        height = ((a - s0) @ nrm) / (un @ nrm)
        dz = np.abs(height - dem.z[j0:j1 + 1, i0:i1 + 1][inside])
        worst = max(worst, float(dz.max()))
    return worst


def main():
    dem = Dem(sys.argv[1])
    root = sys.argv[2]
    ts = json.load(open(os.path.join(root, 'tileset.json')))
    problems, tiles = [], []
    if ts['asset']['version'] != '1.1':
        problems.append('asset.version is not 1.1')
    walk(ts['root'], np.eye(4), tiles, ts['geometricError'], problems, root)
    covered = np.zeros(dem.z.shape, bool)
    tight = 0.0
    yup = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], np.float64)
    for uri, m, ge in tiles:
        pos, idx = glb_read(uri)
        local = pos @ yup.T  # glTF y-up to 3D Tiles z-up
        ecef = local @ m[:3, :3].T + m[:3, 3]
        col, row, h = dem.grid(ecef)
        lev_cov = np.zeros(dem.z.shape, bool)
        worst = measure(dem, ecef, col, row, terrain(col, row, h, idx),
                        lev_cov)
        covered |= lev_cov
        if worst > ge + TOL:
            problems.append('%s: measured %.4f m > geometricError %.4f m' %
                            (uri, worst, ge))
        if ge > 0:
            tight = max(tight, worst / ge)
        print('# %s: measured %.4f m, geometricError %.4f m' %
              (os.path.relpath(uri, root), worst, ge))
    if tight <= 0.5:
        problems.append('vacuous: no tile measures over half its error '
                        '(best %.3f)' % tight)
    if (dem.valid & ~covered).any():
        problems.append('%d valid samples under no triangle' %
                        int((dem.valid & ~covered).sum()))
    for p in problems:
        print('problem: ' + p)
    print('%d tiles, largest measured/geometricError %.3f, %d problems' %
          (len(tiles), tight, len(problems)))
    sys.exit(1 if problems else 0)


main()
