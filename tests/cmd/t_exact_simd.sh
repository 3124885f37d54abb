# t_exact_simd - the exact-error kernel's two copies (exact_error.c,
# undisplaced_scan.c: one compiled for AVX2, one plain, chosen at run time;
# TL_NO_AVX2 forces the plain one) give the same pyramid, byte for byte, on
# real DEMs: QEM-1D (the integer scan) and QEM-3D (the displaced test), a
# DEM with voids (NaN samples, which no maximum may pick), and a piece
# made alone (-p, a window not at column 0).
. "$(dirname "$0")/../lib.sh"
quick_skip "the AVX2 and plain kernels give the same bytes (arithmetic, no memory path of its own)"
PATH=$B:$PATH

if grep -qw avx2 /proc/cpuinfo 2>/dev/null; then
	echo "# this CPU has AVX2: the default runs take the AVX2 copies"
else
	echo "# no AVX2 here: both runs take the plain copies"
fi

# voids: bigtujunga with a band of its nodata and scattered holes
/usr/bin/python3 - "$DATA/bigtujunga.tif" "$T/holes.tif" <<'EOF' ||
import sys
from osgeo import gdal
src = gdal.Open(sys.argv[1])
b = src.GetRasterBand(1)
nd = b.GetNoDataValue()
a = b.ReadAsArray()
a[40:60, :] = nd
a[::37, ::13] = nd
d = gdal.GetDriverByName("GTiff").CreateCopy(sys.argv[2], src)
d.GetRasterBand(1).WriteArray(a)
d = None
EOF
	{ ok 1 "the DEM with voids"; done_testing; exit 1; }

# same DEM MODE: tilepack of the vertex maps with and without the AVX2
# copies, -j2 and -j1, compared file by file
same() {
	dem=$1 m=$2 f=""
	[ "$m" = 3d ] && f=-3
	n=$(basename "$dem")-$m
	dem2vgis -q $f -M "$dem" "$T/vm-$n" || { ok 1 "$n: vertex maps"; return; }
	set -- $(ls "$T/vm-$n"/v*.fqm | sort -V)
	tilepack -q -j2 "$dem" "$T/a-$n" "$@" &&
	    TL_NO_AVX2=1 tilepack -q -j1 "$dem" "$T/b-$n" "$@" &&
	    diff -r "$T/a-$n" "$T/b-$n" >"$T/diff" 2>&1
	s=$?
	[ $s -eq 0 ] || head -5 "$T/diff" | sed 's/^/#   /'
	ok $s "$n: the pyramid of the plain copies (TL_NO_AVX2) is the AVX2 copies', byte for byte ($(find "$T/a-$n" -type f | wc -l) files)"
	[ -n "$(ls "$T/a-$n"/0 2>/dev/null)" ]
	ok $? "$n: level 0 has blocks"
}

same "$DATA/N42E001.hgt" 1d
same "$DATA/N42E001.hgt" 3d
same "$DATA/bigtujunga.tif" 1d
same "$T/holes.tif" 1d
same "$T/holes.tif" 3d

# one piece alone, in a window not starting at column 0 (its own reading
# of the DEM's columns), both ways: N48W125's second piece of level 0
dem2vgis -q -M "$DATA/N48W125.hgt" "$T/vm-big" &&
    set -- $(ls "$T/vm-big"/v*.fqm | sort -V) &&
    p=$(tilepack -l "$DATA/N48W125.hgt" "$T/x" "$@" | grep '^0:' | sed -n 2p)
[ -n "$p" ] && tilepack -q -p "$p" "$DATA/N48W125.hgt" "$T/pa" "$@" &&
    TL_NO_AVX2=1 tilepack -q -p "$p" "$DATA/N48W125.hgt" "$T/pb" "$@" &&
    diff -r "$T/pa" "$T/pb" >/dev/null
ok $? "piece $p alone: the same blocks both ways"

done_testing
