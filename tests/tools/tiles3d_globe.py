#!/usr/bin/python3
"""tiles3d_globe.py TILESET-DIR CROSS: checks a tileset on the globe.

Every region within [-pi, pi] x [-pi/2, pi/2]; west > east never when
CROSS is 0, for some tile when it is 1 (a DEM across the antimeridian),
either way when it is "any" (a global DEM: its seam);
every geometricError finite, >= 0 and under the Earth's radius; every glb
vertex, through the composed transforms, inside its tile's region or box
(float32 rounding allowed); the root's error under 150 km and no
region 100 km below the ellipsoid (skirts sized by errors). Prints the root's error and the deepest
skirt-free height; exits 1 with the first problem."""
import json
import math
import struct
import sys

import numpy as np

A, F = 6378137.0, 1 / 298.257223563
E2 = F * (2 - F)
R_EARTH = 6371000.0


def geodetic(x, y, z):
    """ECEF to longitude, latitude (radians), height (Bowring, 3 steps)."""
    lon = np.arctan2(y, x)
    p = np.hypot(x, y)
    lat = np.arctan2(z, p * (1 - E2))
    for _ in range(5):
        n = A / np.sqrt(1 - E2 * np.sin(lat) ** 2)
        h = np.where(np.cos(lat) > 1e-9, p / np.maximum(np.cos(lat), 1e-300) - n,
                     np.abs(z) - n * (1 - E2))
        lat = np.arctan2(z, p * (1 - E2 * n / (n + h)))
    n = A / np.sqrt(1 - E2 * np.sin(lat) ** 2)
    c = np.cos(lat)
    h = np.where(c > 1e-6, p / np.maximum(c, 1e-300) - n,
                 np.abs(z) / np.maximum(np.abs(np.sin(lat)), 1e-300) - n * (1 - E2))
    return lon, lat, h


def positions(path):
    b = open(path, 'rb').read()
    n = struct.unpack_from('<I', b, 12)[0]
    g = json.loads(b[20:20 + n])
    bin0 = 20 + n + 8
    acc = g['accessors'][g['meshes'][0]['primitives'][0]['attributes']['POSITION']]
    bv = g['bufferViews'][acc['bufferView']]
    off = bin0 + bv.get('byteOffset', 0) + acc.get('byteOffset', 0)
    v = np.frombuffer(b, '<f4', acc['count'] * 3, off).reshape(-1, 3)
    v = v.astype(np.float64)
    return np.stack([v[:, 0], -v[:, 2], v[:, 1]], 1)  # y-up to z-up


def fail(msg):
    print('tiles3d_globe: ' + msg)
    sys.exit(1)


def main():
    d, cross = sys.argv[1], sys.argv[2]
    ts = json.load(open(d + '/tileset.json'))
    stats = {'tiles': 0, 'crossing': 0, 'verts': 0}

    def walk(t, m):
        m = m @ np.array(t.get('transform', np.eye(4).T.ravel()),
                         float).reshape(4, 4).T
        ge = t['geometricError']
        uri = t['content']['uri']
        if not (math.isfinite(ge) and 0 <= ge < R_EARTH):
            fail('%s: geometricError %r' % (uri, ge))
        p = positions(d + '/' + uri)
        w = (m @ np.c_[p, np.ones(len(p))].T).T[:, :3]
        bv = t['boundingVolume']
        if 'region' in bv:
            we, s, ea, no, lo, hi = bv['region']
            if not (-math.pi <= we <= math.pi and -math.pi <= ea <= math.pi
                    and -math.pi / 2 <= s <= no <= math.pi / 2 and lo <= hi):
                fail('%s: region %r out of range' % (uri, bv['region']))
            if lo < -1e5:
                fail('%s: skirts %.0f m deep' % (uri, -lo))
            if we > ea:
                stats['crossing'] += 1
                if cross == '0':
                    fail('%s: west > east off the antimeridian' % uri)
            lon, lat, h = geodetic(w[:, 0], w[:, 1], w[:, 2])
            tol = 2e-6 + 4 * np.abs(p).max() * 2 ** -24 / A
            htol = 1 + 4 * np.abs(p).max() * 2 ** -24
            bad = (lat < s - tol) | (lat > no + tol) | (h < lo - htol) | \
                (h > hi + htol)
            # longitudes turn: measured east of west, modulo a turn, with
            # the rounding's metres over the parallel's radius
            polar = np.cos(lat) < 1e-5
            ltol = tol / np.maximum(np.cos(lat), 1e-5)
            width = (ea - we) % (2 * math.pi)
            if we == -math.pi and ea == math.pi:
                width = 2 * math.pi
            dl = (lon - we) % (2 * math.pi)
            out = (dl > width + ltol) & (dl < 2 * math.pi - ltol)
            bad |= out & ~polar
            if bad.any():
                k = np.argmax(bad)
                fail('%s: vertex %d (lon %.9f lat %.9f h %.3f) outside region '
                     '%r' % (uri, k, lon[k], lat[k], h[k], bv['region']))
        else:
            b = np.array(bv['box'], float)
            c, ax = b[:3], b[3:].reshape(3, 3)
            q = p - c  # the box is in the tile's own frame
            for a in ax:
                r = np.abs(q @ a) / (a @ a)
                if (r > 1 + 1e-6).any():
                    fail('%s: a vertex %.6g half-axes from the box centre'
                         % (uri, r.max()))
        stats['tiles'] += 1
        stats['verts'] += len(p)
        for c in t.get('children', []):
            walk(c, m)

    walk(ts['root'], np.eye(4))
    if not ts['root']['geometricError'] < 1.5e5:
        fail('root error %r m' % ts['root']['geometricError'])
    if cross == '1' and stats['crossing'] == 0:
        fail('no region crosses the antimeridian')
    print('tiles %d vertices %d crossing %d root %.3f tileset %.3f' % (
        stats['tiles'], stats['verts'], stats['crossing'],
        ts['root']['geometricError'], ts['geometricError']))


main()
