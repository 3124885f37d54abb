# t_tileplay - the viewer, headless (EGL; llvmpipe in CI), on pyramids of
# the real DEMs: options scoped to their mode, pictures that are not blank (the terrain's footprint where
# the camera puts it, heights in their colours), no cracks where blocks of
# different levels meet (and cracks without skirts), triangles against the
# tolerance, the cache's cap along a flight over the largest pyramid, and
# the window under Xvfb when there is one. Pictures are read back with
# GDAL (Debian's /usr/bin/python3).
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
MAGENTA=255,0,255 # never a terrain colour: viridis and the level colours
                  # never have red high with green at 0

fails "no pyramid operand: exit 2" 2 'usage: tileplay' tileplay
fails "two operands: exit 2" 2 'usage: tileplay' tileplay a b
fails "--shot with --fly: exit 2" 2 '^tileplay: --shot and --fly: ' \
    tileplay --shot x.png --fly 3 d
fails "--probe without --shot: exit 2" 2 '^tileplay: --probe: only with' \
    tileplay --probe 1,2 d

# Options scoped to their mode (tileplay(1), "Modes and their options"):
# one of another mode is a usage error naming the option and the mode,
# found before any pyramid is opened (d does not exist).
# foreign OPTION MODE ARGS...
foreign() {
	_opt=$1 _mode=$2; shift 2
	fails "$_opt with $_mode: exit 2, both named" 2 \
	    "^tileplay: $_opt: only with .*, not with $_mode\$" tileplay "$@"
}
# the player's options with the checker
foreign --wire --verify --verify d --wire
foreign --size --verify --verify d --size 320x200
foreign --cache --verify --verify d --cache 16
foreign --view --verify --verify d --view overview
foreign --stats --verify --verify d --stats
foreign --probe --verify --verify d --probe 1,2
foreign --path --verify --verify d --path p
foreign --frames --verify --verify d --frames 2
# the checker's options with the player
foreign --dem --shot --dem foo --tau 1 --shot y.png d
foreign --tau --fly --tau 1 --fly 2 d
foreign -s "the window" -s 30 d
foreign -D --shot -D egm96 --shot y.png d
# a flight's camera is its path's; it prints its own statistics
foreign --view --fly --fly 2 --view overview d
foreign --eye --fly --fly 2 --eye 1,2,3 d
foreign --target --fly --target 1,2,3 --fly 2 d
foreign --stats --fly --fly 2 --stats d
# one mode's own options in another
foreign --probe "the window" --probe 1,2 d
foreign --readout "the window" --readout d
foreign --wait "the window" --wait d
foreign --path "the window" --path p d
foreign --frames --shot --shot x.png --frames 3 d
foreign --path --shot --shot x.png --path p d
foreign --wait --shot --wait --shot x.png d
foreign --probe --fly --fly 2 --probe 1,2 d
foreign --readout --fly --fly 2 --readout d
foreign --frames --fly --fly 2 --frames 3 d
fails "the first foreign option is named" 2 \
    '^tileplay: --wire: only with the window, --shot or --fly, not with --verify$' \
    tileplay --verify d --wire --frames 2
grep -q -- '--frames' "$T/err"; ok $(( ! $? )) "... and only it"
# two modes at once, in the order given
fails "--verify with --shot: exit 2" 2 '^tileplay: --verify and --shot: one at a time$' \
    tileplay --verify d --shot x.png
fails "--fly with --verify: exit 2" 2 '^tileplay: --fly and --verify: one at a time$' \
    tileplay --fly 2 --verify d
# every option of a mode together passes the options: the missing
# pyramid is what fails (exit 1), not the usage
fails "the window's options: accepted" 1 "^tileplay: $T/none/index.json: " \
    tileplay --view overview --eye 1,2,3 --target 4,5,6 --size 320x200 \
    --pixels 2 --color level --wire --no-skirts --no-light \
    --background 1,2,3 --cache 16 --stats --frames 2 "$T/none"
fails "--shot's options: accepted" 1 "^tileplay: $T/none/index.json: " \
    tileplay --shot "$T/x.png" --view overview --eye 1,2,3 --target 4,5,6 \
    --size 320x200 --pixels 2 --color error --wire --no-skirts --no-light \
    --background 1,2,3 --cache 16 --stats --readout --probe 1,2 "$T/none"
