# t_oneproc - dem2vgis's two routes, its stages as threads of one process
# (the default) and as processes joined by pipes (--processes,
# TL_PROCESSES=1), give byte-identical pyramids (diff -r) on real DEMs:
# N44W072, a crop of N48W125 with voids, QEM-1D and QEM-3D, a mosaic of
# two tiles, -j 1 and -j 2; and the one process keeps the supervisor's
# promises: a stage that fails (a DEM whose samples cannot be read,
# ulimit -f) ends the run with exit 1 and its one message, as the
# processes' route says it, leaving nothing; SIGTERM mid-run (in the
# chain, in tilepack) leaves nothing and the run dies of it.
. "$(dirname "$0")/../lib.sh"

GDAL_PAM_ENABLED=NO; export GDAL_PAM_ENABLED
TMPDIR=$T/tmp; export TMPDIR; mkdir "$TMPDIR"
c=$T/crop.tif a=$T/a.tif b=$T/b.tif
gdal_translate -q -srcwin 1500 1500 900 700 "$DATA/N48W125.hgt" "$c" &&
    gdal_translate -q -srcwin 0 0 601 500 "$DATA/N44W072.tif" "$a" &&
    gdal_translate -q -srcwin 600 0 601 500 "$DATA/N44W072.tif" "$b" &&
    gdal_translate -q -srcwin 0 0 601 1201 "$DATA/N44W072.tif" "$T/t.tif" ||
    { ok 1 "fixtures"; done_testing; exit 1; }
