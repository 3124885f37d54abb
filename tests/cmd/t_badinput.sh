# t_badinput - bad input gets a clear message, exit status 1 (2 for bad
# usage) and leaves no output file behind.
. "$(dirname "$0")/../lib.sh"

/usr/bin/python3 "$TOP/tests/tools/mkbad.py" "$T" || { ok 1 "fixtures"; done_testing; exit 1; }
o=$T/out.exr

# no_output: nothing named out.exr, nor a temporary beside it
no_output() { [ ! -e "$o" ] && [ -z "$(ls -A "$T" | grep '^\.out\.exr')" ]; }

# bad DESCRIPTION PATTERN CMD...: exit 1, message matching, no output left
bad() {
	_d=$1 _p=$2; shift 2
	fails "$_d" 1 "$_p" "$@"
	no_output; ok $? "$_d: no output file left"
	rm -f "$o"
}

printf 'hello, world\n' >"$T/text.tif"
bad "not a raster" "^dem2fqm: .*text.tif: not a" dem2fqm "$T/text.tif" "$o"
bad "missing DEM" "^dem2fqm: .*nosuch.tif: " dem2fqm "$T/nosuch.tif" "$o"
bad "1x1 DEM" "^dem2fqm: .*1x1 samples: a DEM needs at least 3x3" dem2fqm "$T/one.tif" "$o"
bad "2x2 DEM" "^dem2fqm: .*2x2 samples: a DEM needs at least 3x3" dem2fqm "$T/two.tif" "$o"
bad "all-void DEM" "^dem2fqm: .*allvoid.tif: .*no valid samples" dem2fqm "$T/allvoid.tif" "$o"
bad "all-NaN DEM" "^dem2fqm: .*allnan.tif: .*no valid samples" dem2fqm "$T/allnan.tif" "$o"

# NaN heights among valid ones are voids: filled, marked V = 0, excluded.
run "NaN heights are voids, not errors" dem2fqm "$T/somenan.tif" "$T/nan.exr"
fqmsolve "$T/nan.exr" "$T/nanv.exr" && set -- $(fqmeval "$T/somenan.tif" "$T/nanv.exr") x x
[ "$1" = $((64 * 48 - 200)) ] && [ "$5" = 0.000000 ]
ok $? "NaN voids excluded from errors: $1 valid samples, max error $5"
rsinfo -c "$T/nan.exr" | grep -q '^range V 0 1$'
ok $? "NaN voids marked V = 0"
rsinfo -c "$T/nan.exr" | awk '$1 == "range" && $3 != $3 + 0 { exit 1 }
    $1 == "range" && ($3 == "nan" || $4 == "nan" || $3 == "-nan") { exit 1 }'
ok $? "no NaN reaches the quadric map"

# A good FQM to damage.
dem2fqm "$T/hills.tif" "$T/h0.exr" && dem2fqm "$T/hills.tif" - >"$T/h0.fqm" ||
    ok 1 "fixture FQMs"
sz=$(wc -c <"$T/h0.exr")
head -c $((sz / 2)) "$T/h0.exr" >"$T/trunc.exr"
bad "truncated EXR" "^fqmfilter: .*trunc.exr: " fqmfilter "$T/trunc.exr" "$o"
sz=$(wc -c <"$T/h0.fqm")
head -c $((sz - 100)) "$T/h0.fqm" >"$T/trunc.fqm"
bad "truncated stream" "^fqmfilter: .*trunc.fqm: .*truncat" fqmfilter "$T/trunc.fqm" "$o"
bad "truncated stream on a pipe" "^fqmsolve: stdin: .*truncat" sh -c "head -c $((sz / 3)) '$T/h0.fqm' | fqmsolve - '$o'"
head -c 2000 /dev/urandom >"$T/garbage"
bad "garbage" "^fqmfilter: .*garbage: not" fqmfilter "$T/garbage" "$o"
cp "$T/h0.fqm" "$T/flip.fqm"
printf '\377' | dd of="$T/flip.fqm" bs=1 seek=$((sz / 2)) conv=notrunc 2>/dev/null
bad "corrupt stream row" "^fqmfilter: .*flip.fqm: .*(corrupt|CRC|checksum)" fqmfilter "$T/flip.fqm" "$o"