fails "--fly's options: accepted" 1 "^tileplay: $T/none/index.json: " \
    tileplay --fly 2 --path p --wait --size 320x200 --pixels 2 \
    --color level --wire --no-skirts --no-light --background 1,2,3 \
    --cache 16 "$T/none"
fails "--verify's options: accepted" 1 "^tileplay: $T/none/index.json: " \
    tileplay --verify "$T/none" --dem x.tif --tau 1,2 -D egm96 -e grey \
    -H egm96 -N -9999 -n x.hgt -s 30
fails "--size 10: exit 2" 2 '^tileplay: --size 10: expected WxH' \
    tileplay --size 10 --shot x.png d
fails "--color hue: exit 2" 2 '^tileplay: --color hue: expected' \
    tileplay --color hue --shot x.png d
fails "--background 1,2: exit 2" 2 '^tileplay: --background 1,2: ' \
    tileplay --background 1,2 --shot x.png d
fails "--view side: exit 2" 2 '^tileplay: --view side: unknown view' \
    tileplay --view side --shot x.png d
fails "no pyramid: exit 1" 1 "^tileplay: $T/none/index.json: " \
    tileplay "$T/none" --shot "$T/x.png"
[ ! -e "$T/x.png" ]; ok $? "no pyramid: no picture left behind"

if [ ! -x "$B/dem2vgis" ] || ! $PY -c 'from osgeo import gdal' \
    2>/dev/null; then
	echo "ok $((_n + 1)) - # SKIP dem2vgis or python3-gdal missing"
	_n=$((_n + 1))
	done_testing
	exit
fi

# mk NAME DEM [dem2vgis options]
mk() {
	_name=$1 _dem=$2; shift 2
	"$B/dem2vgis" -q -j 2 "$@" "$DATA/$_dem" "$T/$_name" \
	    >"$T/mk.out" 2>&1
	_s=$?
	[ $_s -eq 0 ] || sed 's/^/#   /' "$T/mk.out" | head -5
	ok $_s "$_name: pyramid of $_dem ($*)"
}
mk bt bigtujunga.tif
mk bt3 bigtujunga.tif -3
mk fuji fuji.png -s 60
mk n42 N42E001.hgt
mk n42-3 N42E001.hgt -3
big n48 || mk n48 N48W125.hgt
big n48 || mk n48-3 N48W125.hgt -3

# An index.json is untrusted input: an empty or absurd level list, or a
# level of the wrong size, is refused with exit 1, never a crash.
hostile() {	# NAME PYTHON-EDIT: a copy of bt with index.json edited
	rm -rf "$T/$1" && cp -r "$T/bt" "$T/$1" &&
	    $PY -c "import json,sys; p=sys.argv[1]; ix=json.load(open(p)); $2; json.dump(ix, open(p, 'w'))" \
	    "$T/$1/index.json"
	fails "index.json with $1: exit 1, no crash" 1 "^tileplay: .*index.json: " \
	    tileplay "$T/$1" --shot "$T/h.png"
}
hostile nolevels "ix['levels'] = []"
hostile 26levels "ix['levels'] = ix['levels'] + [ix['levels'][-1]] * 21"
hostile bigsize "ix['size0'] = [1 << 30, 643]"
hostile wrongsize "ix['levels'][1]['size'] = [5, 5]"

# Every option of a mode at once, on a real pyramid.
run "bt: --shot with all its options" tileplay "$T/bt" --shot "$T/all.png" \
    --view overview --size 320x200 --pixels 2 --color level --wire \
    --no-skirts --no-light --background 1,2,3 --cache 64 --stats --readout \
    --probe 100,100
grep -q '^stats: ' "$T/err" && grep -q '^probe 100,100: ' "$T/out"
ok $? "... its stats and its probe"
printf '%s\n' '# eye target' '-9000 -9000 6000 0 0 500' \
    '9000 -9000 6000 0 0 500' >"$T/bt.path"
run "bt: --fly with all its options" tileplay "$T/bt" --fly 3 \
    --path "$T/bt.path" --wait --size 320x200 --pixels 2 --color error \
    --wire --no-skirts --no-light --background 1,2,3 --cache 64
[ "$(grep -c '^[0-9]' "$T/out")" -eq 3 ]; ok $? "... three frames"
run "bt: --verify with its options" tileplay --verify "$T/bt" --tau 1,10
grep -q '^result: pass$' "$T/out"; ok $? "... result: pass"

