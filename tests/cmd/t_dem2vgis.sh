# t_dem2vgis - the supervisor: usage errors of the stages found before any
# work (exit 2, in seconds); the first failing stage's message alone; the
# stages' warnings passed on; SIGKILL or SIGTERM of the driver at ten
# moments takes every stage down and leaves the old pyramid or the new
# one, never a mix, and no temporary; a killed run's scratch is swept by
# the next run; stdin with -n.
. "$(dirname "$0")/../lib.sh"

dem=$DATA/N44W072.hgt
export TMPDIR=$T/tmp
mkdir -p "$TMPDIR"
# kdem: the DEM of the whole runs below the usage errors and stdin; under
# the sanitizers a 601x601 crop (four levels, runs of seconds there)
kdem=$dem
if [ -n "${TL_QUICK:-}" ]; then
	kdem=$T/crop.tif
	gdal_translate -q -srcwin 300 300 601 601 "$dem" "$kdem" ||
	    { ok 1 "a crop"; done_testing; exit 1; }
fi
dv() { "$B/dem2vgis" "$@"; }
nothing_left() {	# DIR: no output, no temporary beside it, no scratch
	[ ! -e "$1" ] && [ -z "$(ls -A "$(dirname "$1")" | grep '^\.')" ] &&
	    [ -z "$(ls -A "$TMPDIR")" ]
}

# usage errors of the options passed on: before any work, in seconds
for o in "-r 2" "-k foo" "-j 0" "-e bogus" "-N x" "-s -1" "-Z"; do
	start=$(date +%s)
	# shellcheck disable=SC2086
	dv $o "$dem" "$T/u" >"$T/out" 2>"$T/err"; s=$?
	took=$(( $(date +%s) - start ))
	[ $s -eq 2 ] && [ $took -le 10 ] && { [ "$o" = -Z ] || [ "$(wc -l <"$T/err")" -eq 1 ]; } &&
	    nothing_left "$T/u"
	ok $? "dem2vgis $o: exit 2 in ${took} s, one line: $(head -c 80 "$T/err" | tr '\n' ' ')"
done
fails "-r 2: fqmsolve's own message" 2 "^fqmsolve: -r 2: not a number" dv -r 2 "$dem" "$T/u"
fails "-k foo: fqmfilter's own message" 2 "^fqmfilter: -k foo: unknown kernel" dv -k foo "$dem" "$T/u"
fails "no such DEM: exit 1, named" 1 "^dem2vgis: $T/none.hgt: No such file" dv "$T/none.hgt" "$T/u"
fails "one operand: usage" 2 "^usage: dem2vgis " dv "$dem"
dv --help >"$T/h" 2>&1; s=$?
[ $s -eq 0 ] && grep -q "^usage: dem2vgis" "$T/h" && [ "$(grep -c '^  -' "$T/h")" -ge 7 ]
ok $? "--help: usage and every option on stdout, exit 0"
[ "$(dv -V)" = "dem2vgis $(sed -n 's/^#define TL_VERSION "\(.*\)"/\1/p' "$TOP/src/lib/base/util.h")" ]
ok $? "-V: name and version"

# a reference build, then stdin (the copy named by -n) gives the same
run "reference pyramid of $(basename "$dem")" dv -q "$dem" "$T/ref"
cp "$T/err" "$T/ref.err"	# not on a terminal (below)
cat "$dem" | dv -q -n N44W072.hgt - "$T/in" 2>"$T/err"
diff -r "$T/ref" "$T/in" >/dev/null; ok $? "stdin with -n: the same pyramid"

# one progress line for the whole pipeline on a terminal (a pty made by
# script(1)), rising to 100%, no stage's own; none when not a terminal
if command -v script >/dev/null; then
	TL_BIN=$B script -qec "'$B/dem2vgis' -q '$kdem' '$T/pty'" /dev/null >"$T/pty.out" 2>&1
	tr '\r' '\n' <"$T/pty.out" | tr -d '\033' | grep . >"$T/pty.lines"
	awk '!/^dem2vgis: +[0-9]+%$/ { bad = 1 } { p = $2 + 0; if (p < last) bad = 1; last = p }
	    END { exit bad || last != 100 || NR < 10 }' "$T/pty.lines"
	ok $? "on a terminal: one line, dem2vgis: 0% .. 100% ($(wc -l <"$T/pty.lines") updates, last: $(tail -1 "$T/pty.lines"))"
fi
[ ! -s "$T/ref.err" ]; ok $? "not on a terminal: no progress at all"

