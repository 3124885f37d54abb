# t_dem2rgb_list - dem2rgb reads a list of DEM files (dem2fqm(1),
# MOSAICS) as dem2vgis does: a 257x257 crop of SRTM N48W125 (voids
# included) cut into 4 pieces that overlap or abut, listed (relative to
# the list's directory, in any order), gives the tree and the archive of
# the crop as one GeoTIFF byte for byte (Terrarium PNG, Terrain-RGB
# WebP); with a piece left out, those of the VRT of the other three (the
# hole void); the same in UTM. Refused with the reader's own message and
# nothing written: a missing entry, a directory, the output among the
# entries or around one, tiles in two CRSs, overlaps that disagree. The
# plan (--plan, make -j2) on the list: one process's tree and archive;
# an entry changed since the plan refused by its jobs.
. "$(dirname "$0")/../lib.sh"

gdal_translate -q -srcwin 2816 3080 257 257 "$DATA/N48W125.tif" "$T/crop.tif"
# cut SRC NAME: pieces of SRC (W x H) named NAME1.tif .. NAME4.tif
# around its middle (a, b): 1 and 2 abut, 3 overlaps 1 and 2 (8 rows up),
# 4 overlaps 3 and shares 2's last row
cut() {
	# shellcheck disable=SC2046
	set -- "$1" "$2" $(gdalinfo "$1" |
	    sed -n 's/^Size is \([0-9]*\), \([0-9]*\)/\1 \2/p')
	a=$(($3 / 2)) b=$(($4 / 2))
	gdal_translate -q -srcwin 0 0 $((a + 1)) $((b + 1)) "$1" "$T/$2"1.tif &&
	gdal_translate -q -srcwin $((a + 1)) 0 $(($3 - a - 1)) $((b + 1)) \
	    "$1" "$T/$2"2.tif &&
	gdal_translate -q -srcwin 0 $((b - 8)) $((a + 12)) $(($4 - b + 8)) \
	    "$1" "$T/$2"3.tif &&
	gdal_translate -q -srcwin $a $b $(($3 - a)) $(($4 - b)) "$1" "$T/$2"4.tif
}
cut "$T/crop.tif" p
ok $? "the crop cut into 4 pieces"
mkdir "$T/l"
printf '# the pieces\n../p1.tif\n../p2.tif\n\n../p3.tif\n../p4.tif\n' \
    >"$T/l/list.txt"
printf '%s\n' p4.tif p3.tif p2.tif p1.tif >"$T/rev.txt"

# nothing DIR: DIR absent and no temporary (".name.XXXXXX") left in $T
nothing() {
	[ ! -e "$1" ] && [ -z "$(find "$T" -maxdepth 1 -name '.*' ! -name .)" ]
}

# --- the tiles ---------------------------------------------------------
run "the list: a tree" dem2rgb -q -j 2 "$T/l/list.txt" "$T/lt"
dem2rgb -q -j 2 "$T/crop.tif" "$T/ct" && diff -r "$T/lt" "$T/ct" >/dev/null
ok $? "... the crop's tree byte for byte (Terrarium PNG, tiles.json)"
n=$(find "$T/lt" -name '*.png' | wc -l)
[ "$n" -ge 10 ]; ok $? "... $n tiles"
dem2rgb -q -z 11 "$T/crop.tif" "$T/c11" &&
    dem2rgb -q -j 1 -z 11 "$T/rev.txt" "$T/rt" &&
    diff -r "$T/rt" "$T/c11" >/dev/null
ok $? "the list reversed, one thread, -z 11: the crop's tree"
opts="-e mapbox -f webp -z 11"
# shellcheck disable=SC2086
dem2rgb -q $opts -o "$T/l.pmtiles" "$T/l/list.txt" &&
    dem2rgb -q $opts -o "$T/c.pmtiles" "$T/crop.tif" &&
    cmp -s "$T/l.pmtiles" "$T/c.pmtiles"
ok $? "$opts -o: the crop's archive byte for byte"

# a hole: p4 left out; a void as in the VRT of the other three
printf '%s\n' p1.tif p2.tif p3.tif >"$T/three.txt"
(cd "$T" && gdalbuildvrt -q three.vrt p1.tif p2.tif p3.tif)
dem2rgb -q -z 11 "$T/three.txt" "$T/ht" &&
    dem2rgb -q -z 11 "$T/three.vrt" "$T/hv" &&
    diff -r "$T/ht" "$T/hv" >/dev/null
