# t_tilepack - tilepack and dem2vgis: E values derived by hand, bad input,
# interrupted runs, atomic replacement, the examples Makefile.
. "$(dirname "$0")/../lib.sh"

/usr/bin/python3 "$TOP/tests/tools/mkbad.py" "$T" || { ok 1 "fixtures"; done_testing; exit 1; }
PATH=$B:$PATH

# e DIR L GI GJ: the E values stored for a vertex, one per block holding it
e() { pyget "$@" | awk '{ print $4 }' | sort -u | tr '\n' ' ' | sed 's/ $//'; }

# --- by hand --------------------------------------------------------------
# spike.tif: one 129x129 block (level 0), height 0 except 10 m at the
# centre s = (64,64). At level 0 every sample is a vertex, so an error
# comes only from s or from a triangle having s as a corner:
# - (64,64): its diamond is the block's two roots, whose corners are all 0:
#   at s the error is 10; its children score less (below): E = 10.
# - (64,0) (hypotenuse (0,0)-(128,0), apex s): in that triangle the weight
#   of s is y/64, so at the samples (63..65, 63) the plane is 10*63/64
#   above the DEM's 0: local 9.84375, and no triangle in its subtree has a
#   vertex closer to s with a larger weight: E = 9.84375. Likewise (0,64),
#   (128,64), (64,128) and the square (96,96) (hypotenuse s-(128,128):
#   at (65,65) the weight of s is 63/64).
# - (65,64) (a leaf: hypotenuse (64,64)-(66,64)): at itself the plane is
#   (10 + 0)/2 = 5 over the DEM's 0, its other samples are its corners: 5.
# - (1,0) and (127,127): every sample of their subtrees and every corner
#   is 0: E = 0. Corners: FLT_MAX.
dem2fqm "$T/spike.tif" - | fqmsolve - "$T/spike-v0.exr" &&
    tilepack -q "$T/spike.tif" "$T/spike" "$T/spike-v0.exr"
ok $? "tilepack on the 129x129 spike"
for v in "64 64 10" "64 0 9.84375" "0 64 9.84375" "128 64 9.84375" \
    "64 128 9.84375" "96 96 9.84375" "65 64 5" "1 0 0" "127 127 0" \
    "0 0 3.40282347e+38" "128 128 3.40282347e+38"; do
	set -- $v
	[ "$(e "$T/spike" 0 "$1" "$2")" = "$3" ]
	ok $? "spike: E($1,$2) = $3 as derived by hand (got $(e "$T/spike" 0 "$1" "$2"))"
done
# A plane: every triangle interpolates it exactly, all E are 0.
dem2fqm "$T/tilt.tif" - | fqmsolve - "$T/tilt-v0.exr" &&
    tilepack -q "$T/tilt.tif" "$T/tilt" "$T/tilt-v0.exr"
n=0
for j in 0 1 2 31 32 33 63 64 65 96 127 128; do
	for i in 0 1 2 31 32 33 63 64 65 96 127 128; do
		case "$i $j" in "0 0"|"128 0"|"0 128"|"128 128") continue ;; esac
		[ "$(e "$T/tilt" 0 "$i" "$j")" = 0 ] || n=$((n + 1))
	done
done
ok $n "tilted plane: E = 0 at every probed vertex ($n not)"

# --- a real pyramid: structure, borders, reruns ---------------------------
run "dem2vgis bigtujunga.tif" dem2vgis -q "$DATA/bigtujunga.tif" "$T/bt"
[ -f "$T/bt/index.json" ] && [ "$(ls "$T/bt" | tr '\n' ' ')" = "0 1 2 3 4 index.json " ]
ok $? "bigtujunga: levels 0..4 (the first fitting one block) and an index"
[ "$(ls "$T/bt/0" | wc -l)" = 60 ] && [ "$(ls "$T/bt/4")" = "0_0.exr" ]
ok $? "bigtujunga: 10x6 blocks at level 0, one at level 4"
# a border vertex of level 0 shared by four blocks: one Z, one E
[ "$(pyget "$T/bt" 0 128 128 | wc -l)" = 4 ] &&
    [ "$(pyget "$T/bt" 0 128 128 | awk '{ print $3, $4 }' | sort -u | wc -l)" = 1 ] &&
    [ "$(pyget "$T/bt" 1 200 128 | awk '{ print $3, $4 }' | sort -u | wc -l)" = 1 ]
