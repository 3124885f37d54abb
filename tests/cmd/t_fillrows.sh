# t_fillrows - dem2fqm -W in row bands (--fill-pass 1, join, 2, commit;
# filled(5) PARTS): three bands, their pass 1 and pass 2 run at once, give
# the file dem2fqm -W gives, byte for byte, on a crop of N48W125 with
# voids and on a south-up, east-left float32 copy of it with NaN voids;
# nothing is left beside the file; bad usage exits 2, a missing part 1.
. "$(dirname "$0")/../lib.sh"

MK="/usr/bin/python3 $TOP/tests/tools/mkgdal.py"
GDAL_PAM_ENABLED=NO
export GDAL_PAM_ENABLED

# parts DEM OUT: the four parts in bands of 134 rows (3 for 400 rows)
parts() {
	p_rc=0 p_pids=
	for y in 0 134 268; do
		dem2fqm -W "$2" --fill-pass 1 --rows $y,$((y + 134 < 400 ? y + 134 : 400)) "$1" &
		p_pids="$p_pids $!"
	done
	for p in $p_pids; do wait "$p" || p_rc=1; done
	dem2fqm -W "$2" --fill-pass join --band-rows 134 "$1" || p_rc=1
	p_pids=
	for y in 268 134 0; do
		dem2fqm -W "$2" --fill-pass 2 --rows $y,$((y + 134 < 400 ? y + 134 : 400)) "$1" &
		p_pids="$p_pids $!"
	done
	for p in $p_pids; do wait "$p" || p_rc=1; done
	dem2fqm -W "$2" --fill-pass commit --band-rows 134 "$1" || p_rc=1
	return $p_rc
}

cd "$T" || exit 1
gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" crop.tif
ok $? "a 2200 x 400 crop of N48W125 (sea and land)"
$MK flipped crop.tif flip.tif
ok $? "its south-up, east-left float32 copy with NaN voids (mkgdal.py)"
for d in crop flip; do
	run "$d: dem2fqm -W" dem2fqm -W $d.whole $d.tif
	parts $d.tif $d.banded
	ok $? "$d: 3 bands, pass 1 and pass 2 in parallel"
	cmp -s $d.whole $d.banded
	ok $? "$d: the same bytes as dem2fqm -W"
	[ "$(ls -A | grep -c "^\.\?$d\.banded.")" -eq 0 ]
	ok $? "$d: no part nor temporary left"
done
dem2fqm -II crop.tif | grep -q '^voids [1-9]'
ok $? "the crop has voids"

# a band's pass 2 missing: commit names it and commits nothing
for y in 0 134 268; do
	dem2fqm -W m.fd --fill-pass 1 --rows $y,$((y + 134 < 400 ? y + 134 : 400)) crop.tif
done
dem2fqm -W m.fd --fill-pass join --band-rows 134 crop.tif
dem2fqm -W m.fd --fill-pass 2 --rows 0,134 crop.tif
fails "commit with a band's pass 2 missing" 1 \
    '^dem2fqm: m\.fd\.d\.134: missing' \
    dem2fqm -W m.fd --fill-pass commit --band-rows 134 crop.tif
[ ! -e m.fd ]; ok $? "nothing committed"
fails "pass 2 before pass 1 of its band" 1 '^dem2fqm: n\.fd\.e\.0: missing' \
    dem2fqm -W n.fd --fill-pass 2 --rows 0,134 crop.tif
fails "a band past the DEM's rows" 1 '^dem2fqm: .*rows' \
    dem2fqm -W n.fd --fill-pass 1 --rows 300,500 crop.tif

fails "--fill-pass without -W" 2 'only with -W' \
    dem2fqm --fill-pass 1 --rows 0,1 crop.tif
fails "--fill-pass 3" 2 'not 1, join, 2 or commit' \
    dem2fqm -W x --fill-pass 3 --rows 0,1 crop.tif
fails "pass 1 without --rows" 2 'with --rows' \
    dem2fqm -W x --fill-pass 1 crop.tif
fails "join with --rows" 2 'with --band-rows' \
    dem2fqm -W x --fill-pass join --rows 0,1 crop.tif
fails "--rows 5,5" 2 'not rows' \
    dem2fqm -W x --fill-pass 1 --rows 5,5 crop.tif
fails "--band-rows 0" 2 'not a number of rows' \
    dem2fqm -W x --fill-pass commit --band-rows 0 crop.tif
fails "--rows without --fill-pass" 2 'only with --fill-pass' \
    dem2fqm -W x --rows 0,1 crop.tif
fails "a part on stdin" 2 'named file' \
    dem2fqm -W x --fill-pass join --band-rows 3 - <crop.tif
done_testing
