# t_dem_meta - what a DEM says about itself, and DEM input that is not
# what it seems (issue 21, classes 5, 7 and 10): a PNG whose CRS and
# geotransform gdal_translate kept in NAME.aux.xml is georeferenced, and
# no program writes a sidecar (or anything) beside its input; a VRT of
# VRTs of pixel-is-point tiles reads as the tiles listed do; a VRT whose
# sources GDAL would resample is refused unless --resample; a list with a
# UTF-8 BOM; a FIFO as DEM, list entry or VRT source refused at once; a
# long entry cut in the message; a scratch file that cannot be written
# names its directory; the supervisor's own failures name it. Cuts of
# N44W072 (pixel-is-point SRTM) made by GDAL's tools.
# shellcheck disable=SC2086 # numbers split into words on purpose
. "$(dirname "$0")/../lib.sh"

DEM=$DATA/N44W072.tif
D=$T/d	# the user's files: their listing must never change
mkdir -p "$D"
# GDAL's tools write no sidecar of their own but where asked
gt() { GDAL_PAM_ENABLED=NO gdal_translate -q "$@"; }
gv() { GDAL_PAM_ENABLED=NO gdalbuildvrt -q "$@"; }

# --- fixtures: 2 x 2 point tiles sharing an edge, and their VRTs -----------
for t in "a 0 0" "b 120 0" "c 0 120" "d 120 120"; do
	set -- $t
	gt -srcwin "$2" "$3" 121 121 "$DEM" "$D/$1.tif"
done
gt -srcwin 0 0 241 241 "$DEM" "$D/whole.tif"
(cd "$D" && gv top.vrt a.tif b.tif && gv bottom.vrt c.tif d.tif &&
    gv both.vrt top.vrt bottom.vrt)
printf 'a.tif\nb.tif\nc.tif\nd.tif\n' >"$D/tiles.txt"
printf 'top.vrt\nbottom.vrt\n' >"$D/vrts.txt"
# a PNG: its georeferencing only in the .aux.xml gdal_translate writes
GDAL_PAM_ENABLED=YES gdal_translate -q -of PNG -ot UInt16 "$D/whole.tif" \
    "$D/whole.png" 2>/dev/null
gt -ot UInt16 "$D/whole.tif" "$D/whole16.tif" 2>/dev/null
[ -f "$D/whole.png.aux.xml" ]; ok $? "fixture: the PNG's georeferencing is in its .aux.xml"
listing() {
	stat -c '%n %Y' "$D"
	find "$D" -mindepth 1 -maxdepth 1 -printf '%f %s %T@ %m\n' | sort
}
listing >"$T/before"

# unchanged: nothing written, removed or touched in $D
unchanged() {
	listing >"$T/after"
	cmp -s "$T/before" "$T/after" ||
	    { diff "$T/before" "$T/after" | sed 's/^/#   /' | head -40; return 1; }
}
info() { dem2fqm -I "$@" 2>"$T/ierr" | grep -E '^(model|crs|raster|origin|step|size) '; }

# --- class 7: the .aux.xml sidecar, read and never written -----------------
info "$D/whole.png" >"$T/png"
info "$D/whole16.tif" >"$T/tif"
grep -q '^crs EPSG:4326' "$T/png" && cmp -s "$T/png" "$T/tif"
ok $? "PNG + .aux.xml: the CRS, geotransform and pixel-is-point of its sidecar"
! grep -q 'not georeferenced' "$T/ierr"; ok $? "PNG + .aux.xml: no 'not georeferenced'"
run "dem2fqm on the PNG" dem2fqm "$D/whole.png" "$T/png.fqm"
run "dem2fqm on the same heights as GeoTIFF" dem2fqm "$D/whole16.tif" "$T/tif.fqm"
cmp -s "$T/png.fqm" "$T/tif.fqm"; ok $? "PNG + .aux.xml: the GeoTIFF's level-0 map, byte for byte"
run "dem2vgis on the PNG" dem2vgis "$D/whole.png" "$T/pngpyr"
grep -q 'EPSG:4326' "$T/pngpyr/index.json"; ok $? "dem2vgis: the pyramid has the sidecar's CRS"
! grep -q 'not georeferenced' "$T/err"; ok $? "dem2vgis: no 'not georeferenced'"
run "tilecheck --dem on the PNG" tilecheck --dem "$D/whole.png" "$T/pngpyr"
unchanged; ok $? "dem2fqm, dem2vgis, tilecheck: nothing written beside the DEM"

