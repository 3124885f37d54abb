# t_maplibre - raster-dem tiles (Terrarium / Terrain-RGB on the Web
# Mercator quadtree, a z/x/y tree with tiles.json) as MapLibre GL JS's
# terrain: npm maplibre-gl (tests/js) in headless Chromium with software
# WebGL, served from a free localhost port by tests/js/maplibre.js, a
# style of the raster-dem source as `terrain` (exaggeration 1) and a
# `hillshade` layer. The tree: dem2rgb's export of 513x513 SRTM samples
# of southern Vancouver Island (747 voids) where the build has dem2rgb,
# else (or with TL_RGB_FIXTURE=1) the fixture, made here by an
# independent encoder (GDAL's warper onto each zoom's pixel grid, pixel
# centres where MapLibre puts them). Checked by the independent decoder
# tests/tools/rgbdecode.py: the tiles exactly those tiles.json's bounds
# and zooms imply with content; the error per zoom of the surface
# MapLibre draws against every valid DEM sample within what tiles.json
# declares; dem2rgb's no worse than the fixture's (RMS). In the browser:
# no failed request, no console error; map.queryTerrainElevation at 24
# valid DEM samples (6 at each of the 4 deepest zooms) read from a tile
# of the zoom asked, equal to the decoder's surface there (MapLibre draws
# what the decoder says) and within that zoom's error of the DEM. The
# same tiles shifted half a pixel fail the error check (the check can
# fail). TL_MAPLIBRE_PMTILES=FILE.pmtiles (the same tiles as one PMTiles
# archive, npm pmtiles in tests/js): the same style through the pmtiles
# protocol, the same heights; by default dem2rgb -o's archive of the same
# DEM where dem2rgb made the tree. OUT_SHOT=FILE.png: a picture of it there.
# TL_MAPLIBRE_TREE=DIR: that tree instead (made of the same cut:
# gdal_translate -srcwin 2944 2816 513 513 N48W125.hgt).
. "$(dirname "$0")/../lib.sh"

browser_test "MapLibre GL JS raster-dem terrain in Chromium"
JS=$TOP/tests/js
dec() { /usr/bin/python3 "$TOP/tests/tools/rgbdecode.py" "$@"; }
gdal_translate -q -a_srs EPSG:4326 -srcwin 2944 2816 513 513 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"

# the fixture's encoder: per zoom the DEM warped onto that zoom's Web
# Mercator pixel grid (pixel i of a tile at (i + 0.5) / dim, as MapLibre
# samples it), bilinear at maxzoom, averaged above; voids and the tiles'
# parts past the DEM filled (FillNodata, then the mean); tiles without a
# valid sample not written. SHIFT (pixels) moves the grid east.
cat >"$T/enc.py" <<'PY'
import json, math, os, sys
import numpy as np
from osgeo import gdal
gdal.UseExceptions()
src, out, enc, z0, z1, dim, shift = sys.argv[1:8]
z0, z1, dim, shift = int(z0), int(z1), int(dim), float(shift)
H = math.pi * 6378137.0
d = gdal.Open(src)
g = d.GetGeoTransform()
w, n = g[0], g[3]
e, s = w + d.RasterXSize * g[1], n + d.RasterYSize * g[5]
def tile(lon, lat, z):
    k = 1 << z
    y = (1 - math.log(math.tan(math.pi / 4 + math.radians(lat) / 2)) / math.pi) / 2
    return int((lon + 180) / 360 * k), int(y * k)
