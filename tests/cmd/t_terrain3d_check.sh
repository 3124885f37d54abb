# t_terrain3d_check - tilecheck --terrain on the 3D Tiles terrain profile
# (vgis2terrain -f 3dtiles, terrain-3dtiles(5)), read by its own reader
# (verify/t3c_*.c): on an ellipsoidal crop of N48W125 with sea voids
# (geographic) and on a UTM 10N warp of a land crop, tilecheck --terrain
# --dem passes: no tile over E_L = 78271.52 m / 2^L (+1 mm) and the bound
# not vacuous (a tile at 0.45 E_L or more at every level whose E_L / 2 is
# within the DEM's relief, 5 levels or more); its vertices and triangles
# are the quantized-mesh export's (the --dump checksums, levels 6 on);
# hostile tilesets fail, exit 1, naming the file: a glb whose buffer is
# truncated, an index out of range, an edge list short of a vertex, a
# clockwise triangle, a triangle left out, a subtree bit flipped, a
# missing tile, a tile no subtree announces.
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3

# per level "  E_L X m, ... error / E_L over N tiles: max M ... (largest
# D m ...": none over 1 (tilecheck fails past E_L + 1 mm), and at 0.45 or
# more at every level whose E_L / 2 is within the relief (level 0's
# largest error; coarser levels cannot come near their bound)
validated() {
	awk '/error \/ E_L over/ { n++
		for (i = 1; i <= NF; i++) {
			if ($i == "max") m = $(i + 1)
			if ($i == "(largest") d = $(i + 1)
		}
		if (n == 1) rel = d
		if (m > 1) bad++
		if ($2 / 2 <= rel) { want++; if (m >= 0.45) near++ }
	} END { printf "#   %d levels, %d within the relief, %d at 0.45 E_L or more\n",
	    n, want, near
	    exit !(n > 0 && !bad && want >= 5 && near == want) }' "$1"
}

# 257 x 257 samples of N48W125 at 1", 39 % sea voids, ellipsoidal
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 3000 1700 257 257 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
dem2vgis -q "$T/geo.tif" "$T/pyr" 2>/dev/null
run "voids: -f 3dtiles" vgis2terrain -q -f 3dtiles -j 2 "$T/pyr" "$T/t3"
run "voids: -f qm" vgis2terrain -q -j 2 "$T/pyr" "$T/qm"
tilecheck --terrain --dem "$T/geo.tif" "$T/t3" >"$T/check" 2>&1
ok $? "voids: tilecheck --terrain --dem passes on the 3D Tiles profile"
grep -E '^(terrain|  E_L|violations)' "$T/check" | sed 's/^/#   /'
grep -q '^  E_L 78271.5 m' "$T/check"; ok $? "E_0 is the profile's 78271.52 m"
validated "$T/check"; ok $? "voids: no tile over E_L, every level within the relief at 0.45 E_L or more"

# the same meshes as quantized-mesh, read by two decoders
tilecheck --terrain --dump "$T/t3" >"$T/d3" 2>&1
tilecheck --terrain --dump "$T/qm" >"$T/dq" 2>&1
cut -d' ' -f1-5 "$T/d3" >"$T/a"; cut -d' ' -f1-5 "$T/dq" >"$T/b"
[ -s "$T/a" ] && cmp -s "$T/a" "$T/b"
ok $? "the same tiles, vertices and triangles as -f qm ($(wc -l <"$T/a") tiles)"
awk -F/ '$1 >= 6' "$T/d3" >"$T/a"; awk -F/ '$1 >= 6' "$T/dq" >"$T/b"
[ -s "$T/a" ] && cmp -s "$T/a" "$T/b"
ok $? "levels 6 on: the vertices quantised back and the indices are the quantized-mesh tiles'"

# a UTM 10N warp at 30 m of a void-free land crop (513 x 513 samples,
# 0 - 800 m), cut inside its footprint (as t_vgis2terrain's); the
# terrain covers the whole footprint: every valid sample is measured
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1696 2176 513 513 \
    "$DATA/N48W125.hgt" "$T/land.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/land.tif" "$T/lande.tif"
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r bilinear \
    -te 388000 5347000 396000 5360000 "$T/lande.tif" "$T/utm.tif"
dem2vgis -q "$T/utm.tif" "$T/utm.pyr" 2>/dev/null
run "UTM: -f 3dtiles" vgis2terrain -q -f 3dtiles -j 2 "$T/utm.pyr" "$T/u3"
tilecheck --terrain --dem "$T/utm.tif" "$T/u3" >"$T/ucheck" 2>&1
ok $? "UTM: tilecheck --terrain --dem: every valid sample, no violation"
grep -E '^(terrain|  E_L|violations|r[01]/)' "$T/ucheck" | sed 's/^/#   /'
validated "$T/ucheck"; ok $? "UTM: no tile over E_L, every level within the relief at 0.45 E_L or more"

