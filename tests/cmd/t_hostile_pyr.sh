# t_hostile_pyr - hostile pyramids, made from a real one (dem2vgis -H
# ellipsoid on a cut of N44W072.hgt): every reader of a pyramid (tilecheck,
# vgis2tiles, tileplay --shot) refuses each with exit 1, the field or the
# block named, at once (a FIFO never waited on: each run under timeout 20),
# and leaves nothing behind. Then the windowed reads of tilepack: a vertex
# map damaged inside a row is refused, the row named.
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
gdal_translate -q -srcwin 0 0 300 260 "$DATA/N44W072.hgt" "$T/cut.tif"
if ! dem2vgis -q -H ellipsoid -D EPSG:5773 "$T/cut.tif" "$T/P" 2>"$T/err"; then
	sed 's/^/#   /' "$T/err"; ok 1 "the pyramid"; done_testing; exit 1
fi
run "the real pyramid passes tilecheck" tilecheck "$T/P"

# index.json edited by a Python expression on ix (the parsed index) or,
# with -t, on s (its text)
edit() {
	"$PY" - "$@" <<'EOF'
import json, sys
p, kind, expr = sys.argv[1] + "/index.json", sys.argv[2], sys.argv[-1]
if kind == "-t":
    s = open(p).read()
    exec(expr)
    open(p, "w").write(s)
else:
    ix = json.load(open(p))
    exec(expr)
    json.dump(ix, open(p, "w"), indent=1)
EOF
}

# refused NAME PATTERN: each reader refuses it with PATTERN in its
# message, within 20 s, leaving no output: vgis2tiles and tileplay exit 1;
# tilecheck 1 (violations, its report names them) or 3 (tilecheck(1):
# the pyramid cannot be checked at all), never 0
refused() {
	hc=$1 hpat=$2
	timeout 20 tilecheck "$T/$hc" >"$T/out" 2>&1; hs=$?
	{ [ $hs -eq 1 ] || [ $hs -eq 3 ]; } && grep -Eq -- "$hpat" "$T/out"
	hr=$?; [ $hr -eq 0 ] || echo "#   exit $hs: $(head -c 300 "$T/out")"
	ok $hr "$hc: tilecheck refuses it, named"
	fails "$hc: vgis2tiles refuses it, named" 1 "^vgis2tiles: .*($hpat)" \
	    timeout 20 vgis2tiles "$T/$hc" "$T/out3d"
	[ ! -e "$T/out3d" ] && [ -z "$(ls -A "$T" | grep '^\.')" ]
	ok $? "$hc: vgis2tiles leaves nothing"
	fails "$hc: tileplay --shot refuses it, named" 1 "^tileplay: .*($hpat)" \
	    timeout 20 tileplay --shot "$T/shot.png" "$T/$hc"
	[ ! -e "$T/shot.png" ]
	ok $? "$hc: tileplay --shot leaves no picture"
}

copy() { rm -rf "$T/$1"; cp -r "$T/P" "$T/$1"; }

# --- the index ---------------------------------------------------------
copy dup; edit "$T/dup" -t 's = s.replace("\"block\": 129,", "\"block\": 129, \"block\": 129,")'
refused dup 'duplicate|block'
copy size0; edit "$T/size0" -t 's = s.replace("300,", "4294967596,", 1)'
refused size0 'size0'
copy zrange; edit "$T/zrange" 'L = ix["levels"][1]; L["zmin"][3], L["zmax"][3] = L["zmax"][3] + 1, L["zmin"][3]'
refused zrange 'zmin .* > zmax|block \(1,1\)|1/1_1\.exr'
copy step; edit "$T/step" 'ix["georef"]["step"] = [1e-300, -1e-300]'
refused step 'step'
copy emax; edit "$T/emax" 'ix["levels"][1]["max_error"][0] = -3'
refused emax 'max_error|block \(0,0\)|1/0_0\.exr'
copy disp; edit "$T/disp" 'ix["levels"][0]["displaced"] = True'
refused disp 'channels'
copy levels; edit "$T/levels" 'ix["levels"].pop()'
refused levels 'levels'
# a text larger than its pyramid's index can need (9b): refused before
# it is parsed, the reason given
copy big; edit "$T/big" -t 's = s[:-2] + " " * 400000 + s[-2:]'
refused big 'can need'
copy values; edit "$T/values" -t 's = s[:-3] + ", \"x\": [" + ",".join(["0"] * 2000) + "]" + s[-3:]'
refused values 'values'
copy few; edit "$T/few" -t 's = s.replace("300,", "30000,", 1)'
refused few 'values|size0|levels'