# --- class 7: VRT of VRTs of point tiles ----------------------------------
info "$D/tiles.txt" >"$T/i_list"
info "$D/both.vrt" >"$T/i_both"
info "$D/vrts.txt" >"$T/i_vrts"
grep -q '^raster point' "$T/i_list" && cmp -s "$T/i_list" "$T/i_both"
ok $? "VRT of VRTs of point tiles: pixel-is-point, the list's origin"
cmp -s "$T/i_list" "$T/i_vrts"; ok $? "a list of VRTs of point tiles: the same"
run "dem2fqm: the tiles as a list" dem2fqm "$D/tiles.txt" "$T/list.fqm"
run "dem2fqm: the VRT of VRTs" dem2fqm "$D/both.vrt" "$T/both.fqm"
cmp -s "$T/list.fqm" "$T/both.fqm"; ok $? "VRT of VRTs = list, byte for byte"
run "dem2vgis: the VRT of VRTs" dem2vgis "$D/both.vrt" "$T/pyr"
run "tilecheck --dem against the whole DEM" tilecheck --dem "$D/whole.tif" "$T/pyr"
unchanged; ok $? "VRTs and lists: nothing written beside them"

# --- class 7: sources GDAL would resample ---------------------------------
S=$T/s
mkdir -p "$S"
cp "$D/a.tif" "$S/a.tif"
GDAL_PAM_ENABLED=NO gdalwarp -q -tr 0.0016666666666666668 0.0016666666666666668 \
    -r bilinear "$D/b.tif" "$S/b2.tif"
(cd "$S" && gv mixed.vrt a.tif b2.tif && gv -tr 0.00041666666666666669 \
    0.00041666666666666669 fine.vrt a.tif)
printf 'a.tif\nb2.tif\n' >"$S/mixed.txt"
fails "tiles of two pixel sizes as a list: refused" 1 \
    "^dem2fqm: .*b2.tif: pixel size .*never resampled" dem2fqm -I "$S/mixed.txt"
fails "the same tiles as a VRT: refused, naming the source" 1 \
    "^dem2fqm: .*mixed.vrt: its source .*\.tif is scaled .*--resample" \
    dem2fqm -I "$S/mixed.vrt"
fails "a VRT at half the pixel size (gdalbuildvrt -tr): refused" 1 \
    "^dem2fqm: .*fine.vrt: its source a.tif is scaled from 121 x 121 to 242 x 242" \
    dem2fqm "$S/fine.vrt" "$T/x.fqm"
echo mixed.vrt >"$S/vrtlist.txt"
fails "a list whose entry is that VRT: refused the same way" 1 \
    "^dem2fqm: .*mixed.vrt: its source .*is scaled" dem2fqm -I "$S/vrtlist.txt"
run "--resample: the mosaic VRT read" dem2fqm --resample "$S/mixed.vrt" "$T/mixed.fqm"
run "dem2vgis --resample passes it to its stages" dem2vgis --resample \
    "$S/fine.vrt" "$T/finepyr"
dem2vgis --resample -P "$T/plan" "$S/fine.vrt" "$T/planpyr" >"$T/o" 2>"$T/e" &&
    make -s -C "$T/plan" >"$T/o" 2>"$T/e" && [ -f "$T/planpyr/index.json" ]
ok $? "a plan made with --resample: its jobs read the VRT too"
run "tilecheck --dem --resample on it" tilecheck --resample --dem "$S/fine.vrt" "$T/finepyr"
fails "dem2vgis without it: refused" 1 "--resample" dem2vgis "$S/fine.vrt" "$T/finepyr2"
[ ! -e "$T/finepyr2" ]; ok $? "dem2vgis refused: no output"
# pixel-is-point and pixel-is-area sources in one VRT: half a pixel apart
gt -mo AREA_OR_POINT=Area "$D/b.tif" "$S/b_area.tif"
(cd "$S" && gv pa.vrt a.tif b_area.tif)
fails "a VRT mixing point and area sources: refused" 1 \
    "^dem2fqm: .*pa.vrt: its source .*pixel-is-.*half a pixel" dem2fqm -I "$S/pa.vrt"

# --- class 10: a list with a UTF-8 BOM -----------------------------------
printf '\357\273\277a.tif\nb.tif\nc.tif\nd.tif\n' >"$S/bom.txt"
cp "$D/b.tif" "$D/c.tif" "$D/d.tif" "$S/"
run "a list with a UTF-8 BOM" dem2fqm "$S/bom.txt" "$T/bom.fqm"
cmp -s "$T/bom.fqm" "$T/list.fqm"; ok $? "a list with a BOM: the list's map"

# --- class 5: what is not a regular file ---------------------------------
mkfifo "$S/fifo.tif" "$S/fifo.txt"
printf 'a.tif\nfifo.tif\n' >"$S/fifolist.txt"
fails "a FIFO as the DEM: refused at once" 1 \
    "^dem2fqm: .*fifo.tif: not a regular file \(a FIFO\)" \
    timeout 20 dem2fqm -I "$S/fifo.tif"
fails "a FIFO as the list: refused at once" 1 "fifo.txt: not a regular file" \
    timeout 20 dem2fqm -I "$S/fifo.txt"
