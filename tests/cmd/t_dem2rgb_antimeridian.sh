# t_dem2rgb_antimeridian - dem2rgb on a DEM across 180 degrees: a crop
# of SRTM N42E001 (481 x 241 samples, voids and relief) moved to 179.8 E
# .. 180.2 E (longitudes past 180), the same in a CRS wrapping there
# (prime meridian 180), warped to UTM zone 60 and to EPSG:3832 (PDC
# Mercator, its x running on past 180). Tiles on both sides of the seam
# (x = 2^z - 1 and x = 0 at every zoom but 0, whose one tile holds both
# ends); decoded by the tests' own decoder (tests/tools/rgbdecode.py):
# every pixel within half a step of the intended heights (--dump, read
# past the world's east edge), the deepest zoom's within half a step of
# gdalwarp's own warp of the DEM onto each tile's extent; the heights
# continuous across the seam (no wall); the tiles those of the same
# crop straddling 0 degrees moved half a world, within a step, and the
# measured error the same, over every valid DEM sample; the error
# tiles.json declares measured again by the decoder's surface over both
# sides; tiles.json and the PMTiles header's bounds the world's
# longitudes (TileJSON 3.0.0: bounds must not wrap); the plan's jobs
# byte for byte one process's (the split parts sharing zoom 0's tile;
# -m average).
. "$(dirname "$0")/../lib.sh"

TOOLS=$TOP/tests/tools
PY=/usr/bin/python3

gdal_translate -q -srcwin 300 300 481 241 "$DATA/N42E001.tif" "$T/crop.tif"
gdal_translate -q -a_srs EPSG:4326 -a_ullr 179.8 43 180.2 42.8 \
    "$T/crop.tif" "$T/am.tif"
gdal_translate -q -a_srs EPSG:4326 -a_ullr -0.2 43 0.2 42.8 \
    "$T/crop.tif" "$T/zero.tif"
gdal_translate -q -a_srs '+proj=longlat +datum=WGS84 +pm=180 +no_defs' \
    -a_ullr -0.2 43 0.2 42.8 "$T/crop.tif" "$T/pm.tif"
gdalwarp -q -t_srs EPSG:32660 -tr 90 90 -r bilinear "$T/am.tif" "$T/utm.tif"
gdalwarp -q -t_srs EPSG:3832 -tr 120 120 -r bilinear "$T/am.tif" "$T/pdc.tif"