# NaN in an intermediate file, where no checksum catches it: a stream row
# made NaN with its CRC made valid again, an uncompressed EXR (no
# checksum at all) with a NaN in a chunk. An error naming the row, never
# passed on.
/usr/bin/python3 - "$T/h0.fqm" "$T/nan.fqm" 5 <<'PY' || ok 1 "NaN stream fixture"
import struct, sys, zlib
d = bytearray(open(sys.argv[1], "rb").read())
w, h, nch = struct.unpack_from("<3I", d, 12)
rb = w * nch * 4
row0 = len(d) - 16 - h * (rb + 4)
y = int(sys.argv[3]); at = row0 + y * (rb + 4)
struct.pack_into("<I", d, at + 4 * (2 * w + 3), 0x7fc00000)   # channel 2, column 3
struct.pack_into("<I", d, at + rb, zlib.crc32(struct.pack("<I", y) + bytes(d[at:at + rb])))
open(sys.argv[2], "wb").write(d)
PY
dem2fqm -z none "$T/hills.tif" "$T/h0n.exr"
/usr/bin/python3 - "$T/h0n.exr" "$T/nan.exr" 7 <<'PY' || ok 1 "NaN EXR fixture"
import struct, sys
d = bytearray(open(sys.argv[1], "rb").read())
p, h = 8, None
while d[p] != 0:                        # attributes: name, type, size, value
    e = d.index(0, p); name = d[p:e]; t = d.index(0, e + 1)
    n = struct.unpack_from("<i", d, t + 1)[0]
    if name == b"dataWindow":
        x0, y0, x1, y1 = struct.unpack_from("<4i", d, t + 5); h = y1 - y0 + 1
    p = t + 5 + n
off = struct.unpack_from("<Q", d, p + 1 + 8 * int(sys.argv[3]))[0]
struct.pack_into("<I", d, off + 8, 0x7f800000)   # chunk: y, size, data: +inf
open(sys.argv[2], "wb").write(d)
PY
bad "NaN in a stream row: fqmfilter" "^fqmfilter: .*nan.fqm: row 5, channel 2: NaN at column 3 \(damaged\?\)" \
    fqmfilter "$T/nan.fqm" "$o"
bad "NaN in a stream row: fqmsolve" "^fqmsolve: .*nan.fqm: row 5, channel 2: NaN" fqmsolve "$T/nan.fqm" "$o"
bad "NaN in a stream row on a pipe: fqmsolve" "^fqmsolve: stdin: row 5, channel 2: NaN" \
    sh -c "fqmsolve - '$o' <'$T/nan.fqm'"
bad "infinity in an uncompressed EXR: fqmfilter" "^fqmfilter: .*nan.exr: row 7, channel 0: infinite value at column 0" \
    fqmfilter "$T/nan.exr" "$o"
bad "infinity in an uncompressed EXR: fqmsolve -m qem3d" "^fqmsolve: .*nan.exr: row 7, channel 0: infinite" \
    fqmsolve -m qem3d "$T/nan.exr" "$o"
fqmfilter "$T/nan.fqm" - 2>"$T/err" | fqmsolve - "$o" 2>/dev/null
grep -q "row 5" "$T/err" && no_output
ok $? "NaN in a pipeline: the first stage names the row, nothing written"

# Wrong channels: a vertex map is not a quadric map, and vice versa.
fqmsolve "$T/h0.exr" "$T/v0.exr"
bad "vertex map into fqmfilter" "^fqmfilter: .*v0.exr: is a vertices map, expected fqm" fqmfilter "$T/v0.exr" "$o"
bad "vertex map into fqmsolve" "^fqmsolve: .*v0.exr: is a vertices map" fqmsolve "$T/v0.exr" "$o"
bad "a DEM into fqmfilter" "^fqmfilter: .*hills.tif: not an fqm" fqmfilter "$T/hills.tif" "$o"

rsinfo -d Q.a33 -o "$T/noa33.exr" "$T/h0.exr"
bad "FQM without channel Q.a33" "^fqmsolve: .*noa33.exr: no channel Q.a33" fqmsolve "$T/noa33.exr" "$o"
bad "non-writable output directory" "^dem2fqm: .*: (Permission denied|No such file)" dem2fqm "$T/hills.tif" "$T/nodir/out.exr"
if [ "$(id -u)" -ne 0 ]; then
	mkdir "$T/ro" && chmod 555 "$T/ro"
	fails "read-only directory" 1 "Permission denied" dem2fqm "$T/hills.tif" "$T/ro/out.exr"
	[ -z "$(ls -A "$T/ro")" ]; ok $? "read-only directory: nothing left"
