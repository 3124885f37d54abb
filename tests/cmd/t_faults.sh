# t_faults - the fault catalogue: disk full (a small tmpfs, as root), TMPDIR
# full, a read-only output directory, SIGPIPE on every program writing to a
# pipe, SIGKILL of tilepack at ten moments. Each: exit 1 (or death by
# SIGPIPE, as a Unix filter dies), a message naming the cause, nothing
# partial left; an old pyramid intact or the new one complete, never a mix;
# what a killed run left swept by the next.
. "$(dirname "$0")/../lib.sh"

dem=$DATA/N44W072.hgt
# under the sanitizers a 601x601 crop: its outputs are still megabytes,
# far beyond the 256 KiB disk below, the faults' code paths the same
if [ -n "${TL_QUICK:-}" ]; then
	gdal_translate -q -srcwin 300 300 601 601 "$dem" "$T/crop.tif" ||
	    { ok 1 "a crop"; done_testing; exit 1; }
	dem=$T/crop.tif
fi
/usr/bin/python3 "$TOP/tests/tools/mkbad.py" "$T" >/dev/null 2>&1 || { ok 1 "fixtures"; done_testing; exit 1; }
small=$T/hills.tif
dem2fqm "$small" "$T/l0.exr" && fqmsolve "$T/l0.exr" - >"$T/v0.fqm" || ok 1 "fixture maps"
fqmsolve -m qem1d "$T/l0.exr" "$T/v0.exr"
levels=$(dem2fqm -I "$small" | awk '$1 == "levels" { print $2 }')
lv=""; l=0; f="$T/l0.exr"
while [ $l -lt "$levels" ]; do
	fqmsolve "$f" "$T/v$l.exr"; lv="$lv $T/v$l.exr"
	fqmfilter "$f" "$T/l$((l + 1)).exr" 2>/dev/null; f=$T/l$((l + 1)).exr; l=$((l + 1))
done

dem2fqm "$dem" "$T/big0.exr"	# outputs far beyond 256 KiB
empty() { [ -z "$(ls -A "$1")" ]; }

# --- disk full, TMPDIR full, read-only: tmpfs mounts need root -----------
if [ "$(id -u)" -eq 0 ] && mkdir "$T/full" "$T/ro" &&
    mount -t tmpfs -o size=256k tmpfs "$T/full" 2>/dev/null; then
	trap 'umount "$T/full" "$T/ro" 2>/dev/null; rm -rf "$T"' EXIT
	mount -t tmpfs -o ro,size=64k tmpfs "$T/ro"
	full() {	# DESCRIPTION CMD...: exit 1, "No space left", nothing left
		_d=$1; shift
		fails "disk full: $_d" 1 "No space left on device" "$@"
		empty "$T/full"; ok $? "disk full: $_d: nothing left"
		rm -rf "${T:?}/full/"* "$T/full/".[!.]* 2>/dev/null
	}
	full "dem2fqm to EXR" dem2fqm "$dem" "$T/full/l0.exr"
	full "fqmfilter to EXR" fqmfilter "$T/big0.exr" "$T/full/l1.exr"
	full "fqmsolve to EXR" fqmsolve -m qem3d "$T/big0.exr" "$T/full/v.exr"
	fqmsolve "$T/big0.exr" "$T/bigv0.exr"
	full "tilepack" tilepack -q -j 1 "$dem" "$T/full/p" "$T/bigv0.exr"
	full "dem2vgis" dem2vgis -q "$dem" "$T/full/p"
	# full to the last block before anything: the first write, an EXR
	# header, fails (OpenEXRCore calls the error handler under a lock
	# that the handler once took again: a hang, caught by timeout)
	dd if=/dev/zero of="$T/full/fill" bs=4k 2>/dev/null
	fails "disk full from the first byte: dem2fqm to EXR, no hang" 1 \
	    "No space left on device" timeout 60 dem2fqm "$small" "$T/full/l0.exr"
	fails "disk full from the first byte: tilepack, no hang" 1 \
	    "No space left on device" timeout 60 tilepack -q "$small" "$T/full/p" $lv
	rm -f "$T/full/fill"
	empty "$T/full"; ok $? "disk full from the first byte: nothing left"
	# TMPDIR full: the DEM's scratch copy (dem2fqm), the driver's scratch
	fails "TMPDIR full: dem2fqm" 1 "No space left on device" \
	    env TMPDIR="$T/full" dem2fqm "$dem" "$T/x.exr"
	[ ! -e "$T/x.exr" ] && empty "$T/full"; ok $? "TMPDIR full: dem2fqm: nothing left"
	# five times: the readers downstream fail on short input at once,
	# in a race with dem2fqm's own exit; the cause told must be dem2fqm's
	n=0; for i in 1 2 3 4 5; do
		env TMPDIR="$T/full" dem2vgis -q "$dem" "$T/xp" 2>"$T/err"
		[ $? -eq 1 ] && grep -q "^dem2fqm: .*No space left on device" "$T/err" &&
		    [ ! -e "$T/xp" ] && empty "$T/full" && n=$((n + 1))
	done
	ok $((n != 5)) "TMPDIR full: dem2vgis: dem2fqm's message, nothing left ($n of 5; $(head -c 80 "$T/err"))"
	rm -rf "${T:?}/full/"*
	fails "read-only directory: dem2fqm" 1 "Read-only file system" dem2fqm "$small" "$T/ro/l0.exr"
	fails "read-only directory: tilepack" 1 "Read-only file system" tilepack "$small" "$T/ro/p" $lv
	fails "read-only directory: dem2vgis" 1 "Read-only file system" dem2vgis -q "$small" "$T/ro/p"
	empty "$T/ro"; ok $? "read-only directory: nothing left"