# a stage that fails mid-way: its message alone, every stage down, nothing
# left (fake stages: the real ones, but a solver that dies at level 2; the
# processes' route: t_oneproc tests the one process's)
mkdir -p "$T/fake"
for p in dem2fqm fqmfilter tilepack; do ln -s "$B/$p" "$T/fake/$p"; done
cat >"$T/fake/fqmsolve" <<EOS
#!/bin/sh
# the fourth solver started fails after reading a little (mkdir: atomic)
n=0; while ! mkdir "$T/fake/s\$n" 2>/dev/null; do n=\$((n + 1)); done
if [ "\$n" -eq 3 ]; then head -c 100000 >/dev/null; echo "fqmsolve: level 3: made to fail" >&2; exit 1; fi
exec "$B/fqmsolve" "\$@"
EOS
chmod +x "$T/fake/fqmsolve"
start=$(date +%s)
TL_BIN=$T/fake TL_PROCESSES=1 dv -q "$kdem" "$T/f" >"$T/out" 2>"$T/err"; s=$?
took=$(( $(date +%s) - start ))
[ $s -eq 1 ] && [ "$(cat "$T/err")" = "fqmsolve: level 3: made to fail" ]
ok $? "a stage fails: exit 1 ($s), its message alone ($(tr '\n' '|' <"$T/err" | head -c 200))"
nothing_left "$T/f"; ok $? "a stage fails: no output, no temporary, no scratch (${took} s)"

# warnings of stages that succeed are passed on, once (a DEM without
# georeferencing: dem2fqm says what it assumed)
/usr/bin/python3 "$TOP/tests/tools/mkbad.py" "$T" >/dev/null 2>&1 &&
    GDAL_PAM_ENABLED=NO gdal_translate -q -of PNG -ot UInt16 -scale 0 1000 0 1000 \
    "$T/hills.tif" "$T/plain.png" 2>/dev/null
dv -q "$T/plain.png" "$T/w" 2>"$T/err"; s=$?
[ $s -eq 0 ] && [ "$(grep -c . "$T/err")" -eq 1 ] &&
    grep -q "^dem2fqm: .*plain.png: not georeferenced" "$T/err"
ok $? "a stage's warning is passed on once, exit 0 ($(tr '\n' '|' <"$T/err" | head -c 160))"

# SIGKILL / SIGTERM at ten moments, over an old pyramid: afterwards no
# stage alive, the old pyramid or the new one (never a mix), no temporary
# (SIGKILL: the processes' route, whose stages die with it; SIGTERM: the
# one process; its SIGKILL is t_oneproc's, swept by the next run)
cp -r "$T/ref" "$T/old"
# what a finished run leaves, and how long it takes
full=$( { /usr/bin/time -f %e "$B/dem2vgis" -q -3 "$kdem" "$T/new3" ; } 2>&1 | tail -1)
for k in 1 2 3 4 5 6 7 8 9 10; do
	sig=KILL; [ $((k % 3)) -eq 0 ] && sig=TERM
	at=$(awk -v f="$full" -v k="$k" 'BEGIN { printf "%.2f", f * (k - 0.5) / 10 }')
	rm -rf "$T/p"; cp -r "$T/old" "$T/p"
	procs=; [ $sig = KILL ] && procs=1
	TL_PROCESSES=$procs "$B/dem2vgis" -q -3 "$kdem" "$T/p" 2>/dev/null & pid=$!
	sleep "$at"
	kids=$(ps -eo pid,ppid | awk -v p=$pid '$2 == p { print $1 }')
	kill -$sig $pid 2>/dev/null
	wait $pid 2>/dev/null
	# the stages get SIGTERM and remove their temporaries (tilepack a
	# directory of blocks): on a loaded machine that may take a while,
	# so up to 10 s, polled
	n=0
	while :; do
		alive=0
		for c in $kids; do
			[ -d /proc/$c ] && [ "$(awk '{ print $3 }' /proc/$c/stat 2>/dev/null)" != Z ] &&
			    alive=$((alive + 1))
		done
		[ $alive -eq 0 ] || [ $n -ge 100 ] && break
		sleep 0.1; n=$((n + 1))
	done
	state=mixed
	diff -r "$T/p" "$T/old" >/dev/null 2>&1 && state=old
	diff -r "$T/p" "$T/new3" >/dev/null 2>&1 && state=new
	hidden=$(ls -A "$T" | grep -c '^\.' || true)
	[ $alive -eq 0 ] && [ $state != mixed ] && [ "$hidden" -eq 0 ]
	ok $? "SIG$sig at ${at} s of ${full} s: $alive stages alive after $((n / 10)).$((n % 10)) s, pyramid $state, $hidden temporaries"
done
# a killed run's scratch is swept by the next run
rm -rf "$TMPDIR"/*; "$B/dem2vgis" -q "$kdem" "$T/s1" 2>/dev/null & pid=$!
# killed once its scratch is there (a loaded machine takes seconds)
i=0; while [ $i -lt 2000 ] && [ -z "$(ls "$TMPDIR")" ]; do sleep 0.01; i=$((i + 1)); done
kill -KILL $pid; wait $pid 2>/dev/null; sleep 1
n1=$(ls "$TMPDIR" | grep -c '^dem2vgis\.' || true)
dv -q -f "$kdem" "$T/s2"
n2=$(ls "$TMPDIR" | grep -c '^dem2vgis\.' || true)
[ "$n1" -ge 1 ] && [ "$n2" -eq 0 ]
ok $? "scratch of a SIGKILLed run ($n1) removed by the next run ($n2 left)"
done_testing
