# t_fillrows - a plan's fill in row bands (vgis-job fill --pass 1, join,
# 2, commit; filled(5) PARTS): three bands, their pass 1 and pass 2 run at
# once, give the file the whole fill (vgis-job fill) gives, byte for
# byte, on a crop of N48W125 with voids and on a south-up, east-left float32 copy of it with NaN voids;
# nothing is left beside the file; bad usage exits 2, a missing part 1.
. "$(dirname "$0")/../lib.sh"

MK="/usr/bin/python3 $TOP/tests/tools/mkgdal.py"
GDAL_PAM_ENABLED=NO
export GDAL_PAM_ENABLED

# parts DEM OUT: the four parts in bands of 134 rows (3 for 400 rows)
parts() {
	p_rc=0 p_pids=
	for y in 0 134 268; do
		vgis-job fill --pass 1 --rows $y,$((y + 134 < 400 ? y + 134 : 400)) "$1" "$2" &
		p_pids="$p_pids $!"
	done
	for p in $p_pids; do wait "$p" || p_rc=1; done
	vgis-job fill --pass join --band-rows 134 "$1" "$2" || p_rc=1
	p_pids=
	for y in 268 134 0; do
		vgis-job fill --pass 2 --rows $y,$((y + 134 < 400 ? y + 134 : 400)) "$1" "$2" &
		p_pids="$p_pids $!"
	done
	for p in $p_pids; do wait "$p" || p_rc=1; done
	vgis-job fill --pass commit --band-rows 134 "$1" "$2" || p_rc=1
	return $p_rc
}

cd "$T" || exit 1
gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" crop.tif
ok $? "a 2200 x 400 crop of N48W125 (sea and land)"
$MK flipped crop.tif flip.tif
ok $? "its south-up, east-left float32 copy with NaN voids (mkgdal.py)"
for d in crop flip; do
	run "$d: vgis-job fill" vgis-job fill $d.tif $d.whole
	parts $d.tif $d.banded
	ok $? "$d: 3 bands, pass 1 and pass 2 in parallel"
	cmp -s $d.whole $d.banded
	ok $? "$d: the same bytes as the whole fill"
	[ "$(ls -A | grep -c "^\.\?$d\.banded.")" -eq 0 ]
	ok $? "$d: no part nor temporary left"
done
dem2fqm -II crop.tif | grep -q '^voids [1-9]'
ok $? "the crop has voids"

# a band's pass 2 missing: commit names it and commits nothing
for y in 0 134 268; do
	vgis-job fill --pass 1 --rows $y,$((y + 134 < 400 ? y + 134 : 400)) crop.tif m.fd
done
vgis-job fill --pass join --band-rows 134 crop.tif m.fd
vgis-job fill --pass 2 --rows 0,134 crop.tif m.fd
fails "commit with a band's pass 2 missing" 1 \
    '^vgis-job fill: m\.fd\.d\.134: missing' \
    vgis-job fill --pass commit --band-rows 134 crop.tif m.fd
[ ! -e m.fd ]; ok $? "nothing committed"
fails "pass 2 before pass 1 of its band" 1 '^vgis-job fill: n\.fd\.e\.0: missing' \
    vgis-job fill --pass 2 --rows 0,134 crop.tif n.fd
fails "a band past the DEM's rows" 1 '^vgis-job fill: .*rows' \
    vgis-job fill --pass 1 --rows 300,500 crop.tif n.fd

fails "--pass 3" 2 'not 1, join, 2 or commit' \
    vgis-job fill --pass 3 --rows 0,1 crop.tif x
fails "pass 1 without --rows" 2 'with --rows' \
    vgis-job fill --pass 1 crop.tif x
fails "join with --rows" 2 'with --band-rows' \
    vgis-job fill --pass join --rows 0,1 crop.tif x
fails "--rows 5,5" 2 'not rows' \
    vgis-job fill --pass 1 --rows 5,5 crop.tif x
fails "--band-rows 0" 2 '^vgis-job fill: --band-rows 0: not an integer in 1 \.\.' \
    vgis-job fill --pass commit --band-rows 0 crop.tif x
fails "--rows without --pass" 2 'only with --pass' \
    vgis-job fill --rows 0,1 crop.tif x
fails "a part on stdin" 2 'named file' \
    vgis-job fill --pass join --band-rows 3 - x <crop.tif
done_testing
