# t_plan_dem - a plan whose DEM or state changes under it. The DEM
# replaced between stages (same size and georeferencing, heights
# changed; or another file, its size and mtime set back): every job
# refuses it, naming the file and saying to write the plan again, and no
# pyramid appears; so for a VRT's source and a mosaic's tile. Written
# again, the plan builds the new DEM's pyramid. Two makes at once, make
# and GNU parallel at once, work/ or vmaps/ removed before the gather:
# the pyramid byte for byte, no stale done/ marker left failing.
. "$(dirname "$0")/../lib.sh"
quick_skip "a plan whose DEM changes under it"
PATH=$B:$PATH

gdal_translate -q -srcwin 0 0 257 257 "$DATA/N44W072.hgt" "$T/dem.tif"
ok $? "a 257x257 crop of N44W072"
dem2vgis -q "$T/dem.tif" "$T/ref"; ok $? "dem2vgis in one run"
# raise FILE: its heights 7 m higher, in place (same size, inode and
# georeferencing; a new mtime)
raise() {
	/usr/bin/python3 -c 'import sys
from osgeo import gdal
d = gdal.Open(sys.argv[1], gdal.GA_Update)
b = d.GetRasterBand(1)
b.WriteArray(b.ReadAsArray() + 7)
d = None' "$1"
}
cd "$T" || exit 1

# --- the DEM replaced between stages ------------------------------------
cp dem.tif d1.tif
dem2vgis --plan p1 d1.tif o1 && make -s -C p1 done/chain >/dev/null 2>&1 &&
    grep -q " $T/d1.tif\$" p1/dem.stamp
ok $? "the plan records its DEM (dem.stamp), the chain made"
sz=$(wc -c <d1.tif)
raise d1.tif && [ "$(wc -c <d1.tif)" -eq "$sz" ]
ok $? "the DEM's heights changed in place, same size"
make -s -C p1 >/dev/null 2>"$T/err"; s=$?
[ $s -ne 0 ] && [ ! -e o1 ] &&
    grep -q "d1.tif: changed since $T/p1/dem.stamp recorded it: written to" \
    "$T/err" && grep -q "write the plan again" "$T/err"
ok $? "make: refused, naming the DEM, saying to write the plan again; no pyramid"
[ $s -ne 0 ] || sed 's/^/#   /' "$T/err"
make -s -C p1 >/dev/null 2>&1; [ $? -ne 0 ] && [ ! -e o1 ]
ok $? "make again: still refused"
dem2vgis -q d1.tif ref1 && dem2vgis -f --plan p1 d1.tif o1 &&
    make -s -C p1 >/dev/null 2>&1 && diff -r ref1 o1 >/dev/null &&
    ! diff -r ref ref1 >/dev/null
ok $? "written again (-f): the new DEM's pyramid, byte for byte"

# another file in its place, its size and mtime those of the old one
cp dem.tif d2.tif
dem2vgis --plan p2 d2.tif o2 && make -s -C p2 done/pieces.mk >/dev/null 2>&1 &&
    cp dem.tif d2.new && raise d2.new && touch -r d2.tif d2.new &&
    mv d2.new d2.tif
fails "another file, same size and mtime: refused (inode)" 2 \
    "d2.tif: changed since .*replaced by another file" make -s -C p2
[ ! -e o2 ]; ok $? "no pyramid"

# --- a VRT's source, a mosaic's tile, a list's entry --------------------
gdal_translate -q -srcwin 0 0 128 257 dem.tif w.tif &&
    gdal_translate -q -srcwin 128 0 129 257 dem.tif e.tif &&
    gdalbuildvrt -q m.vrt w.tif e.tif && printf 'w.tif\ne.tif\n' >m.txt
ok $? "two halves, their VRT and their list"
dem2vgis --plan pv m.vrt ov && dem2vgis --plan pm w.tif e.tif om &&
    dem2vgis --plan pl m.txt ol
ok $? "plans of the VRT, of the two tiles, of the list"
recorded() { awk 'NR > 1 { print $5 }' "$1/dem.stamp" | sed "s|^$T/||" | tr '\n' ' '; }
[ "$(recorded pv)" = "e.tif m.vrt w.tif " ] &&
    [ "$(recorded pm)" = "e.tif w.tif " ] &&
    [ "$(recorded pl)" = "e.tif m.txt w.tif " ]
ok $? "recorded: the VRT and its sources ($(recorded pv)), the tiles ($(recorded pm)), the list and its entries ($(recorded pl))"
make -s -C pv done/chain >/dev/null 2>&1 && make -s -C pm done/chain \
    >/dev/null 2>&1 && make -s -C pl done/chain >/dev/null 2>&1 && raise e.tif
ok $? "the chains made, then the east half's heights changed"
for p in pv pm pl; do
	fails "$p: the changed tile named" 2 "$T/e.tif: changed since $T/$p/dem.stamp" \
	    make -s -C $p
done

# --- two makes at once; make and GNU parallel at once ------------------
dem2vgis --part-samples 20000 --plan p3 dem.tif o3 && {
	make -s -C p3 -j2 >m1.log 2>&1 & a=$!
	make -s -C p3 -j2 >m2.log 2>&1 & b=$!
	make -s -C p3 >m3.log 2>&1; c=$?
	wait $a; a=$?; wait $b; b=$?
	[ $a -eq 0 ] && [ $b -eq 0 ] && [ $c -eq 0 ]
}
ok $? "three makes at once on one plan (pieces in parts): each exits 0"
diff -r ref o3 >/dev/null && [ ! -e p3/work ]
ok $? "the pyramid byte for byte, no work/ left"
make -C p3 2>&1 | grep -q "Nothing to be done"
ok $? "make again: nothing to do"
if command -v parallel >/dev/null; then
	dem2vgis --part-samples 20000 --plan p4 dem.tif o4 && {
		make -s -C p4 >m1.log 2>&1 & a=$!
		PARALLEL=-j2 sh p4/parallel.sh >m2.log 2>&1; b=$?
		wait $a; a=$?
		[ $a -eq 0 ] && [ $b -eq 0 ]
	} && diff -r ref o4 >/dev/null && [ ! -e p4/work ]
	ok $? "make and GNU parallel at once: both exit 0, the pyramid byte for byte"
else
	ok 0 "make and GNU parallel at once # SKIP no GNU parallel"
fi

# --- outputs removed before the gather ---------------------------------
dem2vgis --part-samples 20000 --plan p5 dem.tif o5 &&
    make -s -C p5 done/pieces.mk >/dev/null 2>&1 &&
    make -s -C p5 $(cat p5/done/parts p5/done/targets) >/dev/null 2>&1 &&
    [ "$(wc -l <p5/done/parts)" -ge 2 ] && rm -rf p5/work
ok $? "every piece and part made, then work/ removed"
make -s -C p5 >/dev/null 2>"$T/err" && diff -r ref o5 >/dev/null &&
    grep -q "outputs gone, their jobs to be run again .*p-0-0-2.*q-0-0-2-" "$T/err"
ok $? "make: the stale markers removed and said, the jobs run again, the pyramid byte for byte"
dem2vgis --plan p6 dem.tif o6 && make -s -C p6 done/pieces.mk >/dev/null 2>&1 &&
    rm -rf p6/vmaps && make -s -C p6 >/dev/null 2>"$T/err" &&
    diff -r ref o6 >/dev/null && grep -q "again .*: chain" "$T/err"
ok $? "vmaps/ removed after the chain: made again, the pyramid byte for byte"
done_testing
