# t_vgis2terrain - quantized-mesh terrain from a pyramid of a real DEM
# (an ellipsoidal crop of SRTM N48W125: southern Vancouver Island and the
# sea): layer.json's available rectangles are exactly the files, every
# ancestor of a tile and both roots exist, every level within E_L by the
# program's own measure and not vacuously, reruns and -j 1 / -j 2
# byte-identical, -z the same tiles gzipped, the options in layer.json;
# a UTM variant exported the same way; tilecheck --terrain --dem, the
# independent validator, on a crop of SRTM with voids, on the UTM
# variant and on a DEM edged on a lattice line; its --dump equal to
# loaders.gl's decoding; hostile pyramids refused; an orthometric pyramid refused
# with the way out, an OUTDIR
# inside the pyramid refused, a killed run leaves nothing.
. "$(dirname "$0")/../lib.sh"

# 513 x 513 void-free samples at 1", relief 0 - 800 m, ellipsoidal
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1696 2176 513 513 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
/usr/bin/python3 "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
dem2vgis -H ellipsoid "$T/srtm.tif" "$T/pyr" 2>/dev/null
dem2vgis "$T/srtm.tif" "$T/egm.pyr" 2>/dev/null

# the report: per level "... level Z: ... measured M m; bound B m = F E_L";
# every F <= 1 (the bound holds) and the error measured at the samples
# at least 0.4 E_L at 5 levels or more (the bound is not vacuous)
bounds() {
	awk '/ level [0-9]+: .*bound/ {
		z = $3; sub(":", "", z); el = 77067.34 / 2 ^ z
		for (i = 1; i <= NF; i++) if ($i == "measured") m = $(i + 1)
		if ($(NF - 1) > 1) bad++
		if (m >= 0.4 * el) near++; n++
	} END { exit !(n > 0 && bad == 0 && near >= 5) }' "$1"
}

# every sample measured (VGIS2TERRAIN_MEASURE=all), for the report; the
# reruns skip the tiles their bound clears, byte for byte the same
run "export, 2 threads" env VGIS2TERRAIN_MEASURE=all \
    vgis2terrain -j 2 --attribution "SRTM (NASA)" \
    --parent-url "https://example.org/terrain/" "$T/pyr" "$T/qm"
cp "$T/err" "$T/report"
sed 's/^/#   /' "$T/report"

# layer.json against the files
/usr/bin/python3 - "$T/qm" >"$T/check" 2>&1 <<'PY'
import glob, json, os, re, sys
d = sys.argv[1]
L = json.load(open(os.path.join(d, "layer.json")))
files = set()
for p in glob.glob(os.path.join(d, "*", "*", "*.terrain")):
    z, x, y = map(int, re.match(r".*/(\d+)/(\d+)/(\d+)\.terrain$", p).groups())
    files.add((z, x, y))
ann = set()
for z, rects in enumerate(L["available"]):
    for r in rects:
        for x in range(r["startX"], r["endX"] + 1):
            for y in range(r["startY"], r["endY"] + 1):
                ann.add((z, x, y))