ok $? "bigtujunga: border vertices identical in every block holding them"
dem2vgis -q "$DATA/bigtujunga.tif" "$T/bt2" && diff -r "$T/bt" "$T/bt2" >/dev/null
ok $? "bigtujunga: a rerun is byte-identical"
dem2vgis -q -3 "$DATA/bigtujunga.tif" "$T/bt3"
grep -q '"displaced": true' "$T/bt3/index.json" && [ "$(pyget "$T/bt3" 1 100 100 | wc -w)" = 6 ]
ok $? "bigtujunga -3: displaced levels with X and Y"

# --- bad input, interrupted runs, replacement -----------------------------
nothing_left() { [ -z "$(ls -A "$1" | grep -v '^keep$')" ]; }
mkdir "$T/o" "$T/scratch"
dem2fqm "$T/hills.tif" "$T/h0.exr" && fqmfilter "$T/h0.exr" "$T/h1.exr" &&
    fqmsolve "$T/h0.exr" "$T/hv0.exr" && fqmsolve "$T/h1.exr" "$T/hv1.exr"
fails "levels out of order" 1 "^tilepack: .*hv1.exr: is level 1, expected level 0" \
    tilepack "$T/hills.tif" "$T/o/p" "$T/hv1.exr" "$T/hv0.exr"
nothing_left "$T/o"; ok $? "levels out of order: nothing left"
fails "a level of another DEM" 1 "^tilepack: .*made from a 64x48 DEM, the DEM is 129x129" \
    tilepack "$T/spike.tif" "$T/o/p" "$T/hv0.exr"
fails "an FQM instead of a vertex map" 1 "is a fqm map, expected vertices" \
    tilepack "$T/hills.tif" "$T/o/p" "$T/h0.exr"
fails "a level too many" 1 "^tilepack: 2 levels given, a 64x48 DEM's pyramid has 1" \
    tilepack "$T/hills.tif" "$T/o/p" "$T/hv0.exr" "$T/hv1.exr"
# a NaN height in a vertex map (a stream row made NaN, its CRC made valid
# again): an error naming the row, no pyramid
fqmsolve "$T/h0.exr" - >"$T/hv0.fqm"
/usr/bin/python3 - "$T/hv0.fqm" "$T/hvnan.fqm" 7 <<'PY' || ok 1 "NaN vertex map fixture"
import struct, sys, zlib
d = bytearray(open(sys.argv[1], "rb").read())
w, h, nch = struct.unpack_from("<3I", d, 12)
rb = w * nch * 4
row0 = len(d) - 16 - h * (rb + 4)
y = int(sys.argv[3]); at = row0 + y * (rb + 4)
struct.pack_into("<I", d, at + 4 * 11, 0x7fc00000)   # channel 0, column 11
struct.pack_into("<I", d, at + rb, zlib.crc32(struct.pack("<I", y) + bytes(d[at:at + rb])))
open(sys.argv[2], "wb").write(d)
PY
fails "a NaN in a vertex map" 1 "^tilepack: .*hvnan.fqm: row 7, channel 0: NaN at column 11" \
    tilepack "$T/hills.tif" "$T/o/p" "$T/hvnan.fqm"
nothing_left "$T/o"; ok $? "a NaN in a vertex map: nothing left"
gdal_translate -q -srcwin 0 0 200 150 "$DATA/bigtujunga.tif" "$T/crop.tif" &&
    dem2fqm "$T/crop.tif" - | fqmsolve - "$T/cv0.exr"
fails "a level too few" 1 "^tilepack: 1 levels given, a 200x150 DEM's pyramid has 2" \
    tilepack "$T/crop.tif" "$T/o/p" "$T/cv0.exr"
