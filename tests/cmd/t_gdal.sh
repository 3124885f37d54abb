# t_gdal - what the GDAL reader must handle, each as a fixture made with
# GDAL's tools (tests/tools/mkgdal.py for what they cannot do) from crops
# of the real DEMs, each with its answer read from the fixture by gdalinfo,
# gdallocationinfo, numpy or cs2cs, never by our code: scale/offset,
# vertical units, mask bands, NaN nodata, south-up rows, a geotransform
# without CRS, world files, other formats (.asc, ENVI, .hgt.zip, VRT), an
# .hgt on stdin, sparse tiles, rotation, -s, and vertical datums (-H, -D).
# shellcheck disable=SC2086 # lists of numbers split into words on purpose
. "$(dirname "$0")/../lib.sh"

PATH=$TOP/scripts:$PATH
PY=/usr/bin/python3
MK="$PY $TOP/tests/tools/mkgdal.py"
GDAL_PAM_ENABLED=NO	# the GDAL tools: no .aux.xml sidecars
export GDAL_PAM_ENABLED
HGT=$DATA/N44W072.hgt BT=$DATA/bigtujunga.tif

# info NAME DEM [opts]: dem2fqm -I into $T/NAME.I; key NAME K: its value;
# voids NAME DEM [opts]: dem2fqm -II (the voids too: every sample read)
info() { i_f=$1; shift; dem2fqm -I "$@" >"$T/$i_f.I" 2>"$T/$i_f.Ierr"; }
voids() { i_f=$1; shift; dem2fqm -II "$@" >"$T/$i_f.I" 2>"$T/$i_f.Ierr"; }
key() { awk -v k="$2" '$1 == k { $1 = ""; print substr($0, 2) }' "$T/$1.I"; }
# near A B TOL: |A - B| <= TOL
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(d <= t && -d <= t) }'; }
# near2 "A1 A2" "B1 B2" TOL
near2() { set -- $1 $2 "$3"; near "$1" "$3" "$5" && near "$2" "$4" "$5"; }
# z0 DIR I J: level-0 Z of sample (I, J) as stored (first block holding it)
z0() { pyget "$1" 0 "$2" "$3" | awk 'NR == 1 { print $3 }'; }
# gv FILE I J: the raw sample (gdallocationinfo)
gv() { gdallocationinfo -valonly "$1" "$2" "$3"; }
# zhash DEM [opts]: the pixel hash of its level-0 heights as solved (the
# DEM's samples, filled): not of the FQM, whose quadrics carry the ground
# cell size, which a projection's scale factor makes depend on the origin
zhash() {
	h_d=$1; shift
	dem2fqm "$@" "$h_d" - | fqmsolve - - | rsinfo -c - | awk '$1 == "hash" { print $2 }'
}
# zrange DIR: per level "l min(zmin) max(zmax)" of index.json
zrange() {
	$PY -c 'import json, sys
for l in json.load(open(sys.argv[1]))["levels"]:
    print(l["level"], min(l["zmin"]), max(l["zmax"]))' "$1/index.json"
}
# pyramid NAME DEM [opts]: dem2vgis into $T/NAME
pyramid() {
	p_n=$1 p_d=$2; shift 2
	dem2vgis -q "$@" "$p_d" "$T/$p_n" >"$T/$p_n.mk" 2>&1 ||
	    { sed "s/^/#   /" "$T/$p_n.mk" | head -5; return 1; }
}
# A few samples of a 200x150 crop: corners, inside, and in the void region
# of mkgdal.py (not 40..69 x 50..109, not the diagonal)
SAMPLES="0 0  199 0  0 149  199 149  17 33  120 77  150 30  190 140"

# The crops: n.tif, 200x150 of N44W072.hgt (geographic, pixel-is-point,
# Int16, nodata -32768); u.tif, 200x150 of bigtujunga.tif (UTM 11N,
# pixel-is-area, Int16, nodata 32767).
gdal_translate -q -srcwin 600 500 200 150 "$HGT" "$T/n.tif" &&
    gdal_translate -q -srcwin 300 200 200 150 "$BT" "$T/u.tif" &&
    info n "$T/n.tif" && info u "$T/u.tif"
