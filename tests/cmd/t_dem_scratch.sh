# t_dem_scratch - the DEM reader's scratch file is written a band of GDAL
# windows at a time (dem_load_band) and void-filled in chunks of rows
# (dem_voidfill.c): the same samples in any block layout give the same
# level-0 map, byte for byte (dem2fqm), and the same void count
# (dem2fqm -II). On a crop of N48W125 with voids, 3601 x 2500: striped
# (the reference), tiled 256 x 256 (2500 rows: the last band short),
# tiled 16 x 2400 (its first band is over DEM_BANDBYTES, 32 MiB, so its
# puts write unstaged; the second is staged), tiled 512 x 128 with a
# column window of the mosaic route (a list of two crops); and a DEM one
# row high, striped and tiled.
. "$(dirname "$0")/../lib.sh"

GDAL_PAM_ENABLED=NO; export GDAL_PAM_ENABLED
TMPDIR=$T/tmp; export TMPDIR; mkdir "$TMPDIR"
c=$T/crop.tif
gdal_translate -q -srcwin 0 1100 3601 2500 "$DATA/N48W125.tif" "$c" &&
    gdal_translate -q -co TILED=YES "$c" "$T/t256.tif" &&
    gdal_translate -q -co TILED=YES -co BLOCKXSIZE=16 -co BLOCKYSIZE=2400 \
    "$c" "$T/tall.tif" &&
    gdal_translate -q -co TILED=YES -co BLOCKXSIZE=512 -co BLOCKYSIZE=128 \
    -srcwin 0 0 1900 2500 "$c" "$T/a.tif" &&
    gdal_translate -q -srcwin 1800 0 1801 2500 "$c" "$T/b.tif" &&
    gdal_translate -q -srcwin 0 700 3601 1 "$c" "$T/row.tif" &&
    gdal_translate -q -co TILED=YES -srcwin 0 700 3601 1 "$c" \
    "$T/rowt.tif" ||
    { ok 1 "fixtures"; done_testing; exit 1; }
printf '%s\n%s\n' "$T/a.tif" "$T/b.tif" >"$T/list"

# voids FILE: the void count dem2fqm -II reads
voids() {
	dem2fqm -II "$1" 2>/dev/null | sed -n 's/^voids //p'
}

run "striped crop: level-0 map" dem2fqm "$c" "$T/ref.fqm"
v=$(voids "$c")
[ "${v:-0}" -gt 100000 ]; ok $? "the crop has voids ($v)"
for f in t256 tall list; do
	in=$T/$f.tif
	[ $f = list ] && in=$T/list
	dem2fqm "$in" "$T/$f.fqm" 2>"$T/err"
	cmp -s "$T/ref.fqm" "$T/$f.fqm"
	ok $? "$f: the striped crop's level-0 map, byte for byte"
	[ "$(voids "$in")" = "$v" ]
	ok $? "$f: the striped crop's void count"
done
r=$(voids "$T/row.tif")
[ "${r:-0}" -gt 0 ] && [ "$r" = "$(voids "$T/rowt.tif")" ]
ok $? "one row high, striped and tiled: the same void count ($r)"
[ -z "$(ls -A "$TMPDIR")" ]
ok $? "no scratch file left in TMPDIR"
done_testing