# --- hostile tilesets: exit 1, the file named ---------------------------
leaf=$(cd "$T/t3" && find . -path './r*/14/*' -name '*.glb' | sort | head -1)
leaf=${leaf#./}
cat >"$T/glb.py" <<'PY'
"""glb.py FILE ACTION: rewrites a glb (JSON and BIN chunks repacked)."""
import json, struct, sys
path, act = sys.argv[1], sys.argv[2]
b = open(path, "rb").read()
jl = struct.unpack_from("<I", b, 12)[0]
g = json.loads(b[20:20 + jl])
bl = struct.unpack_from("<I", b, 20 + jl)[0]
bn = bytearray(b[28 + jl:28 + jl + bl])
prim = g["meshes"][0]["primitives"][0]
def view(acc):
    a = g["accessors"][acc]
    return g["bufferViews"][a["bufferView"]]["byteOffset"] + a.get("byteOffset", 0)
if act == "truncate":          # the BIN chunk 64 bytes short
    bn = bn[:len(bn) - 64]
elif act == "index":           # triangle 0's first index past the vertices
    o = view(prim["indices"])
    n = g["accessors"][prim["attributes"]["POSITION"]]["count"]
    struct.pack_into("<H", bn, o, n + 7)
elif act == "edge":            # the left list one vertex short
    g["accessors"][prim["extensions"]["CESIUM_tile_edges"]["left"]]["count"] -= 1
elif act == "drop":            # the last triangle left out
    g["accessors"][prim["indices"]]["count"] -= 3
elif act == "winding":         # triangle 0 turned clockwise
    o = view(prim["indices"])
    i0, i1 = struct.unpack_from("<HH", bn, o)
    struct.pack_into("<HH", bn, o, i1, i0)
js = json.dumps(g).encode()
js += b" " * (-len(js) % 4)
bn += b"\0" * (-len(bn) % 4)
out = (struct.pack("<4sII", b"glTF", 2, 28 + len(js) + len(bn)) +
       struct.pack("<I4s", len(js), b"JSON") + js +
       struct.pack("<I4s", len(bn), b"BIN\0") + bytes(bn))
open(path, "wb").write(out)
PY
# hostile NAME ACTION PATTERN: a copy of the voids' tileset with ACTION
# done to the leaf's glb; tilecheck exits 1, the leaf named, PATTERN said
hostile() {
	rm -rf "$T/h" && cp -r "$T/t3" "$T/h"
	$PY "$T/glb.py" "$T/h/$leaf" "$2"
	tilecheck --terrain "$T/h" >"$T/hout" 2>&1
	[ $? -eq 1 ] && grep -Eq "^$leaf: $3" "$T/hout"
	ok $? "$1: exit 1, $(grep -E "^$leaf: " "$T/hout" | head -1 | cut -c1-90)"
}
hostile "a glb whose buffer is truncated" truncate "decode: truncated"
hostile "an index out of range" index "index: triangle 0"
hostile "an edge list one vertex short" edge "edges: vertex [0-9]+ .* on the left edge but not in"
hostile "a clockwise triangle" winding "winding: triangle 0"
hostile "a triangle left out" drop "hole: [0-9]+ edges inside the tile belong to one triangle"

# a subtree's bit flipped: the last available tile of the leaf's subtree
# made unavailable; its glb is then a file no subtree announces
rm -rf "$T/h" && cp -r "$T/t3" "$T/h"
sub=$($PY - "$T/h" "$leaf" <<'PY'
import json, os, struct, sys
d, leaf = sys.argv[1], sys.argv[2]
r, z, x, y = leaf[:-4].split("/")
z, x, y = int(z[0:]), int(x), int(y)
s = 12                       # the subtree holding level 14 (subtreeLevels 6)
px, py = x >> (z - s), y >> (z - s)
p = os.path.join(d, r, str(s), str(px), str(py) + ".subtree")
b = bytearray(open(p, "rb").read())
jl = struct.unpack_from("<Q", b, 8)[0]
j = json.loads(b[24:24 + jl])
v = j["bufferViews"][j["tileAvailability"]["bitstream"]]
o = 24 + jl + v["byteOffset"]
last = max(i for i in range(8 * v["byteLength"]) if b[o + i // 8] >> (i % 8) & 1)
b[o + last // 8] ^= 1 << (last % 8)
open(p, "wb").write(b)
print(os.path.relpath(p, d))
PY
)
tilecheck --terrain "$T/h" >"$T/hout" 2>&1
st=$?
grep -E 'unannounced|subtree' "$T/hout" | head -3 | sed 's/^/#   /'
[ $st -eq 1 ] && grep -q "^tileset: tileset: $sub: " "$T/hout" &&
    grep -Eq '^r[01]/[0-9/]+\.glb: unannounced: a file no subtree announces' "$T/hout"
ok $? "a subtree bit flipped: exit 1, $sub and the glb it no longer announces named"

rm -rf "$T/h" && cp -r "$T/t3" "$T/h" && rm "$T/h/$leaf"
tilecheck --terrain "$T/h" >"$T/hout" 2>&1
[ $? -eq 1 ] && grep -q "^$leaf: missing: announced by its subtree" "$T/hout"
ok $? "a missing tile: exit 1, $leaf named"

rm -rf "$T/h" && cp -r "$T/t3" "$T/h"
z=${leaf#*/}; z=${z%%/*}; x=${leaf#*/*/}; x=${x%%/*}; r=${leaf%%/*}
mkdir -p "$T/h/$r/$z/$((x + 40))"
cp "$T/h/$leaf" "$T/h/$r/$z/$((x + 40))/5.glb"
tilecheck --terrain "$T/h" >"$T/hout" 2>&1
[ $? -eq 1 ] && grep -q "^$r/$z/$((x + 40))/5.glb: unannounced" "$T/hout"
ok $? "a tile no subtree announces: exit 1, $r/$z/$((x + 40))/5.glb named"

rm -rf "$T/h" && cp -r "$T/t3" "$T/h" && rm "$T/h/tileset.json"
fails "no tileset.json (nor layer.json): cannot check, exit 3" 3 \
    'layer.json' tilecheck --terrain "$T/h"
done_testing
