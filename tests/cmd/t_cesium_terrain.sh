# t_cesium_terrain - quantized-mesh terrain of vgis2terrain as CesiumJS's
# globe terrain: CesiumJS (npm cesium, tests/js) in headless Chromium
# with software WebGL, the tileset served as plain files from a free
# localhost port by tests/js/terrain.js, CesiumTerrainProvider.fromUrl,
# a checkerboard draped through SingleTileImageryProvider. Checked: every
# level from 0 to maxzoom fetched, no failed request, no console error;
# sampleTerrainMostDetailed at 24 DEM samples within the deepest level's
# E_L of the DEM's ellipsoidal height; the checkerboard on the terrain
# where its rectangle projects; from low views where levels meet, no
# background pixel enclosed by terrain (no crack), and the same views
# with globe.showSkirts = false do show cracks: the check can fail.
# OUT_SHOT=FILE.png: also a picture of the draped terrain, lit, there.
. "$(dirname "$0")/../lib.sh"

browser_test "CesiumJS terrain in Chromium"
JS=$TOP/tests/js
# 513x513 SRTM samples of southern Vancouver Island (relief -6 to
# 1061 m, 747 voids, which the pyramid fills), heights made ellipsoidal
# by PROJ: the DEM the heights are checked against; levels 0 to 14
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 2944 2816 513 513 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
/usr/bin/python3 "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
dem2vgis "$T/geo.tif" "$T/pyr" 2>/dev/null
run "vgis2terrain exports the pyramid" vgis2terrain -q -j 2 "$T/pyr" "$T/qm"

# the DEM's rectangle (the checkerboard's) and 24 samples on land, none
# a void (lon lat ellipsoidal height, at the samples' centres), fixed seed
/usr/bin/python3 - "$T/geo.tif" "$T/samples" >"$T/rect" <<'PY'
import sys
import numpy as np
from osgeo import gdal
d = gdal.Open(sys.argv[1])
z = d.ReadAsArray().astype(np.float64)
g = d.GetGeoTransform()
h, w = z.shape
print("%.12f,%.12f,%.12f,%.12f" % (g[0], g[3] + h * g[5], g[0] + w * g[1], g[3]))
jj, ii = np.nonzero(np.isfinite(z) & (z > 0))
k = np.random.RandomState(23).choice(len(jj), 24, replace=False)
with open(sys.argv[2], "w") as f:
    for j, i in zip(jj[k], ii[k]):
        f.write("%.10f %.10f %.4f\n" % (g[0] + (i + .5) * g[1],
                                        g[3] + (j + .5) * g[5], z[j, i]))
PY
rect=$(cat "$T/rect")

# views lon,lat,height,heading,pitch[,least levels]: from 30 km above,
# the whole DEM (the imagery's view); low (700-800 m above the
# ellipsoid, over land below 200 m) and oblique with the horizon in the
# frame, levels 7 to 15 meeting
top=-124.1111,48.1467,30000,0,-90
low="-124.0756,48.20,700,200,-12,3 -124.15444,48.16222,800,90,-12,3"
# the browser's profile under $T: nothing of it may outlive a run
browser() {
	TMPDIR=$T timeout -k 5 "${limit:-150}" node "$JS/terrain.js" "$@"
}
s=$(date +%s)
# shellcheck disable=SC2086
browser --imagery --samples "$T/samples" --shot "$T/shot.png" "$T/qm" "$rect" \
    $top $low >"$T/out" 2>"$T/err"
st=$?
grep -v '^sample ' "$T/out" | sed 's/^/#   /'
sed 's/^/#   /' "$T/err"
echo "#   $(($(date +%s) - s)) s"
[ $st -ne 2 ] && grep -q '^tiles fetched' "$T/out" &&
    ! grep -Eq 'console error|page error|request failed|terrain.js: [0-9]{3} |no tile fetched' "$T/err"
ok $? "every level from 0 to maxzoom fetched; no failed request; no console error"
grep -q '^sampleTerrainMostDetailed: 24 samples' "$T/out" &&
    ! grep -q 'off by' "$T/err"
ok $? "sampleTerrainMostDetailed at 24 DEM samples within the deepest level's E_L"
# the check sees a datum: CesiumJS's heights against the DEM's
# orthometric (EGM96) heights, the geoid here some 20 m below the
# ellipsoid, are off by more than E_L at every sample
/usr/bin/python3 - "$T/srtm.tif" "$T/out" >"$T/ortho" <<'PY'
import sys
from osgeo import gdal
d = gdal.Open(sys.argv[1])
z = d.ReadAsArray()
g = d.GetGeoTransform()
n = off = 0
for line in open(sys.argv[2]):
    f = line.split()
    if f[0] != "sample":
        continue
    lon, lat, h = float(f[1]), float(f[2]), float(f[7])
    i, j = int((lon - g[0]) / g[1]), int((lat - g[3]) / g[5])
    n += 1
    off += abs(h - float(z[j, i])) > 77067.34 / 2 ** int(f[5])
print(n, off)
PY
read -r n off <"$T/ortho"
echo "#   against orthometric heights: $off of $n samples off by more than E_L"
[ "$n" -eq 24 ] && [ "$off" -eq 24 ]
ok $? "the same samples against the DEM's orthometric heights: all off by more than E_L"
grep -q "checkerboard .* of the rectangle's projection" "$T/out" &&
    ! grep -Eq 'checkerboard on|draped rectangle|colours missing' "$T/err"
ok $? "the draped checkerboard seen on the terrain, where its rectangle projects"
[ "$(grep -c ' 0 holes$' "$T/out")" -eq 3 ] &&
    ! grep -Eq 'cracks|no background|levels drawn, <' "$T/err"
ok $? "no crack from the low views where >= 3 levels meet"
[ $st -eq 0 ]; ok $? "terrain.js: every check passed"
[ "$(head -c 4 "$T/shot.png" | tail -c 3)" = PNG ]
ok $? "a PNG screenshot"

# shellcheck disable=SC2086
fails "globe.showSkirts = false: the crack check fires" 1 \
    'background pixels enclosed by terrain \(cracks\)' \
    browser --noskirts "$T/qm" "$rect" $low
grep cracks "$T/err" | sed 's/^/#   /'

if [ -n "${OUT_SHOT:-}" ]; then	# for the README: lit, low, oblique
	limit=300 browser --lit --size 800x450 --shot "$OUT_SHOT" "$T/qm" \
	    "$rect" -124.0756,48.20,1100,200,-10 >"$T/out" 2>"$T/err"
	ok $? "a picture of the draped terrain in $OUT_SHOT"
fi

! ps -eo args | grep -q "[/]$(basename "$T")/playwright"
ok $? "no browser left running"
done_testing