fails "a missing level file" 1 "^tilepack: .*nosuch.exr" \
    tilepack "$T/hills.tif" "$T/o/p" "$T/hv0.exr" "$T/nosuch.exr"
fqmsolve "$T/h1.exr" - | head -c 5000 >"$T/cut.fqm"
fails "a truncated vertex map" 1 "^tilepack: .*cut.fqm: .*truncat" \
    tilepack "$T/hills.tif" "$T/o/p" "$T/hv0.exr" "$T/cut.fqm"
nothing_left "$T/o"; ok $? "failed runs leave nothing in the output directory"
fails "too few operands" 2 "usage: tilepack" tilepack "$T/hills.tif" "$T/o/p"
# the DEM read with other options than its levels were made with
fails "the DEM read with -s 2: georeferencing (cell) differs" 1 \
    "^tilepack: .*hv0.exr: georeferencing \(cell\) differs from the DEM's" \
    tilepack -s 2 "$T/hills.tif" "$T/o/p" "$T/hv0.exr"
fails "-j not a number: exit 2" 2 "^tilepack: -j x: not an integer in 1 \.\." \
    tilepack -j x "$T/hills.tif" "$T/o/p" "$T/hv0.exr"
fails "stdin for two inputs: exit 2" 2 "^tilepack: stdin can feed only one input" \
    tilepack "$T/hills.tif" "$T/o/p" - -
nothing_left "$T/o"; ok $? "refused runs leave nothing in the output directory"
run "--help exits 0" tilepack --help
grep -q '^usage: tilepack \[-flq\]' "$T/out"; ok $? "--help prints the usage on stdout"
run "-V exits 0" tilepack -V
grep -q '^tilepack [0-9]' "$T/out"; ok $? "-V prints the version"
# named after argv[0]'s last component, getopt's messages and its own alike
fails "run by its path: an unknown option" 2 "^tilepack: (invalid|unrecognized) option" \
    "$B/tilepack" -Q "$T/hills.tif" "$T/o/p" "$T/hv0.exr"
grep -q "^usage: tilepack " "$T/err"; ok $? "... and the usage, both under the name tilepack"

mkdir "$T/o/keep" && touch "$T/o/keep/precious"
fails "a directory that is not a pyramid is not replaced" 1 "not a pyramid" \
    tilepack "$T/hills.tif" "$T/o/keep" "$T/hv0.exr" "$T/hv1.exr"
[ -f "$T/o/keep/precious" ]; ok $? "... and keeps its files"
fqmsolve -m subsample "$T/h0.exr" "$T/hs0.exr"
tilepack -q "$T/hills.tif" "$T/o/p" "$T/hv0.exr" &&
    tilepack -q "$T/hills.tif" "$T/o/p" "$T/hs0.exr" &&
    grep -q '"mode": "subsample"' "$T/o/p/index.json" &&
    [ "$(ls -A "$T/o" | tr '\n' ' ')" = "keep p " ]
ok $? "a pyramid is replaced by a newer one, atomically, nothing else left"

# killed in the middle: no pyramid, no temporary directory
(tilepack -q "$DATA/N44W072.hgt" "$T/o/k" "$T/dummy" 2>/dev/null; true)
dem2fqm "$DATA/N44W072.hgt" - | fqmsolve - "$T/nv0.exr"
tilepack -q "$DATA/N44W072.hgt" "$T/o/k" "$T/nv0.exr" 2>/dev/null & p=$!
if mid_run $p "$T/o/k"; then
	kill -TERM $p; kill -CONT $p; wait $p
	[ "$(ls -A "$T/o" | tr '\n' ' ')" = "keep p " ]
	ok $? "tilepack killed by SIGTERM leaves no directory, no temporary"
else
	wait $p; rm -rf "$T/o/k"; skip "tilepack ended before the SIGTERM"
