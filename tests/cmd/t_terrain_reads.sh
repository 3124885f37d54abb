# t_terrain_reads - vgis2terrain's sweep of the deep levels (each tile
# made with its ancestor, so that a level-0 block is read once for all
# of them) writes what the levels made one by one write: an ellipsoidal
# 700x700 crop of N48W125 (1", sea voids over 43 % of it: levels 10 to
# 14 swept, from 2 x 2 ancestors or more in serpentine rows) with a 5.5
# km spike, so that swept levels hold only at a later try and are made
# again; -j 1 and -j 2 identical, and both identical to the plan's jobs
# (run by make: every level made range by range at its own tries). The
# same crop warped to UTM 10N (nearest, the spike kept): a projected
# sweep keeps an ancestor's tiles of every level and measures them in
# one pass over its blocks (tr_batch_own), and its selection skips the
# squares far from a tile (tr_far.c); the same checks.
. "$(dirname "$0")/../lib.sh"
quick_skip "the terrain sweep against the plan's jobs"
PY=/usr/bin/python3

gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1500 1500 700 700 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
$PY "$TOP/tests/tools/spike.py" "$T/geo.tif" "$T/spike.tif" 500 400
dem2vgis -q "$T/spike.tif" "$T/pyr"; ok $? "a pyramid of the crop with a spike"
run "vgis2terrain -j 1" vgis2terrain -j 1 "$T/pyr" "$T/j1"
cp "$T/err" "$T/err1"
later=$(grep -c 'level 1[0-4]: .*try [2-9]' "$T/err1")
[ "$(grep -c 'level 1[0-4]:' "$T/err1")" -eq 5 ] && [ "$later" -ge 1 ]
ok $? "levels 10 to 14 made, $later of them held only at a later try"
run "vgis2terrain -j 2" vgis2terrain -j 2 "$T/pyr" "$T/j2"
cmp -s "$T/err1" "$T/err" && diff -r "$T/j1" "$T/j2" >/dev/null
ok $? "-j 1 and -j 2: the same tiles, layer.json and report"
vgis2terrain --plan "$T/plan" --part-samples 400000 "$T/pyr" "$T/jobs" \
    2>/dev/null && make -s -C "$T/plan" -j2 >/dev/null 2>&1 &&
    diff -r "$T/j1" "$T/jobs" >/dev/null
ok $? "the plan's jobs (levels one by one): the same tiles and layer.json"

gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r near "$T/spike.tif" "$T/utm.tif"
dem2vgis -q "$T/utm.tif" "$T/upyr"; ok $? "UTM: a pyramid of the warp"
run "UTM: vgis2terrain -j 1" vgis2terrain -j 1 "$T/upyr" "$T/u1"
cp "$T/err" "$T/uerr1"
[ "$(grep -c 'level 1[0-4]: .*try [2-9]' "$T/uerr1")" -ge 1 ]
ok $? "UTM: a deep level held only at a later try"
run "UTM: vgis2terrain -j 2" vgis2terrain -j 2 "$T/upyr" "$T/u2"
cmp -s "$T/uerr1" "$T/err" && diff -r "$T/u1" "$T/u2" >/dev/null
ok $? "UTM: -j 1 and -j 2: the same tiles, layer.json and report"
vgis2terrain --plan "$T/uplan" --part-samples 100000 "$T/upyr" "$T/ujobs" \
    2>/dev/null && make -s -C "$T/uplan" -j2 >/dev/null 2>&1 &&
    diff -r "$T/u1" "$T/ujobs" >/dev/null
ok $? "UTM: the plan's jobs (levels one by one): the same tiles and layer.json"
done_testing
