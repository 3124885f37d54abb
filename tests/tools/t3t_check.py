"""t3t_check.py - an independent reader of vgis2terrain -f 3dtiles output
(the 3D Tiles terrain profile, terrain-3dtiles(5)), sharing no code with
the writer. Usage: t3t_check.py OUTDIR. From tileset.json it walks both
implicit quadtrees' subtree files (header, JSON, binary, availability
bitstreams in Morton order) and checks: every subtree parses; the tiles
and child subtrees marked available are exactly the .glb and .subtree
files present (no file unannounced, none missing); the property table has
one row per available tile; each glb has one primitive with POSITION,
NORMAL, triangles and CESIUM_tile_edges; its vertices, placed by the node
matrix and Y-up to Z-up, lie inside the tile's rectangle, between the
TILE_MINIMUM_HEIGHT and TILE_MAXIMUM_HEIGHT and inside the
TILE_BOUNDING_SPHERE; each edge list holds exactly the vertices on that
edge, in the order the skirts walk. Prints a summary; exit 1 on the first failure."""
import json
import math
import os
import struct
import sys

import numpy as np

A, F = 6378137.0, 1 / 298.257223563
B = A * (1 - F)
E2 = 1 - (B / A) ** 2


def fail(msg):
    print("t3t_check: " + msg)
    sys.exit(1)


def geodetic(p):
    """ECEF (n, 3) to longitude, latitude (radians) and height."""
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    lon = np.arctan2(y, x)
    r = np.hypot(x, y)
    lat = np.arctan2(z, r * (1 - E2))
    for _ in range(8):
        n = A / np.sqrt(1 - E2 * np.sin(lat) ** 2)
        h = r / np.maximum(np.cos(lat), 1e-12) - n
        lat = np.arctan2(z, r * (1 - E2 * n / (n + h)))
    n = A / np.sqrt(1 - E2 * np.sin(lat) ** 2)
    h = r * np.cos(lat) + z * np.sin(lat) - A * A / n
    return lon, lat, h


def read_glb(path):
    b = open(path, "rb").read()
    magic, ver, total = struct.unpack_from("<4sII", b, 0)
    if magic != b"glTF" or ver != 2 or total != len(b):
        fail(path + ": not a glb 2")
    jl, jt = struct.unpack_from("<I4s", b, 12)
    g = json.loads(b[20:20 + jl])
    bl, bt = struct.unpack_from("<I4s", b, 20 + jl)
    if jt != b"JSON" or bt != b"BIN\0":
        fail(path + ": chunks")
    return g, b[28 + jl:28 + jl + bl]


def accessor(g, binc, i):
    a = g["accessors"][i]
    v = g["bufferViews"][a["bufferView"]]
    dt = {5126: "<f4", 5123: "<u2", 5125: "<u4"}[a["componentType"]]
    n = {"VEC3": 3, "SCALAR": 1}[a["type"]] * a["count"]
    off = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    return np.frombuffer(binc, dt, n, off)


def check_glb(path, root, z, x, y, meta):
    g, binc = read_glb(path)
    prims = [p for m in g["meshes"] for p in m["primitives"]]
    if len(g["meshes"]) != 1 or len(prims) != 1:
        fail(path + ": not one mesh of one primitive")
    p = prims[0]
    ed = p.get("extensions", {}).get("CESIUM_tile_edges")
    if set(p["attributes"]) != {"POSITION", "NORMAL"} or ed is None:
        fail(path + ": POSITION, NORMAL, CESIUM_tile_edges expected")
    m = np.array(g["nodes"][0]["matrix"], float).reshape(4, 4).T
    yup2zup = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0],
                        [0, 0, 0, 1]], float)
    m = yup2zup @ m
    pos = accessor(g, binc, p["attributes"]["POSITION"]).reshape(-1, 3)
    ecef = pos.astype(float) @ m[:3, :3].T + m[:3, 3]
    lon, lat, h = geodetic(ecef)
    w = math.pi / (1 << z)
    x0 = -math.pi + (x + (root << z)) * w
    y0 = -math.pi / 2 + y * w
    # float positions: a few 1e-7 of the tile's radius
    tol = 2e-6 * meta[5] + 1e-3
    ang = tol / A
    # longitude relative to the tile's west edge, wrapped (-180 = 180);
    # at a pole it means nothing: those vertices skip the longitude tests
    lon = x0 + np.mod(lon - x0 + math.pi / 2, 2 * math.pi) - math.pi / 2
    polar = np.cos(lat) * A <= 100 * tol
    lon[polar] = x0 + w / 2
    if (lon.min() < x0 - ang or lon.max() > x0 + w + ang or
            lat.min() < y0 - ang or lat.max() > y0 + w + ang):
        fail(path + ": a vertex outside the tile's rectangle")
    if h.min() < meta[0] - tol or h.max() > meta[1] + tol:
        fail(path + ": a vertex outside TILE_MINIMUM/MAXIMUM_HEIGHT")
    d = np.linalg.norm(ecef - np.array(meta[2:5]), axis=1)
    if d.max() > meta[5] + tol:
        fail(path + ": a vertex outside TILE_BOUNDING_SPHERE")
    idx = accessor(g, binc, p["indices"])
    if idx.size % 3 or idx.max() >= len(pos):
        fail(path + ": indices")
    # the order CesiumJS's skirts walk: west south to north, south east
    # to west, east north to south, north west to east
    for name, c, v, along, sign in (
            ("left", lon, x0, lat, 1), ("right", lon, x0 + w, lat, -1),
            ("bottom", lat, y0, lon, -1), ("top", lat, y0 + w, lon, 1)):
        e = accessor(g, binc, ed[name])
        k = [i for i in e.tolist() if not polar[i]]
        if np.any(sign * np.diff(along[k]) < -ang):
            fail("%s: edge %s out of order" % (path, name))
        on = set(np.nonzero(np.abs(c - v) <= ang)[0].tolist())
        listed = set(e.tolist())
        if c is lon:
            skip = set(np.nonzero(polar)[0].tolist())
            on, listed = on - skip, listed - skip
        if listed != on or len(set(e.tolist())) != len(e):
            fail("%s: edge %s: %d listed, %d on it" % (path, name,
                                                      len(e), len(on)))
    return len(idx) // 3


