# t_mosaic - a mosaic is a DEM: N44W072.tif cut by gdal_translate into
# 2 x 2 tiles sharing their edge row and column (like SRTM), read as a
# list file, as a VRT made by gdalbuildvrt and (dem2vgis) as several
# files, gives the uncut DEM's header and, block file for block file, its
# pyramid (QEM-1D and QEM-3D); tiles that do not fit (pixel size, CRS,
# grid, sample type, nodata, a shared edge that differs) are refused
# naming the file; a missing tile is a void of the size the tiles' extents
# give (awk), and tiles without nodata get the type's lowest for it.
# Fixtures from GDAL's tools; answers from GDAL, awk and numpy only.
# shellcheck disable=SC2086 # numbers split into words on purpose
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
GDAL_PAM_ENABLED=NO	# the GDAL tools: no .aux.xml sidecars
export GDAL_PAM_ENABLED
DEM=$DATA/N44W072.tif HGT=$DATA/N44W072.hgt
D=$T/t	# the tiles, their list and VRT
mkdir -p "$D"
# side: a tile's (the uncut DEM is 2 side - 1 square); last: a tile's
# last sample; mid: its middle one. Under TL_QUICK (the sanitizers) the
# uncut DEM is a 601x601 crop of N44W072.tif, its tiles 301 square: the
# same code, a quarter of the samples.
side=601
if [ -n "${TL_QUICK:-}" ]; then
	side=301
	gdal_translate -q -srcwin 0 0 601 601 "$DEM" "$T/uncut.tif" ||
	    { ok 1 "a crop"; done_testing; exit 1; }
	DEM=$T/uncut.tif
fi
N=$((2 * side - 1)) last=$((side - 1)) mid=$((side / 2))

# same_blocks A B: the same block files (*/*.exr), each byte-identical
same_blocks() {
	(cd "$1" && ls -- */*.exr) >"$T/ba" 2>/dev/null &&
	    (cd "$2" && ls -- */*.exr) >"$T/bb" 2>/dev/null &&
	    [ "$(wc -l <"$T/ba")" -gt 10 ] && cmp -s "$T/ba" "$T/bb" || return 1
	while read -r f; do cmp -s "$1/$f" "$2/$f" || { echo "#   $f differs"; return 1; }; done <"$T/ba"
}
# origin FILE: "x y" of its upper left corner; px FILE: "dx dy" (gdalinfo)
origin() { gdalinfo "$1" | sed -n 's/^Origin = (\(.*\),\(.*\))$/\1 \2/p'; }
px() { gdalinfo "$1" | sed -n 's/^Pixel Size = (\(.*\),\(.*\))$/\1 \2/p'; }
# mklist NAME TILE...: a list in $D, with a comment and a blank line
mklist() {
	l_n=$1; shift
	{ echo "# tiles of N44W072"; echo; printf '%s\n' "$@"; } >"$D/$l_n"
}

# --- the tiles ------------------------------------------------------------
# a b / c d, side x side each, a's last column b's first, a's last row c's
for t in "a 0 0" "b $last 0" "c 0 $last" "d $last $last"; do
	set -- $t
	gdal_translate -q -srcwin "$2" "$3" $side $side "$DEM" "$D/$1.tif" || break
done
[ "$(gdallocationinfo -valonly "$D/a.tif" $last $mid)" = "$(gdallocationinfo -valonly "$D/b.tif" 0 $mid)" ] &&
    [ "$(gdallocationinfo -valonly "$D/a.tif" $mid $last)" = "$(gdallocationinfo -valonly "$D/c.tif" $mid 0)" ] &&
    gdalinfo "$D/d.tif" | grep -q "^Size is $side, $side" &&
    gdalinfo "$D/a.tif" | grep -q 'AREA_OR_POINT=Point'
ok $? "4 tiles of $side x $side, edges shared, pixel-is-point (gdallocationinfo, gdalinfo)" ||
    { done_testing; exit 1; }
mklist tiles.txt a.tif b.tif c.tif d.tif
(cd "$D" && gdalbuildvrt -q m.vrt a.tif b.tif c.tif d.tif) &&
    ! grep -q AREA_OR_POINT "$D/m.vrt"
