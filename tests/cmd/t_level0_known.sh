#!/bin/sh
# t_level0_known - level 0's vertex map is known, not computed: every plane
# of a level-0 quadric passes through its vertex (b = 0), so fqmsolve
# takes the vertex as the minimiser and skips the fold check of rows on
# the grid (solve.c). On real DEMs with voids (filled samples, V = 0) and
# without: the vertex map with the known answers taken is the one fully
# computed (TL_SOLVE_FULL), byte for byte, in both modes; it is the known
# answer (QEM-1D's heights are the FQM's Z, QEM-3D's Z and V are QEM-1D's
# and its offsets zero); and a QEM-3D pyramid is the same either way.
. "$(dirname "$0")/../lib.sh"
quick_skip "the shortcut gives the full solve's bytes (its code runs in every pyramid built under the sanitizers)"

# a window of N48W125 across its coast: half voids, half land
gdal_translate -q -srcwin 1200 1500 500 600 "$DATA/N48W125.hgt" "$T/coast.tif"
# a window of N42E001 with 2000-odd scattered voids
gdal_translate -q -srcwin 500 850 400 350 "$DATA/N42E001.hgt" "$T/pyrenees.tif"

# hash F [CHANNEL...]: the pixel hash of F without the channels named
hash() {
	f=$1; shift
	for c in "$@"; do
		rsinfo -d "$c" -o "$T/strip.exr" "$f" >/dev/null &&
			cp "$T/strip.exr" "$T/h.exr" && f=$T/h.exr
	done
	rsinfo -c "$f" | sed -n 's/^hash //p'
}

for dem in "$T/coast.tif" "$T/pyrenees.tif" "$DATA/bigtujunga.tif"; do
	n=$(basename "$dem")
	run "$n: level 0" dem2fqm "$dem" "$T/l0.exr" || continue
	for m in qem1d qem3d filtered; do
		fqmsolve -m $m "$T/l0.exr" "$T/$m.exr" &&
			TL_SOLVE_FULL=1 fqmsolve -m $m "$T/l0.exr" "$T/$m-full.exr"
		ok $? "$n: $m of level 0, known and computed"
		cmp -s "$T/$m.exr" "$T/$m-full.exr"
		ok $? "$n: $m: the known answers are the computed ones, byte for byte"
	done
	if [ "$n" != bigtujunga.tif ]; then
		rsinfo -c "$T/l0.exr" | grep -q '^range V 0 '
		ok $? "$n: voids at level 0 (V = 0)"
	fi
	# the known answer: Z the FQM's (filtered's Z), zero offsets
	h1=$(hash "$T/qem1d.exr") hf=$(hash "$T/filtered.exr")
	h3=$(hash "$T/qem3d.exr" X Y)
	[ -n "$h1" ] && [ "$h1" = "$hf" ]
	ok $? "$n: QEM-1D's level 0 is the FQM's heights ($h1 $hf)"
	[ "$h3" = "$h1" ]
	ok $? "$n: QEM-3D's level 0 has QEM-1D's heights and validities"
	rsinfo -c "$T/qem3d.exr" | grep -c '^range [XY] 0 0$' | grep -qx 2
	ok $? "$n: QEM-3D's level-0 offsets are zero"
done

# the pyramid, every level and tile, through dem2vgis's route
dem2vgis -q -3 "$T/coast.tif" "$T/p" &&
	TL_SOLVE_FULL=1 dem2vgis -q -3 "$T/coast.tif" "$T/pfull"
ok $? "coast: QEM-3D pyramids, known and computed"
diff -r "$T/p" "$T/pfull" >/dev/null
ok $? "coast: the two pyramids are the same, byte for byte"

done_testing
