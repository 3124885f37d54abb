#!/bin/sh
# t_tilepack_z - tilepack -z: the blocks' EXR compression. The default is
# ZIP and -z zip is the same pyramid, byte for byte; every other choice
# stores the same pixels and the same index (only the blocks' bytes
# differ), and the pyramid passes tilecheck against its DEM; a QEM-3D
# level's X and Y too. An unknown name is a usage error.
. "$(dirname "$0")/../lib.sh"
quick_skip "the blocks compressed by OpenEXR, our code only names the compressor"

# a window of N42E001 with voids, 1D and 3D vertex maps
gdal_translate -q -srcwin 500 850 300 260 "$DATA/N42E001.hgt" "$T/d.tif"
run "vertex maps" dem2vgis -q -M "$T/d.tif" "$T/vm1"
run "QEM-3D vertex maps" dem2vgis -q -3 -M "$T/d.tif" "$T/vm3"

# pixels DIR: every block's pixel hash, by path
pixels() {
	(cd "$1" && find . -name '*.exr' | sort | while read -r f; do
		echo "$f $(rsinfo -c "$f" | sed -n 's/^hash //p')"
	done)
}

for m in 1 3; do
	vm=$(ls "$T/vm$m"/v*.fqm | sort -V)
	# shellcheck disable=SC2086
	tilepack -q "$T/d.tif" "$T/p$m" $vm &&
		tilepack -q -z zip "$T/d.tif" "$T/p$m-zip" $vm
	ok $? "$m: tilepack, and -z zip"
	diff -r "$T/p$m" "$T/p$m-zip" >/dev/null
	ok $? "$m: -z zip is the default, byte for byte"
	pixels "$T/p$m" >"$T/h$m"
	[ -s "$T/h$m" ] && ! grep -q ' $' "$T/h$m"
	ok $? "$m: the blocks' pixel hashes"
	for z in none zips rle piz; do
		p=$T/p$m-$z
		# shellcheck disable=SC2086
		run "$m: -z $z" tilepack -q -z $z "$T/d.tif" "$p" $vm || continue
		cmp -s "$T/p$m/index.json" "$p/index.json"
		ok $? "$m: -z $z: the same index"
		pixels "$p" | cmp -s - "$T/h$m"
		ok $? "$m: -z $z: the same pixels in every block"
		[ -f "$p/0/0_0.exr" ] && ! cmp -s "$T/p$m/0/0_0.exr" "$p/0/0_0.exr"
		ok $? "$m: -z $z: other bytes"
		run "$m: -z $z: tilecheck against the DEM" \
		    tilecheck --dem "$T/d.tif" "$p"
	done
done
fails "-z lzw: a usage error" 2 "unknown compression" \
    tilepack -q -z lzw "$T/d.tif" "$T/bad" "$T/vm1/v0.fqm"

done_testing