ok $? "three pieces, a hole: the tree of their VRT"
! diff -r "$T/ht" "$T/c11" >/dev/null
ok $? "... not the whole crop's"

# UTM zone 10: pieces of the crop warped there
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r near "$T/crop.tif" "$T/utm.tif" &&
    cut "$T/utm.tif" u
printf '%s\n' u1.tif u2.tif u3.tif u4.tif >"$T/utm.txt"
dem2rgb -q -z 11 "$T/utm.txt" "$T/ut" &&
    dem2rgb -q -z 11 "$T/utm.tif" "$T/uc" && diff -r "$T/ut" "$T/uc" >/dev/null
ok $? "UTM pieces: the UTM DEM's tree byte for byte"

# --- refused ---------------------------------------------------------------
printf '%s\n' p1.tif nope.tif >"$T/miss.txt"
fails "a missing entry: refused, naming its line" 1 \
    "miss.txt: line 2: .*nope.tif: No such file" \
    dem2rgb -q "$T/miss.txt" "$T/res"
nothing "$T/res"; ok $? "... nothing written"
mkdir "$T/dd"
printf '%s\n' p1.tif dd >"$T/dir.txt"
fails "a directory entry: refused" 1 "dir.txt: line 2: .*dd: a directory" \
    dem2rgb -q -o "$T/res.pmtiles" "$T/dir.txt"
nothing "$T/res.pmtiles"; ok $? "... nothing written"
cp "$T/p4.tif" "$T/keep.tif"
fails "the output is an entry: refused" 1 \
    "p4.tif: is .*p4.tif, an entry of the input DEM list" \
    dem2rgb -q -o "$T/p4.tif" "$T/rev.txt"
cmp -s "$T/p4.tif" "$T/keep.tif" && nothing "$T/res"
ok $? "... the entry untouched, nothing written"
mkdir "$T/od" && cp "$T/p2.tif" "$T/od/x.tif"
printf '%s\n' p1.tif od/x.tif >"$T/in.txt"
fails "the output around an entry: refused" 1 \
    "od: contains .*x.tif, an entry of the input DEM list" \
    dem2rgb -q "$T/in.txt" "$T/od"
[ -f "$T/od/x.tif" ] && [ "$(ls "$T/od")" = x.tif ]
ok $? "... the directory untouched"
printf '%s\n' p1.tif u2.tif >"$T/crs.txt"
fails "tiles in two CRSs: refused" 1 "u2.tif: CRS .*UTM.*first file's" \
    dem2rgb -q "$T/crs.txt" "$T/res"
nothing "$T/res"; ok $? "... nothing written"
gdal_calc.py --quiet -A "$T/p3.tif" --outfile="$T/q3.tif" --calc="A+1" \
    >/dev/null 2>&1 && gdal_edit.py -mo AREA_OR_POINT=Point "$T/q3.tif"
printf '%s\n' p1.tif p2.tif q3.tif p4.tif >"$T/ov.txt"
fails "overlaps that disagree: refused, as dem2vgis refuses them" 1 \
    "q3.tif: sample .* where it overlaps .*p1.tif.*must agree" \
    dem2rgb -q "$T/ov.txt" "$T/res"
nothing "$T/res"; ok $? "... nothing written"

# --- the plan ----------------------------------------------------------------
P=$T/plan
dem2rgb --plan "$P" --part-tiles 1 "$T/l/list.txt" "$T/pt" 2>/dev/null &&
    [ "$(wc -l <"$P/targets1")" -ge 2 ] &&
    make -s -C "$P" -j2 >/dev/null 2>&1 && diff -r "$T/pt" "$T/lt" >/dev/null
ok $? "--plan on the list, parts by make -j2: one process's tree"
# shellcheck disable=SC2086
dem2rgb --plan "$T/plan2" --parts 2 $opts -o "$T/p.pmtiles" "$T/rev.txt" \
    2>/dev/null && make -s -C "$T/plan2" -j2 >/dev/null 2>&1 &&
    cmp -s "$T/p.pmtiles" "$T/l.pmtiles"
ok $? "--plan -o on the list: one process's archive"
dem2rgb --plan "$T/plan3" "$T/rev.txt" "$T/out3" 2>/dev/null &&
    touch -d '2001-01-01' "$T/p2.tif"
! make -s -C "$T/plan3" >"$T/make3.log" 2>&1 &&
    grep -q 'write the plan again' "$T/make3.log" && [ ! -e "$T/out3" ]
ok $? "an entry changed since the plan: its jobs refuse it"
done_testing