fails "a FIFO line in a list: dem2vgis refuses it at once" 1 \
    "^dem2(vgis|fqm): .*fifolist.txt: line 2: .*fifo.tif: a FIFO" \
    timeout 20 dem2vgis "$S/fifolist.txt" "$T/fifopyr"
fails "a FIFO among dem2vgis's DEMs: refused at once" 1 "fifo.tif: a FIFO" \
    timeout 20 dem2vgis "$S/a.tif" "$S/fifo.tif" "$T/fifopyr"
sed 's/top.vrt/fifo.tif/' "$D/both.vrt" >"$S/fifo.vrt"
fails "a FIFO as a VRT's source: refused at once" 1 \
    "fifo.vrt: its source .*fifo.tif is not a regular file \(a FIFO\)" \
    timeout 20 dem2fqm -I "$S/fifo.vrt"
fails "a directory as a list entry" 1 "line 2: .*: a directory" \
    sh -c 'printf "a.tif\n.\n" >"$1/dir.txt" && dem2fqm -I "$1/dir.txt"' sh "$S"
dem2fqm -I - <"$D/a.tif" >"$T/o" 2>"$T/e"; ok $? "stdin (-) still read"
dem2vgis -n N44W072.hgt - "$T/hgtpyr" <"$DATA/N44W072.hgt" >"$T/o" 2>"$T/e"
ok $? "dem2vgis -n NAME - still read"
(cd "$S" && zip -q a.zip a.tif)
dem2fqm -I "/vsizip/$S/a.zip/a.tif" >"$T/o" 2>"$T/e" && grep -q '^size 121 121' "$T/o"
ok $? "/vsizip/ paths go to GDAL"

# --- class 10: messages --------------------------------------------------
{ echo a.tif; printf 'x%.0s' $(seq 5000); echo; } >"$S/long.txt"
dem2fqm -I "$S/long.txt" >"$T/o" 2>"$T/e"; s=$?
n=$(wc -c <"$T/e")
[ $s -eq 1 ] && [ "$n" -lt 300 ] && grep -q '^dem2fqm: .*long.txt: line 2: .*xx\.\.\.xx*: ' "$T/e"
ok $? "a 5000-character entry: cut with ... ($n bytes)"
# the scratch file: its directory and what to do
(trap '' XFSZ; ulimit -f 200; TMPDIR=$T dem2fqm "$D/whole.tif" "$T/big.fqm") \
    >"$T/o" 2>"$T/e"; s=$?
[ $s -eq 1 ] && grep -q "^dem2fqm: scratch file in $T: write: .*TMPDIR" "$T/e"
ok $? "a scratch file that cannot grow: its directory and TMPDIR named"
# the fill's scratch on a full disk (a 256 KiB tmpfs, as root): a DEM
# whose copy fits and whose fill does not
if [ "$(id -u)" -eq 0 ] && mkdir "$T/full" &&
    mount -t tmpfs -o size=256k tmpfs "$T/full" 2>/dev/null; then
	trap 'umount "$T/full" 2>/dev/null; rm -rf "$T"' EXIT
	GDAL_PAM_ENABLED=NO /usr/bin/python3 - "$DEM" "$T/voids.tif" <<'PY'
import sys
from osgeo import gdal
gdal.UseExceptions()
d = gdal.Open(sys.argv[1])
a = d.ReadAsArray(0, 0, 200, 200).astype("float32")
a[20:180:2, :] = float("nan")
o = gdal.GetDriverByName("GTiff").Create(sys.argv[2], 200, 200, 1,
                                         gdal.GDT_Float32)
o.SetGeoTransform(d.GetGeoTransform())
o.SetProjection(d.GetProjection())
o.GetRasterBand(1).WriteArray(a)
o = None
PY
	fails "the fill's scratch on a full disk: its directory, TMPDIR" 1 \
	    "^dem2fqm: scratch file in $T/full: write: No space left on device \(it needs up to [0-9]+ MiB: set TMPDIR" \
	    env TMPDIR="$T/full" dem2fqm "$T/voids.tif" "$T/voids.fqm"
	[ -z "$(ls -A "$T/full")" ]; ok $? "the full disk: nothing left on it"
	umount "$T/full"
else
	ok 0 "# SKIP the fill's scratch on a full disk: tmpfs needs root"
	ok 0 "# SKIP the full disk: nothing left on it"
fi
# too few descriptors: the supervisor's own messages name it
bad=0
for n in 10 12 14; do
	(ulimit -n $n; dem2vgis -f "$D/a.tif" "$T/fdpyr") >"$T/o" 2>"$T/e"
	grep -vqE '^[a-z0-9]+: ' "$T/e" && bad=1
	grep -qE '^dem2vgis: pipe: .*ulimit -n' "$T/e" && bad=$((bad + 0))
done
[ $bad -eq 0 ]; ok $? "too few descriptors: every line names its program"
unchanged; ok $? "after every program: nothing written beside the inputs"

done_testing
