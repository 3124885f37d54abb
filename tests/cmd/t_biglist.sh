# t_biglist - a list of thousands of entries is read as the DEM it tiles
# (issue 21, class 9): 400 tiles of 31 x 31 samples cut from N44W072 by
# GDAL's Translate (-srcwin), sharing their edge rows and columns like
# SRTM, each listed 10 times under other relative paths (4000 lines): the
# map is the uncut DEM's byte for byte, and a tile changed on a shared
# edge is still refused naming it. The checks were quadratic (every pair
# of entries, the directory listed at each open); only the results are
# asserted here, never the time.
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
D=$T/tiles
mkdir -p "$D/sub"
GDAL_PAM_ENABLED=NO $PY - "$DATA/N44W072.tif" "$D" "$T/whole.tif" <<'PY' || ok 1 "fixture: 400 tiles"
import sys
from osgeo import gdal
gdal.UseExceptions()
src, out, whole = sys.argv[1:4]
d = gdal.Open(src)
gdal.Translate(whole, d, srcWin=[0, 0, 601, 601])
for j in range(0, 600, 30):
    for i in range(0, 600, 30):
        gdal.Translate("%s/t_%03d_%03d.tif" % (out, i, j), d,
                       srcWin=[i, j, 31, 31])
PY
# each tile under 10 relative paths: t.tif, ./t.tif, sub/../t.tif, ...
(cd "$D" && ls t_*.tif) >"$T/names"
for k in 0 1 2 3 4 5 6 7 8 9; do
	case $k in
	0) p= ;; 1) p=./ ;; 2) p=sub/../ ;; 3) p=././ ;; 4) p=./sub/../ ;;
	5) p=sub/.././ ;; 6) p=../tiles/ ;; 7) p=./../tiles/ ;;
	8) p=../tiles/sub/../ ;; 9) p=sub/../../tiles/ ;;
	esac
	sed "s|^|$p|" "$T/names"
done >"$D/list.txt"
n=$(wc -l <"$D/list.txt")
[ "$n" -eq 4000 ]; ok $? "fixture: a list of 4000 entries, 400 tiles ($n)"

run "dem2fqm -I of the list" dem2fqm -I "$D/list.txt"
grep -q '^size 601 601' "$T/out"; ok $? "the list's size is the uncut DEM's"
run "dem2fqm of the list" dem2fqm "$D/list.txt" "$T/list.fqm"
run "dem2fqm of the uncut DEM" dem2fqm "$T/whole.tif" "$T/whole.fqm"
cmp -s "$T/list.fqm" "$T/whole.fqm"; ok $? "the list's map is the uncut DEM's, byte for byte"

# one tile's shared edge changed: the check still compares every pair
GDAL_PAM_ENABLED=NO $PY - "$D/t_300_300.tif" <<'PY' || ok 1 "fixture: a changed edge"
import sys
from osgeo import gdal
gdal.UseExceptions()
d = gdal.Open(sys.argv[1], gdal.GA_Update)
b = d.GetRasterBand(1)
a = b.ReadAsArray()
a[0, 7] += 1	# its first row is the tile above's last
b.WriteArray(a)
d = None
PY
fails "a changed shared edge among 4000 entries: refused naming the tile" 1 \
    "^dem2fqm: .*t_300_300.tif: sample 7,0 is .* where it overlaps .*t_300_270.tif, whose sample 7,30 is" \
    dem2fqm "$D/list.txt" "$T/bad.fqm"
[ ! -e "$T/bad.fqm" ]; ok $? "refused: no map"

done_testing
