# t_leftovers - what a run leaves and what it loses: the temporaries of
# SIGKILLed runs swept by the next output to ANOTHER name in the same
# directory (a live run's and another tool's never), ulimit -f (exit 1,
# "File too large", nothing left), too few descriptors (exit 1, a message
# that says so, nothing left), and every print mode on a full stdout (exit
# 1). The disk-full, SIGPIPE and same-name cases are t_faults'.
. "$(dirname "$0")/../lib.sh"

dem=$DATA/N44W072.hgt
s=$T/s.tif m=$T/m.tif
gdal_translate -q -srcwin 0 0 300 300 "$dem" "$s" &&
    gdal_translate -q -srcwin 0 0 1201 600 "$dem" "$m" &&
    dem2vgis -q "$s" "$T/p" && dem2vgis -q -M "$m" "$T/vm" &&
    dem2vgis -q -M "$s" "$T/svm" && dem2vgis -q "$m" "$T/pm" &&
    dem2fqm "$s" "$T/l0.exr" || { ok 1 "fixtures"; done_testing; exit 1; }
vm=$(ls "$T"/vm/v*.fqm | sort -V) svm=$(ls "$T"/svm/v*.fqm | sort -V)
TMPDIR=$T/tmp; export TMPDIR; mkdir "$TMPDIR"
hidden() { ls -A "$1" | grep '^\.' ; }	# DIR: its hidden entries
nothing() { [ -z "$(hidden "$1")" ] && [ -z "$(ls -A "$TMPDIR")" ]; }
# the user attribute that marks a temporary as ours (outfile.c)
marked() { /usr/bin/python3 -c 'import os, sys
sys.exit(0 if "user.terrain-lod.tmp" in os.listxattr(sys.argv[1], follow_symlinks=False) else 1)' "$1"; }

# whether $T's file system keeps user attributes (else nothing is marked)
: >"$T/.xa"
/usr/bin/python3 -c 'import os, sys
os.setxattr(sys.argv[1], "user.t", b"1")' "$T/.xa" 2>/dev/null && _xa=0 || _xa=1
rm -f "$T/.xa"
xattrs() { return $_xa; }

# wait_tmp DIR NAME PID: until .NAME.XXXXXX is in DIR and marked as ours
# (or PID ended), then SIGSTOP PID; 0 when the temporary is there. A kill
# between its creation and its mark (microseconds) leaves one that only
# the next output of the same name removes (outfile.h): not what is
# tested here.
wait_tmp() {
	_i=0
	while [ $_i -lt 2000 ] && kill -0 "$3" 2>/dev/null; do
		_f=$(hidden "$1" | grep "^\.$2\.......\$" | head -1)
		if [ -n "$_f" ] && { ! xattrs || marked "$1/$_f"; }; then
			kill -STOP "$3"; return 0
		fi
		sleep 0.01; _i=$((_i + 1))
	done
	return 1
}

# --- SIGKILL mid-run; the next output to another name sweeps -------------
# killed DESCRIPTION NAME SWEEPER... : the command started in the
# background (in $cmd) writes D/NAME; killed once its temporary is there;
# SWEEPER writes another name in D
killed() {
	_d=$1 _nm=$2; shift 2
	wait_tmp "$D" "$_nm" $pid; _w=$?
	kill -KILL $pid 2>/dev/null; kill -CONT $pid 2>/dev/null
	wait $pid 2>/dev/null
	_left=$(hidden "$D" | grep -c "^\.$_nm\." || true)
	[ $_w -eq 0 ] && [ "$_left" -eq 1 ]
	ok $? "$_d SIGKILLed: its temporary .$_nm.XXXXXX stays ($_left)"
	"$@" >/dev/null 2>"$T/err"; _s=$?
	_left=$(hidden "$D" | grep -c "^\.$_nm\." || true)
	[ $_s -eq 0 ] && [ "$_left" -eq 0 ]
	ok $? "$_d: swept by $1 writing another name in the directory (exit $_s, $_left left)"
}
D=$T/k1; mkdir "$D"
tilepack -q -j 1 "$m" "$D/pyr" $vm 2>/dev/null & pid=$!
killed "tilepack" pyr dem2fqm "$s" "$D/other.exr"
D=$T/k2; mkdir "$D"
vgis2tiles -q -j 1 "$T/pm" "$D/tiles" 2>/dev/null & pid=$!
killed "vgis2tiles" tiles tilepack -q "$s" "$D/pyr2" $svm
D=$T/k3; mkdir "$D"
dem2fqm "$m" "$D/l0.exr" 2>/dev/null & pid=$!
killed "dem2fqm to a file" l0.exr vgis2tiles -q "$T/p" "$D/t"
D=$T/k4; mkdir "$D"
dem2vgis -q -M "$m" "$D/maps" 2>/dev/null & pid=$!
killed "dem2vgis -M" maps fqmsolve "$T/l0.exr" "$D/v0.exr"
# dem2vgis itself: its stages die with it and remove theirs; its scratch
# (locked in TMPDIR) goes with the next dem2vgis
D=$T/k5; mkdir "$D"
dem2vgis -q "$m" "$D/pyr" 2>/dev/null & pid=$!
wait_tmp "$D" pyr $pid; kill -KILL $pid; kill -CONT $pid 2>/dev/null
wait $pid 2>/dev/null; sleep 1	# the stages' SIGTERM
sc=$(ls "$TMPDIR" | grep -c '^dem2vgis\.' || true)
dem2vgis -q "$s" "$D/pyr3"; st=$?
[ "$sc" -eq 1 ] && [ $st -eq 0 ] && nothing "$D"
ok $? "dem2vgis SIGKILLed: its scratch ($sc) and temporaries gone after the next run ($(hidden "$D") $(ls "$TMPDIR"))"
# a plan's piece job killed in its work directory: the pieces that follow
# sweep their level's directory, the retry its own; the gathered pyramid
# holds no temporary
# (a piece may end between two looks on a loaded machine: up to 5 tries)
W=$T/work n0=0 try=0
while [ "$n0" -eq 0 ] && [ $try -lt 5 ]; do
	rm -rf "$W"
	tilepack -q -j 1 -p 0:0:10 "$m" "$W" $vm 2>/dev/null & pid=$!
	i=0
	while [ $i -lt 2000 ] && kill -0 $pid 2>/dev/null &&
	    ! find "$W" -name '.*.??????' 2>/dev/null | grep -q .; do
		sleep 0.01; i=$((i + 1)); done
	kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
	n0=$(find "$W" -name '.*.??????' 2>/dev/null | wc -l)
	try=$((try + 1))
done
st=0; for p in $(tilepack -l "$m" "$W" $vm | sort -r); do
	tilepack -q -j 1 -p "$p" "$m" "$W" $vm || st=1; done
tilepack -q -g "$W" "$m" "$T/gathered" $vm || st=1
n1=$(find "$T/gathered" -name '.*' | wc -l)
[ "$n0" -ge 1 ] && [ $st -eq 0 ] && [ "$n1" -eq 0 ] && tilecheck "$T/gathered" >/dev/null
ok $? "tilepack -p killed in a work directory: the retry sweeps, the gathered pyramid holds no temporary ($n0 after $try tries, then $n1)"

# --- a live writer's temporary, and other tools', are never swept --------
D=$T/live; mkdir "$D"
: >"$D/.rsync.Ab12Cd"	# another tool's temporary: unmarked, unlocked
mkdir "$D/.other.Xy34Zw"; : >"$D/.other.Xy34Zw/.lock"
touch -d '-1 hour' "$D/.other.Xy34Zw"
tilepack -q -j 1 "$m" "$D/pyr" $vm 2>/dev/null & pid=$!
wait_tmp "$D" pyr $pid; w=$?
live=$(hidden "$D" | grep '^\.pyr\.')
marked "$D/$live"; mk=$?
dem2fqm "$s" "$D/x.exr" && vgis2tiles -q "$T/p" "$D/t" &&
    [ -d "$D/$live" ] && [ -e "$D/.rsync.Ab12Cd" ] && [ -d "$D/.other.Xy34Zw" ]
ok $? "a stopped tilepack's temporary ($live, marked: $mk) survives two other outputs; another tool's stay"
kill -CONT $pid; wait $pid; st=$?
tilecheck "$D/pyr" >/dev/null; ck=$?
[ $w -eq 0 ] && [ $st -eq 0 ] && [ $ck -eq 0 ] && [ ! -e "$D/$live" ]
ok $? "continued, it completes its pyramid (exit $st, tilecheck $ck)"
marked "$D/pyr" || marked "$D/x.exr" || marked "$D/pyr/index.json"
ok $((! $?)) "committed outputs carry no mark"
D=$T/live2; mkdir "$D"
dem2fqm "$m" "$D/l0.exr" & pid=$!
wait_tmp "$D" l0.exr $pid; w=$?
live=$(hidden "$D" | grep '^\.l0\.exr\.')
tilepack -q "$s" "$D/pyr" $svm && [ -f "$D/$live" ]
ok $? "a stopped dem2fqm's temporary file ($live) survives another output"
kill -CONT $pid; wait $pid; st=$?
dem2fqm "$m" "$T/ref.exr"
[ $w -eq 0 ] && [ $st -eq 0 ] && [ -z "$(hidden "$D")" ] && cmp -s "$D/l0.exr" "$T/ref.exr"
ok $? "continued, it completes, the same bytes as an undisturbed run (exit $st)"

# --- ulimit -f: exit 1, "File too large", nothing left -------------------
# big KIB DESCRIPTION CMD...: CMD under ulimit -f KIB in an empty $D
big() {
	_k=$1 _d=$2; shift 2
	rm -rf "$D"; mkdir "$D"
	sh -c 'ulimit -f "$0"; exec "$@"' "$_k" "$@" >"$T/out" 2>"$T/err"; _s=$?
	[ $_s -eq 1 ] && grep -q "File too large.*ulimit -f" "$T/err" &&
	    [ -z "$(ls -A "$D")" ] && [ -z "$(ls -A "$TMPDIR")" ]
	ok $? "ulimit -f $_k: $_d: exit $_s, nothing left ($(head -c 120 "$T/err"))"
}
D=$T/f
big 400 "dem2fqm to EXR" dem2fqm "$s" "$D/l0.exr"
big 20 "dem2fqm (its scratch)" dem2fqm "$s" "$D/l0.exr"
big 100 "vgis-job fill" vgis-job fill "$m" "$D/fill.exr"
big 100 "fqmfilter" fqmfilter "$T/l0.exr" "$D/l1.exr"
big 20 "fqmsolve" fqmsolve "$T/l0.exr" "$D/v0.exr"
big 20 "fqmsolve -m qem3d" fqmsolve -m qem3d -j 2 "$T/l0.exr" "$D/v0.exr"
big 20 "tilepack" tilepack -q "$m" "$D/pyr" $vm
big 400 "dem2vgis" dem2vgis -q "$s" "$D/pyr"
big 400 "dem2vgis -M" dem2vgis -q -M "$s" "$D/maps"
big 20 "vgis2tiles" vgis2tiles -q "$T/p" "$D/t"
gl=0; tileplay --shot "$T/shot.png" "$T/p" 2>/dev/null || gl=1
if [ $gl -eq 0 ]; then
	big 1 "tileplay --shot" tileplay --shot "$D/s.png" "$T/p"
else
	ok 0 "# SKIP tileplay --shot: no headless OpenGL here"
fi

# --- too few descriptors: exit 1, says so, nothing left ------------------
# fds N DESCRIPTION STATUS CMD...: CMD with ulimit -n N (fds 3-9 closed)
fds() {
	_k=$1 _d=$2 _want=$3; shift 3
	rm -rf "$D"; mkdir "$D"
	sh -c 'exec 3>&- 4>&- 5>&- 6>&- 7>&- 8>&- 9>&-; ulimit -n "$0"; exec "$@"' \
	    "$_k" "$@" >"$T/out" 2>"$T/err"; _s=$?
	[ $_s -eq "$_want" ] && grep -q "descriptors: raise ulimit -n" "$T/err" &&
	    [ -z "$(ls -A "$D")" ] && [ -z "$(ls -A "$TMPDIR")" ]
	ok $? "ulimit -n $_k: $_d: exit $_s, nothing left ($(head -c 120 "$T/err"))"
}
D=$T/n
# the sanitizers' runtime (make check-asan) needs descriptors of its own
if [ -n "${TL_QUICK:-}" ]; then ok 0 "# SKIP ulimit -n: sanitizer build"; else
for k in 4 5 6; do
	fds $k "vgis2tiles -j 4" 1 vgis2tiles -q -j 4 "$T/p" "$D/t"
done
fds 4 "vgis2tiles (PROJ's database, not the CRS)" 1 vgis2tiles -q -j 2 "$T/p" "$D/t"
grep -q CRS "$T/err"; ok $((! $?)) "vgis2tiles: the CRS not blamed"
fds 4 "dem2fqm" 1 dem2fqm "$s" "$D/l0.exr"
fds 5 "dem2fqm" 1 dem2fqm "$s" "$D/l0.exr"
fds 4 "fqmfilter" 1 fqmfilter "$T/l0.exr" "$D/l1.exr"
fds 4 "fqmsolve" 1 fqmsolve -m qem3d -j 2 "$T/l0.exr" "$D/v0.exr"
for k in 4 6; do
	fds $k "tilepack" 1 tilepack -q -j 4 "$m" "$D/pyr" $vm
done
# (the processes' route: its pipes; the one process needs fewer)
for k in 4 16; do
	fds $k "dem2vgis --processes" 1 dem2vgis --processes -q "$s" "$D/pyr"
done
fds 4 "dem2vgis" 1 dem2vgis -q "$s" "$D/pyr"
fds 4 "tilecheck --dem" 3 tilecheck --dem "$s" "$T/p"
if [ $gl -eq 0 ]; then
	fds 4 "tileplay --shot (libEGL)" 1 tileplay --shot "$D/s.png" "$T/p"
	fds 5 "tileplay --shot" 1 tileplay --shot "$D/s.png" "$T/p"
fi
fi

# --- a full stdout: exit 1, "stdout: No space left on device" ------------
full() {	# DESCRIPTION CMD...
	_d=$1; shift
	"$@" >/dev/full 2>"$T/err"; _s=$?
	[ $_s -eq 1 ] && grep -q "stdout: .*No space left on device" "$T/err" &&
	    [ "$(grep -c . "$T/err")" -eq 1 ]
	ok $? "stdout full: $_d: exit $_s ($(head -c 100 "$T/err"))"
}
for p in dem2fqm fqmfilter fqmsolve tilepack dem2vgis tilecheck tileplay vgis2tiles; do
	full "$p --help" $p --help
	full "$p -V" $p -V
done
full "dem2fqm -I" dem2fqm -I "$s"
full "dem2fqm -II" dem2fqm -II "$s"
full "dem2fqm to stdout" dem2fqm "$s" -
full "tilecheck" tilecheck "$T/p"
full "tilecheck --dem" tilecheck --dem "$s" "$T/p"
full "tileplay --verify" tileplay --verify "$T/p"
full "tilepack -l" tilepack -l "$m" "$T/w" $vm
if [ $gl -eq 0 ]; then
	full "tileplay --fly" tileplay --fly 2 "$T/p"
	full "tileplay --shot --probe" tileplay --shot "$T/s2.png" --probe 5,5 "$T/p"
fi
# --plan prints nothing on stdout: nothing to lose
dem2vgis --plan "$T/plan" "$s" "$T/pp" >"$T/out" && [ ! -s "$T/out" ] &&
    dem2vgis --plan "$T/plan2" "$s" "$T/pp" >/dev/full
ok $? "dem2vgis --plan: nothing on stdout, so a full one loses nothing"
done_testing