fi
# at a quarter and at three fifths of a whole run (measured: it must not
# have ended before the signal)
full=$( { /usr/bin/time -f %e dem2vgis -q "$DATA/N44W072.hgt" "$T/o/timing"; } 2>&1 | tail -1)
rm -rf "$T/o/timing"
for f in 0.25 0.6; do
	t=$(awk -v a="$full" -v f="$f" 'BEGIN { printf "%.2f", a * f }')
	rm -f "$T/killed"
	(TMPDIR=$T/scratch dem2vgis -q "$DATA/N44W072.hgt" "$T/o/k2" & p=$!
	    sleep $t; kill -TERM $p; wait $p
	    [ $? -ne 0 ] && : >"$T/killed") 2>/dev/null
	sleep 0.3
	if [ -e "$T/killed" ]; then
		[ "$(ls -A "$T/o" | tr '\n' ' ')" = "keep p " ] && nothing_left "$T/scratch"
		ok $? "dem2vgis killed by SIGTERM after $t s of $full s leaves no directory, no scratch"
	else	# a loaded machine: the run was quicker than the one timed
		ok 0 "# SKIP dem2vgis ended before the SIGTERM at $t s of $full s"
		rm -rf "$T/o/k2"
	fi
done
printf 'not a raster\n' >"$T/garbage.txt"
fails "dem2vgis on a non-raster" 1 "not a" dem2vgis "$T/garbage.txt" "$T/o/g"

# --- the examples Makefile: parallel and incremental ----------------------
mkdir "$T/dems" && cp "$T/hills.tif" "$T/spike.tif" "$T/dems/"
exmake() {
	make -s -f "$TOP/examples/Makefile" -j2 DEMS="$T/dems" OUT="$T/pyrs" \
	    DEM2VGIS="$B/dem2vgis" >"$T/mk" 2>&1 &&
	    [ -f "$T/pyrs/hills.tif/index.json" ] &&
	    [ -f "$T/pyrs/spike.tif/index.json" ]
}
# Once in a CI dry run under ASan and a loaded machine this failed, and
# never since in isolation: the first failure is shown, then one retry
# (make redoes only what is missing), so that its cause gets on record.
exmake || { echo "# examples/Makefile failed once; its output:"
	sed 's/^/#   /' "$T/mk"; ls -la "$T/pyrs" 2>&1 | sed 's/^/#   /'; exmake; }
st=$?; [ $st -eq 0 ] || sed 's/^/#   /' "$T/mk"
ok $st "examples/Makefile builds a pyramid per DEM with -j2"
before=$(ls -l --time-style=+%s.%N "$T/pyrs/hills.tif/index.json")
sleep 1; touch "$T/dems/spike.tif"
make -f "$TOP/examples/Makefile" -j2 DEMS="$T/dems" OUT="$T/pyrs" DEM2VGIS="$B/dem2vgis" >"$T/mk" 2>&1
[ "$(grep -c dem2vgis "$T/mk")" = 1 ] && grep -q spike.tif "$T/mk" &&
    [ "$(ls -l --time-style=+%s.%N "$T/pyrs/hills.tif/index.json")" = "$before" ]
ok $? "examples/Makefile redoes only the changed DEM"
# --- levels through FIFOs fed by one pipeline: read at once, no stall ------
# (the level-0 stream is megabytes: a level left unread fills its pipe,
# stops the tee, and starves the level being read)
fdem=$DATA/N44W072.hgt
fn=$(dem2fqm -I "$fdem" | awk '$1 == "levels" { print $2 }')
mkdir "$T/fifo"
fl=""; l=0
while [ $l -lt "$fn" ]; do mkfifo "$T/fifo/v$l"; fl="$fl $T/fifo/v$l"; l=$((l + 1)); done
chain() {	# L: level L's FQM on stdin; its vertex map and those above
	if [ "$1" -eq $((fn - 1)) ]; then fqmsolve - - >"$T/fifo/v$1"; return; fi
	mkfifo "$T/fifo/q$1"
	(fqmfilter - - <"$T/fifo/q$1" | chain $(($1 + 1))) &
	tee "$T/fifo/q$1" | fqmsolve - - >"$T/fifo/v$1"
	wait
}
(dem2fqm "$fdem" - | chain 0) 2>/dev/null &
# shellcheck disable=SC2086
timeout 60 tilepack -q -j 2 "$fdem" "$T/o/ff" $fl; st=$?
if [ $st -ne 0 ]; then	# a stall: the writers left blocked are let go
	for f in $fl; do timeout 20 cat "$f" >/dev/null 2>&1 & done
