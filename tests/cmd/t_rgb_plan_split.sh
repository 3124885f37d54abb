# t_rgb_plan_split - dem2rgb --plan splits the work: the warp job puts
# the DEM on the deepest zoom's grid once (its voids filled), each part
# runs the chain's first segment on a band of that grid's columns (its
# own and a halo) and the gather the rest; the outputs are byte for byte
# one process's (tree with tiles.json and its measured error, PMTiles
# archive, the report) for 1, 2 and 5 parts, through make -j2 and GNU
# parallel, on a crop of SRTM N48W125, the same with a block of voids,
# and a UTM DEM. A part reads only its band: its window of columns is
# under the grid's width, and with the filled grid spoiled outside it,
# the part writes the same pieces (a part whose band meets the spoiled
# columns does not).
. "$(dirname "$0")/../lib.sh"
quick_skip "dem2rgb's split plan run by make and GNU parallel"

gdal_translate -q -srcwin 2000 3080 769 129 "$DATA/N48W125.hgt" \
    "$T/srtm.tif"
cp "$T/srtm.tif" "$T/void.tif"
/usr/bin/python3 - "$T/void.tif" <<'EOF'
import sys
from osgeo import gdal
d = gdal.Open(sys.argv[1], gdal.GA_Update)
b = d.GetRasterBand(1)
a = b.ReadAsArray()
a[40:70, 300:420] = -32768
b.WriteArray(a)
b.SetNoDataValue(-32768)
EOF
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r bilinear "$T/srtm.tif" \
    "$T/utm.tif"
O="-t 256 -z 13"
have_par=0
command -v parallel >/dev/null && have_par=1

# plan DEM N HOW [-o]: the plan of N parts run by HOW (make, parallel),
# its tree (or archive) compared with one process's ref-DEM
plan() {
	dem=$1 n=$2 how=$3 arch=${4:-} P=$T/plan-$1-$2
	if [ "$how" = parallel ] && [ $have_par -eq 0 ]; then
		ok 0 "$dem, $n parts, GNU parallel # SKIP not installed"
		return
	fi
	if [ -n "$arch" ]; then
		# shellcheck disable=SC2086
		dem2rgb $O --plan "$P" --parts "$n" -o "$T/out.pmtiles" \
		    "$T/$dem.tif" 2>/dev/null
	else
		# shellcheck disable=SC2086
		dem2rgb $O --plan "$P" --parts "$n" "$T/$dem.tif" "$T/out" \
		    2>/dev/null
	fi || { ok 1 "$dem: the plan of $n parts"; return; }
	if [ "$how" = make ]; then
		make -s -C "$P" -j2 >"$T/log" 2>&1
	else
		PARALLEL=-j2 sh "$P/parallel.sh" >"$T/log" 2>&1
	fi &&
	if [ -n "$arch" ]; then
		cmp "$T/ref-$dem.pmtiles" "$T/out.pmtiles"
	else
		diff -r "$T/ref-$dem" "$T/out" >/dev/null
	fi && [ ! -e "$P/work" ] && [ ! -e "$P/work.grid" ] &&
	    [ ! -e "$P/work.parts" ]
	ok $? "$dem, $n parts, $how${arch:+, -o}: byte for byte one process's, nothing left"
	rm -rf "$T/out" "$T/out.pmtiles"
}

for dem in srtm void utm; do
	# shellcheck disable=SC2086
	dem2rgb -j 2 $O "$T/$dem.tif" "$T/ref-$dem" 2>"$T/rep-$dem"
	ok $? "$dem: one process"
done
# shellcheck disable=SC2086
dem2rgb -q -j 2 $O -o "$T/ref-srtm.pmtiles" "$T/srtm.tif"
ok $? "srtm: one process, an archive"

# 5 parts, step by step: the warp and the parts, then the gather
P=$T/plan-5
# shellcheck disable=SC2086
dem2rgb $O --plan "$P" --parts 5 "$T/srtm.tif" "$T/out" 2>/dev/null &&
    grep -q '^done/p-4: done/warp$' "$P/Makefile"
ok $? "5 parts, each after the warp"
# shellcheck disable=SC2046
make -s -C "$P" -j2 $(cat "$P/targets1") >/dev/null 2>&1 &&
    [ -f "$P/work.grid/seg0.filled" ] && [ ! -e "$T/out" ]
ok $? "the warp and the parts: the filled grid, no tree yet"
# window X0 X1 of W: the columns each part read
bad=0
for k in 0 1 2 3 4; do
	awk '$1 == "window" && $4 == "of" && $3 > $2 &&
	    $3 - $2 < $5 { f = 1 } END { exit !f }' "$P/work.parts/$k" || bad=1
done
[ $bad -eq 0 ]
ok $? "each part read fewer columns than the grid's"

# the filled grid spoiled outside part 2's window: part 2 writes the
# same pieces, part 0 (whose band lies there) does not
read -r x0 x1 w <<EOF
$(awk '$1 == "window" { print $2, $3, $5 }' "$P/work.parts/2")
EOF
cp "$P/work.grid/seg0.filled" "$T/filled.keep"
cp -r "$P/work.grid/2" "$T/p2" && cp -r "$P/work.grid/0" "$T/p0"
/usr/bin/python3 - "$P/work.grid/seg0.filled" "$x0" "$x1" <<'EOF'
import struct, sys
import numpy as np
p, x0, x1 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
with open(p, 'r+b') as f:
	h = f.read(64)
	w, n = struct.unpack_from('<II', h, 12)
	z = struct.unpack_from('<Q', h, 40)[0]
	f.seek(z)
	a = np.frombuffer(f.read(4 * w * n), '<f4').reshape(n, w).copy()
	a[:, :x0] = 3000.0
	a[:, x1:] = 3000.0
	f.seek(z)
	f.write(a.tobytes())
EOF
# shellcheck disable=SC2086
vgis-job rgb-part $O 2:5 "$T/srtm.tif" "$P/work" 2>/dev/null &&
    diff -r "$T/p2" "$P/work.grid/2" >/dev/null
ok $? "columns $x0 .. $x1 of $w: part 2 reads only those (spoiled past them, the same pieces)"
# shellcheck disable=SC2086
vgis-job rgb-part $O 0:5 "$T/srtm.tif" "$P/work" 2>/dev/null &&
    ! diff -r "$T/p0" "$P/work.grid/0" >/dev/null
ok $? "part 0, whose band was spoiled: other pieces"
cp "$T/filled.keep" "$P/work.grid/seg0.filled"
# shellcheck disable=SC2086
vgis-job rgb-part $O 0:5 "$T/srtm.tif" "$P/work" 2>/dev/null &&
    make -s -C "$P" -j2 >"$T/log" 2>&1 &&
    diff -r "$T/ref-srtm" "$T/out" >/dev/null
ok $? "part 0 again, the gather: the tree byte for byte one process's"
grep 'rgb-gather: zoom ' "$T/log" | sed 's/^[^:]*: //' >"$T/a" &&
    sed 's/^[^:]*: //' "$T/rep-srtm" | diff - "$T/a" >/dev/null
ok $? "the gather's report is one process's: per zoom tiles, bytes, error"
rm -rf "$T/out"

plan srtm 1 make
plan srtm 2 parallel -o
plan void 2 make
plan void 5 parallel
plan utm 5 make
plan utm 1 parallel
done_testing
