# t_metres - true metres through the whole toolchain: the same terrain (a
# crop of N44W072.hgt) as EPSG:4326 and warped by gdalwarp to Web Mercator,
# UTM 19N and Arctic polar stereographic. The distance between two samples
# in the viewer's world (tileplay --probe) must agree with the WGS84
# geodesic between them (gdaltransform for their latitude and longitude,
# GeodSolve for the distance: neither is our code) within 0.1 %; and the
# QEM-1D level-1 RMS error of the Web Mercator and UTM versions, which
# have the same ground resolution, within 2 % of each other.
. "$(dirname "$0")/../lib.sh"
PATH=$TOP/scripts:$PATH

gdal_translate -q -srcwin 300 300 400 400 "$DATA/N44W072.hgt" "$T/w4326.tif"
for c in 3857 32619 3995; do
	gdalwarp -q -t_srs EPSG:$c -r cubic "$T/w4326.tif" "$T/w$c.tif"
done

# world F I J: the viewer's world x y of level-0 sample (I, J) of F
world() {
	tileplay "$T/p" --shot "$T/x.png" --size 32x32 --probe "$2,$3" |
	    sed -n 's/.* world \([-0-9.]*\),\([-0-9.]*\),.*/\1 \2/p'
}

# geod F I J I2 J2: WGS84 geodesic metres between the samples' centres
# (pixel-is-point rasters have them on the integer positions)
geod() {
	h=0.5
	gdalinfo "$1" | grep -q 'AREA_OR_POINT=Point' && h=0
	awk -v h="$h" -v a="$2" -v b="$3" -v c="$4" -v d="$5" \
	    'BEGIN { print a + h, b + h; print c + h, d + h }' |
	    gdaltransform "$1" -t_srs EPSG:4326 -output_xy |
	    awk 'NR == 1 { a = $2 " " $1 } NR == 2 { print a, $2, $1 }' |
	    GeodSolve -i -p 6 | awk '{ print $3 }'
}

for c in 4326 3857 32619 3995; do
	f=$T/w$c.tif
	rm -rf "$T/p"
	run "EPSG:$c: dem2vgis" dem2vgis -q "$f" "$T/p" || continue
	# a row, a column and a diagonal, about a quarter of the crop
	for pair in "60 80 160 80" "60 80 60 180" "60 80 160 180" \
	    "200 250 120 170"; do
		set -- $pair
		a=$(world "$f" "$1" "$2") b=$(world "$f" "$3" "$4")
		g=$(geod "$f" "$1" "$2" "$3" "$4")
		r=$(echo "$a $b $g" |
		    awk '{ printf "%.6f", sqrt(($3-$1)^2 + ($4-$2)^2) / $5 }')
		awk -v r="$r" 'BEGIN { exit !(r > 0.999 && r < 1.001) }'
		ok $? "EPSG:$c: samples ($1,$2)-($3,$4): viewer distance / \
geodesic = $r"
	done
done

# level-1 RMS (fqmeval: every valid DEM sample) of F's QEM-1D level 1
rms() {
	dem2fqm "$1" - | fqmfilter - - | fqmsolve - "$T/v1.exr" &&
	    fqmeval "$1" "$T/v1.exr" | awk '{ print $2 }'
}
a=$(rms "$T/w3857.tif") b=$(rms "$T/w32619.tif")
r=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.4f", a / b }')
awk -v r="$r" 'BEGIN { exit !(r > 0.98 && r < 1.02) }'
ok $? "level-1 RMS, Web Mercator $a m, UTM $b m: ratio $r within 2 %"
done_testing
