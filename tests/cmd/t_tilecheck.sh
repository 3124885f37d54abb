# t_tilecheck - tilecheck, the checker as its own program: usage and its
# exit statuses (0 pass, 1 violations, 2 usage, 3 cannot check), a real
# pyramid that passes, corrupted copies that fail, no GL linked, and
# tileplay --verify printing the same report.
. "$(dirname "$0")/../lib.sh"

run "--help exits 0" tilecheck --help
grep -q '^usage: tilecheck \[--dem dem\]' "$T/out"; ok $? "--help prints the usage"
run "--version exits 0" tilecheck --version
grep -q '^tilecheck [0-9]' "$T/out"; ok $? "--version prints the version"
fails "no operand: exit 2" 2 'usage: tilecheck' tilecheck
fails "two operands: exit 2" 2 'usage: tilecheck' tilecheck x y
fails "unknown option: exit 2" 2 'usage: tilecheck' tilecheck -Q x
fails "--tau not numbers: exit 2" 2 '^tilecheck: --tau 1,x: ' \
    tilecheck --tau 1,x x
fails "bad DEM option: exit 2" 2 '^tilecheck: -e ' tilecheck -e nosuch x
fails "missing directory: exit 3" 3 "^tilecheck: $T/none/index.json: " \
    tilecheck "$T/none"
# named after argv[0]'s last component, getopt's messages and its own alike
fails "run by its path: an unknown option, exit 2" 2 \
    "^tilecheck: (invalid|unrecognized) option" "$B/tilecheck" -Q x
grep -q "^usage: tilecheck " "$T/err"; ok $? "... and the usage, both under the name tilecheck"
run "-V exits 0" tilecheck -V
grep -q '^tilecheck [0-9]' "$T/out"; ok $? "-V prints the version"

# No GL library linked (the viewer's libraries stay in tileplay).
if command -v ldd >/dev/null; then
	ldd "$B/tilecheck" >"$T/ldd" 2>&1
	s=$?
	! grep -E 'GL|glfw|epoxy' "$T/ldd" >/dev/null && [ $s -eq 0 ]
	ok $? "no GL library linked (ldd: $(grep -cE 'GL|glfw|epoxy' \
	    "$T/ldd") of $(wc -l <"$T/ldd") match GL|glfw|epoxy)"
fi

if [ ! -x "$B/tilepack" ] || [ ! -x "$B/dem2vgis" ] ||
    ! command -v gdal_translate >/dev/null || [ ! -f "$DATA/N44W072.hgt" ]; then
	echo "ok $((_n + 1)) - # SKIP tilepack, dem2vgis, gdal_translate or N44W072.hgt missing"
	_n=$((_n + 1))
	done_testing
	exit
fi

# A 300x260 crop of a real DEM (geographic, WGS84): 3x3 blocks on level 0.
gdal_translate -q -srcwin 600 500 300 260 "$DATA/N44W072.hgt" "$T/dem.tif"
ok $? "fixture: gdal_translate -srcwin crop of N44W072.hgt"
"$B/dem2vgis" -q "$T/dem.tif" "$T/p" >"$T/mk.out" 2>&1
ok $? "fixture: dem2vgis"

run "a real pyramid against its DEM: exit 0" tilecheck --dem "$T/dem.tif" "$T/p"
grep -q '^result: pass$' "$T/out"; ok $? "... result: pass"
[ "$(grep -c '^level' "$T/out")" -ge 2 ]; ok $? "... a block per level"
grep -q "^pyramid $T/p: .*DEM $T/dem.tif" "$T/out"; ok $? "... the DEM named"
cp "$T/out" "$T/good.txt"
run "--tau 0,1,10: exit 0" tilecheck --tau 0,1,10 "$T/p"
grep -Eq '^ +10 +[0-9]+ *$' "$T/out"; ok $? "... a row for tau 10"

# tileplay --verify: the same library call, the same report
tileplay --verify "$T/p" --dem "$T/dem.tif" >"$T/alias.txt" 2>&1
ok $? "tileplay --verify on it: exit 0"
cmp -s "$T/good.txt" "$T/alias.txt"; ok $? "... the same report as tilecheck"

# copy DIR: a fresh copy of the good pyramid to corrupt
copy() { rm -rf "$T/$1"; cp -R "$T/p" "$T/$1"; }

# A block deleted.
copy gone
rm "$T/gone/0/1_1.exr"
tilecheck "$T/gone" >"$T/out" 2>"$T/err"
ok $(( $? != 1 )) "a block deleted: exit 1"
grep -q '^result: FAIL, [0-9]* violations:.* index' "$T/out" &&
    grep -q 'level 0 block (1,1): index: .*1_1.exr' "$T/out"
ok $? "... an index violation naming the block"

# A block replaced by its neighbour: wrong vgis:block, E and Z differ.
copy swap
cp "$T/swap/0/0_1.exr" "$T/swap/0/0_0.exr"
tilecheck --dem "$T/dem.tif" "$T/swap" >"$T/out" 2>"$T/err"
ok $(( $? != 1 )) "a block replaced by its neighbour: exit 1"
grep -q '^result: FAIL.* border' "$T/out"; ok $? "... border violations"

# An E value in the index: max_error of level 0's first block raised.
copy emax
python3 - "$T/emax/index.json" <<'EOF'
import json, sys
p = sys.argv[1]
ix = json.load(open(p))
ix["levels"][0]["max_error"][0] += 1
json.dump(ix, open(p, "w"))
EOF
tilecheck "$T/emax" >"$T/out" 2>"$T/err"
ok $(( $? != 1 )) "max_error changed in index.json: exit 1"
grep -q 'level 0 block (0,0): index: ' "$T/out"; ok $? "... the block's index violation"

# index.json that is not JSON, or not a pyramid's: cannot check, exit 3.
copy nojson
printf '{"levels": [' >"$T/nojson/index.json"
fails "index.json not JSON: exit 3" 3 \
    "^tilecheck: $T/nojson/index.json: not JSON: " tilecheck "$T/nojson"
[ ! -s "$T/out" ]; ok $? "... no report"
copy nogeo
python3 - "$T/nogeo/index.json" <<'EOF'
import json, sys
p = sys.argv[1]
ix = json.load(open(p))
del ix["georef"]["step"]
json.dump(ix, open(p, "w"))
EOF
fails "index.json without georef.step: exit 3" 3 \
    "^tilecheck: .*index.json: not a pyramid index \(georef.step\)" \
    tilecheck "$T/nogeo"
fails "a DEM of another size: exit 3" 3 '^tilecheck: .*samples, the pyramid' \
    tilecheck --dem "$DATA/N44W072.hgt" "$T/p"
done_testing
