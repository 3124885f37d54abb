# t_dem2rgb_edges - dem2rgb at the edges of what it takes: a DEM with a
# large void (a crop of SRTM N44W072 with 340 x 340 samples made nodata):
# no tile without a valid DEM sample within a pixel of it is written,
# every tile holding one is, tiles.json's counts and the PMTiles archive
# hold exactly the tiles written (MapLibre gets 404 for the others, as
# outside the bounds); a DEM near 84 N (a crop of SRTM N48W125
# re-georeferenced there; Web Mercator ends at 85.05): tiles decoded by
# the tests' own decoder (tests/tools/rgbdecode.py) within half a step of
# the heights intended (--dump), the error tiles.json declares measured
# again at every valid sample; one past 85.05 N clamped there; refused,
# with a message and nothing written: the whole world in a CRS whose
# longitudes wrap at the antimeridian (a DEM across it:
# t_dem2rgb_antimeridian), an EXR; a list of DEMs and its VRT give the
# tiles of the whole (t_dem2rgb_list).
. "$(dirname "$0")/../lib.sh"

TOOLS=$TOP/tests/tools
PY=/usr/bin/python3

# void.tif: 500 x 500 samples of N44W072 (3", no voids of its own) with
# samples 90..429 in both axes nodata (0.28 degrees, whole tiles of zooms
# 11 and 12)
$PY - "$DATA/N44W072.hgt" "$T/void.tif" <<'PY'
import sys
import numpy as np
from osgeo import gdal
gdal.UseExceptions()
src = gdal.Open(sys.argv[1])
a = src.GetRasterBand(1).ReadAsArray(100, 100, 500, 500).astype(np.int16)
a[90:430, 90:430] = -32768
gt = list(src.GetGeoTransform())
gt[0] += 100 * gt[1]; gt[3] += 100 * gt[5]
d = gdal.GetDriverByName("GTiff").Create(sys.argv[2], 500, 500, 1, gdal.GDT_Int16)
d.SetGeoTransform(gt); d.SetProjection(src.GetProjection())
d.GetRasterBand(1).SetNoDataValue(-32768); d.GetRasterBand(1).WriteArray(a)
d = None
PY
# crop.tif: 257 x 257 samples of N48W125 (1", relief and voids);
# polar.tif: the same samples at 83.93 .. 84.00 N
gdal_translate -q -srcwin 2560 2824 257 257 "$DATA/N48W125.hgt" "$T/crop.tif"
gdal_translate -q -a_srs EPSG:4326 -a_ullr -124.289 84.0 -124.2176 83.9286 \
    "$T/crop.tif" "$T/polar.tif"

# tiles TREE DUMP DEM: the tiles written against the DEM's valid samples,
# both ways, and every pixel decoded against the dump; prints the tiles
# inside the bounds' rectangle of the deepest zoom left unwritten
tiles() {
	$PY - "$TOOLS" "$@" >"$T/check" 2>&1 <<'PY'
import math, sys
import numpy as np
from osgeo import gdal
sys.path.insert(0, sys.argv[1])
import rgbdecode as R
tree, dump, dem = sys.argv[2:5]
tj, tiles = R.read_tree(tree)
H = 20037508.342789244
dim, st = tj["tileSize"], R.step(tj["encoding"])
bad = R.tile_set_check(tj, tiles, dem)   # every tile holding a sample
lon, lat, _ = R.dem_samples(dem)
wx, wy = R.merc(lon, lat)
count = {x["zoom"]: x["tiles"] for x in tj["error"]}
skipped = 0
for z in range(tj["minzoom"], tj["maxzoom"] + 1):
    n = 1 << z
    have = {(x, y) for (q, x, y) in tiles if q == z}
    # no tile without a valid sample within one of its pixels: the
    # surface MapLibre draws at a sample reads the pixels around it
    e = 1.0 / (n * dim)
    near = set()
    for dx in (-e, 0, e):
        for dy in (-e, 0, e):
            near |= set(zip(np.floor((wx + dx) * n).astype(int).tolist(),
                np.floor((wy + dy) * n).astype(int).tolist()))
    for x, y in sorted(have - near)[:3]:
        bad.append("tile %d/%d/%d: no valid DEM sample within a pixel" % (z, x, y))
    if count.get(z) != len(have):
        bad.append("zoom %d: %d tiles, tiles.json counts %s" % (z, len(have), count.get(z)))
    x0, y0, x1, y1 = R.tile_range(tj["bounds"], z)
    if z == tj["maxzoom"]:
        skipped = (x1 - x0 + 1) * (y1 - y0 + 1) - len(have)
    # every pixel within half a step of the heights intended
    g = gdal.Open("%s/%d.tif" % (dump, z))
    zh = g.ReadAsArray().astype(np.float64)
    gt = g.GetGeoTransform()
    res = 2 * H / (dim * n)
    gx, gy = round((gt[0] + H) / res), round((H - gt[3]) / res)
    gh, gw = zh.shape
    for x, y in have:
        h = R.decode(tiles[(z, x, y)], tj["encoding"])
        cols = np.clip(x * dim + np.arange(dim) - gx, 0, gw - 1)
        rows = np.clip(y * dim + np.arange(dim) - gy, 0, gh - 1)
        d = np.abs(h - zh[np.ix_(rows, cols)]).max()
        if not d <= st / 2 + 1e-6:
            bad.append("tile %d/%d/%d: a pixel %.4f m off" % (z, x, y, d))
print(skipped)
for b in bad[:8]:
    print("# " + b)
sys.exit(1 if bad else 0)
PY
}

