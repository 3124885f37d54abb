# t_terrain_rim - a projected DEM's terrain covers its whole footprint
# (tr_rim.c): an ellipsoidal crop of N48W125 warped to UTM 10N and to
# Canada's Atlas Lambert (EPSG:3978, a conic whose meridian 95 W turns the
# footprint 22 degrees here, its corners left void by the warp),
# exported; tilecheck --terrain --dem, the independent validator,
# measures every valid sample of the DEM (none voided at the edges) with
# no tile over E_L and no crack (its seam and hole checks); where a tile
# reaches past the footprint its surface there is the ellipsoid (a tile
# corner outside the DEM at height 0); -f 3dtiles the same meshes.
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1696 2176 257 257 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r bilinear -te 388000 5350000 \
    394000 5356000 "$T/geo.tif" "$T/utm.tif"
gdalwarp -q -t_srs EPSG:3978 -tr 30 30 -r bilinear -dstnodata -32768 \
    "$T/geo.tif" "$T/lcc.tif"

# valid samples of a DEM
valid() {
	$PY - "$1" <<'PY'
import sys
import numpy as np
from osgeo import gdal
s = gdal.Open(sys.argv[1])
b = s.GetRasterBand(1)
a = b.ReadAsArray().astype(float)
nd = b.GetNoDataValue()
ok = np.isfinite(a) if nd is None else np.isfinite(a) & (a != nd)
print(int(ok.sum()))
PY
}

# tiles of the deepest level that reach past the footprint: a tile
# corner with no DEM under it is the ellipsoid (height 0 within a
# quantum) while the tile holds the DEM too (heights far from 0)
rim() {
	$PY - "$1" <<'PY'
import glob, json, os, struct, sys
d = sys.argv[1]
z = json.load(open(os.path.join(d, "layer.json")))["maxzoom"]
found = 0
for p in glob.glob(os.path.join(d, str(z), "*", "*.terrain")):
    b = open(p, "rb").read()
    lo, hi = struct.unpack_from("<2f", b, 24)
    n, = struct.unpack_from("<I", b, 88)
    vals = []
    for k in range(3):
        s, o = 0, []
        for c in struct.unpack_from("<%dH" % n, b, 92 + 2 * n * k):
            s += (c >> 1) ^ -(c & 1)
            o.append(s)
        vals.append(o)
    q = (hi - lo) / 32767
    hs = [(u, v, lo + h / 32767 * (hi - lo)) for u, v, h in zip(*vals)]
    if any(u in (0, 32767) and v in (0, 32767) and abs(h) <= q + 1e-3
           for u, v, h in hs) and max(abs(h) for _, _, h in hs) > 1:
        found += 1
print("tiles reaching past the footprint, the ellipsoid there:", found)
sys.exit(found == 0)
PY
}

for crs in utm lcc; do
	dem2vgis "$T/$crs.tif" "$T/$crs.pyr" 2>/dev/null
	run "$crs: exported (every level within E_L by its own measure)" \
	    vgis2terrain -j 2 "$T/$crs.pyr" "$T/$crs.qm"
	cp "$T/err" "$T/$crs.report"
	tilecheck --terrain --dem "$T/$crs.tif" "$T/$crs.qm" >"$T/$crs.check" 2>&1
	ok $? "$crs: tilecheck --terrain --dem passes"
	grep -E '^(  E_L|violations)' "$T/$crs.check" | sed 's/^/#   /'
	n=$(valid "$T/$crs.tif")
	# every level measures every valid sample
	awk -v n="$n" '/valid samples/ { k++; if ($4 != n) bad++ }
	    END { exit !(k > 0 && !bad) }' "$T/$crs.check"
	ok $? "$crs: every level measures all $n valid samples of the DEM"
	awk '/error \/ E_L over/ { for (i = 1; i <= NF; i++) if ($i == "max")
		if ($(i + 1) > 1) bad++; k++ } END { exit !(k > 0 && !bad) }' \
	    "$T/$crs.check"
	ok $? "$crs: no tile over E_L"
	# the bound each level reports (max(tau, base) + the distance from
	# the selection at each sample's grid place, the CRS map's bending
	# included) holds every valid sample the validator measures
	awk 'FNR == NR { if (match($0, / level [0-9]+:/)) {
		z = substr($0, RSTART + 7, RLENGTH - 8) + 0
		if (match($0, /bound [0-9.]+ m/))
			b[z] = substr($0, RSTART + 6, RLENGTH - 8) + 0 }
		next }
	    /^level [0-9]+:/ { z = $2 + 0 }
	    /largest [0-9.]+ m/ { match($0, /largest [0-9.]+ m/)
		v = substr($0, RSTART + 8, RLENGTH - 10) + 0; k++
		if (!(z in b) || v > b[z] + 0.001) { bad++
		    printf "# level %d: %.3f m over its bound %.3f m\n", z, v, b[z] } }
	    END { exit !(k > 0 && !bad) }' "$T/$crs.report" "$T/$crs.check"
	ok $? "$crs: each level's reported bound holds at every valid sample"
	grep -q 'seam 0 coverage 0 error 0' "$T/$crs.check" &&
	    grep -q ' hole 0 ' "$T/$crs.check"
	ok $? "$crs: no crack between neighbours, no hole in a tile"
	rim "$T/$crs.qm" >"$T/out" 2>&1
	ok $? "$crs: $(cat "$T/out")"