fi
wait
dem2vgis -q "$fdem" "$T/o/fv"
[ $st -eq 0 ] && diff -r "$T/o/ff" "$T/o/fv" >/dev/null
ok $? "$fn levels from FIFOs fed by one pipeline: no stall (status $st), the pyramid dem2vgis makes"
# Options dem2vgis passes on are tried first: no hang, exit 2, no output.
for bad in "-r 2" "-k lanczos" "-j x"; do
	# shellcheck disable=SC2086
	fails "dem2vgis $bad: a usage error before any work" 2 \
	    "^(fqmsolve|fqmfilter|dem2vgis): " \
	    timeout 20 dem2vgis $bad "$T/hills.tif" "$T/o/bad"
	[ ! -e "$T/o/bad" ]; ok $? "dem2vgis $bad: no output"
done
# --- a pyramid in separate processes: pieces (-p), then gather (-g) ------
# vmaps DEM DIR MODE: the vertex maps of every level into DIR/v0 ... as
# files (the chain by hand, each level's FQM kept as a file)
vmaps() {
	mkdir -p "$2" && dem2fqm "$1" "$2/q0" || return 1
	vm_n=$(dem2fqm -I "$1" | awk '$1 == "levels" { print $2 }') vm_l=0
	while [ $vm_l -lt "$vm_n" ]; do
		fqmsolve -m "$3" "$2/q$vm_l" - >"$2/v$vm_l" || return 1
		[ $((vm_l + 1)) -lt "$vm_n" ] &&
		    { fqmfilter "$2/q$vm_l" "$2/q$((vm_l + 1))" || return 1; }
		vm_l=$((vm_l + 1))
	done
}
# levels DIR: the vertex maps' paths in order
levels() { ls "$1"/v* | sort -t v -k 2 -n | tr '\n' ' '; }
# gathered WORK OUT REF LABEL: no temporary left in the work directory,
# tilepack -g (of $d and $vl) makes OUT of it, byte for byte REF, and
# the work directory became OUT
gathered() {
	half=$(find "$1" -name '.*.??????' | wc -l)
	[ "$half" -eq 0 ]; ok $? "$4: no temporary left in the work directory ($half)"
	# shellcheck disable=SC2086
	tilepack -q -g "$1" "$d" "$2" $vl && diff -r "$3" "$2" >/dev/null
	ok $? "$4: the gathered pyramid is tilepack's, byte for byte (index included)"
	[ ! -e "$1" ]; ok $? "$4: the work directory became the pyramid"
}
gdal_translate -q -srcwin 1800 3000 1700 500 "$DATA/N48W125.hgt" "$T/wide.tif"
# a piece reads only its window of DEM columns, unfilled: voids (across a
# piece's border too) on a DEM whose columns and rows run backwards
gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" "$T/crop.tif"
/usr/bin/python3 "$TOP/tests/tools/mkgdal.py" flipped "$T/crop.tif" "$T/flip.tif"
ok $? "a crop of N48W125 flipped both ways, with voids"
# qem1d: the whole of N48W125 (13 M samples); under the sanitizers the
# crop, unflipped (level 0 in two pieces, every level in parts, as well)
q1=$DATA/N48W125.hgt q1b=3000000
[ -n "${TL_QUICK:-}" ] && q1=$T/crop.tif q1b=200000
for c in qem1d qem3d flip; do
	d=$q1 m=$c
	[ $c = qem3d ] && d=$T/wide.tif
	[ $c = flip ] && d=$T/flip.tif m=qem1d
	vmaps "$d" "$T/pv-$c" $m
	vl=$(levels "$T/pv-$c")
	# shellcheck disable=SC2086
	tilepack -q "$d" "$T/pref-$c" $vl
	# shellcheck disable=SC2086
	pieces=$(tilepack -l "$d" - $vl)
	np=$(echo "$pieces" | wc -l)
	n0=$(echo "$pieces" | grep -c '^0:')
	[ "$n0" -ge 2 ]; ok $? "$c: level 0 of $(basename "$d") is cut in $n0 pieces ($np in all)"
	# every piece its own process, two at a time, the last ones first;
	# the first one killed (SIGKILL) in the middle, then run again
	first=$(echo "$pieces" | head -n 1)
	# shellcheck disable=SC2086
	tilepack -j 1 -p "$first" "$d" "$T/pw-$c" $vl & kp=$!
	i=0	# killed once its first block is written
	while [ $i -lt 600 ] && kill -0 $kp 2>/dev/null &&
	    [ -z "$(ls "$T/pw-$c/0" 2>/dev/null)" ]; do
		sleep 0.02; i=$((i + 1))
	done
	# killed, not ended first: a child that has just exited can still
	# be signalled, its status tells
	kill -9 $kp 2>/dev/null; wait $kp 2>/dev/null
	if [ $? -eq 137 ]; then
		[ ! -e "$T/pw-$c/.pieces/$(echo "$first" | tr : -)" ]
		ok $? "$c: a piece killed in the middle leaves no record"
	else
		ok 0 "# SKIP $c: the piece ended before it could be killed"
	fi
	# {} as the placeholder: a capital P may be in $T (mktemp's letters)
	# shellcheck disable=SC2086
	echo "$pieces" | sort -r |
	    xargs -P 2 -I {} tilepack -j 1 -p {} "$d" "$T/pw-$c" $vl 2>"$T/xargs.err"
	st=$?; [ $st -eq 0 ] || sed 's/^/#   /' "$T/xargs.err"
	ok $st "$c: every piece, two processes at a time"
	gathered "$T/pw-$c" "$T/pout-$c" "$T/pref-$c" "$c"