# --- the blocks (level 1: the picture draws it) --------------------------
for c in "negE E 5 5 -1" "nanE E 7 3 nan" "nanZ Z 5 5 nan" "infZ Z 9 9 inf" \
    "cornerE E 0 0 12"; do
	set -- $c
	copy "$1"; pyset "$T/$1/1/1_1.exr" "$2" "$3" "$4" "$5"
	refused "$1" '1_1\.exr|block \(1,1\)'
done

# --- what is not a regular file (class 5) ----------------------------------
copy fifoidx; rm "$T/fifoidx/index.json"; mkfifo "$T/fifoidx/index.json"
refused fifoidx 'index\.json: not a regular file \(a FIFO\)'
copy diridx; rm "$T/diridx/index.json"; mkdir "$T/diridx/index.json"
refused diridx 'index\.json: not a regular file \(a directory\)'
copy fifoblk; rm "$T/fifoblk/1/1_1.exr"; mkfifo "$T/fifoblk/1/1_1.exr"
refused fifoblk '1_1\.exr: not a regular file \(a FIFO\)'
copy fifotop; rm "$T/fifotop/2/0_0.exr"; mkfifo "$T/fifotop/2/0_0.exr"
refused fifotop '0_0\.exr: not a regular file \(a FIFO\)'

# --- windowed reads check every row's CRC (class 3) -----------------------
dem2fqm -D EPSG:5773 "$T/cut.tif" - >"$T/l0.fqm" &&
fqmfilter "$T/l0.fqm" - >"$T/l1.fqm" && fqmfilter "$T/l1.fqm" - >"$T/l2.fqm" &&
for l in 0 1 2; do fqmsolve "$T/l$l.fqm" - >"$T/v$l.fqm" || exit 1; done
ok $? "vertex maps as streams"
run "tilepack on the sound maps" \
    tilepack -q -D EPSG:5773 "$T/cut.tif" "$T/S" "$T/v0.fqm" "$T/v1.fqm" "$T/v2.fqm"
# damage DEST ROW COLUMN: 4 bytes of a row of v0 changed, in Z or X
damage() {
	"$PY" - "$T/v0.fqm" "$1" "$2" "$3" <<'EOF'
import sys
d = bytearray(open(sys.argv[1], "rb").read())
row, col = int(sys.argv[3]), int(sys.argv[4])
rec = (len(d) - 16 - 322) // 260          # row records: data + CRC
o = 322 + row * rec + 4 * col
d[o:o + 4] = bytes(x ^ 0x5a for x in d[o:o + 4])
open(sys.argv[2], "wb").write(d)
EOF
}
damage "$T/bad.fqm" 100 250
fails "a vertex map damaged in row 100: tilepack exits 1, the row named" 1 \
    "^tilepack: .*bad\.fqm: corrupt row 100 of 260" \
    tilepack -q -D EPSG:5773 "$T/cut.tif" "$T/B" "$T/bad.fqm" "$T/v1.fqm" "$T/v2.fqm"
[ ! -e "$T/B" ]; ok $? "... and no pyramid"
damage "$T/bad2.fqm" 259 3
fails "damaged in the last row, first columns: the row named" 1 \
    "corrupt row 259 of 260" \
    tilepack -q -j 3 -D EPSG:5773 "$T/cut.tif" "$T/B" "$T/bad2.fqm" "$T/v1.fqm" "$T/v2.fqm"
# the same maps as EXR files: the same pyramid, byte for byte
for l in 0 1 2; do fqmsolve "$T/l$l.fqm" "$T/v$l.exr" || exit 1; done
run "tilepack on EXR maps" \
    tilepack -q -D EPSG:5773 "$T/cut.tif" "$T/E" "$T/v0.exr" "$T/v1.exr" "$T/v2.exr"
diff -r "$T/S" "$T/E" >/dev/null
ok $? "streams read by spans give the pyramid EXR maps give"
# EXR maps have no row checksums, but a ZIP chunk's zlib Adler-32 and
# size (fqm(5)): damage inside one is refused, its rows named
"$PY" - "$T/v0.exr" "$T/bad.exr" <<'EOF'
import sys
d = bytearray(open(sys.argv[1], "rb").read())
o = len(d) * 2 // 3
d[o:o + 4] = bytes(x ^ 0x5a for x in d[o:o + 4])
open(sys.argv[2], "wb").write(d)
EOF
fails "an EXR map damaged inside a ZIP chunk: tilepack exits 1, the row named" 1 \
    "^tilepack: .*bad\.exr: corrupt data at row [0-9]+ of 260" \
    tilepack -q -D EPSG:5773 "$T/cut.tif" "$T/B" "$T/bad.exr" "$T/v1.exr" "$T/v2.exr"
[ ! -e "$T/B" ]; ok $? "... and no pyramid"
done_testing