ok $? "gdalbuildvrt's VRT of the tiles (which drops AREA_OR_POINT)"

# --- the header -----------------------------------------------------------
# from another directory: the list's entries are relative to the list
dem2fqm -I "$DEM" >"$T/u.I"
(cd "$T" && dem2fqm -I t/tiles.txt) >"$T/l.I" 2>"$T/l.err"
diff "$T/u.I" "$T/l.I" >"$T/l.diff" && grep -q "^size $N $N\$" "$T/l.I"
ok $? "dem2fqm -I of the list: the uncut DEM's size, georeferencing, levels ($(head -c 200 "$T/l.diff" "$T/l.err" | tr '\n' ' '))"
printf '  a.tif \r\n\t# b.tif\r\nb.tif\r\n\r\nc.tif\r\n\td.tif\n' >"$D/crlf.txt" &&
    dem2fqm -I "$D/crlf.txt" >"$T/crlf.I" && diff "$T/u.I" "$T/crlf.I" >/dev/null
ok $? "a list with CRLF line ends, blanks around names, an indented comment: the same"
dem2fqm -I "$D/m.vrt" >"$T/v.I" && diff "$T/u.I" "$T/v.I" >/dev/null
ok $? "dem2fqm -I of gdalbuildvrt's VRT: the same, pixel-is-point from its tiles"
# an .hgt in a list: still EGM96 heights, as the .hgt alone
echo "$HGT" >"$T/hgt.txt" && gdalbuildvrt -q "$T/hgt.vrt" "$HGT" &&
    dem2fqm -I "$HGT" >"$T/h.I" && dem2fqm -I "$T/hgt.txt" >"$T/hl.I" &&
    dem2fqm -I "$T/hgt.vrt" >"$T/hv.I" && grep -q '^vdatum EPSG:5773$' "$T/h.I" &&
    diff "$T/h.I" "$T/hl.I" >/dev/null && diff "$T/h.I" "$T/hv.I" >/dev/null
ok $? "an .hgt listed or in a VRT: -I as the .hgt's own (vdatum EPSG:5773, point)"

# --- pyramids ---------------------------------------------------------------
pyramid() {	# pyramid DIR DEM...: dem2vgis -q DEM... $T/DIR
	p_n=$1; shift
	dem2vgis -q "$@" "$T/$p_n" >"$T/$p_n.out" 2>&1 ||
	    { sed 's/^/#   /' "$T/$p_n.out" | head -5; return 1; }
}
run "the uncut DEM's pyramid (QEM-1D)" pyramid pu "$DEM"
pyramid pl "$D/tiles.txt" && same_blocks "$T/pu" "$T/pl"
ok $? "the list's pyramid: every block byte-identical to the uncut DEM's ($(wc -l <"$T/ba") blocks)"
pyramid pv "$D/m.vrt" && same_blocks "$T/pu" "$T/pv"
ok $? "gdalbuildvrt's VRT's pyramid: every block byte-identical"
# relative names from the current directory, into dem2vgis's own list
(cd "$D" && pyramid pm a.tif b.tif c.tif d.tif) && same_blocks "$T/pu" "$T/pm"
ok $? "dem2vgis a.tif b.tif c.tif d.tif: every block byte-identical"
tilecheck --dem "$D/tiles.txt" "$T/pl" >"$T/tc" 2>&1 && grep -q '^result: pass' "$T/tc"
ok $? "tilecheck --dem of the list: the pyramid passes ($(grep '^result' "$T/tc"))"
pyramid p3u -3 "$DEM" && pyramid p3l -3 "$D/tiles.txt" && same_blocks "$T/p3u" "$T/p3l"
ok $? "QEM-3D: the list's pyramid byte-identical to the uncut DEM's"