for z in range(z0, z1 + 1):
    (tx0, ty0), (tx1, ty1) = tile(w, n, z), tile(e, s, z)
    size = 2 * H / (1 << z)
    mx0, my1 = -H + tx0 * size + shift * size / dim, H - ty0 * size
    ntx, nty = tx1 - tx0 + 1, ty1 - ty0 + 1
    v = gdal.Warp("", d, format="MEM", dstSRS="EPSG:3857",
        outputBounds=(mx0, my1 - nty * size, mx0 + ntx * size, my1),
        width=ntx * dim, height=nty * dim, outputType=gdal.GDT_Float64,
        resampleAlg="bilinear" if z == z1 else "average",
        srcNodata=-32768, dstNodata=-99999)
    b = v.GetRasterBand(1)
    valid = b.ReadAsArray() != -99999
    gdal.FillNodata(b, None, 16, 0)
    h = b.ReadAsArray()
    h[h == -99999] = h[valid].mean() if valid.any() else 0
    for j in range(nty):
        for i in range(ntx):
            sl = np.s_[j * dim:(j + 1) * dim, i * dim:(i + 1) * dim]
            if not valid[sl].any():
                continue
            if enc == "terrarium":
                q = np.rint((h[sl] + 32768) * 256).astype(np.int64)
            else:
                q = np.rint((h[sl] + 10000) * 10).astype(np.int64)
            m = gdal.GetDriverByName("MEM").Create("", dim, dim, 3, gdal.GDT_Byte)
            for c in range(3):
                m.GetRasterBand(c + 1).WriteArray(((q >> (16 - 8 * c)) & 255).astype(np.uint8))
            p = "%s/%d/%d/%d.png" % (out, z, tx0 + i, ty0 + j)
            os.makedirs(os.path.dirname(p), exist_ok=True)
            gdal.GetDriverByName("PNG").CreateCopy(p, m)
json.dump({"tilejson": "3.0.0", "name": "t_maplibre fixture", "scheme": "xyz",
    "tiles": ["{z}/{x}/{y}.png"], "minzoom": z0, "maxzoom": z1,
    "bounds": [w, s, e, n], "center": [(w + e) / 2, (s + n) / 2, z1],
    "encoding": enc, "tileSize": dim, "vertical_datum": "EGM96"},
    open(out + "/tiles.json", "w"), indent=1)
PY
# declare: the error the decoder measures, into a tree's tiles.json (what
# dem2rgb writes in its "error" field)
cat >"$T/declare.py" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[3])
import rgbdecode as r
tj, tiles = r.read_tree(sys.argv[1])
tj["error"] = [{"zoom": z, "max": m, "rms": q, "samples": k}
    for z, (k, m, q) in sorted(r.errors(tj, tiles, sys.argv[2]).items())]
json.dump(tj, open(sys.argv[1] + "/tiles.json", "w"), indent=1)
PY
run "the fixture: zooms 8 to 11, 512 px, Terrarium" \
    /usr/bin/python3 "$T/enc.py" "$T/srtm.tif" "$T/ref" terrarium 8 11 512 0 &&
    /usr/bin/python3 "$T/declare.py" "$T/ref" "$T/srtm.tif" "$TOP/tests/tools"

# the tree under test: TL_MAPLIBRE_TREE=DIR (one made of the same 513 x
# 513 cut elsewhere), else dem2rgb's, else the fixture
if [ -n "${TL_MAPLIBRE_TREE:-}" ]; then
	under=$TL_MAPLIBRE_TREE
	cp -R "$TL_MAPLIBRE_TREE" "$T/tree"
elif [ -x "$B/dem2rgb" ] && [ -z "${TL_RGB_FIXTURE:-}" ]; then
	under=dem2rgb
	run "dem2rgb exports the DEM" dem2rgb -q -Z 8 "$T/srtm.tif" "$T/tree"
	if [ -z "${TL_MAPLIBRE_PMTILES:-}" ]; then	# the PMTiles route too
		run "dem2rgb -o: the same tiles as one PMTiles archive" \
		    dem2rgb -q -Z 8 -o "$T/tree.pmtiles" "$T/srtm.tif" &&
		    TL_MAPLIBRE_PMTILES=$T/tree.pmtiles
	fi
else
	under=fixture
	cp -R "$T/ref" "$T/tree"
fi
echo "#   the tree: $under"