print("announced", len(ann), "files", len(files))
print("exact", ann == files)
print("roots", (0, 0, 0) in files and (0, 1, 0) in files)
print("ancestors", all((z - 1, x // 2, y // 2) in files
                       for z, x, y in files if z > 0))
print("maxzoom", L["maxzoom"] == len(L["available"]) - 1 ==
      max(z for z, _, _ in files))
want = {"tilejson": "2.1.0", "format": "quantized-mesh-1.0",
        "scheme": "tms", "projection": "EPSG:4326", "minzoom": 0,
        "tiles": ["{z}/{x}/{y}.terrain?v={version}"],
        "extensions": ["octvertexnormals"],
        "attribution": "SRTM (NASA)",
        "parentUrl": "https://example.org/terrain/"}
print("fields", all(L.get(k) == v for k, v in want.items()) and
      "version" in L and "ellipsoid" in L["description"] and
      len(L["bounds"]) == 4)
# SRTM 1": the deepest level holds 64 samples a tile or fewer
print("level14", L["maxzoom"] == 14)
PY
sed 's/^/#   /' "$T/check"
grep -q "exact True" "$T/check"; ok $? "layer.json's available: exactly the files written"
grep -q "roots True" "$T/check"; ok $? "both root tiles exist"
grep -q "ancestors True" "$T/check"; ok $? "every tile's parent exists"
grep -q "maxzoom True" "$T/check"; ok $? "maxzoom: the deepest level written"
grep -q "level14 True" "$T/check"; ok $? "SRTM 1\": maxzoom 14"
grep -q "fields True" "$T/check"; ok $? "layer.json's fields, attribution and parentUrl"

# the bound: every level within E_L, and at the deep levels close to it
bounds "$T/report"
ok $? "every level's bound within E_L; measured, at least 5 levels at 0.4 E_L or more"

run "rerun, 2 threads" vgis2terrain -q -j 2 --attribution "SRTM (NASA)" \
    --parent-url "https://example.org/terrain/" "$T/pyr" "$T/qm2"
run "rerun, 1 thread" vgis2terrain -q -j 1 --attribution "SRTM (NASA)" \
    --parent-url "https://example.org/terrain/" "$T/pyr" "$T/qm1"
diff -r "$T/qm" "$T/qm2" >/dev/null; ok $? "a rerun is byte-identical"
diff -r "$T/qm" "$T/qm1" >/dev/null; ok $? "-j 1 and -j 2 are byte-identical"
run "an existing terrain directory is replaced" \
    vgis2terrain -q "$T/pyr" "$T/qm1"
grep -q parentUrl "$T/qm1/layer.json"; [ $? -ne 0 ]
ok $? "the replacement is the new export (no parentUrl)"

run "-z" vgis2terrain -q -z -j 2 "$T/pyr" "$T/gz"
n=0
for f in "$T"/qm1/13/*/*.terrain; do
	g=$T/gz/${f#"$T"/qm1/}
	[ "$(head -c 2 "$g" | od -An -tx1 | tr -d ' ')" = 1f8b ] &&
	    gzip -dc <"$g" | cmp -s - "$f" || n=$((n + 1))
done
[ $n -eq 0 ]; ok $? "-z: the same tiles, gzipped"

# refusals, before anything is written
fails "EGM96 heights: refused, saying how to rebuild" 1 \
    'EPSG:5773.*dem2vgis -H ellipsoid' vgis2terrain "$T/egm.pyr" "$T/egm.qm"
[ ! -e "$T/egm.qm" ]; ok $? "nothing written for a refusal"
# a projected DEM: the crop warped to UTM 10N at 30 m, cut inside its
# valid footprint (no warped nodata corners)
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r bilinear -te 388000 5347000 \
    396000 5360000 "$T/geo.tif" "$T/utm.tif"
dem2vgis "$T/utm.tif" "$T/utm.pyr" 2>/dev/null
run "a UTM pyramid exported, every sample measured" env \
    VGIS2TERRAIN_MEASURE=all vgis2terrain -j 2 "$T/utm.pyr" "$T/utm.qm"
cp "$T/err" "$T/utmreport"
bounds "$T/utmreport"
ok $? "UTM: every level's bound within E_L; measured, at least 5 levels at 0.4 E_L or more"
/usr/bin/python3 - "$T/utm.qm" <<'PY'
import glob, json, os, re, sys
d = sys.argv[1]
L = json.load(open(os.path.join(d, "layer.json")))
files = {tuple(map(int, re.match(r".*/(\d+)/(\d+)/(\d+)\.terrain$", p).groups()))
         for p in glob.glob(os.path.join(d, "*", "*", "*.terrain"))}
ann = {(z, x, y) for z, rs in enumerate(L["available"]) for r in rs
       for x in range(r["startX"], r["endX"] + 1)
       for y in range(r["startY"], r["endY"] + 1)}
sys.exit(not (ann == files and all((z - 1, x // 2, y // 2) in files
                                   for z, x, y in files if z > 0)))
PY
ok $? "UTM: available is exactly the files, every parent exists"

# --- the independent validator (tilecheck --terrain, verify/qm_*.c) ----
# per level "E_L X m, ... error / E_L over N tiles: max M ... (largest D
# m ...": no tile over E_L (tilecheck exits 1 past E_L + 1 mm) and the
# bound not vacuous: a tile at 0.45 E_L or more at every level whose
# E_L / 2 is within the DEM's relief (level 0's largest error; coarser
# levels cannot come near their bound), 5 levels or more
validated() {
	awk '/error \/ E_L over/ { n++
		for (i = 1; i <= NF; i++) {
			if ($i == "max") m = $(i + 1)
			if ($i == "(largest") d = $(i + 1)
		}
		if (n == 1) rel = d
		if (m > 1) bad++
		if ($2 / 2 <= rel) { want++; if (m >= 0.45) near++ }
	} /^result: pass$/ { pass = 1 }
	END { printf "#   %d levels, %d within the relief, %d at 0.45 E_L or more\n",
	    n, want, near
	    exit !(pass && n > 0 && !bad && want >= 5 && near == want) }' "$1"
}
# SRTM 3" in the Pyrenees with 1.7 k voids (geographic); its row 143 is
# latitude 42.1875, a tile edge from level 6 on (a crack once)
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 672 832 257 257 \
    "$DATA/N42E001.hgt" "$T/void.tif"
dem2vgis -q -H ellipsoid "$T/void.tif" "$T/void.pyr"
run "voids: exported" vgis2terrain -q -j 2 "$T/void.pyr" "$T/void.qm"
tilecheck --terrain --dem "$T/void.tif" -H ellipsoid "$T/void.qm" \
    >"$T/vcheck" 2>&1
