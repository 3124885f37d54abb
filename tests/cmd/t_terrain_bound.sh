# t_terrain_bound - vgis2terrain's analytic bound of the drawn surface
# against the selection (tr_bound.c), which spares the measure of a
# geographic DEM's tiles whose bound fits the level's budget: with
# VGIS2TERRAIN_MEASURE=all every sample is measured and checked against
# its triangle's bound (the export fails on one over it), and the
# terrain made without measuring those tiles is byte for byte the one
# made measuring all, in both formats, -j 1 and -j 2. On real DEMs: an
# ellipsoidal crop of N48W125 with coast cliffs and sea voids, a crop of
# N42E001 (the Pyrenees, SRTM 3"), UTM 10N warps of two crops of N48W125
# and one moved to 85 N in polar stereographic (projected: the CRS term
# in the bound, the sides' samples measured).
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3

# levels measured in part or not at all: the share the report gives
# ("measured D m at S% of samples"); every level's bound within E_L
shares() {
	awk '/ level [0-9]+: .*bound/ {
		for (i = 1; i <= NF; i++) if ($i == "at") s = $(i + 1) + 0
		if ($(NF - 1) > 1) bad++
		if (s < 100) part++; n++
	} END { printf "#   %d levels, %d not measured whole\n", n, part
	    exit !(n > 0 && !bad && part >= '"$2"') }' "$1"
}

# DEM LABEL: its pyramid exported measuring all (checked) and not, both
# formats; the second argument of shares: levels that must skip
exports() {
	dem2vgis -q "$1" "$T/pyr" 2>/dev/null
	run "$2: every sample within its triangle's bound (qm)" \
	    env VGIS2TERRAIN_MEASURE=all vgis2terrain -j 2 "$T/pyr" "$T/all"
	! grep 'level ' "$T/err" | grep -vq 'at 100.0% of samples; bound'
	ok $? "$2: measuring all, every level at 100% of samples"
	run "$2: the bound's tiles not measured, -j 2" \
	    vgis2terrain -j 2 "$T/pyr" "$T/skip2"
	cp "$T/err" "$T/rep"
	shares "$T/rep" "$3"; ok $? "$2: within E_L; $3 levels or more measured in part"
	run "$2: -j 1" vgis2terrain -q -j 1 "$T/pyr" "$T/skip1"
	diff -r "$T/all" "$T/skip2" >/dev/null && diff -r "$T/all" "$T/skip1" \
	    >/dev/null
	ok $? "$2: qm byte-identical measuring all or not, -j 1 and -j 2"
	run "$2: every sample within its triangle's bound (3dtiles)" \
	    env VGIS2TERRAIN_MEASURE=all vgis2terrain -q -j 2 -f 3dtiles \
	    "$T/pyr" "$T/all3"
	run "$2: 3dtiles, -j 1" vgis2terrain -q -j 1 -f 3dtiles "$T/pyr" \
	    "$T/skip3"
	diff -r "$T/all3" "$T/skip3" >/dev/null
	ok $? "$2: 3dtiles byte-identical measuring all or not"
	rm -rf "$T/pyr" "$T/all" "$T/skip1" "$T/skip2" "$T/all3" "$T/skip3"
}

# 769 x 769 samples of N48W125 at 1": the coast, sea voids, cliffs
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 2700 1500 769 769 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/n48.tif"
exports "$T/n48.tif" "N48W125 coast" 8

# 601 x 601 of N42E001 (SRTM 3"): steep mountains
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 300 300 601 601 \
    "$DATA/N42E001.hgt" "$T/srtm2.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm2.tif" "$T/n42.tif"
exports "$T/n42.tif" "N42E001 mountains" 8

# UTM (projected: the bound holds the CRS term, tr_crs.c, and the
# samples near the grid's sides are measured): a land crop warped
# inside its valid footprint, and the coast crop warped whole (its
# corners past the footprint, sea against cliffs)
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1696 2176 513 513 \
    "$DATA/N48W125.hgt" "$T/srtm3.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm3.tif" "$T/land.tif"
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r bilinear -te 388000 5347000 \
    396000 5360000 "$T/land.tif" "$T/utm.tif"
exports "$T/utm.tif" "UTM land" 8
gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 2700 1500 769 769 \
    "$DATA/N48W125.hgt" "$T/srtm4.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm4.tif" "$T/coast.tif"
gdalwarp -q -t_srs EPSG:32610 -r bilinear "$T/coast.tif" "$T/utmc.tif"
exports "$T/utmc.tif" "UTM coast" 8
# polar stereographic (EPSG:3413) at 85 N: the coast crop moved there,
# the map's curve at its strongest, long band triangles bowing far in
gdal_translate -q -a_srs EPSG:4326 -a_ullr -40 85.2 -39.786 84.986 \
    "$T/coast.tif" "$T/polar.tif"
gdalwarp -q -t_srs EPSG:3413 -r bilinear "$T/polar.tif" "$T/pst.tif"
exports "$T/pst.tif" "polar stereographic" 8

done_testing
