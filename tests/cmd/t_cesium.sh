# t_cesium - a tileset of vgis2tiles in a real browser: CesiumJS (npm
# cesium, tests/js) in headless Chromium with software WebGL, served from
# a free localhost port by tests/js/cesium.js, loads it, waits until every
# tile it wants is loaded and checks each picture: no console errors, the
# terrain where the projected tileset is, and, at views where levels
# meet, no background pixel enclosed by terrain (no cracks). The same
# views with the skirts discarded by the page's shader must show cracks:
# the check can fail.
. "$(dirname "$0")/../lib.sh"

browser_test "CesiumJS in Chromium"
JS=$TOP/tests/js
# 1025x1025 void-free SRTM samples of southern Vancouver Island (relief
# 0-800 m), ellipsoidal: 4 levels, 85 tiles
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1696 2176 1025 1025 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
/usr/bin/python3 "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
dem2vgis "$T/geo.tif" "$T/pyr" 2>/dev/null
run "vgis2tiles" vgis2tiles -q -j 2 "$T/pyr" "$T/tiles"

# views heading,pitch,range (root bounding-sphere radii)[,least levels]:
# from above and oblique, the whole tileset in the frame (its projected
# bounding box checked); low and close, levels meeting
views="0,-90,2.5 30,-30,1.2 0,-20,0.4,2 45,-15,0.3,2"
# the browser's profile under $T: nothing of it may outlive a run
browser() {
	TMPDIR=$T timeout -k 5 150 node "$JS/cesium.js" "$@"
}
s=$(date +%s)
# shellcheck disable=SC2086
browser --shot "$T/shot.png" "$T/tiles" $views >"$T/out" 2>"$T/err"
ok $? "CesiumJS loads the tileset; no console errors; terrain where its bounding box projects; >= 2 levels drawn and no cracks at the close views"
sed 's/^/#   /' "$T/out" "$T/err"
echo "#   $(($(date +%s) - s)) s"
[ "$(head -c 4 "$T/shot.png" | tail -c 3)" = PNG ]
ok $? "a PNG screenshot"

# shellcheck disable=SC2086
fails "skirts discarded: the crack check fires" 1 \
    'background pixels enclosed by terrain \(cracks\)' \
    browser --noskirts "$T/tiles" ${views#* * }
grep cracks "$T/err" | sed 's/^/#   /'

! ps -eo args | grep -q "[/]$(basename "$T")/playwright"
ok $? "no browser left running"
done_testing
