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
# reads PYR OUT SAMPLES LABEL: -j 1 into OUT1 (its report in OUT.err),
# then -j 2 and the plan's jobs the same
reads() {
	run "${4}vgis2terrain -j 1" vgis2terrain -j 1 "$1" "$2.1"
	cp "$T/err" "$2.err"
	run "${4}vgis2terrain -j 2" vgis2terrain -j 2 "$1" "$2.2"
	cmp -s "$2.err" "$T/err" && diff -r "$2.1" "$2.2" >/dev/null
	ok $? "${4}-j 1 and -j 2: the same tiles, layer.json and report"
	vgis2terrain --plan "$2.plan" --part-samples "$3" "$1" "$2.jobs" \
	    2>/dev/null && make -s -C "$2.plan" -j2 >/dev/null 2>&1 &&
	    diff -r "$2.1" "$2.jobs" >/dev/null
	ok $? "${4}the plan's jobs (levels one by one): the same tiles and layer.json"
}
reads "$T/pyr" "$T/j" 400000 ""
later=$(grep -c 'level 1[0-4]: .*try [2-9]' "$T/j.err")
[ "$(grep -c 'level 1[0-4]:' "$T/j.err")" -eq 5 ] && [ "$later" -ge 1 ]
ok $? "levels 10 to 14 made, $later of them held only at a later try"

gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r near "$T/spike.tif" "$T/utm.tif"
dem2vgis -q "$T/utm.tif" "$T/upyr"; ok $? "UTM: a pyramid of the warp"
reads "$T/upyr" "$T/u" 100000 "UTM: "
[ "$(grep -c 'level 1[0-4]: .*try [2-9]' "$T/u.err")" -ge 1 ]
ok $? "UTM: a deep level held only at a later try"
done_testing