dec check "$T/tree" "$T/srtm.tif" >"$T/out" 2>"$T/err"
ok $? "the tiles: exactly those tiles.json's bounds and zooms imply with content"
sed 's/^/#   /' "$T/out" "$T/err"
dec claim "$T/tree" "$T/srtm.tif" >"$T/claim" 2>"$T/err"
ok $? "the error of the surface MapLibre draws, per zoom, within tiles.json's"
sed 's/^/#   /' "$T/claim" "$T/err"
if [ "$under" = dem2rgb ]; then	# the quadric chain against averaging
	dec error "$T/ref" "$T/srtm.tif" >"$T/ref.err"
	# ("zoom Z n N max M rms R" against "zoom Z measured max M rms R ...")
	awk 'NR == FNR { rms[$2] = $8; next }
	    ($2 in rms) { n++; if ($7 > 1.1 * rms[$2] + 1 / 256) {
		print "#   zoom " $2 ": rms " $7 " > 1.1 x the fixture'"'"'s " rms[$2]; bad++ } }
	    END { exit !(n > 0 && !bad) }' "$T/ref.err" "$T/claim"
	ok $? "dem2rgb's error per zoom no worse (RMS) than the averaging fixture's"
fi

# the check can fail: the same tiles half a pixel east, the true tiles.json
/usr/bin/python3 "$T/enc.py" "$T/srtm.tif" "$T/shift" terrarium 8 11 512 0.5
cp "$T/ref/tiles.json" "$T/shift/tiles.json"
fails "tiles half a pixel off: the error check fails" 1 'exceeds the declared' \
    dec claim "$T/shift" "$T/srtm.tif"

# 24 valid DEM samples on land, 6 at each of the 4 deepest zooms, in one
# 256 x 256 px view a zoom (the view's centre a sample, the others in
# its middle half): "lon lat camera-zoom centre-lon centre-lat zoom",
# the camera 2.5 zooms above the raster-dem zoom (MapLibre's terrain tiles
# are twice the source's size and load the DEM one zoom below them)
/usr/bin/python3 - "$T/srtm.tif" "$T/tree/tiles.json" >"$T/samples" <<'PY'
import json, math, sys
import numpy as np
from osgeo import gdal
d = gdal.Open(sys.argv[1])
z = d.ReadAsArray().astype(np.float64)
g = d.GetGeoTransform()
tj = json.load(open(sys.argv[2]))
rs = np.random.RandomState(24)
jj, ii = np.nonzero(z > 0)
lon, lat = g[0] + (ii + .5) * g[1], g[3] + (jj + .5) * g[5]
for dz in range(tj["maxzoom"] - 3, tj["maxzoom"] + 1):
    span = 256 / (512 * 2 ** (dz + 2.5)) * 360	# the view, degrees of lon
    while True:
        c = rs.randint(len(jj))
        k = np.nonzero((abs(lon - lon[c]) < span / 4) &
            (abs(lat - lat[c]) < span / 4 * math.cos(math.radians(lat[c]))))[0]
        if len(k) >= 6:
            break
    for s in [c] + list(rs.choice(k[k != c], 5, replace=False)):
        print("%.10f %.10f %.1f %.10f %.10f %d" % (lon[s], lat[s], dz + 2.5,
            lon[c], lat[c], dz))
PY
cut -d' ' -f1-5 "$T/samples" >"$T/views"

pm=${TL_MAPLIBRE_PMTILES:-}
[ -z "$pm" ] || [ -d "$JS/node_modules/pmtiles" ] || {
	echo "#   TL_MAPLIBRE_PMTILES: no npm pmtiles in tests/js"; pm=; }
s=$(date +%s)
# (a picture, OUT_SHOT: 640 x 360, its views holding the 256 x 256 ones)
TMPDIR=$T timeout -k 5 400 node "$JS/maplibre.js" --size 256x256 \
    --samples "$T/views" ${pm:+--pmtiles "$pm"} \
    ${OUT_SHOT:+--shot "$OUT_SHOT" --size 640x360} "$T/tree" \
    >"$T/out" 2>"$T/err"
st=$?
grep -v '^sample ' "$T/out" | sed 's/^/#   /'
sed 's/^/#   /' "$T/err"
echo "#   $(($(date +%s) - s)) s in the browser"
[ $st -eq 0 ] && grep -q '^tree: [1-9][0-9]* raster-dem responses' "$T/out"
ok $? "MapLibre loads the tree: no failed request, no console error"

# the samples against the decoder and the DEM; per route one line:
# samples, at the zoom asked, equal to the decoder, within the error
cat >"$T/cmp.py" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv[4])
import rgbdecode as r
tj, tiles = r.read_tree(sys.argv[1])
zs = r.zooms(tj, tiles)
lon, lat, h = r.dem_samples(sys.argv[2])
key = {("%.10f %.10f" % (a, b)): c for a, b, c in zip(lon, lat, h)}
err = r.errors(tj, tiles, sys.argv[2])
bound = {z: min(m, r.declared(tj).get(z, (m,))[0]) for z, (_, m, _) in err.items()}
want = {}
for l in open(sys.argv[3]):
    f = l.split()
    want["%.10f %.10f" % (float(f[0]), float(f[1]))] = int(f[5])
got = {}
for l in sys.stdin:
    f = l.split()
    if f[0] != "sample":
        continue
    k = "%.10f %.10f" % (float(f[2]), float(f[3]))
    ml, dz = float(f[5]), int(f[6])
    wx, wy = r.merc([float(f[2])], [float(f[3])])
    pred = zs[dz].surface_many(wx, wy)[0] if dz in zs else np.nan
    dem = key[k]
    ok = [dz == want[k], abs(ml - pred) <= 1e-3,
        abs(ml - dem) <= bound.get(dz, -1) + 1e-3]
    if not all(ok):
        print("#   %s %s: MapLibre %.4f from zoom %d (asked %d), decoder %.4f, "
            "DEM %.1f, bound %.3f" % (f[1], k, ml, dz, want[k], pred, dem,
            bound.get(dz, np.nan)))
    g = got.setdefault(f[1], [0, 0, 0, 0, 0.0])
    g[0] += 1
    for i in range(3):
        g[i + 1] += ok[i]
    g[4] = max(g[4], abs(ml - dem))
for name, g in got.items():
    print("%s %d %d %d %d %.3f" % (name, *g))
PY
/usr/bin/python3 "$T/cmp.py" "$T/tree" "$T/srtm.tif" "$T/samples" \
    "$TOP/tests/tools" <"$T/out" >"$T/cmp"
grep '^#' "$T/cmp"
read -r _ n atz same within worst <<EOF
$(grep '^tree ' "$T/cmp")
EOF
echo "#   tree: $n samples, $atz at the zoom asked, $same equal to the decoder, $within within the zoom's error (largest distance to the DEM $worst m)"
[ "${n:-0}" -eq 24 ] && [ "$atz" -eq 24 ]
ok $? "queryTerrainElevation at 24 DEM samples, read from tiles of the 4 deepest zooms"
[ "${same:-0}" -eq 24 ]
ok $? "MapLibre's heights those of the decoder's surface (pixel centres, bilinear)"
[ "${within:-0}" -eq 24 ]
ok $? "MapLibre's heights within the error of the zoom drawn of the DEM's"

if [ -n "$pm" ]; then
	grep -q '^pmtiles: [1-9][0-9]* raster-dem responses' "$T/out" &&
	    ! grep -q 'maplibre.js: pmtiles' "$T/err"
	ok $? "MapLibre loads the PMTiles archive: no failed request, no console error"
	[ "$(grep '^sample tree ' "$T/out" | cut -d' ' -f3-)" = \
	    "$(grep '^sample pmtiles ' "$T/out" | cut -d' ' -f3-)" ]
	ok $? "through the pmtiles protocol, the same heights at the same samples"
else
	ok 0 "the PMTiles route # SKIP no TL_MAPLIBRE_PMTILES archive"
fi
if [ -n "${OUT_SHOT:-}" ]; then
	[ "$(head -c 4 "$OUT_SHOT" | tail -c 3)" = PNG ]
	ok $? "a picture of the hillshaded terrain in $OUT_SHOT"
fi

! ps -eo args | grep -q "[/]$(basename "$T")/playwright"
ok $? "no browser left running"
done_testing