# --- refusals: exit 1, the file named ---------------------------------------
# other pixel size; other CRS; origin 0.3 pixel east; one shared sample
gdal_translate -q -outsize $mid $mid "$D/b.tif" "$D/b_res.tif"
gdal_translate -q -a_srs EPSG:4269 "$D/b.tif" "$D/b_crs.tif"
set -- $(origin "$D/b.tif") $(px "$D/b.tif")
gdal_translate -q -a_ullr $(awk -v x="$1" -v y="$2" -v dx="$3" -v dy="$4" \
    -v k=$side 'BEGIN { x += 0.3 * dx; printf "%.15f %.15f %.15f %.15f", x, y, x + k * dx, y + k * dy }') \
    "$D/b.tif" "$D/b_off.tif"
gdal_translate -q -ot Float32 "$D/b.tif" "$D/b_f32.tif"
gdal_translate -q -a_nodata -9999 "$D/b.tif" "$D/b_nd.tif"
cp "$D/b.tif" "$D/b_edge.tif" && $PY -c 'import sys
from osgeo import gdal
ds = gdal.Open(sys.argv[1], gdal.GA_Update)
b = ds.GetRasterBand(1)
r = int(sys.argv[2])
a = b.ReadAsArray(0, r, 1, 1)
a[0, 0] += 1
b.WriteArray(a, 0, r)' "$D/b_edge.tif" $mid
[ "$(gdallocationinfo -valonly "$D/b_edge.tif" 0 $mid)" -eq $(( $(gdallocationinfo -valonly "$D/a.tif" $last $mid) + 1 )) ] &&
    gdalinfo "$D/b_res.tif" | grep -q "Size is $mid, $mid" &&
    gdalsrsinfo -o epsg "$D/b_crs.tif" | grep -q 4269 &&
    [ "$(origin "$D/b_off.tif" | cut -d' ' -f2)" = "$(origin "$D/b.tif" | cut -d' ' -f2)" ] &&
    [ "$(origin "$D/b_off.tif")" != "$(origin "$D/b.tif")" ]