ok $? "the crops of N44W072.hgt and bigtujunga.tif read" || { done_testing; exit 1; }

# --- 1. scale and offset ------------------------------------------------
# raw = (h - 100) / 0.1 as UInt16; GDAL's scale 0.1 and offset 100 give h.
$MK raw "$T/n.tif" "$T/raw.tif" &&
    gdal_translate -q -a_scale 0.1 -a_offset 100 "$T/raw.tif" "$T/scaled.tif" &&
    gdalinfo "$T/scaled.tif" | grep -q 'Offset: 100, *Scale:0.1'
ok $? "scaled: fixture UInt16 with scale 0.1 and offset 100 (gdalinfo)"
if pyramid scaled "$T/scaled.tif"; then
	bad=0; set -- $SAMPLES
	while [ $# -ge 2 ]; do
		h=$(gv "$T/n.tif" "$1" "$2") z=$(z0 "$T/scaled" "$1" "$2")
		near "$z" "$h" 0.05 || { echo "# ($1,$2): stored $z, DEM $h"; bad=1; }
		shift 2
	done
	ok $bad "scaled: level-0 heights = raw * 0.1 + 100 within 5 cm at 8 samples"
else
	ok 1 "scaled: dem2vgis"
fi

# --- 2. feet by the vertical CRS ------------------------------------------
# NAVD88 height (ftUS), EPSG:6360: heights in US survey feet, metres out.
$MK feet "$T/n.tif" "$T/ft0.tif" &&
    gdal_translate -q -a_srs EPSG:4269+6360 "$T/ft0.tif" "$T/feet.tif" &&
    gdalsrsinfo -o wkt1 "$T/feet.tif" | grep -q 'VERT_CS\["NAVD88 height (ftUS)"'
ok $? "feet: fixture with compound CRS EPSG:4269+6360 (gdalsrsinfo)"
info feet "$T/feet.tif"
[ "$(key feet vdatum)" = EPSG:6360 ] && [ "$(key feet crs)" = EPSG:4269 ]
ok $? "feet: -I says crs EPSG:4269, vdatum EPSG:6360 (got $(key feet crs), $(key feet vdatum))"
near "$(key feet zunit)" 0.3048006096012192 1e-12
ok $? "feet: -I says zunit 1200/3937 (got '$(key feet zunit)')"
if pyramid feet "$T/feet.tif"; then
	bad=0; set -- $SAMPLES
	while [ $# -ge 2 ]; do
		# the value in feet times 1200/3937, and the metres it came from
		ft=$(gv "$T/feet.tif" "$1" "$2") h=$(gv "$T/n.tif" "$1" "$2")
		z=$(z0 "$T/feet" "$1" "$2")
		near "$z" "$(awk -v f="$ft" 'BEGIN { printf "%.9f", f * 1200 / 3937 }')" 0.001 &&
		    near "$z" "$h" 0.05 ||
		    { echo "# ($1,$2): stored $z, file $ft ft, metres $h"; bad=1; }
		shift 2
	done
	ok $bad "feet: level-0 heights in metres (ft x 1200/3937) at 8 samples"
else
	ok 1 "feet: dem2vgis"
fi

# --- 3. a mask band over -32768, no nodata value -------------------------
$MK mask "$T/n.tif" "$T/mask.tif" &&
    gdalinfo "$T/mask.tif" | grep -q 'Mask Flags: PER_DATASET' &&
    ! gdalinfo "$T/mask.tif" | grep -q 'NoData' &&
    [ "$(gv "$T/mask.tif" 60 50)" = -32768 ]
ok $? "mask: fixture with an internal mask, -32768 under it, no nodata (gdalinfo)"
set -- $($MK stat "$T/mask.tif")	# voids N min X max Y count C
mvoids=$2 mmin=$4 mmax=$6
voids mask "$T/mask.tif"
[ "$(key mask voids)" = "$mvoids" ] && [ "$mvoids" -gt 1000 ]
ok $? "mask: -II voids = the $mvoids masked samples (got $(key mask voids))"
if pyramid mask "$T/mask.tif"; then
	zrange "$T/mask" >"$T/mask.z"
	awk -v lo="$mmin" -v hi="$mmax" '$1 == 0 && ($2 < lo - 0.001 || $3 > hi + 0.001) { exit 1 }' "$T/mask.z"
	ok $? "mask: level-0 heights within the crop's real range $mmin..$mmax (got $(awk '$1 == 0 { print $2 ".." $3 }' "$T/mask.z"))"
	awk -v lo="$mmin" '$2 < lo - 50 { exit 1 }' "$T/mask.z"
	ok $? "mask: no pits below $mmin - 50 m on any level ($(tr '\n' ' ' <"$T/mask.z"))"
	tileplay --verify "$T/mask" --dem "$T/mask.tif" >"$T/mask.v" 2>&1
	grep -q '^result: pass' "$T/mask.v"
	ok $? "mask: the checker passes against the masked DEM"
else
	ok 1 "mask: dem2vgis"
fi

# --- 4. NaN nodata ------------------------------------------------------
$MK nan "$T/n.tif" "$T/nan.tif" && gdalinfo "$T/nan.tif" | grep -qi 'NoData Value=nan'
ok $? "nan: fixture Float32 with NaN samples, nodata nan (gdalinfo)"
set -- $($MK stat "$T/nan.tif")
voids nan "$T/nan.tif"
[ "$(key nan voids)" = "$2" ] && [ "$(key nan nodata)" = nan ]
ok $? "nan: -II voids $2 and nodata nan (got $(key nan voids), $(key nan nodata))"
if pyramid nan "$T/nan.tif"; then
	tileplay --verify "$T/nan" --dem "$T/nan.tif" >"$T/nan.v" 2>&1
	grep -q '^result: pass' "$T/nan.v"
	ok $? "nan: the checker passes ($(grep '^result' "$T/nan.v"))"
	grep -q '"nodata": "nan"' "$T/nan/index.json"
	ok $? "nan: index.json has \"nodata\": \"nan\""
else
	ok 1 "nan: dem2vgis"
fi

# --- 5. south-up ----------------------------------------------------------
for c in n u; do
	$MK southup "$T/$c.tif" "$T/${c}s.tif" &&
	    gdalinfo "$T/${c}s.tif" | grep -Eq '^Pixel Size = \([0-9.]+,[0-9.]+\)' &&
	    [ "$(gv "$T/${c}s.tif" 5 149)" = "$(gv "$T/$c.tif" 5 0)" ]
	ok $? "south-up $c: fixture rows flipped, positive y step (gdalinfo)"
	info "${c}s" "$T/${c}s.tif"
	bad=0
	for k in size origin step crs raster; do
		[ "$(key "${c}s" $k)" = "$(key "$c" $k)" ] ||
		    { echo "# $k: '$(key "${c}s" $k)', north-up '$(key "$c" $k)'"; bad=1; }
	done
	ok $bad "south-up $c: -I size, origin, step, crs as the north-up crop's"
	pyramid "${c}n" "$T/$c.tif" && pyramid "${c}s" "$T/${c}s.tif" &&
	    diff -r "$T/${c}n" "$T/${c}s" >/dev/null
	ok $? "south-up $c: pyramid byte-identical to the north-up crop's (blocks, index)"
done

# --- 6. a geotransform without CRS -----------------------------------------
gdal_translate -q -a_ullr 1000 5500 7000 1000 "$T/u.tif" "$T/nocrs.tif" &&
    gdal_edit.py -a_srs "" "$T/nocrs.tif" &&
    ! gdalinfo "$T/nocrs.tif" | grep -q 'Coordinate System is' &&
    gdalinfo "$T/nocrs.tif" | grep -q '^Pixel Size = (30.0*,-30.0*)'
ok $? "no CRS: fixture with a 30 m geotransform and no CRS (gdalinfo)"
info nocrs "$T/nocrs.tif"
[ "$(key nocrs model)" = none ] && [ "$(key nocrs crs)" = - ] &&
    [ "$(key nocrs step)" = "30 -30" ] && [ "$(key nocrs origin)" = "1000 5500" ]
ok $? "no CRS: -I model none, crs -, step 30 -30, origin 1000 5500 (got $(key nocrs model), $(key nocrs step), $(key nocrs origin))"
dem2fqm "$T/nocrs.tif" "$T/nocrs.exr" 2>"$T/nocrs.err"
s=$?
[ $s -eq 0 ] && [ "$(rsinfo "$T/nocrs.exr" | awk '$2 == "geo:step" { print $4, $5 }')" = "30 -30" ]
ok $? "no CRS: dem2fqm exit 0, geo:step 30 -30 (exit $s)"
! grep -Eq -- '(^|[^[:alnum:]_-])-n([^[:alnum:]_-]|$)' "$T/nocrs.err" &&
    ! grep -Eq '(taken as|cells of) 1 m' "$T/nocrs.err"
ok $? "no CRS: the warning neither suggests -n nor says 1 m ($(head -c 200 "$T/nocrs.err"))"

# --- 7. PNG with a world file ---------------------------------------------
gdal_translate -q -of PNG -ot UInt16 -co WORLDFILE=YES "$T/u.tif" "$T/wf.png" &&
    [ -f "$T/wf.wld" ] && [ ! -e "$T/wf.png.aux.xml" ]
ok $? "world file: fixture wf.png + wf.wld, no .aux.xml"
# a world file gives the centre of pixel (0,0): the corner is half a step off
wf=$(awk 'NR == 1 { a = $1 } NR == 4 { e = $1 } NR == 5 { x = $1 } NR == 6 { y = $1 }
    END { printf "%.17g %.17g %.17g %.17g", x - a / 2, y - e / 2, a, e }' "$T/wf.wld")
set -- $wf
info wf "$T/wf.png"
near2 "$(key wf origin)" "$1 $2" 1e-6 && near2 "$(key wf step)" "$3 $4" 0
ok $? "world file: -I origin $1 $2 step $3 $4 (got $(key wf origin), $(key wf step))"
set -- $($MK stat "$T/wf.png")
[ "$(dem2fqm "$T/wf.png" - 2>/dev/null | rsinfo -c - | awk '$2 == "Z" { print $3, $4 }')" = "$4 $6" ]
ok $? "world file: heights range $4..$6 as the PNG's"

# --- 8. other formats: .asc, ENVI, .hgt.zip, VRT ----------------------------
gdal_translate -q -of AAIGrid "$T/u.tif" "$T/u.asc" &&
    gdal_translate -q -of ENVI -co INTERLEAVE=BIL "$T/u.tif" "$T/u.bil" &&
    gdal_translate -q -srcwin 0 0 100 150 "$T/u.tif" "$T/ul.tif" &&
    gdal_translate -q -srcwin 100 0 100 150 "$T/u.tif" "$T/ur.tif" &&
    gdalbuildvrt -q "$T/u.vrt" "$T/ul.tif" "$T/ur.tif" &&
    [ -f "$T/u.prj" ] && [ -f "$T/u.hdr" ]
ok $? "formats: u.asc (+.prj), u.bil (+.hdr), u.vrt (mosaic of two halves)"
hu=$(zhash "$T/u.tif")
for f in u.asc u.bil u.vrt; do
	info "$f" "$T/$f"
	[ "$(key "$f" size)" = "$(key u size)" ] &&
	    [ "$(key "$f" step)" = "$(key u step)" ] &&
	    near2 "$(key "$f" origin)" "$(key u origin)" 1e-6
	ok $? "$f: -I size, step, origin as u.tif's (got $(key "$f" size), $(key "$f" step), $(key "$f" origin))"
	[ "$(key "$f" crs)" = EPSG:32611 ]
	ok $? "$f: -I crs EPSG:32611 as u.tif's (got $(key "$f" crs | cut -c 1-60))"
	[ "$(zhash "$T/$f")" = "$hu" ]
	ok $? "$f: level-0 heights identical to u.tif's"
done
dem2fqm "$T/u.vrt" - >"$T/uv.fqm" && dem2fqm "$T/u.tif" - | cmp -s - "$T/uv.fqm"
ok $? "u.vrt: dem2fqm stream byte-identical to u.tif's"
mkdir "$T/z" && cp "$HGT" "$T/z/N44W072.hgt" &&
    if command -v zip >/dev/null; then
	(cd "$T/z" && zip -q N44W072.hgt.zip N44W072.hgt)
    else
	$PY -c 'import sys, zipfile
zipfile.ZipFile(sys.argv[1], "w", zipfile.ZIP_DEFLATED).write(sys.argv[2], "N44W072.hgt")' \
	    "$T/z/N44W072.hgt.zip" "$T/z/N44W072.hgt"
    fi && rm "$T/z/N44W072.hgt"
info hgtzip "$T/z/N44W072.hgt.zip"
info hgt "$HGT"
[ -s "$T/hgt.I" ] && cmp -s "$T/hgt.I" "$T/hgtzip.I"
ok $? "N44W072.hgt.zip: -I identical to the .hgt's"
dem2fqm "$HGT" - >"$T/hgt.fqm" && dem2fqm "$T/z/N44W072.hgt.zip" - | cmp -s - "$T/hgt.fqm"
ok $? "N44W072.hgt.zip: dem2fqm stream byte-identical to the .hgt's"

# --- 9. an .hgt on stdin through the driver --------------------------------
pyramid hgt "$HGT" &&
    dem2vgis -q -n N44W072.hgt - "$T/hgtin" <"$HGT" >"$T/hgtin.mk" 2>&1 &&
    diff -r "$T/hgt" "$T/hgtin" >/dev/null
ok $? "stdin: dem2vgis -n N44W072.hgt - gives the pyramid of the file ($(head -c 200 "$T/hgtin.mk"))"
fails "stdin: an .hgt without -n: exit 1, a message naming -n" 1 '(^|[^[:alnum:]_-])-n([^[:alnum:]_-]|$)' \
    sh -c 'dem2vgis -q - "$1" <"$2"' sh "$T/hgtno" "$HGT"

# --- 10. a sparse tiled GeoTIFF ------------------------------------------
gdal_translate -q -srcwin 300 200 256 200 "$BT" "$T/u2.tif" &&
    $MK sparse "$T/u2.tif" "$T/sp0.tif" &&
    gdal_translate -q -co TILED=YES -co BLOCKXSIZE=128 -co BLOCKYSIZE=128 \
	-co SPARSE_OK=TRUE "$T/sp0.tif" "$T/sparse.tif" &&
    [ "$($MK sparse_tiles "$T/sparse.tif")" = 1 ]
ok $? "sparse: fixture with one absent 128x128 tile (TIFF block offsets)"
set -- $($MK stat "$T/sparse.tif")
voids sparse "$T/sparse.tif"
s=$?
[ $s -eq 0 ] && [ "$(key sparse voids)" = "$2" ] && [ "$2" -ge 16384 ]
ok $? "sparse: reads (exit $s), voids $2 (got $(key sparse voids))"
dem2fqm "$T/sparse.tif" - >/dev/null 2>"$T/sparse.err"
ok $? "sparse: dem2fqm converts it"

# --- 11. rotation refused, -s on a georeferenced DEM ----------------------
$MK rotated "$T/u.tif" "$T/rot.tif" && gdalinfo "$T/rot.tif" | grep -q 'GeoTransform'
ok $? "rotated: fixture with rotation terms (gdalinfo shows a GeoTransform)"
fails "rotated: refused, exit 1" 1 'rotated' dem2fqm -I "$T/rot.tif"
fails "rotated: dem2fqm conversion refused, exit 1" 1 'rotated' dem2fqm "$T/rot.tif" -
info cell -s 25 "$T/u.tif"
[ "$(key cell cell)" = "25 25" ]
ok $? "-s 25 on a georeferenced DEM: -I says cell 25 25 (got '$(key cell cell)')"
info cell2 -s 25,20 "$T/n.tif"
[ "$(key cell2 cell)" = "25 20" ]
ok $? "-s 25,20 on a geographic DEM: -I says cell 25 20 (got '$(key cell2 cell)')"

# --- 12. ellipsoidal heights ----------------------------------------------
info hgte -H ellipsoid "$HGT"
[ "$(key hgte vdatum)" = EPSG:4979 ]
ok $? "-H ellipsoid on N44W072.hgt: vdatum EPSG:4979 (got '$(key hgte vdatum)')"
# the crop with its vertical datum (EGM96 height) in a compound CRS
gdal_translate -q -srcwin 600 500 200 150 -a_srs EPSG:4326+5773 "$HGT" "$T/egm.tif" &&
    gdalsrsinfo -o wkt1 "$T/egm.tif" | grep -q 'VERT_CS\["EGM96 height"'
ok $? "ellipsoid: crop with CRS EPSG:4326+5773 (gdalsrsinfo)"
if pyramid ell "$T/egm.tif" -H ellipsoid; then
	bad=0
	for s in "10 20" "150 30" "190 140"; do
		set -- $s
		# SRTM is pixel-is-point: crop sample (i,j) is tile sample
		# (600+i, 500+j) at lon -72 + (600+i)/1200, lat 45 - (500+j)/1200
		lon=$(awk -v i="$1" 'BEGIN { printf "%.12f", -72 + (600 + i) / 1200 }')
		lat=$(awk -v j="$2" 'BEGIN { printf "%.12f", 45 - (500 + j) / 1200 }')
		N=$(echo "$lat $lon 0" | cs2cs -f %.6f EPSG:4326+5773 EPSG:4979 | awk '{ print $3 }')
		h=$(gv "$T/egm.tif" "$1" "$2") z=$(z0 "$T/ell" "$1" "$2")
		d=$(awk -v z="$z" -v h="$h" 'BEGIN { printf "%.6f", z - h }')
		near "$d" "$N" 0.05 || { echo "# ($1,$2) lat $lat lon $lon: Z $z - DEM $h = $d, EGM96 undulation $N"; bad=1; }
	done
	ok $bad "ellipsoid: stored Z - DEM = EGM96 undulation (cs2cs) within 5 cm at 3 samples"
else
	ok 1 "ellipsoid: dem2vgis -H ellipsoid"
fi
fails "-H EPSG:3855: EGM2008 grid missing, exit 1" 1 'egm08' \
    dem2fqm -I -H EPSG:3855 "$HGT"
fails "-H ellipsoid on a crop without vertical datum: exit 1, names -D" 1 '(^|[^[:alnum:]_-])-D([^[:alnum:]_-]|$)' \
    dem2fqm -I -H ellipsoid "$T/n.tif"
info nD -H ellipsoid -D EPSG:5773 "$T/n.tif"
s=$?
[ $s -eq 0 ] && [ "$(key nD vdatum)" = EPSG:4979 ] &&
    [ "$(zhash "$T/n.tif" -H ellipsoid -D EPSG:5773)" = "$(zhash "$T/egm.tif" -H ellipsoid)" ]
ok $? "-D EPSG:5773 -H ellipsoid on that crop works, heights as the EGM96-tagged crop's (exit $s)"

# --- 13. -I reads the header only; -II counts the voids -------------------
voids hgtII "$HGT"
[ -z "$(key hgt voids)" ] && [ "$(key hgtII voids)" = 0 ] &&
    [ "$(grep -v '^voids ' "$T/hgtII.I")" = "$(cat "$T/hgt.I")" ] &&
    [ -n "$(key hgt levels)" ]
ok $? "-I: no voids line, the levels line; -II: the same lines and voids ($(key hgtII voids))"
dem2fqm -I -I "$HGT" | cmp -s - "$T/hgtII.I"
ok $? "-I -I is -II"
# a DEM of 10^10 samples (a VRT upsampling the .hgt, so --resample): the
# header's answer at once, nothing spooled
mkdir "$T/scratch"
gdal_translate -q -of VRT -outsize 100000 100000 "$HGT" "$T/huge.vrt"
t0=$(date +%s.%N)
TMPDIR=$T/scratch dem2fqm --resample -I "$T/huge.vrt" >"$T/huge.I" \
    2>"$T/huge.Ierr"
s=$?
t=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
[ $s -eq 0 ] && [ "$(key huge size)" = "100000 100000" ] &&
    [ "$(key huge levels)" = 11 ] && [ -z "$(key huge voids)" ] &&
    awk -v t="$t" 'BEGIN { exit !(t < 10) }'
ok $? "-I on a 100000x100000 VRT: size, levels 11, in $t s (under 10) (exit $s $(head -c 200 "$T/huge.Ierr"))"
[ -z "$(ls -A "$T/scratch")" ]
ok $? "-I on it leaves nothing in TMPDIR"

done_testing