done
# the 3D Tiles profile from the same meshes
run "lcc: -f 3dtiles" vgis2terrain -j 2 -f 3dtiles "$T/lcc.pyr" "$T/lcc.t3"
grep -o 'level [0-9]*: [0-9]* tiles, [0-9]* triangles' "$T/err" >"$T/b"
grep -o 'level [0-9]*: [0-9]* tiles, [0-9]* triangles' "$T/lcc.report" >"$T/a"
[ -s "$T/a" ] && cmp -s "$T/a" "$T/b"
ok $? "lcc: -f 3dtiles has the tiles and triangles of -f qm"
vgis2terrain -q -j 1 "$T/lcc.pyr" "$T/lcc1.qm" 2>/dev/null
diff -r "$T/lcc.qm" "$T/lcc1.qm" >/dev/null
ok $? "lcc: -j 1 and -j 2 are byte-identical"
vgis2terrain -q -j 1 -f 3dtiles "$T/lcc.pyr" "$T/lcc1.t3" 2>/dev/null
diff -r "$T/lcc.t3" "$T/lcc1.t3" >/dev/null
ok $? "lcc: -f 3dtiles -j 1 and -j 2 are byte-identical"

# A projected DEM's vertex longitudes and latitudes go through PROJ once a
# run, into a scratch file in TMPDIR (tr_grid.c): unlinked at once, so a
# run killed with it open leaves nothing there; a scratch that cannot be
# made (no TMPDIR) or written (ulimit -f: its writes fail with EFBIG) is
# a run without it, the same tiles.
S=$T/tmp; mkdir "$S"
TMPDIR=$S vgis2terrain -q -j 2 "$T/lcc.pyr" "$T/lcck.qm" 2>/dev/null & pid=$!
i=0 open=
while [ $i -lt 2000 ] && [ -z "$open" ] && kill -0 $pid 2>/dev/null; do
	open=$(ls -l /proc/$pid/fd 2>/dev/null | grep -F " -> $S/" |
	    grep -F '(deleted)')
	sleep 0.005; i=$((i + 1))
done
kill -STOP $pid 2>/dev/null; named=$(ls -A "$S")
kill -KILL $pid 2>/dev/null; kill -CONT $pid 2>/dev/null; wait $pid 2>/dev/null
[ -n "$open" ] && [ -z "$named" ] && [ -z "$(ls -A "$S")" ]
ok $? "killed with its scratch open (${open##* -> }), it leaves nothing in TMPDIR ($named$(ls -A "$S"))"
for crs in utm lcc; do
	TMPDIR=$T/none vgis2terrain -q -j 2 "$T/$crs.pyr" "$T/$crs.nt.qm" &&
	    diff -r "$T/$crs.qm" "$T/$crs.nt.qm" >/dev/null
	ok $? "$crs: no scratch file (TMPDIR missing): the same tiles"
	# one block's longitudes and latitudes are 266 KiB: a second one fails
	TMPDIR=$S sh -c 'ulimit -f 400; exec "$@"' sh vgis2terrain -q -j 2 \
	    "$T/$crs.pyr" "$T/$crs.fz.qm" && diff -r "$T/$crs.qm" "$T/$crs.fz.qm" >/dev/null
	ok $? "$crs: the scratch's writes failing (ulimit -f): the same tiles"
done
done_testing