# check TREE DUMP DEM [ZERO]: the tree of DEM against its dump, gdalwarp,
# the seam, the declared error (and the tree ZERO of the crop at 0 E)
check() {
	$PY - "$TOOLS" "$@" >"$T/check" 2>&1 <<'PY'
import json, math, sys
import numpy as np
from osgeo import gdal
sys.path.insert(0, sys.argv[1])
import rgbdecode as R
gdal.UseExceptions()
tree, dump, dem = sys.argv[2:5]
zero = sys.argv[5] if len(sys.argv) > 5 else None
tj, tiles = R.read_tree(tree)
H = 20037508.342789244
dim, enc = tj["tileSize"], tj["encoding"]
st = R.step(enc)
bad = []
b = tj["bounds"]
if b[0] != -180 or b[2] != 180 or not -180 <= tj["center"][0] < 180:
    bad.append("tiles.json: bounds %s, center %s" % (b, tj["center"]))
dec = {k: R.decode(p, enc) for k, p in tiles.items()}
for z in range(tj["minzoom"], tj["maxzoom"] + 1):
    n = 1 << z
    have = sorted((x, y) for (q, x, y) in tiles if q == z)
    xs = {x for x, y in have}
    if z > 0 and not (n - 1 in xs and 0 in xs):
        bad.append("zoom %d: tile columns %s, not both sides" % (z, sorted(xs)))
    # every pixel on the grid within half a step of the dump's height,
    # a column west of the grid's first one read a world east
    g = gdal.Open("%s/%d.tif" % (dump, z))
    zh = g.ReadAsArray().astype(np.float64)
    gt = g.GetGeoTransform()
    res = 2 * H / (dim * n)
    gx, gy = round((gt[0] + H) / res), round((H - gt[3]) / res)
    gh, gw = zh.shape
    if gx + gw <= n * dim:
        bad.append("zoom %d: the grid ends before the world's east edge" % z)
    for x, y in have:
        X = x * dim + np.arange(dim)
        X = np.where(X < gx, X + n * dim, X) - gx
        on = (X >= 0) & (X < gw)
        rows = np.clip(y * dim + np.arange(dim) - gy, 0, gh - 1)
        d = np.abs(dec[(z, x, y)][:, on] - zh[np.ix_(rows, X[on])]).max()
        if not d <= st / 2 + 1e-6:
            bad.append("tile %d/%d/%d: a pixel %.4f m off the dump" % (z, x, y, d))
    # the seam: no step across it larger than the largest inside
    for y in sorted({y for x, y in have}):
        w, e = dec.get((z, n - 1, y)), dec.get((z, 0, y))
        if w is None or e is None:
            continue
        seam = np.abs(w[:, -1] - e[:, 0]).max()
        inner = max(np.abs(np.diff(w, axis=1)).max(), np.abs(np.diff(e, axis=1)).max())
        if not seam <= inner:
            bad.append("zoom %d row %d: a step of %.2f m across 180 (%.2f inside)"
                % (z, y, seam, inner))
# the deepest zoom against gdalwarp onto each tile (the tiles east of
# 180 at their extent past the world's east edge)
z = tj["maxzoom"]; n = 1 << z; res = 2 * H / (dim * n); far = 0
for (q, x, y) in sorted(tiles):
    if q != z:
        continue
    xe = x + n if x < n // 2 else x
    te = [-H + xe * dim * res, H - (y + 1) * dim * res,
        -H + (xe + 1) * dim * res, H - y * dim * res]
    ref = gdal.Warp("", dem, format="MEM", dstSRS="EPSG:3857",
        outputBounds=te, width=dim, height=dim, resampleAlg="bilinear",
        outputType=gdal.GDT_Float32, dstNodata=float("nan"),
        errorThreshold=0).ReadAsArray().astype(np.float64)
    ok = np.isfinite(ref)
    d = np.abs(dec[(z, x, y)][ok] - ref[ok])
    far = max(far, d.max() if ok.any() else 0)
    if ok.sum() == 0 or not d.max() <= st / 2 + 1e-4:
        bad.append("tile %d/%d/%d: %d pixels gdalwarp warps, one %.4f m off"
            % (z, x, y, ok.sum(), d.max() if ok.any() else math.nan))
# the declared error measured again: the decoder's surface on a world
# repeated once (each tile also a world east), the samples unwrapped
from osgeo import osr
d = gdal.Open(dem); bd = d.GetRasterBand(1)
a = bd.ReadAsArray().astype(np.float64); nd = bd.GetNoDataValue()
ok = np.isfinite(a) if nd is None else np.isfinite(a) & (a != nd)
jj, ii = np.nonzero(ok); g = d.GetGeoTransform()
px, py = g[0] + (ii + .5) * g[1], g[3] + (jj + .5) * g[5]
s = osr.SpatialReference(wkt=d.GetProjection()); t = osr.SpatialReference()
t.ImportFromEPSG(4326)
for r in (s, t):
    r.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
p = np.array(osr.CoordinateTransformation(s, t).TransformPoints(
    np.column_stack([px, py])))
lon = np.where(p[:, 0] < 0, p[:, 0] + 360, p[:, 0])
wx, wy = R.merc(lon, p[:, 1])
for e in tj["error"]:
    z = e["zoom"]; n = 1 << z
    zm = R.Zoom(z, tiles, enc)
    for (x, y), hh in list(zm.h.items()):
        zm.h[(x + n, y)] = hh
    m = zm.surface_many(wx, wy) - a[jj, ii]
    m = m[np.isfinite(m)]
    mx, rms = np.abs(m).max(), np.sqrt(np.mean(m * m))
    if len(m) != len(jj) or e["samples"] != len(jj):
        bad.append("zoom %d: %d samples measured, %d declared, %d valid"
            % (z, len(m), e["samples"], len(jj)))
    for k, v in (("max", mx), ("rms", rms)):
        if not abs(v - e[k]) <= 0.05 * e[k] + st:
            bad.append("zoom %d: %s %.4f measured, %.4f declared" % (z, k, v, e[k]))
# the same crop at 0 E: the same tiles half a world west, within a step
if zero:
    zj, zt = R.read_tree(zero)
    for z in range(zj["minzoom"] + 1, zj["maxzoom"] + 1):
        n = 1 << z
        want = {(z, (x + n // 2) % n, y) for (q, x, y) in zt if q == z}
        if want != {k for k in tiles if k[0] == z}:
            bad.append("zoom %d: not the tiles at 0 E moved" % z)
            continue
        for (q, x, y), pth in zt.items():
            if q == z:
                dd = np.abs(R.decode(pth, enc) - dec[(z, (x + n // 2) % n, y)]).max()
                if not dd <= st + 1e-6:
                    bad.append("tile %d/%d/%d: %.4f m off the tile at 0 E" % (z, x, y, dd))
    for e, f in zip(tj["error"], zj["error"]):
        if e["samples"] != f["samples"] or abs(e["max"] - f["max"]) > 1e-3 \
            or abs(e["rms"] - f["rms"]) > 1e-3:
            bad.append("zoom %d: error %s, at 0 E %s" % (e["zoom"], e, f))
print("deepest zoom vs gdalwarp: %.5f m" % far)
for e in bad[:8]:
    print("# " + e)
sys.exit(1 if bad else 0)
PY
}

run "179.8 E .. 180.2 E: the tree" dem2rgb -q -j 2 --dump "$T/da" "$T/am.tif" "$T/am"
run "the same crop at -0.2 .. 0.2 E" dem2rgb -q -j 2 "$T/zero.tif" "$T/zero"
check "$T/am" "$T/da" "$T/am.tif" "$T/zero"
ok $? "179.8 E .. 180.2 E: tiles both sides; pixels as intended, as gdalwarp's; no wall at 180; the tiles and error of the crop at 0 E; the error measured again"
sed -n '1,9p' "$T/check" | sed 's/^/# /'
run "prime meridian 180: the tree" dem2rgb -q -j 2 "$T/pm.tif" "$T/pm"
diff -r -x tiles.json "$T/pm" "$T/am" >/dev/null && $PY - "$T/pm" "$T/am" <<'PY'
import json, sys
a, b = (json.load(open(d + "/tiles.json")) for d in sys.argv[1:3])
ea, eb = a.pop("error"), b.pop("error")   # samples placed through PROJ
sys.exit(not (a == b and all(x["samples"] == y["samples"] and
    abs(x["max"] - y["max"]) < 1e-6 and abs(x["rms"] - y["rms"]) < 1e-6
    for x, y in zip(ea, eb))))
PY
ok $? "prime meridian 180 (longitudes -0.2 .. 0.2 wrapping at 180): the tiles of longitudes past 180, byte for byte; tiles.json the same (the error within 1e-6 m)"
for c in utm pdc; do
	run "$c: the tree" dem2rgb -q -j 2 --dump "$T/d$c" "$T/$c.tif" "$T/$c"
	check "$T/$c" "$T/d$c" "$T/$c.tif"
	ok $? "$c: tiles both sides; pixels as intended, as gdalwarp's; no wall at 180; the error measured again"
	sed -n '1,9p' "$T/check" | sed 's/^/# /'
done

# the plan: zoom 0 in the split segment (its one tile from both ends)
for o in "-t 256 -z 3" "-z 10" "-m average -z 6"; do
	# shellcheck disable=SC2086
	dem2rgb -q -j 2 $o "$T/am.tif" "$T/ref" &&
	    dem2rgb $o --plan "$T/plan" --part-tiles 1 "$T/am.tif" \
	    "$T/tree" 2>/dev/null && make -s -C "$T/plan" -j2 >/dev/null 2>&1 &&
	    [ "$(wc -l <"$T/plan/targets1")" -ge 2 ] &&
	    diff -r "$T/tree" "$T/ref" >/dev/null
	ok $? "the plan ($o, 2 parts or more) byte for byte one process's"
	rm -rf "$T/ref" "$T/tree" "$T/plan"
done

JS=$TOP/tests/js
if command -v node >/dev/null && [ -d "$JS/node_modules/pmtiles" ]; then
	run "the archive" dem2rgb -q -j 2 -o "$T/am.pmtiles" "$T/am.tif"
	node "$JS/pmtiles_read.mjs" "$T/am.pmtiles" "$T/am" >"$T/read.json" 2>&1 &&
	    $PY - "$T/read.json" <<'PY'
import json, sys
h = json.load(open(sys.argv[1]))["header"]
sys.exit(not (h["minLon"] == -180 and h["maxLon"] == 180 and
    -180 <= h["centerLon"] < 180 and 42.79 < h["minLat"] < h["maxLat"] < 43.01))
PY
	ok $? "npm pmtiles: the tree's tiles, byte-identical; the header's bounds the world's longitudes"
else
	ok 0 "the archive # SKIP no node or no tests/js/node_modules"
	ok 0 "npm pmtiles # SKIP"
fi
done_testing
