# t_dem2rgb - raster-dem tiles (dem2rgb) of a crop of SRTM N48W125 with
# voids (southern Vancouver Island) and of a UTM variant of it, both
# encodings, PNG and WebP, decoded by an independent decoder (GDAL reads
# the images, the formulas are written out here): every pixel within half
# a step of the height the chain intended at the pixel centres (--dump,
# on each zoom's pixel grid), the tiles exactly those whose pixels are
# over valid samples, inside the TileJSON's bounds,
# each over a valid DEM sample, pixels past the DEM within its range;
# tiles.json's fields, the error measured at every valid DEM sample (for
# the UTM DEM measured again by the decoder); the
# datums; QEM-1D's error under averaging's; -m average's zoom the 2 x 2
# mean of the one below;
# reruns and -j 1 / -j 2 byte-identical; heights past the encoding's
# range, an unwritable output, an output on the input refused; a killed
# run leaves nothing.
. "$(dirname "$0")/../lib.sh"

# 513 x 513 samples at 1", relief 0 - 1061 m, 961 voids
gdal_translate -q -srcwin 2560 2824 513 513 "$DATA/N48W125.hgt" "$T/srtm.tif"
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r bilinear "$T/srtm.tif" "$T/utm.tif"

# check TREE DUMP DEM ENC EXT DIM: the independent decoder
check() {
	/usr/bin/python3 - "$@" >"$T/check" 2>&1 <<'PY'
import json, math, os, sys
import numpy as np
from osgeo import gdal, osr
gdal.UseExceptions()
tree, dump, dem, enc, ext, dim = sys.argv[1:7]
dim = int(dim)
H = 20037508.342789244
tj = json.load(open(os.path.join(tree, "tiles.json")))
step = 1 / 256 if enc == "terrarium" else 0.1
bad = []
assert tj["tilejson"] == "3.0.0" and tj["encoding"] == enc
assert tj["tileSize"] == dim and len(tj["tiles"]) == 1 and tj["tiles"][0].endswith("{z}/{x}/{y}." + ext)
# the DEM's valid samples in lon/lat, to see each tile lies over one
ds = gdal.Open(dem)
a = ds.GetRasterBand(1).ReadAsArray().astype(float)
nd = ds.GetRasterBand(1).GetNoDataValue()
gt = ds.GetGeoTransform()
jj, ii = np.nonzero(a != nd) if nd is not None else np.nonzero(np.isfinite(a))
px = gt[0] + (ii + 0.5) * gt[1]
py = gt[3] + (jj + 0.5) * gt[5]
s = osr.SpatialReference(); s.ImportFromWkt(ds.GetProjection())
t = osr.SpatialReference(); t.ImportFromEPSG(4326)
s.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
t.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
ct = osr.CoordinateTransformation(s, t)
ll = np.array(ct.TransformPoints(np.c_[px, py]))
lo, hi = a[jj, ii].min(), a[jj, ii].max()
mx = ll[:, 0] * math.pi / 180 * 6378137
my = 6378137 * np.log(np.tan(math.pi / 4 + ll[:, 1] * math.pi / 360))
b = tj["bounds"]
ntiles = 0
for z in range(tj["minzoom"], tj["maxzoom"] + 1):
    g = gdal.Open(os.path.join(dump, "%d.tif" % z))
    zh = g.ReadAsArray().astype(np.float32)
    zv = gdal.Open(os.path.join(dump, "%d.valid.tif" % z)).ReadAsArray() > 0
    res = 2 * H / (dim * 2 ** z)
    ggt = g.GetGeoTransform()
    # the dump is on the zoom's own pixel grid (pixel centres, where
    # MapLibre puts the heights): its corners on pixel corners
    x0f, y0f = (ggt[0] + H) / res, (H - ggt[3]) / res
    assert abs(x0f - round(x0f)) < 1e-6 and abs(y0f - round(y0f)) < 1e-6, (x0f, y0f)
    x0 = round(x0f); y0 = round(y0f)
    gh, gw = zh.shape
    # the tiles with a valid pixel
    want = set()
    for (r, c) in zip(*np.nonzero(zv)):
        want.add(((x0 + c) // dim, (y0 + r) // dim))
    have = set()
    zdir = os.path.join(tree, str(z))
    for xs in (os.listdir(zdir) if os.path.isdir(zdir) else []):
        for f in os.listdir(os.path.join(zdir, xs)):
            have.add((int(xs), int(f.split(".")[0])))
            assert f.endswith("." + ext), f
    if have != want:
        bad.append("zoom %d: tiles %s, expected %s" % (z, sorted(have ^ want)[:4], len(want)))
    # inside the bounds' tile rectangle
    n = 2 ** z
    def tx(lon): return int(math.floor((lon + 180) / 360 * n))
    def ty(lat):
        p = math.radians(lat)
        return int(math.floor((1 - math.log(math.tan(p) + 1 / math.cos(p)) / math.pi) / 2 * n))
    for (x, y) in have:
        if not (tx(b[0]) <= x <= tx(b[2]) and ty(b[3]) <= y <= ty(b[1])):
            bad.append("zoom %d: tile %d/%d outside the bounds" % (z, x, y))
        # a valid DEM sample within the tile (a pixel of margin)
        tres = 2 * H / n
        inx = (mx >= -H + x * tres - res) & (mx <= -H + (x + 1) * tres + res)
        iny = (my <= H - y * tres + res) & (my >= H - (y + 1) * tres - res)
        if not np.any(inx & iny):
            bad.append("zoom %d: tile %d/%d over no DEM sample" % (z, x, y))
        im = gdal.Open(os.path.join(zdir, str(x), "%d.%s" % (y, ext))).ReadAsArray()
        assert im.shape[0] >= 3 and im.shape[1:] == (dim, dim), im.shape
        R, G, B = (im[k].astype(np.float64) for k in range(3))
        if enc == "terrarium":
            h = R * 256 + G + B / 256 - 32768
        else:
            h = -10000 + (R * 65536 + G * 256 + B) * 0.1
        # intended: the dump at pixel (x dim + i, y dim + j), past the
        # grid its edge
        cols = np.clip(x * dim + np.arange(dim) - x0, 0, gw - 1)
        rows = np.clip(y * dim + np.arange(dim) - y0, 0, gh - 1)
        want_h = zh[np.ix_(rows, cols)].astype(np.float64)
        d = np.abs(h - want_h).max()
        if d > step / 2 + 1e-6:
            bad.append("zoom %d tile %d/%d: a pixel %.5f m off" % (z, x, y, d))
        # past the DEM and in its voids the fill's heights: at maxzoom
        # inside the DEM's range, no wall to 0 or -10000
        if z == tj["maxzoom"] and not (lo - 0.01 <= h.min() and h.max() <= hi + 0.01):
            bad.append("zoom %d tile %d/%d: %.2f .. %.2f past the DEM's %.2f .. %.2f" % (z, x, y, h.min(), h.max(), lo, hi))
        ntiles += 1
print("tiles %d" % ntiles)
for m in bad[:10]:
    print(m)
sys.exit(1 if bad or ntiles == 0 else 0)
PY
	_s=$?
	sed 's/^/#   /' "$T/check" | head -12
	return $_s
}

run "SRTM crop, terrarium PNG (-j 2)" dem2rgb -j 2 --dump "$T/d1" \
    "$T/srtm.tif" "$T/t1"
cp "$T/err" "$T/report1"
check "$T/t1" "$T/d1" "$T/srtm.tif" terrarium png 512
ok $? "terrarium PNG: every pixel within half a step, tiles exactly the covered ones"
run "SRTM crop, mapbox WebP 256" dem2rgb -q -e mapbox -f webp -t 256 \
    --dump "$T/d2" "$T/srtm.tif" "$T/t2"
check "$T/t2" "$T/d2" "$T/srtm.tif" mapbox webp 256
ok $? "mapbox WebP 256: every pixel within half a step, tiles exactly the covered ones"
run "UTM DEM, terrarium WebP" dem2rgb -q -f webp --dump "$T/d3" \
    "$T/utm.tif" "$T/t3"
check "$T/t3" "$T/d3" "$T/utm.tif" terrarium webp 512
ok $? "UTM terrarium WebP: every pixel within half a step, tiles exactly the covered ones"
# the error declared for the UTM DEM, measured again here: its samples
# placed by GDAL/OSR, the tiles decoded and drawn as MapLibre draws them
# (tests/tools/rgbdecode.py: bilinear between pixel centres)
/usr/bin/python3 - "$T/t3" "$T/utm.tif" "$(dirname "$0")/../tools" <<'PY' >"$T/check" 2>&1
import math, sys
import numpy as np
from osgeo import gdal, osr
sys.path.insert(0, sys.argv[3])
import rgbdecode as R
tj, tiles = R.read_tree(sys.argv[1])
d = gdal.Open(sys.argv[2]); b = d.GetRasterBand(1)
z = b.ReadAsArray().astype(float); nd = b.GetNoDataValue()
ok = np.isfinite(z) if nd is None else np.isfinite(z) & (z != nd)
jj, ii = np.nonzero(ok); g = d.GetGeoTransform()
s = osr.SpatialReference(); s.ImportFromWkt(d.GetProjection())
t = osr.SpatialReference(); t.ImportFromEPSG(4326)
for r in (s, t):
    r.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
ll = np.array(osr.CoordinateTransformation(s, t).TransformPoints(
    np.c_[g[0] + (ii + .5) * g[1], g[3] + (jj + .5) * g[5]]))
wx, wy = R.merc(ll[:, 0], ll[:, 1])
dec = {x["zoom"]: x for x in tj["error"]}
bad = 0
for zz, zm in sorted(R.zooms(tj, tiles).items()):
    e = zm.surface_many(wx, wy) - z[jj, ii]
    mx, rms = np.abs(e).max(), math.sqrt((e * e).mean())
    x = dec[zz]
    good = (x["samples"] == len(e) and abs(x["max"] - mx) <= 0.01 * mx + 0.01
        and abs(x["rms"] - rms) <= 0.01 * rms + 0.01)
    bad += not good
    print("zoom %d: measured %.3f / %.3f, declared %.3f / %.3f%s" % (zz, mx, rms, x["max"], x["rms"], "" if good else " DIFFERENT"))
sys.exit(bad > 0)
PY
ok $? "UTM: the error tiles.json declares is the surface's, measured again at every valid sample"
sed 's/^/#   /' "$T/check" | tail -3
run "UTM DEM, mapbox PNG 256, -Z 5" dem2rgb -q -e mapbox -t 256 -Z 5 -u http://h/t \
    --dump "$T/d4" "$T/utm.tif" "$T/t4"
check "$T/t4" "$T/d4" "$T/utm.tif" mapbox png 256
ok $? "UTM mapbox PNG 256: every pixel within half a step, tiles exactly the covered ones"
[ ! -e "$T/t4/4" ] && [ -d "$T/t4/5" ] && grep -q '"minzoom": 5' "$T/t4/tiles.json"
ok $? "-Z 5: zooms 5 and deeper only"
grep -q '"http://h/t/{z}/{x}/{y}.png"' "$T/t4/tiles.json"; ok $? "-u: absolute tile URLs"

# tiles.json: the zoom rule (SRTM 1" at 48 N: 20.6 m; 512 px: zoom 12
# has 12.7 m pixels, zoom 11 25.3 m), datum, errors per zoom
/usr/bin/python3 - "$T/t1/tiles.json" "$T/report1" "$T/srtm.tif" <<'PY' >"$T/check" 2>&1
import json, sys
import numpy as np
from osgeo import gdal
t = json.load(open(sys.argv[1]))
ds1 = gdal.Open(sys.argv[3])  # kept: a band outliving its dataset crashes
b1 = ds1.GetRasterBand(1)
nvalid = int(np.count_nonzero(b1.ReadAsArray() != b1.GetNoDataValue()))
assert t["minzoom"] == 0 and t["maxzoom"] == 12, (t["minzoom"], t["maxzoom"])
b = t["bounds"]
assert abs(b[0] + 124.28903) < 1e-4 and abs(b[3] - 48.21569) < 1e-4, b
assert t["vertical_datum"] and t["method"] == "qem1d" and t["scheme"] == "xyz"
e = {x["zoom"]: x for x in t["error"]}
assert sorted(e) == list(range(13))
assert all(0 <= x["rms"] <= x["max"] for x in e.values())
# measured at every valid sample of the DEM itself (not of its warp)
assert all(x["samples"] == nvalid for x in e.values()), (nvalid, e[12])
# zoom 12 is the bilinear warp of the 20.6 m DEM onto 12.7 m pixels:
# under a metre RMS, and the coarser the zoom the larger the error
assert e[12]["rms"] < 1 and e[12]["rms"] < e[11]["rms"] < e[8]["rms"], e[12]
assert e[8]["rms"] > 1 and e[8]["samples"] > 200000, e[8]
rep = open(sys.argv[2]).read()
assert "zoom 12: " in rep and "rms" in rep
PY
ok $? "tiles.json: tilejson fields, maxzoom 12 by the rule, bounds, datum, an error per zoom"
sed 's/^/#   /' "$T/check" | head -5

# QEM-1D against averaging: lower RMS at every zoom from 2 (all three
# segments)
run "-m average" dem2rgb -q -m average --dump "$T/da" "$T/srtm.tif" "$T/ta"
/usr/bin/python3 - "$T/t1/tiles.json" "$T/ta/tiles.json" <<'PY' >"$T/check" 2>&1
import json, sys
q, a = ({x["zoom"]: x["rms"] for x in json.load(open(f))["error"]} for f in sys.argv[1:3])
for z in range(0, 12):
    print("zoom %d: qem1d %.3f average %.3f" % (z, q[z], a[z]))
# (not at zooms 0 and 1, pixels of 78 and 39 km at the equator over a
# DEM of 10 km: QEM-1D extrapolates its few planes, 428 m RMS against
# 143 m; dem2rgb(1), CAVEATS)
for z in range(2, 12):
    assert q[z] < a[z], z
PY
ok $? "qem1d's RMS under average's at zooms 2 .. 11"
sed 's/^/#   /' "$T/check" | tail -6
/usr/bin/python3 - "$T/da" <<'PY' >"$T/check" 2>&1
import os, sys
import numpy as np
from osgeo import gdal
H = 20037508.342789244
n = 0
for z in range(12, 6, -1):
    def grid(z):
        g = gdal.Open(os.path.join(sys.argv[1], "%d.tif" % z))
        v = gdal.Open(os.path.join(sys.argv[1], "%d.valid.tif" % z))
        t = g.GetGeoTransform()
        return (g.ReadAsArray().astype(float), v.ReadAsArray() > 0,
            round((t[0] + H) / t[1]), round((H - t[3]) / -t[5]))
    f, fv, fx, fy = grid(z)
    c, cv, cx, cy = grid(z - 1)
    # the coarse pixels whose 4 fine pixels are all valid: their mean
    for r in range(c.shape[0]):
        for k in range(c.shape[1]):
            i, j = 2 * (cx + k) - fx, 2 * (cy + r) - fy
            if i < 0 or j < 0 or i + 2 > f.shape[1] or j + 2 > f.shape[0]:
                continue
            if fv[j:j + 2, i:i + 2].all():
                m = f[j:j + 2, i:i + 2].mean()
                assert abs(c[r, k] - m) < 1e-3, (z - 1, r, k, c[r, k], m)
                assert cv[r, k]
                n += 1
print("pixels %d" % n)
assert n > 1000
PY
ok $? "-m average: a pixel the mean of the 4 pixels of the zoom below it"
sed 's/^/#   /' "$T/check" | head -3

# determinism
run "rerun" dem2rgb -q -j 2 --dump "$T/d1b" "$T/srtm.tif" "$T/t1b"
diff -r "$T/t1" "$T/t1b" >/dev/null; ok $? "rerun: byte-identical tree"
run "-j 1" dem2rgb -q -j 1 "$T/srtm.tif" "$T/t1c"
diff -r "$T/t1" "$T/t1c" >/dev/null; ok $? "-j 1 and -j 2: byte-identical trees"
run "replace" dem2rgb -q "$T/srtm.tif" "$T/t1b"
diff -r "$T/t1" "$T/t1b" >/dev/null; ok $? "an existing tree replaced"

# heights: orthometric by default, the datum in tiles.json; -H
# ellipsoid moves them by the geoid (about -20 m here); an ellipsoidal
# DEM (-D ellipsoid) comes back to EGM96
gdal_translate -q -a_srs EPSG:4326+5773 "$T/srtm.tif" "$T/egm.tif"
/usr/bin/python3 "$TOP/tests/tools/ellipsoidal.py" "$T/egm.tif" "$T/ell.tif"
dem2rgb -q -z 9 --dump "$T/dA" "$T/egm.tif" "$T/tA" &&
    dem2rgb -q -z 9 -H ellipsoid --dump "$T/dB" "$T/egm.tif" "$T/tB" &&
    dem2rgb -q -z 9 -D ellipsoid --dump "$T/dC" "$T/ell.tif" "$T/tC"
ok $? "datums: three exports"
grep -q '"vertical_datum": "EPSG:5773"' "$T/tA/tiles.json" &&
    grep -q '"vertical_datum": "EPSG:4979"' "$T/tB/tiles.json" &&
    grep -q '"vertical_datum": "EPSG:5773"' "$T/tC/tiles.json"
ok $? "datums: EPSG:5773 as declared, EPSG:4979 with -H ellipsoid, EPSG:5773 from an ellipsoidal DEM"
/usr/bin/python3 - "$T" <<'PY' >"$T/check" 2>&1
import sys
from osgeo import gdal
t = sys.argv[1]
a, b, c = (gdal.Open("%s/%s/9.tif" % (t, d)).ReadAsArray() for d in ("dA", "dB", "dC"))
print((b - a).min(), (b - a).max(), abs(c - a).max())
assert -22 < (b - a).min() and (b - a).max() < -19
assert abs(c - a).max() < 0.05
PY
ok $? "datums: -H ellipsoid 19 to 22 m lower (EGM96 here), the ellipsoidal DEM's heights back within 5 cm"
sed 's/^/#   /' "$T/check" | head -3

# failures
/usr/bin/python3 - "$T/srtm.tif" "$T/high.tif" "$T/low.tif" <<'PY'
import sys
from osgeo import gdal
import numpy as np
s = gdal.Open(sys.argv[1])
for out, add in ((sys.argv[2], 40000.0), (sys.argv[3], -12000.0)):
    d = gdal.GetDriverByName("GTiff").Create(out, s.RasterXSize, s.RasterYSize, 1, gdal.GDT_Float32)
    d.SetGeoTransform(s.GetGeoTransform()); d.SetProjection(s.GetProjection())
    a = s.ReadAsArray().astype(np.float32) + add
    d.GetRasterBand(1).WriteArray(a); d = None
PY
fails "terrarium: 40000 m refused" 1 "outside the terrarium encoding's range" \
    dem2rgb -q -z 8 "$T/high.tif" "$T/hi"
[ ! -e "$T/hi" ]; ok $? "... and no output"
run "mapbox: 40000 m taken" dem2rgb -q -z 8 -e mapbox "$T/high.tif" "$T/hi"
fails "mapbox: -12000 m refused" 1 "outside the mapbox encoding's range" \
    dem2rgb -q -z 8 -e mapbox "$T/low.tif" "$T/lo"
gdal_translate -q -srcwin 0 0 64 64 "$DATA/N48W125.hgt" "$T/void.tif"
fails "a DEM of voids only refused" 1 "void.tif .*no valid samples" \
    dem2rgb -q "$T/void.tif" "$T/void"
[ ! -e "$T/void" ]; ok $? "... and no output"
: >"$T/file"
fails "unwritable output" 1 "dem2rgb: .*file" dem2rgb -q -z 8 "$T/srtm.tif" "$T/file/out"
mkdir -p "$T/in"; cp "$T/srtm.tif" "$T/in/"
fails "output holding the input refused" 1 "contains|is the input" \
    dem2rgb -q -z 8 "$T/in/srtm.tif" "$T/in"
fails "output equal to the input refused" 1 "is the input" \
    dem2rgb -q -z 8 "$T/in/srtm.tif" "$T/in/srtm.tif"
mkdir -p "$T/other"; : >"$T/other/keep"
fails "a folder that is not a tree is not replaced" 1 "not a raster-dem tree" \
    dem2rgb -q -z 8 "$T/srtm.tif" "$T/other"
[ -f "$T/other/keep" ]; ok $? "... and kept"
fails "usage: -t 300" 2 "300" dem2rgb -t 300 "$T/srtm.tif" "$T/x"
fails "usage: one operand" 2 "usage" dem2rgb "$T/srtm.tif"
dem2rgb --help >/dev/null; ok $? "--help exits 0"

# killed: by TERM nothing is left; by KILL the next run clears it
dem2rgb -q -j 1 "$T/srtm.tif" "$T/killed" &
pid=$!
if mid_run $pid "$T/killed"; then
	kill -TERM $pid; kill -CONT $pid; wait $pid
	[ ! -e "$T/killed" ] && [ -z "$(ls -a "$T" | grep killed)" ]
	ok $? "TERM: no OUT and no temporary left"
else
	wait $pid; skip "the run ended before the kill"
fi
rm -rf "$T/killed"
dem2rgb -q -j 1 "$T/srtm.tif" "$T/killed" &
pid=$!
if mid_run $pid "$T/killed"; then
	kill -KILL $pid; kill -CONT $pid 2>/dev/null; wait $pid
	[ ! -e "$T/killed" ]; ok $? "KILL: no OUT"
else
	wait $pid; skip "the run ended before the kill"
fi
dem2rgb -q -j 2 -z 9 "$T/srtm.tif" "$T/killed"
[ -z "$(ls -a "$T" | grep '^\.killed\.')" ] && [ -f "$T/killed/tiles.json" ]
ok $? "KILL: the next run removes the dead run's temporary"
done_testing