# The picture checks, in numpy over GDAL's reading of the PNG.
cat >"$T/px.py" <<'EOF'
import json, math, sys
import numpy as np
from osgeo import gdal

def rgb(path):
    d = gdal.Open(path)
    return np.dstack([d.GetRasterBand(b + 1).ReadAsArray()
                      for b in range(3)]).astype(int)

def terrain(path, bg):
    return ~np.all(rgb(path) == np.array(bg), axis=2)

def holes(path, bg):
    """Background pixels with terrain to their left and right in their
    row and above and below in their column: inside the silhouette."""
    t = terrain(path, bg)
    def before(a, ax): return np.maximum.accumulate(a, axis=ax)
    def after(a, ax): return np.flip(before(np.flip(a, ax), ax), ax)
    inside = before(t, 1) & after(t, 1) & before(t, 0) & after(t, 0)
    return int((~t & inside).sum())

def footprint(path, bg, index, eye_z, fovy):
    """Straight down from (0, 0, eye_z), north up: the DEM's footprint
    (a projected DEM: (n - 1) steps, centred) lies between its outlines
    at the highest and the lowest height of level 0."""
    ix = json.load(open(index))
    hx = (ix["size0"][0] - 1) * abs(ix["georef"]["step"][0]) / 2
    hy = (ix["size0"][1] - 1) * abs(ix["georef"]["step"][1]) / 2
    L = ix["levels"][0]
    zlo, zhi = min(L["zmin"]), max(L["zmax"])
    t = terrain(path, bg)
    h, w = t.shape
    k = math.tan(math.radians(fovy) / 2)
    def rect(z):  # pixel bounds x0, x1, y0, y1
        d = eye_z - z
        sx = w / 2 / (d * k * w / h); sy = h / 2 / (d * k)
        return (w / 2 - hx * sx, w / 2 + hx * sx,
                h / 2 - hy * sy, h / 2 + hy * sy)
    ys, xs = np.mgrid[0:h, 0:w] + 0.5
    def within(r, m):
        return ((xs >= r[0] - m) & (xs <= r[1] + m) &
                (ys >= r[2] - m) & (ys <= r[3] + m))
    inner = within(rect(zlo), -1)  # lowest terrain: smallest outline
    outer = within(rect(zhi), 1)
    print(int((inner & ~t).sum()), int((t & ~outer).sum()),
          int(inner.sum()), int(t.sum()), int(outer.sum()))

def pixel(path, x, y):
    print(*rgb(path)[y, x])

def extremes(dem):
    """fuji.png (Terrain-RGB): the highest and the lowest sample off the
    edges (an edge sample lands on the terrain's outline), as column,row
    and height."""
    d = gdal.Open(dem)
    r, g, b = [d.GetRasterBand(k + 1).ReadAsArray().astype(float)
               for k in range(3)]
    z = (r * 65536 + g * 256 + b) / 10 - 10000
    zi = z[1:-1, 1:-1]
    for i in (np.argmax(zi), np.argmin(zi)):
        j, c = np.unravel_index(i, zi.shape)
        print("%d,%d %.1f" % (c + 1, j + 1, zi[j, c]), end=" ")
    print()

f = sys.argv[1]
if f == "holes": print(holes(sys.argv[2], [int(v) for v in sys.argv[3].split(",")]))
elif f == "footprint": footprint(sys.argv[2], [int(v) for v in sys.argv[3].split(",")],
                                 sys.argv[4], float(sys.argv[5]), float(sys.argv[6]))
elif f == "pixel": pixel(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
elif f == "extremes": extremes(sys.argv[2])
EOF

# stat FIELD: a number from the --stats line in $T/err
stat() {
	case $1 in
	triangles) sed -n 's/.*), \([0-9]*\) triangles.*/\1/p' "$T/err" ;;
	skirts) sed -n 's/.* \([0-9]*\) skirt triangles.*/\1/p' "$T/err" ;;
	blocks) sed -n 's/^stats: \([0-9]*\) blocks.*/\1/p' "$T/err" ;;
	levels) sed -n 's/^stats: [0-9]* blocks (\([^)]*\)).*/\1/p' "$T/err" |
	    grep -o 'level' | wc -l ;;
	level0) sed -n 's/^stats: [0-9]* blocks (\([^)]*\)).*/\1/p' "$T/err" |
	    sed -n 's/^level 0: \([0-9]*\)$/\1/p' ;;
	esac
}

# --- not blank -------------------------------------------------------------