voids=$(/usr/bin/python3 -c 'import sys; from osgeo import gdal
d = gdal.Open(sys.argv[1]); b = d.GetRasterBand(1)
print(int((b.ReadAsArray() == b.GetNoDataValue()).sum()))' "$c")
[ "$voids" -gt 1000 ]; ok $? "the crop of N48W125 has voids ($voids)"

# both NAME ARGS...: the pyramid by either route, identical
both() {
	_nm=$1; shift
	dem2vgis -q "$@" "$T/$_nm.1" 2>"$T/err1"; _s1=$?
	TL_PROCESSES=1 dem2vgis -q "$@" "$T/$_nm.p" 2>"$T/errp"; _sp=$?
	[ $_s1 -eq 0 ] && [ $_sp -eq 0 ] && [ -f "$T/$_nm.1/index.json" ] &&
	    diff -r "$T/$_nm.1" "$T/$_nm.p" >/dev/null
	ok $? "$_nm: one process and processes, byte-identical (exit $_s1 $_sp)"
}
# (under the sanitizers the crop and the mosaic alone: the same routes on
# real DEMs, N44W072 whole four runs more of the same code)
if [ -z "${TL_QUICK:-}" ]; then
	both n44 "$DATA/N44W072.hgt"
	both n44-3d -3 "$DATA/N44W072.hgt"
fi
both crop "$c"
both crop-3d -3 "$c"
both mosaic "$a" "$b"
both mosaic-3d -3 "$a" "$b"
dem2vgis -q --processes "$c" "$T/crop.pp" && diff -r "$T/crop.1" "$T/crop.pp" >/dev/null
ok $? "--processes is TL_PROCESSES=1"
dem2vgis -q -j 1 "$c" "$T/j1" && dem2vgis -q -j 2 "$c" "$T/j2" &&
    diff -r "$T/j1" "$T/j2" >/dev/null && diff -r "$T/j1" "$T/crop.1" >/dev/null
ok $? "-j 1 and -j 2: the same pyramid"
[ -z "$(ls -A "$TMPDIR")" ]; ok $? "no scratch left ($(ls -A "$TMPDIR"))"

# --- a stage that fails: one message, exit 1, nothing left ---------------
# samples that cannot be read: the header (dem2fqm -I) reads, a strip not
tr=$T/trunc.tif
gdal_translate -q -co TILED=NO -co COMPRESS=DEFLATE "$c" "$tr" &&
    truncate -s $(($(stat -c %s "$tr") / 2)) "$tr"
# fail2 DESCRIPTION ULIMIT ARGS...: both routes fail the same way
fail2() {
	_d=$1 _k=$2; shift 2
	rm -rf "$T/D"; mkdir "$T/D"
	sh -c 'ulimit -f "$0"; exec "$@"' "$_k" dem2vgis -q "$@" "$T/D/p" \
	    2>"$T/e1"; _s1=$?
	_l1=$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$' | wc -l)
	TL_PROCESSES=1 sh -c 'ulimit -f "$0"; exec "$@"' "$_k" dem2vgis -q \
	    "$@" "$T/D/p" 2>"$T/ep"; _sp=$?
	[ $_s1 -eq 1 ] && [ $_sp -eq 1 ] && [ "$(wc -l <"$T/e1")" -eq 1 ] &&
	    [ "$_l1" -eq 0 ] && [ -z "$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$')" ]
	ok $? "$_d: exit $_s1 ($_sp), one line, nothing left ($_l1): $(head -c 150 "$T/e1")"
}
fail2 "a DEM whose samples cannot be read" unlimited "$tr"
grep -q '^dem2fqm: ' "$T/e1" && cmp -s "$T/e1" "$T/ep"
ok $? "dem2fqm's message, as the processes' route says it ($(head -c 100 "$T/ep"))"
# (dem2fqm's scratch needs 2 MiB, level 0's vertex map 5.5 MiB)
fail2 "ulimit -f 6000: a vertex map" 6000 "$T/t.tif"
grep -q '^fqmsolve: .*File too large.*ulimit -f' "$T/e1" && cmp -s "$T/e1" "$T/ep"
ok $? "fqmsolve's message, the limit named, as the processes' route says it"
# tilepack refuses a directory that is no pyramid, after the chain
mkdir "$T/np"; : >"$T/np/x"
dem2vgis -q "$a" "$T/np" 2>"$T/e1"; s1=$?
TL_PROCESSES=1 dem2vgis -q "$a" "$T/np" 2>"$T/ep"; sp=$?
[ $s1 -eq 1 ] && [ $sp -eq 1 ] && grep -q '^tilepack: .*not a pyramid' "$T/e1" &&
    cmp -s "$T/e1" "$T/ep" && [ "$(ls -A "$T/np")" = x ] && [ -z "$(ls -A "$TMPDIR")" ]
ok $? "tilepack's refusal: exit $s1, its message, as the processes' route says it"

# --- SIGTERM mid-run: nothing left, the run dies of it -------------------
# term DESCRIPTION WHAT: SIGTERM once WHAT (a find pattern under $T/D and
# $TMPDIR) exists
term() {
	rm -rf "$T/D"; mkdir "$T/D"
	dem2vgis -q -3 "$DATA/N44W072.hgt" "$T/D/p" 2>"$T/e1" & _pid=$!
	_i=0
	while [ $_i -lt 3000 ] && kill -0 $_pid 2>/dev/null &&
	    ! find "$T/D" "$TMPDIR" -name "$2" 2>/dev/null | grep -q .; do
		sleep 0.01; _i=$((_i + 1)); done
	kill -TERM $_pid; wait $_pid; _s=$?
	[ $_s -eq 143 ] && [ -z "$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$')" ]
	ok $? "SIGTERM $1: exit $_s, nothing left ($(ls -A "$T/D" "$TMPDIR" | tr '\n' ' '))"
}
term "in the chain" 'v1.fqm'
term "in tilepack" '.p.*'
# SIGKILL in tilepack: its temporary and the scratch stay, the next run
# into the same directory removes both. Killed once the temporary holds
# its lock file: one killed between its mkdtemp and its lock is kept for
# a minute (sweep.h), a moment a loaded machine can hit
rm -rf "$T/D"; mkdir "$T/D"
dem2vgis -q -3 "$DATA/N44W072.hgt" "$T/D/p" 2>/dev/null & pid=$!
i=0
while [ $i -lt 3000 ] && kill -0 $pid 2>/dev/null &&
    ! find "$T/D" -path '*/.p.*/.lock' 2>/dev/null | grep -q .; do
	sleep 0.01; i=$((i + 1)); done
kill -KILL $pid; wait $pid 2>/dev/null
n1=$(ls -A "$T/D" "$TMPDIR" | grep -c '^\.p\.\|^dem2vgis\.' || true)
dem2vgis -q "$a" "$T/D/p"; s=$?
[ "$n1" -eq 2 ] && [ $s -eq 0 ] && [ "$(ls -A "$T/D")" = p ] && [ -z "$(ls -A "$TMPDIR")" ]
ok $? "SIGKILL in tilepack: its temporary and scratch ($n1) swept by the next run (exit $s)"
done_testing
