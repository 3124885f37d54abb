# t_terrain3d - vgis2terrain -f 3dtiles, the 3D Tiles terrain profile
# (terrain-3dtiles(5)) on an ellipsoidal crop of N48W125: every glb passes
# the Khronos glTF validator with no error, tileset.json the 3D Tiles 1.1
# schema; an independent reader (tests/tools/t3t_check.py) parses every
# subtree and finds its availability exactly the files present, each glb
# one primitive within its tile's rectangle, heights and bounding sphere
# (TILE_* metadata), its CESIUM_tile_edges exactly the edge vertices in
# the order the skirts walk them; CesiumJS's own ImplicitSubtree
# (tests/js/t3t_subtrees.mjs) agrees; both readers fail on a missing tile; -j 1 and -j 2 give the same bytes; the
# same meshes as -f qm (same triangle counts per level).
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
JS=$TOP/tests/js
# 257x257 void-free SRTM samples (coast and hills, 0-500 m), ellipsoidal
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1696 2176 257 257 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
dem2vgis "$T/geo.tif" "$T/pyr" 2>/dev/null
run "vgis2terrain -f 3dtiles -j 2" vgis2terrain -f 3dtiles -j 2 "$T/pyr" \
    "$T/t3"
cp "$T/err" "$T/rep3"
n=$(find "$T/t3" -name '*.glb' | wc -l)
[ "$n" -gt 20 ] && [ -f "$T/t3/tileset.json" ]
ok $? "tileset.json and $n glbs"
[ -z "$(find "$T/t3" -name '*.terrain' -o -name layer.json)" ]
ok $? "no quantized-mesh files"

find "$T/t3" -name '*.glb' | sort >"$T/glbs"
# shellcheck disable=SC2046
run "every glb passes the glTF validator with 0 errors" \
    node "$JS/validate.js" glb $(cat "$T/glbs")
run "tileset.json passes the 3D Tiles 1.1 schema" \
    node "$JS/validate.js" tileset "$T/t3/tileset.json"
run "every subtree parses; availability is exactly the files; glbs agree with their TILE_* metadata and edges" \
    $PY "$TOP/tests/tools/t3t_check.py" "$T/t3"
sed 's/^/#   /' "$T/out"
run "CesiumJS's ImplicitSubtree reads every subtree: availability is exactly the files, TILE_* metadata present" \
    node "$JS/t3t_subtrees.mjs" "$T/t3"
sed 's/^/#   /' "$T/out"
grep -q '"subdivisionScheme":"QUADTREE"' "$T/t3/tileset.json" &&
    grep -q TILE_HORIZON_OCCLUSION_POINT "$T/t3/tileset.json" &&
    grep -q '"geometricError":78271.52' "$T/t3/tileset.json"
ok $? "implicit quadtrees, the TILE_* semantics, level 0's error 78271.52 m"

# the reader can fail: a tile announced but missing, a file unannounced
cp -r "$T/t3" "$T/bad"
rm "$(sed -n 5p "$T/glbs" | sed "s|$T/t3|$T/bad|")"
$PY "$TOP/tests/tools/t3t_check.py" "$T/bad" >"$T/out" 2>&1
[ $? -eq 1 ] && grep -q "availability 1, file False" "$T/out"
ok $? "the reader finds a missing tile"
node "$JS/t3t_subtrees.mjs" "$T/bad" >"$T/out" 2>&1
[ $? -eq 1 ] && grep -q "available true" "$T/out"
ok $? "and so does CesiumJS's reader"
cp -r "$T/t3" "$T/bad2"
cp "$(sed -n 5p "$T/glbs")" "$T/bad2/r0/0/0/9.glb"
$PY "$TOP/tests/tools/t3t_check.py" "$T/bad2" >"$T/out" 2>&1
[ $? -eq 1 ]; ok $? "the reader finds an unannounced file"

# the same meshes as quantized-mesh: triangles per level
run "vgis2terrain -f qm" vgis2terrain -j 2 "$T/pyr" "$T/qm"
grep -o 'level [0-9]*: [0-9]* tiles, [0-9]* triangles' "$T/err" >"$T/a"
grep -o 'level [0-9]*: [0-9]* tiles, [0-9]* triangles' "$T/rep3" >"$T/b"
[ -s "$T/a" ] && cmp -s "$T/a" "$T/b"; ok $? "the same tiles and triangles as -f qm"

run "-j 1" vgis2terrain -q -f 3dtiles -j 1 "$T/pyr" "$T/one"
diff -r "$T/t3" "$T/one" >/dev/null; ok $? "-j 1 and -j 2 are byte-identical"
run "an existing 3D Tiles terrain is replaced" \
    vgis2terrain -q -f 3dtiles -j 2 "$T/pyr" "$T/one"
diff -r "$T/t3" "$T/one" >/dev/null; ok $? "and the rerun is byte-identical"
mkdir "$T/m3d" && echo "{}" >"$T/m3d/tileset.json"
fails "a tileset.json of another kind (vgis2tiles): not replaced" 1 \
    "not a terrain tileset" vgis2terrain -q -f 3dtiles "$T/pyr" "$T/m3d"
fails "an unknown format: usage, exit 2" 2 usage \
    vgis2terrain -f b3dm "$T/pyr" "$T/x"
fails "-z with -f 3dtiles: usage, exit 2" 2 usage \
    vgis2terrain -z -f 3dtiles "$T/pyr" "$T/x"
done_testing