# bigtujunga (UTM, 30 m) straight down from 40 km: its footprint, between
# its outlines at 315 and 2295 m, computed here from the camera alone.
run "bt: overview shot" tileplay "$T/bt" --shot "$T/ov.png" --size 640x480 \
    --eye 0,0,40000 --target 0,0,0 --background $MAGENTA --stats
$PY "$T/px.py" footprint "$T/ov.png" $MAGENTA "$T/bt/index.json" 40000 50 \
    >"$T/fp" 2>&1
read -r miss stray inner terr outer <"$T/fp"
echo "# footprint: terrain $terr pixels, between $inner and $outer;" \
    "background inside $miss, terrain outside $stray"
[ "${miss:-1}" -eq 0 ] && [ "${stray:-1}" -eq 0 ] &&
    [ "$terr" -ge "$inner" ] && [ "$terr" -le "$outer" ]
ok $? "bt: the terrain covers the frame where the camera puts it"
$PY -c "from osgeo import gdal; d = gdal.Open('$T/ov.png');
assert (d.RasterXSize, d.RasterYSize, d.RasterCount) == (640, 480, 3)" \
    2>/dev/null
ok $? "bt: the PNG is 640x480 RGB"
tileplay "$T/bt" --shot "$T/ov2.png" --size 640x480 --eye 0,0,40000 \
    --target 0,0,0 --background $MAGENTA 2>/dev/null
cmp -s "$T/ov.png" "$T/ov2.png"; ok $? "bt: the same shot twice, the same bytes"

# fuji: its highest and lowest samples (13.7 to 3751 m; the lowest off
# the edge is 14.5 m, 0.02 % up the range) in the last and first colours
# of viridis, (253, 231, 37) and (68, 1, 84), where --probe says they land.
$PY "$T/px.py" extremes "$DATA/fuji.png" >"$T/ext"
read -r hi zhi lo zlo <"$T/ext"
for p in "$hi $zhi 253 231 37" "$lo $zlo 68 1 84"; do
	set -- $p
	run "fuji: probe $1" tileplay "$T/fuji" --shot "$T/fu.png" \
	    --size 640x640 --view overview --pixels 0 --no-light --probe "$1"
	# probe I,J: height Z m, world X,Y,Z, pixel PX PY, colour R G B
	read -r z px py r g b <<EOF
$(sed -n 's/.*height \([^ ]*\) m, .*pixel \([0-9]*\) \([0-9]*\), colour \(.*\)/\1 \2 \3 \4/p' "$T/out")
EOF
	set -- "$@" $($PY "$T/px.py" pixel "$T/fu.png" "${px:-0}" "${py:-0}")
	echo "# probe $1 (${2} m in the DEM, $z m in the pyramid): pixel" \
	    "$px,$py is $6 $7 $8, the map gives $r $g $b, viridis $3 $4 $5"
	awk -v z="$z" -v dz="$2" 'BEGIN { exit !(z - dz < 0.05 && dz - z < 0.05) }'
	ok $? "fuji: probe $1 reads the DEM's height $2 m"
	[ "$r $g $b" = "$3 $4 $5" ]
	ok $? "fuji: the map gives $2 m viridis' end colour $3 $4 $5"
	awk -v a="$6 $7 $8" -v b="$3 $4 $5" 'BEGIN { split(a, p); split(b, q)
	    for (k = 1; k <= 3; k++) if ((p[k] - q[k])^2 > 36) exit 1 }'
	ok $? "fuji: the picture has that colour (within 6) where it lands"
done

# --- no cracks -------------------------------------------------------------