done
# A missing piece, a piece not of the cut, both -g and -p: refused.
d=$q1 vl=$(levels "$T/pv-qem1d")
# shellcheck disable=SC2086
first=$(tilepack -l "$d" - $vl | head -n 1)
# shellcheck disable=SC2086
n0=$(tilepack -l "$d" - $vl | grep -c '^0:')
# shellcheck disable=SC2086
for p in $(tilepack -l "$d" - $vl | sed 1d); do
	tilepack -j 1 -p "$p" "$d" "$T/pw-miss" $vl || echo "piece $p failed"
done
# shellcheck disable=SC2086
fails "-g with a piece missing" 1 "^tilepack: .*pw-miss: level 0, block columns 0\.\.$((${first##*:} - 1)): piece not made" \
    tilepack -q -g "$T/pw-miss" "$d" "$T/pout-miss" $vl
[ ! -e "$T/pout-miss" ]; ok $? "-g with a piece missing: no output"
# shellcheck disable=SC2086
fails "-p 0:0:3, not one of level 0's pieces" 1 "^tilepack: piece 0:0:3: not one of level 0's $n0 pieces" \
    tilepack -p 0:0:3 "$d" "$T/pw-bad" $vl
# shellcheck disable=SC2086
fails "-g and -p together" 2 "^tilepack: -g, -l and -p: one at most" \
    tilepack -g "$T/pw-miss" -p 0:0:14 "$d" "$T/x" $vl