else
	ok 0 "# SKIP disk full, TMPDIR full, read-only: tmpfs needs root"
fi

# --- SIGPIPE: a reader that stops early ---------------------------------
# A writer dies of SIGPIPE (status 141 in the shell), or exits 1 naming
# the broken pipe; one whose whole output fit in the pipe may end well.
pipe() {	# MAYEND DESCRIPTION CMD: CMD's stdout read for 100 bytes
	_e=$1 _d=$2; shift 2
	s=$(sh -c "$* 2>\"$T/perr\"; echo \$? >\"$T/pst\"" | head -c 100 | wc -c)
	st=$(cat "$T/pst")
	{ [ "$st" -eq 141 ] || { [ "$st" -eq 1 ] && grep -q "Broken pipe" "$T/perr"; } ||
	    { [ "$_e" = ends ] && [ "$st" -eq 0 ]; }; } &&
	    [ "$s" -eq 100 ] && [ -z "$(ls -A "$T" | grep '^\.')" ]
	ok $? "SIGPIPE: $_d: status $st, nothing left ($(head -c 80 "$T/perr"))"
}
pipe dies "dem2fqm" dem2fqm "$dem" -
pipe dies "fqmfilter" fqmfilter "$T/big0.exr" -
pipe dies "fqmsolve" fqmsolve "$T/big0.exr" -
pipe dies "fqmsolve -m qem3d" fqmsolve -m qem3d "$T/big0.exr" -
pipe ends "dem2fqm -I" dem2fqm -I "$dem"
dem2vgis -q "$small" "$T/pp"
pipe ends "tilecheck" tilecheck --dem "$small" "$T/pp"

# --- SIGKILL of tilepack at ten moments, over an old pyramid -------------
dem2vgis -q "$dem" "$T/old"
dem2vgis -q -3 "$dem" "$T/new"	# what the runs below build
dem2fqm "$dem" - | fqmfilter - - >/dev/null	# warm
for k in 1 2 3 4 5 6 7 8 9 10; do
	rm -rf "$T/p"; cp -r "$T/old" "$T/p"
	# the levels of the new pyramid, then tilepack alone, killed
	[ -d "$T/lv" ] || { mkdir "$T/lv"; f=-; l=0
		dem2fqm "$dem" "$T/lv/l0.exr"
		n=$(dem2fqm -I "$dem" | awk '$1 == "levels" { print $2 }')
		while [ $l -lt "$n" ]; do
			fqmsolve -m qem3d "$T/lv/l$l.exr" "$T/lv/v$l.exr"
			[ $((l + 1)) -lt "$n" ] && fqmfilter "$T/lv/l$l.exr" "$T/lv/l$((l + 1)).exr"
			l=$((l + 1))
		done
		tp=$( { /usr/bin/time -f %e tilepack -q "$dem" "$T/tpt" "$T"/lv/v*.exr; } 2>&1 | tail -1)
	}
	at=$(awk -v f="$tp" -v k="$k" 'BEGIN { printf "%.2f", f * (k - 0.5) / 10 }')
	tilepack -q "$dem" "$T/p" $(ls "$T"/lv/v*.exr | sort -V) 2>/dev/null & pid=$!
	sleep "$at"; kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
	state=mixed
	diff -r "$T/p" "$T/old" >/dev/null 2>&1 && state=old
	diff -r "$T/p" "$T/new" >/dev/null 2>&1 && state=new
	[ $state != mixed ]
	ok $? "tilepack SIGKILLed at $at s of $tp s: the pyramid is the $state one"
done
# what the killed runs left (hidden temporaries beside the output) goes
# with the next run into the same place
hidden=$(ls -A "$T" | grep -c '^\.p\.' || true)
tilepack -q -f "$dem" "$T/p" $(ls "$T"/lv/v*.exr | sort -V)
left=$(ls -A "$T" | grep -c '^\.p\.' || true)
[ "$left" -eq 0 ]; ok $? "the next tilepack removes what killed runs left ($hidden before, $left after)"
diff -r "$T/p" "$T/new" >/dev/null; ok $? "and builds the new pyramid"
done_testing