def read_subtree(path):
    b = open(path, "rb").read()
    magic, ver, jl, bl = struct.unpack_from("<4sIQQ", b, 0)
    if magic != b"subt" or ver != 1 or jl % 8 or 24 + jl + bl != len(b):
        fail(path + ": subtree header")
    j = json.loads(b[24:24 + jl])
    binc = b[24 + jl:]
    if j["buffers"][0]["byteLength"] != bl or bl % 8:
        fail(path + ": buffer length")
    for v in j["bufferViews"]:
        if v["byteOffset"] % 8 or v["byteOffset"] + v["byteLength"] > bl:
            fail(path + ": buffer view")
    return j, binc


def bits(j, binc, av, n):
    if "constant" in av:
        return [bool(av["constant"])] * n
    v = j["bufferViews"][av["bitstream"]]
    raw = binc[v["byteOffset"]:v["byteOffset"] + v["byteLength"]]
    out = [bool(raw[i >> 3] >> (i & 7) & 1) for i in range(n)]
    if "availableCount" in av and sum(out) != av["availableCount"]:
        fail("availableCount")
    return out


def demorton(m):
    x = y = 0
    for b in range(16):
        x |= (m >> (2 * b) & 1) << b
        y |= (m >> (2 * b + 1) & 1) << b
    return x, y


def walk(out, root, tile, seen, stats):
    it = tile["implicitTiling"]
    k, nlev = it["subtreeLevels"], it["availableLevels"]
    subt, cont = it["subtrees"]["uri"], tile["content"]["uri"]

    def uri(t, z, x, y):
        return os.path.join(out, t.replace("{level}", str(z)).replace(
            "{x}", str(x)).replace("{y}", str(y)))
    todo = [(0, 0, 0)]
    while todo:
        s, sx, sy = todo.pop()
        path = uri(subt, s, sx, sy)
        if not os.path.exists(path):
            fail(path + ": announced, missing")
        seen.add(path)
        stats["subtrees"] += 1
        j, binc = read_subtree(path)
        ntile = (4 ** k - 1) // 3
        ta = bits(j, binc, j["tileAvailability"], ntile)
        ca = bits(j, binc, j["contentAvailability"][0], ntile)
        sa = bits(j, binc, j["childSubtreeAvailability"], 4 ** k)
        if ta != ca or not ta[0]:
            fail(path + ": content availability differs from tiles")
        pt = j["propertyTables"][j["tileMetadata"]]
        if pt["count"] != sum(ta):
            fail(path + ": property table rows != available tiles")
        cols = {}
        for name, w in (("minimumHeight", 1), ("maximumHeight", 1),
                        ("boundingSphere", 4), ("horizonOcclusionPoint", 3)):
            v = j["bufferViews"][pt["properties"][name]["values"]]
            cols[name] = np.frombuffer(binc, "<f8", w * pt["count"],
                                       v["byteOffset"]).reshape(-1, w)
        row, first, d = 0, 0, 0
        for i in range(ntile):
            if i == first + 4 ** d:
                first, d = i, d + 1
            lx, ly = demorton(i - first)
            z, x, y = s + d, (sx << d) + lx, (sy << d) + ly
            f = uri(cont, z, x, y)
            if ta[i] != os.path.exists(f) or (ta[i] and z >= nlev):
                fail(f + ": availability %d, file %s" % (ta[i],
                     os.path.exists(f)))
            if not ta[i]:
                continue
            meta = list(cols["minimumHeight"][row]) + \
                list(cols["maximumHeight"][row]) + \
                list(cols["boundingSphere"][row]) + \
                list(cols["horizonOcclusionPoint"][row])
            row += 1
            seen.add(f)
            stats["tiles"] += 1
            stats["tris"] += check_glb(f, root, z, x, y, meta)
        for i in range(4 ** k):
            lx, ly = demorton(i)
            z, x, y = s + k, (sx << k) + lx, (sy << k) + ly
            f = uri(subt, z, x, y)
            if sa[i] != os.path.exists(f):
                fail(f + ": child subtree availability %d, file %s" %
                     (sa[i], os.path.exists(f)))
            if sa[i]:
                todo.append((z, x, y))


def main():
    out = sys.argv[1]
    ts = json.load(open(os.path.join(out, "tileset.json")))
    kids = ts["root"]["children"]
    if len(kids) != 2:
        fail("tileset.json: not two root tiles")
    for r, t in enumerate(kids):
        reg = t["boundingVolume"]["region"]
        if abs(reg[0] - (-math.pi if r == 0 else 0)) > 1e-12 or \
                abs(reg[2] - (0 if r == 0 else math.pi)) > 1e-12:
            fail("tileset.json: root %d's region" % r)
    seen, stats = set(), {"subtrees": 0, "tiles": 0, "tris": 0}
    for r, t in enumerate(kids):
        walk(out, r, t, seen, stats)
    files = set()
    for d, _, fs in os.walk(out):
        files |= {os.path.join(d, f) for f in fs if f != "tileset.json"}
    if files != seen:
        fail("files not announced: %s" % sorted(files - seen)[:5])
    print("%(subtrees)d subtrees, %(tiles)d tiles, %(tris)d triangles: "
          "availability matches the files" % stats)


main()