# crack NAME EYE TARGET: the view with skirts has no background pixel
# inside the silhouette; adds the count without skirts to $open.
crack() {
	for _px in 1 2; do
		tileplay "$T/$1" --shot "$T/c.png" --size 480x360 --eye "$2" \
		    --target "$3" --pixels $_px --background $MAGENTA \
		    --stats >"$T/out" 2>"$T/err"
		_h=$($PY "$T/px.py" holes "$T/c.png" $MAGENTA)
		_lv=$(stat levels)
		tileplay "$T/$1" --shot "$T/c.png" --size 480x360 --eye "$2" \
		    --target "$3" --pixels $_px --background $MAGENTA \
		    --no-skirts 2>/dev/null
		_o=$($PY "$T/px.py" holes "$T/c.png" $MAGENTA)
		open=$((open + ${_o:-0}))
		_b=$(sed -n 's/^stats: \([^)]*)\).*/\1/p' "$T/err")
		[ "${_h:-1}" -eq 0 ] && [ "${_lv:-0}" -ge 2 ]
		ok $? "$1: no holes at $_px px from $2 ($_lv levels meet: $_b;\
 without skirts $_o holes)"
	done
}
for p in bt bt3 n42 n42-3 n48 n48-3; do
	big $p && { ok 0 "# SKIP $p under TL_QUICK"; continue; }
	open=0
	case $p in
	bt*)	crack $p -18658,-10015,3346 0,0,-727
		crack $p -7176,10015,2531 3588,-1926,-727 ;;
	n42*)	crack $p -42414,-57761,8634 327,2,-5185
		crack $p -16112,57766,5870 8547,-11106,-5185 ;;
	n48*)	crack $p 5000,-62000,3000 30000,-30000,0
		crack $p -10000,-20000,4000 30000,-45000,0 ;;
	esac
	[ $open -gt 0 ]; ok $? "$p: the test sees cracks: $open holes without skirts"
done

# --- triangles against the tolerance ----------------------------------------

prev="" mono=0 series=""
for px in 0.5 1 2 4 8 16; do
	tileplay "$T/bt" --shot "$T/t.png" --pixels $px --stats 2>"$T/err"
	t=$(stat triangles)
	series="$series $t"
	[ -z "$prev" ] || [ "${t:-0}" -le "$prev" ] || mono=1
	prev=${t:-0}
done
set -- $series
[ $mono -eq 0 ] && [ "$1" -gt "$6" ]
ok $? "bt: triangles fall as the tolerance grows (0.5..16 px:$series)"
run "bt: --pixels 0" tileplay "$T/bt" --shot "$T/t.png" --pixels 0 \
    --eye -18658,-10015,3346 --target 0,0,-727 --stats
b=$(stat blocks) b0=$(stat level0) t=$(stat triangles)
echo "# --pixels 0: $b blocks, $b0 on level 0, $t triangles"
[ -n "$b" ] && [ "$b" = "$b0" ] && [ "$b" -gt 0 ] && [ "$b" -lt 60 ] &&
    [ "$t" -eq $((2 * 128 * 128 * b)) ]
ok $? "bt: at 0 px the full grid of the visible level-0 blocks (2x128x128 x $b)"

# --- the cache's cap ------------------------------------------------------------

# flycheck DESCRIPTION ARGS...: the flight completes within a 16 MB cap;
# over the largest pyramid, and under the sanitizers over n42, whose
# flight reaches the cap too (evictions): the cache's code is the same
fly=n48 capmb=16
big n48 && fly=n42
flycheck() {
	_d=$1; shift
	run "$fly: $_d" tileplay "$T/$fly" --fly 60 --cache $capmb --size 480x360 "$@"
	_f=$(grep -c '^[0-9]' "$T/out")
	_sum=$(tail -1 "$T/out")
	echo "$_sum"
	set -- $(echo "$_sum" | sed -n 's/.*cache peak \([0-9]*\) of \([0-9]*\) bytes.*, \([0-9]*\) evictions.*/\1 \2 \3/p')
	[ "$_f" -eq 60 ] && [ -n "${1:-}" ] && [ "$1" -le "$2" ] &&
	    [ "$2" -eq $((capmb * 1048576)) ]
	ok $? "$fly: peak ${1:-?} <= cap ${2:-?} bytes, 60 frames"
	evictions=${3:-0}
}
flycheck "free flight (loads behind the frames)"
flycheck "flight that waits for every block" --wait
[ "$evictions" -gt 0 ]; ok $? "$fly: the cap was reached ($evictions evictions)"

# --- the window --------------------------------------------------------------

if command -v xvfb-run >/dev/null && command -v xauth >/dev/null; then
	# blocks load behind the frames: on a busy machine the first ten
	# may all come before one has loaded, so more frames then
	for n in 10 100 1000; do
		run "window under Xvfb: $n frames" xvfb-run -a tileplay "$T/bt" \
		    --frames $n --size 320x240 --stats
		t=$(stat triangles)
		[ "${t:-0}" -gt 0 ] && break
	done
	[ "${t:-0}" -gt 0 ]; ok $? "window: it drew ${t:-0} triangles"
else
	echo "ok $((_n + 1)) - # SKIP no xvfb-run or xauth: the window untested"
	_n=$((_n + 1))
fi
done_testing