ok $? "misfits of b.tif: ${mid}x$mid, EPSG:4269, origin moved east, one edge sample +1 (GDAL)"
for m in "res pixel size" "crs CRS" "off origin off" "f32 Float32 samples" \
    "nd nodata -9999"; do
	k=${m%% *} why=${m#* }
	mklist "l_$k.txt" a.tif "b_$k.tif" c.tif d.tif
	fails "b_$k.tif in the list: exit 1, '$why', named" 1 \
	    "^dem2fqm: [^ ]*b_$k.tif: $why" dem2fqm -I "$D/l_$k.txt"
done
mklist l_edge.txt a.tif b_edge.tif c.tif d.tif
fails "a shared edge that differs: exit 1, the sample and both files named" 1 \
    "^dem2fqm: [^ ]*b_edge.tif: sample 0,$mid is [0-9]+ where it overlaps [^ ]*a.tif, whose sample $last,$mid" \
    dem2fqm "$D/l_edge.txt" "$T/edge.fqm"
[ ! -e "$T/edge.fqm" ]; ok $? "... and no output left"
fails "dem2vgis with that tile: exit 1, dem2fqm's message" 1 \
    "^dem2fqm: [^ ]*b_edge.tif: sample 0,$mid " \
    dem2vgis -q "$D/a.tif" "$D/b_edge.tif" "$D/c.tif" "$D/d.tif" "$T/pe"
[ ! -e "$T/pe" ]; ok $? "... and no pyramid"
fails "dem2vgis with a missing tile: exit 1, named" 1 \
    "^dem2vgis: $D/none.tif: No such file" \
    dem2vgis -q "$D/a.tif" "$D/none.tif" "$T/pn"
fails "dem2vgis with - among several: exit 2" 2 "^dem2vgis: -: stdin" \
    dem2vgis -q "$D/a.tif" - "$T/pn"
mklist l_none.txt a.tif none.tif c.tif
fails "a list line naming no file: exit 1, the list and the line named" 1 \
    "^dem2fqm: [^ ]*l_none.txt: line 4: [^ ]*none.tif: No such file" \
    dem2fqm -I "$D/l_none.txt"
printf 'some text\nnot naming files\n' >"$D/text.txt"
fails "a text file naming no file: not a raster nor a list" 1 \
    "^dem2fqm: [^ ]*text.txt: not a raster .* nor a list" dem2fqm -I "$D/text.txt"

# --- a missing tile: a void -------------------------------------------------
# a, b, c: the void is what d alone covered, counted over the grid of the
# tiles' extents (gdalinfo origins and sizes) by awk; the DEM has no
# nodata sample of its own (numpy)
mklist l3.txt a.tif b.tif c.tif
for t in a b c; do
	set -- $(origin "$D/$t.tif") $(px "$D/$t.tif")
	echo "$1 $2 $3 $4 $side $side"
done >"$T/ext"
want=$(awk 'NR == 1 { x0 = $1; y0 = $2; dx = $3; dy = $4 }
    { c0[NR] = int(($1 - x0) / dx + 0.5); r0[NR] = int(($2 - y0) / dy + 0.5)
      w[NR] = $5; h[NR] = $6; n = NR
      if (c0[NR] + w[NR] > W) W = c0[NR] + w[NR]; if (r0[NR] + h[NR] > H) H = r0[NR] + h[NR] }
    END { for (j = 0; j < H; j++) for (i = 0; i < W; i++) {
        in_ = 0; for (k = 1; k <= n; k++)
            if (i >= c0[k] && i < c0[k] + w[k] && j >= r0[k] && j < r0[k] + h[k]) { in_ = 1; break }
        if (!in_) v++ }
      print W, H, v + 0 }' "$T/ext")
own=$($PY -c 'import sys
from osgeo import gdal
ds = gdal.Open(sys.argv[1])
b = ds.GetRasterBand(1)
print(int((b.ReadAsArray() == b.GetNoDataValue()).sum()))' "$DEM")
set -- $want
dem2fqm -II "$D/l3.txt" >"$T/l3.I" 2>"$T/l3.err"
[ "$1 $2" = "$N $N" ] && [ "$own" = 0 ] &&
    grep -q "^size $1 $2\$" "$T/l3.I" && grep -q "^voids $3\$" "$T/l3.I" &&
    grep -q '^nodata -32768$' "$T/l3.I"
ok $? "3 tiles of 4: -II voids $3 (awk: ${1}x$2, $own of its own; got $(grep -E '^(size|voids)' "$T/l3.I" | tr '\n' ' ')$(head -c 100 "$T/l3.err"))"
pyramid p3 "$D/l3.txt" && [ -f "$T/p3/index.json" ] && [ -n "$(ls "$T/p3/0")" ]
ok $? "3 tiles of 4: the pyramid builds over the void"
# no nodata: the gap gets the type's lowest (Int16) or NaN (Float32)
for t in a b c; do
	gdal_translate -q -a_nodata none "$D/$t.tif" "$D/${t}_nn.tif" &&
	    gdal_translate -q -a_nodata none -ot Float32 "$D/$t.tif" "$D/${t}_fl.tif"
done
mklist l3nn.txt a_nn.tif b_nn.tif c_nn.tif
mklist l3fl.txt a_fl.tif b_fl.tif c_fl.tif
! gdalinfo "$D/a_nn.tif" | grep -q NoData && dem2fqm -II "$D/l3nn.txt" >"$T/nn.I" &&
    dem2fqm -II "$D/l3fl.txt" >"$T/fl.I" &&
    grep -q '^nodata -32768$' "$T/nn.I" && grep -q "^voids $3\$" "$T/nn.I" &&
    grep -q '^nodata nan$' "$T/fl.I" && grep -q "^voids $3\$" "$T/fl.I"
ok $? "3 tiles without nodata: the void's nodata -32768 (Int16), nan (Float32), $3 voids each"
gdal_translate -q -a_nodata none "$D/d.tif" "$D/d_nn.tif"
mklist l4nn.txt a_nn.tif b_nn.tif c_nn.tif d_nn.tif
dem2fqm -I "$D/l4nn.txt" >"$T/nn4.I" && ! grep -q '^nodata' "$T/nn4.I"
ok $? "4 tiles without nodata and no gap: no nodata made up"
done_testing