# --- pieces in parts of DEM rows (-b): each part its own process ---------
# With -b, a piece whose DEM window holds more samples is made in parts of
# DEM rows: -l lists them just before it, they run first (in any order),
# then the piece from them. On the vertex maps above; -b such that every
# level is cut, level 0 too.
parts_of() { grep -E '^[0-9]+:[0-9]+:[0-9]+:[0-9]+:[0-9]+$'; }
for c in qem1d qem3d flip; do
	case $c in
	qem1d) d=$q1 b=$q1b ;;
	qem3d) d=$T/wide.tif b=200000 ;;
	*) d=$T/flip.tif b=200000 ;;
	esac
	vl=$(levels "$T/pv-$c") w=$T/qw-$c
	# shellcheck disable=SC2086
	jobs=$(tilepack -l -b $b "$d" - $vl)
	parts=$(echo "$jobs" | parts_of)
	np=$(echo "$parts" | grep -c .)
	nl=$(echo "$parts" | cut -d: -f1 | sort -u | wc -l)
	n0=$(echo "$parts" | grep -c '^0:')
	[ "$np" -ge 20 ] && [ "$nl" -ge 4 ] && [ "$n0" -ge 4 ]
	ok $? "$c, -b $b: $np parts, on $nl levels, $n0 on level 0"
	# the pieces are those listed without -b; a piece's parts come just
	# before it, at least 2, its rows 0..H-1 in order in bands of nearly
	# equal height; a level's only piece spans the DEM's width: it is in
	# ceil(W x H / b) parts
	wh=$(dem2fqm -I "$d" | awk '$1 == "size" { print $2, $3 }')
	bad=$(echo "$jobs" | awk -F: -v W="${wh% *}" -v H="${wh#* }" -v b=$b '
	NF == 5 {
		if (n == 0) { L = $1; B0 = $2; B1 = $3; y = 0; lo = H; hi = 0 }
		if ($1 != L || $2 != B0 || $3 != B1 || $4 != y)
			print "part " $0 " out of place"
		y = $5; h = $5 - $4; lo = h < lo ? h : lo; hi = h > hi ? h : hi
		n++; next
	}
	{
		if (n > 0 && ($1 != L || $2 != B0 || $3 != B1 || y != H ||
		    n < 2 || hi - lo > 1))
			print "piece " $0 ": " n " parts, rows to " y ", " lo ".." hi
		k[NR] = n > 0 ? n : 1; lev[NR] = $1; cnt[$1]++; n = 0
	}
	END {
		if (n > 0) print "parts after the last piece"
		want = int((W * H + b - 1) / b)
		for (i in lev)
			if (cnt[lev[i]] == 1 && k[i] != want)
				print "level " lev[i] ": " k[i] " parts, not " want
	}' | head -3)
	# shellcheck disable=SC2086
	[ -z "$bad" ] &&
	    [ "$(echo "$jobs" | grep -vE '(:.*){4}')" = "$(tilepack -l "$d" - $vl)" ]
	ok $? "$c: each piece after its parts, rows cut as the rule says${bad:+ ($bad)}"
	# a part killed (SIGKILL) once its local errors' temporary is there,
	# polled without a fork: a part takes tenths of a second
	# shellcheck disable=SC2046
	set -- $(echo "$parts" | head -n 1 | tr : ' ')
	# shellcheck disable=SC2086
	tilepack -b $b -j 1 -p "$1:$2:$3:$4:$5" "$d" "$w" $vl & kp=$!
	rec=$w/.parts/$1-$2-$3-$4 i=0
	while [ $i -lt 1000000 ] && [ ! -e "$rec" ] && kill -0 $kp 2>/dev/null; do
		set -- "$w"/.parts/.*.exr.??????
		[ -e "$1" ] && break
		i=$((i + 1))
	done
	kill -9 $kp 2>/dev/null; wait $kp 2>/dev/null
	if [ $? -eq 137 ]; then
		[ ! -e "$rec" ]
		ok $? "$c: a part killed in the middle leaves no record ($(find "$w" -name '.*.??????' | wc -l) temporary left)"
	else
		ok 0 "# SKIP $c: the part ended before it could be killed"
	fi
	# shellcheck disable=SC2086
	echo "$parts" | sort -r |
	    xargs -P 2 -I {} tilepack -b $b -j 1 -p {} "$d" "$w" $vl 2>"$T/xargs.err"
	st=$?; [ $st -eq 0 ] || sed 's/^/#   /' "$T/xargs.err"
	ok $st "$c: every part, two processes at a time, the killed one again"
	# the piece of a part whose record is missing: refused, no record
	# shellcheck disable=SC2046
	set -- $(echo "$parts" | sed -n 2p | tr : ' ')
	rm -f "$w/.parts/$1-$2-$3-$4"
	# shellcheck disable=SC2086
	fails "$c: piece $1:$2:$3 without its part $4:$5's record: refused" 1 \
	    "^tilepack: .*/qw-$c: piece $1:$2:$3: its part of DEM rows $4\.\.$(($5 - 1)) not made$" \
	    tilepack -b $b -j 1 -p "$1:$2:$3" "$d" "$w" $vl
	[ ! -e "$w/.pieces/$1-$2-$3" ]; ok $? "... and leaves no record of the piece"
	# shellcheck disable=SC2086
	tilepack -b $b -j 1 -p "$1:$2:$3:$4:$5" "$d" "$w" $vl &&
	    echo "$jobs" | grep -vE '(:.*){4}' | sort -r |
	    xargs -P 2 -I {} tilepack -b $b -j 1 -p {} "$d" "$w" $vl 2>"$T/xargs.err"
	st=$?; [ $st -eq 0 ] || sed 's/^/#   /' "$T/xargs.err"
	ok $st "$c: that part again, then every piece from its parts"
	gathered "$w" "$T/qout-$c" "$T/pref-$c" "$c, from parts"
	rm -rf "$T/qout-$c"
done
# Parts refused: rows not of the cut, a piece made whole, a piece not of
# the cut, malformed; nothing made.
d=$T/flip.tif b=200000 vl=$(levels "$T/pv-flip") w=$T/qw-bad
# shellcheck disable=SC2086
jobs=$(tilepack -l -b $b "$d" - $vl)
# shellcheck disable=SC2046
set -- $(echo "$jobs" | parts_of | head -n 1 | tr : ' ')
n=$(echo "$jobs" | grep -c "^$1:$2:$3:")
# shellcheck disable=SC2086
fails "-p $1:$2:$3:$4:$(($5 + 1)), rows not of the cut: refused" 1 \
    "^tilepack: part $1:$2:$3:$4:$(($5 + 1)): not one of the piece's $n parts$" \
    tilepack -b $b -p "$1:$2:$3:$4:$(($5 + 1))" "$d" "$w" $vl
for o in "-b 0" "-b 1000000000" ""; do
	# shellcheck disable=SC2086
	fails "-p $1:$2:$3:$4:$5 ${o:-(default -b)}: the piece is made whole" 1 \
	    "^tilepack: part $1:$2:$3:$4:$5: not one of the piece's 1 parts \(it is made whole: -b sets how many samples a part holds\)$" \
	    tilepack $o -p "$1:$2:$3:$4:$5" "$d" "$w" $vl
done
n=$(echo "$jobs" | grep -cE '^0:[0-9]+:[0-9]+$')
# shellcheck disable=SC2086
fails "-p 0:0:3:0:100, a part of no piece: refused" 1 \
    "^tilepack: piece 0:0:3: not one of level 0's $n pieces$" \
    tilepack -b $b -p 0:0:3:0:100 "$d" "$w" $vl
for p in 0:0:14:5 "$1:$2:$3:$4:$4" "$1:$2:$3:$4:"; do
	# shellcheck disable=SC2086
	fails "-p $p: a usage error" 2 "^tilepack: -p $p: expected level:b0:b1 or level:b0:b1:y0:y1" \
	    tilepack -b $b -p "$p" "$d" "$w" $vl
done
# shellcheck disable=SC2086
fails "-b -3: a usage error" 2 "^tilepack: -b -3: not an integer in 0 \.\." \
    tilepack -b -3 -l "$d" - $vl
[ ! -e "$w" ]; ok $? "refused parts leave no work directory"
done_testing