# nothing OUT: no OUT and no temporary left in T
nothing() {
	[ ! -e "$1" ] && [ -z "$(ls -A "$T" | grep '^\.')" ]
}

# --- a large void -----------------------------------------------------------
run "void: the tree" dem2rgb -q -j 2 -t 256 -z 12 --dump "$T/dv" \
    "$T/void.tif" "$T/vt"
tiles "$T/vt" "$T/dv" "$T/void.tif"
ok $? "void: the tiles with a valid sample within a pixel, no other; counts as tiles.json's; every pixel within half a step"
sed -n '2,9p' "$T/check"
skipped=$(head -1 "$T/check")
[ "${skipped:-0}" -ge 4 ]
ok $? "void: tiles over the void alone inside the bounds not written (zoom 12: $skipped)"
JS=$TOP/tests/js
if command -v node >/dev/null && [ -d "$JS/node_modules/pmtiles" ]; then
	run "void: the archive" dem2rgb -q -j 2 -t 256 -z 12 \
	    -o "$T/v.pmtiles" "$T/void.tif"
	node "$JS/pmtiles_read.mjs" "$T/v.pmtiles" "$T/vt" >"$T/read.json" 2>&1
	ok $? "void: npm pmtiles lists exactly the tree's tiles, byte-identical"
else
	ok 0 "void: the archive # SKIP no node or no tests/js/node_modules"
	ok 0 "void: npm pmtiles # SKIP"
fi

# --- near the pole ----------------------------------------------------------
run "84 N: the tree" dem2rgb -q -j 2 --dump "$T/dp" "$T/polar.tif" "$T/pt"
grep -q '"maxzoom": 12' "$T/pt/tiles.json"
ok $? "84 N: maxzoom 12 (the rule at 84 N: 2 m pixels under the 3.2 m cell)"
tiles "$T/pt" "$T/dp" "$T/polar.tif"
ok $? "84 N: tiles exactly over the samples; every pixel within half a step"
sed -n '2,9p' "$T/check"
$PY "$TOOLS/rgbdecode.py" claim "$T/pt" "$T/polar.tif" >"$T/claim" 2>&1
ok $? "84 N: the error tiles.json declares, measured again at every valid sample"
grep EXCEEDED "$T/claim" | head -3 | sed 's/^/#   /'

# past Web Mercator's 85.0511 N: 85.03 .. 85.10, clamped there
gdal_translate -q -a_srs EPSG:4326 -a_ullr -124.289 85.1 -124.2176 85.0286 \
    "$T/crop.tif" "$T/p85.tif"
run "85.03 .. 85.10 N: the tree" dem2rgb -q -z 8 "$T/p85.tif" "$T/p85"
[ "$(cd "$T/p85" && ls -d 8/*/0.png | wc -l)" -ge 1 ] &&
    [ -z "$(cd "$T/p85" && ls -d 8/*/* | grep -v '/0.png$')" ]
ok $? "85.03 .. 85.10 N: tiles in the world's first row alone (clamped at its edge)"

# --- refused ---------------------------------------------------------------
# the whole world in a CRS wrapping at the antimeridian (its seam inside
# the grid; across 180 otherwise: t_dem2rgb_antimeridian)
gdal_translate -q -a_srs '+proj=longlat +datum=WGS84 +pm=180 +no_defs' \
    -a_ullr -180 80 180 -80 "$T/crop.tif" "$T/pm.tif"
fails "the whole world across the antimeridian refused" 1 \
    "pm.tif: spans the whole world across the antimeridian" \
    dem2rgb -q -o "$T/res.pmtiles" "$T/pm.tif"
nothing "$T/res.pmtiles"; ok $? "... nothing written"
# an EXR of heights (fqmsolve's): no georeferencing GDAL reads
dem2fqm "$T/crop.tif" "$T/l0.exr" 2>/dev/null && fqmsolve "$T/l0.exr" "$T/h.exr" 2>/dev/null
fails "an EXR refused" 1 "h.exr: an EXR carries no georeferencing" \
    dem2rgb -q "$T/h.exr" "$T/res"
nothing "$T/res"; ok $? "... nothing written"
# a list: two crops sharing a column
gdal_translate -q -srcwin 0 0 129 257 "$T/crop.tif" "$T/a.tif"
gdal_translate -q -srcwin 128 0 129 257 "$T/crop.tif" "$T/b.tif"
printf 'a.tif\nb.tif\n' >"$T/list.txt"
(cd "$T" && gdalbuildvrt -q -input_file_list list.txt list.vrt)
run "the list's VRT" dem2rgb -q -z 10 "$T/list.vrt" "$T/lt"
dem2rgb -q -z 10 "$T/crop.tif" "$T/ct" && diff -r "$T/lt" "$T/ct" >/dev/null
ok $? "the list's VRT: the tiles and tiles.json of the whole crop"
dem2rgb -q -z 10 "$T/list.txt" "$T/ll" && diff -r "$T/ll" "$T/ct" >/dev/null
ok $? "the list itself: the same"
done_testing