fi
fails "/dev/full as output stream" 1 "^dem2fqm: stdout: .*(No space|write)" sh -c "dem2fqm '$T/hills.tif' - >/dev/full"

# A killed pipeline: the consumer sees truncation, writes nothing.
sh -c "dem2fqm '$DATA/N44W072.hgt' - | head -c 300000 | fqmfilter - '$o'" 2>"$T/err"
s=$?
[ $s -ne 0 ] && grep -q "truncat" "$T/err" && no_output
ok $? "a pipeline cut short leaves no output (exit $s: $(head -c 120 "$T/err"))"
dem2fqm "$DATA/N44W072.hgt" "$o" 2>/dev/null & pid=$!
if mid_run $pid "$o"; then
	kill -TERM $pid; kill -CONT $pid; wait $pid
	no_output; ok $? "dem2fqm killed by SIGTERM leaves no output, no temporary"
else
	wait $pid; rm -f "$o"; skip "dem2fqm ended before the SIGTERM"
fi

# Usage errors: exit 2.
fails "unknown option" 2 "usage: fqmfilter" fqmfilter -Q
fails "unknown kernel" 2 "^fqmfilter: -k lanczos: unknown kernel" fqmfilter -k lanczos
fails "unknown mode" 2 "^fqmsolve: -m 2d: unknown mode" fqmsolve -m 2d
fails "too many operands" 2 "usage: dem2fqm" dem2fqm a b c
fails "bad compression" 2 "^dem2fqm: -z lzw: unknown compression" dem2fqm -z lzw a b
fails "bad DEM option value" 2 "^dem2fqm: -s 0: " dem2fqm -s 0 a b
fails "missing option argument" 2 "^fqmsolve: option requires an argument" fqmsolve -m
for p in dem2fqm fqmfilter fqmsolve vgis-job; do
	$p --help >"$T/help" && grep -q "^usage: $p" "$T/help"
	ok $? "$p --help prints usage on stdout, exit 0"
	$p -h >"$T/h" && cmp -s "$T/h" "$T/help"
	ok $? "$p -h is --help"
	[ "$($p --version)" = "$p $(sed -n 's/^#define TL_VERSION "\(.*\)"/\1/p' "$TOP/src/lib/base/util.h")" ] &&
	    [ "$($p -V)" = "$($p --version)" ]
	ok $? "$p --version and -V"
	# called by a path: getopt's message and ours name it the same way
	"$B/$p" -Q 2>"$T/err" >/dev/null; s=$?
	[ $s -eq 2 ] && head -1 "$T/err" | grep -q "^$p: " &&
	    ! grep -q "$B" "$T/err" && grep -q "^usage: $p " "$T/err"
	ok $? "$B/$p -Q: exit 2, named $p in every message ($(head -1 "$T/err"))"
done
# The same file as input and output: refused, the input untouched.
cp "$T/hills.tif" "$T/same.tif" && cp "$T/h0.exr" "$T/same.exr"
fails "dem2fqm DEM DEM" 1 "^dem2fqm: .*same.tif: is both the input and the output" \
    dem2fqm "$T/same.tif" "$T/same.tif"
cmp -s "$T/same.tif" "$T/hills.tif"; ok $? "dem2fqm DEM DEM: the DEM untouched"
fails "fqmfilter L L" 1 "^fqmfilter: .*same.exr: is both the input and the output" \
    fqmfilter "$T/same.exr" "$T/same.exr"
fails "fqmsolve - - <L >>L" 1 "^fqmsolve: stdout: is both the input and the output" \
    sh -c 'fqmsolve - - <"$1" >>"$1"' sh "$T/same.exr"
cmp -s "$T/same.exr" "$T/h0.exr"; ok $? "fqmfilter, fqmsolve: the map untouched"
# "-" where a directory is written: standard output cannot hold one, and
# a directory named "-" made in the working directory is seldom meant
for p in "dem2vgis $T/hills.tif" "dem2rgb $T/hills.tif" "vgis2tiles $T" \
    "vgis2terrain $T"; do
	# shellcheck disable=SC2086
	fails "${p%% *} IN -: a usage error" 2 \
	    "^${p%% *}: -: the output is a directory" \
	    sh -c 'cd "$0" && exec "$@"' "$T" $p -
	[ ! -e "$T/-" ]; ok $? "${p%% *} IN -: no directory - made"
done
done_testing