ok $? "voids: tilecheck --terrain --dem passes"
grep -E '^(level|  E_L|violations)' "$T/vcheck" | sed 's/^/#   /'
validated "$T/vcheck"; ok $? "voids: no tile over E_L, every level within the relief at 0.45 E_L or more"
# a projected DEM's terrain covers its whole footprint (the ellipsoid
# past it): every valid sample measured, none voided
tilecheck --terrain --dem "$T/utm.tif" "$T/utm.qm" >"$T/ucheck" 2>&1
ok $? "UTM: tilecheck --terrain --dem passes on every sample of the DEM"
validated "$T/ucheck"; ok $? "UTM: no tile over E_L, every level within the relief at 0.45 E_L or more"
# a DEM whose north edge is latitude 45, a lattice line from level 2 on:
# the cells above it fan onto its edge (no T-junction, a hole once)
gdal_translate -q -srcwin 0 0 257 257 "$DATA/N44W072.hgt" "$T/n45.tif"
dem2vgis -q -D EPSG:5773 -H ellipsoid "$T/n45.tif" "$T/n45.pyr"
run "latitude 45: exported" vgis2terrain -q "$T/n45.pyr" "$T/n45.qm"
run "latitude 45: tilecheck --terrain --dem passes (no hole)" tilecheck \
    --terrain --dem "$T/n45.tif" -D EPSG:5773 -H ellipsoid "$T/n45.qm"
# a third-party decoder (loaders.gl) reads what tilecheck reads
run "voids, -z: exported" vgis2terrain -q -z "$T/void.pyr" "$T/void.gz"
for d in void.qm void.gz utm.qm; do
	tilecheck --terrain --dump "$T/$d" >"$T/c.txt" 2>&1
	if ! command -v node >/dev/null; then
		ok 0 "$d: loaders.gl # SKIP no node"; continue
	fi
	node "$TOP/tests/js/qmdecode.js" "$T/$d" >"$T/js.txt" 2>&1
	[ -s "$T/c.txt" ] && cmp -s "$T/c.txt" "$T/js.txt"
	ok $? "$d: loaders.gl decodes $(wc -l <"$T/c.txt") tiles as tilecheck --dump does"
done
# hostile pyramids (as t_hostile_pyr for vgis2tiles): refused, named,
# nothing left
cp -r "$T/void.pyr" "$T/h1"
/usr/bin/python3 -c 'import json, sys; p = sys.argv[1]; ix = json.load(open(p))
ix["levels"].pop(); json.dump(ix, open(p, "w"))' "$T/h1/index.json"
fails "a level missing from index.json: refused" 1 'levels: 1, a 257x257' \
    timeout 20 vgis2terrain "$T/h1" "$T/h1.qm"
cp -r "$T/void.pyr" "$T/h2"
rm "$T/h2/1/0_0.exr" && mkfifo "$T/h2/1/0_0.exr"
fails "a FIFO for a block: refused at once" 1 '0_0\.exr: not a regular file' \
    timeout 20 vgis2terrain "$T/h2" "$T/h2.qm"
[ ! -e "$T/h1.qm" ] && [ ! -e "$T/h2.qm" ] &&
    [ -z "$(ls -A "$T" | grep '^\.h')" ]
ok $? "hostile pyramids: nothing left"
fails "OUTDIR inside the pyramid: refused" 1 'inside' \
    vgis2terrain "$T/pyr" "$T/pyr/qm"
[ ! -e "$T/pyr/qm" ]; ok $? "nothing written inside the pyramid"
mkdir "$T/other"
fails "an OUTDIR that is no terrain: not replaced" 1 'not a terrain' \
    vgis2terrain "$T/pyr" "$T/other"
fails "no operands: usage, exit 2" 2 usage vgis2terrain
fails "-j 0: exit 2" 2 '-j' vgis2terrain -j 0 "$T/pyr" "$T/x"
vgis2terrain --help | grep -q '^usage: vgis2terrain'; ok $? "--help"

# killed: by TERM nothing is left; by KILL the next run clears it
vgis2terrain -q -j 1 "$T/pyr" "$T/killed" &
pid=$!
if mid_run $pid "$T/killed"; then
	kill -TERM $pid; kill -CONT $pid; wait $pid
	[ ! -e "$T/killed" ] && [ -z "$(ls -a "$T" | grep killed)" ]
	ok $? "TERM: no OUTDIR and no temporary left"
else
	wait $pid; skip "the run ended before the kill"
fi
rm -rf "$T/killed"
vgis2terrain -q -j 1 "$T/pyr" "$T/killed" &
pid=$!
if mid_run $pid "$T/killed"; then
	kill -KILL $pid; kill -CONT $pid 2>/dev/null; wait $pid
	[ ! -e "$T/killed" ]; ok $? "KILL: no OUTDIR"
else
	wait $pid; skip "the run ended before the kill"
fi
vgis2terrain -q -j 2 "$T/pyr" "$T/killed"
[ -z "$(ls -a "$T" | grep '^\.killed\.')" ] && [ -f "$T/killed/layer.json" ]
ok $? "KILL: the next run removes the dead run's temporary"
done_testing
