# t_vgis2tiles - the 3D Tiles export: every glb passes the Khronos glTF
# validator, tileset.json the 3D Tiles 1.1 schema; every tile's mesh,
# decoded and taken back to the DEM's CRS by a reader of the test's own
# (tests/tools/tiles3d_truth.py), lies within its geometricError of every
# valid DEM sample under it, and some tile comes within half of it;
# reruns and thread counts give the same bytes; datums, usage, failures.
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
JS=$TOP/tests/js
# a projected DEM (UTM) and a geographic one with voids (SRTM, EGM96
# heights made ellipsoidal by PROJ); 385 samples: 3 levels, 14 tiles
gdal_translate -q -srcwin 400 100 385 385 "$DATA/bigtujunga.tif" "$T/utm.tif"
gdal_translate -q -srcwin 700 300 257 257 "$DATA/bigtujunga.tif" "$T/q3d.tif"
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 2700 1650 385 385 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
# and QEM-3D levels (vertices offset in x, y), 257 samples: 5 tiles
for d in utm geo q3d; do
	o=; [ $d = q3d ] && o=-3
	dem2vgis $o "$T/$d.tif" "$T/$d.pyr" 2>/dev/null
	# tau0 3 m: fewer triangles for the truth check to walk
	run "$d: vgis2tiles" vgis2tiles -q -j 2 -t 3 "$T/$d.pyr" "$T/$d.3d"
	ls "$T/$d.3d"/*/*.glb >"$T/glbs"
	run "$d: every glb passes the glTF validator with 0 errors" \
	    node "$JS/validate.js" glb $(cat "$T/glbs")
	run "$d: tileset.json passes the 3D Tiles 1.1 schema" \
	    node "$JS/validate.js" tileset "$T/$d.3d/tileset.json"
	run "$d: contents exist, errors never grow down the tree, every mesh within its error of the DEM (1 mm), not vacuously" \
	    $PY "$TOP/tests/tools/tiles3d_truth.py" "$T/$d.tif" "$T/$d.3d"
	grep -h "tiles, largest" "$T/out" | sed 's/^/#   /'
done
n=$(grep -c '"region"' "$T/geo.3d/tileset.json")
[ "$n" -eq 14 ] && ! grep -q '"box"' "$T/geo.3d/tileset.json"
ok $? "geographic DEM: regions ($n)"
n=$(grep -c '"box"' "$T/utm.3d/tileset.json")
[ "$n" -eq 14 ]; ok $? "projected DEM: boxes ($n)"

# same bytes: a rerun, one thread
run "rerun -j 2" vgis2tiles -q -j 2 -t 3 "$T/utm.pyr" "$T/again.3d"
run "rerun -j 1" vgis2tiles -q -j 1 -t 3 "$T/utm.pyr" "$T/one.3d"
diff -r "$T/utm.3d" "$T/again.3d" >/dev/null; ok $? "a rerun is byte-identical"
diff -r "$T/utm.3d" "$T/one.3d" >/dev/null; ok $? "-j 1 and -j 2 are byte-identical"
run "an existing tileset is replaced" vgis2tiles -q "$T/utm.pyr" "$T/one.3d"

# datums: orthometric refused with the way out, -H ellipsoid accepted,
# unknown used with a warning
dem2vgis "$T/srtm.tif" "$T/egm.pyr" 2>/dev/null
fails "EGM96 heights: refused, saying how to rebuild" 1 \
    'EPSG:5773.*dem2vgis -H ellipsoid' vgis2tiles "$T/egm.pyr" "$T/egm.3d"
[ ! -e "$T/egm.3d" ]; ok $? "nothing written for a refusal"
dem2vgis -H ellipsoid "$T/srtm.tif" "$T/ell.pyr" 2>/dev/null
vgis2tiles "$T/ell.pyr" "$T/ell.3d" 2>"$T/err"
[ $? -eq 0 ] && ! grep -q warn "$T/err" && ! grep -q unknown "$T/err"
ok $? "dem2vgis -H ellipsoid: exported without a warning"
vgis2tiles "$T/geo.pyr" "$T/geo2.3d" 2>"$T/err"
grep -q "vertical datum unknown" "$T/err"; ok $? "unknown datum: a warning"

# usage and failures
fails "no operands: usage, exit 2" 2 usage vgis2tiles
fails "-j 0: exit 2" 2 '-j 0' vgis2tiles -j 0 "$T/utm.pyr" "$T/x"
fails "-t x: exit 2" 2 '-t x' vgis2tiles -t x "$T/utm.pyr" "$T/x"
vgis2tiles --help | grep -q '^usage: vgis2tiles'; ok $? "--help"
vgis2tiles -V >/dev/null; ok $? "-V"
mkdir "$T/notpyr"
fails "a directory that is no pyramid: exit 1, a message" 1 \
    '^vgis2tiles: .*notpyr' vgis2tiles "$T/notpyr" "$T/x"
fails "an OUTDIR that is no tileset: not replaced" 1 'not a tileset' \
    vgis2tiles "$T/utm.pyr" "$T/notpyr"

# killed: no OUTDIR, no temporary (every vertex, one thread: long enough)
dem2vgis "$DATA/bigtujunga.tif" "$T/big.pyr" 2>/dev/null
vgis2tiles -q -j 1 -t 0 "$T/big.pyr" "$T/killed.3d" &
pid=$!
if mid_run $pid "$T/killed.3d"; then
	kill -TERM $pid; kill -CONT $pid; wait $pid
	[ ! -e "$T/killed.3d" ] && [ -z "$(ls -a "$T" | grep killed)" ]
	ok $? "killed: no OUTDIR and no temporary left"
else
	wait $pid; skip "the run ended before the kill"
fi
done_testing
