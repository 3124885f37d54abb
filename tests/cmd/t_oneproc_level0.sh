#!/bin/sh
# t_oneproc_level0 - dem2vgis as one process packs level 0 beside the
# chain: its vertex map is known (the DEM's heights, zero offsets), so
# tilepack's work makes level 0's blocks from the DEM while the chain
# still runs, and the other levels once it has ended. The pyramid is the
# processes' route's, byte for byte (diff -r): a DEM with voids, QEM-1D
# and QEM-3D, -j 1 and -j 2; a float DEM with samples -0 (where the
# solver's Z + 0 may be +0), whose level 0 is then read from its vertex
# map. Level 0's blocks are written while the chain's threads live.
# SIGTERM then, or a failure of the chain's (ulimit -f on a vertex map),
# leaves nothing; SIGKILL then leaves what the next run sweeps.
. "$(dirname "$0")/../lib.sh"

GDAL_PAM_ENABLED=NO; export GDAL_PAM_ENABLED
TMPDIR=$T/tmp; export TMPDIR; mkdir "$TMPDIR"
c=$T/crop.tif
gdal_translate -q -srcwin 1500 1500 900 700 "$DATA/N48W125.hgt" "$c" &&
    gdal_translate -q -srcwin 2500 2000 100 80 "$DATA/N48W125.hgt" "$T/one.tif" &&
    /usr/bin/python3 -c 'import sys; from osgeo import gdal
s = gdal.Open(sys.argv[1]); z = s.GetRasterBand(1).ReadAsArray()
d = gdal.GetDriverByName("GTiff").Create(sys.argv[2], 300, 200, 1,
    gdal.GDT_Float32)
d.SetGeoTransform(s.GetGeoTransform()); d.SetProjection(s.GetProjection())
z = z[:200, :300].astype("float32"); z[z < 0] = 0; z[:20, :] = -0.0
z[100:110, 50:60] = -0.0
d.GetRasterBand(1).WriteArray(z); d = None' "$c" "$T/negz.tif" ||
    { ok 1 "fixtures"; done_testing; exit 1; }

# both NAME ARGS...: the pyramid by either route, identical
both() {
	_nm=$1; shift
	dem2vgis -q "$@" "$T/$_nm.1" 2>"$T/err1"; _s1=$?
	dem2vgis -q --processes "$@" "$T/$_nm.p" 2>"$T/errp"; _sp=$?
	[ $_s1 -eq 0 ] && [ $_sp -eq 0 ] && [ -f "$T/$_nm.1/index.json" ] &&
	    diff -r "$T/$_nm.1" "$T/$_nm.p" >/dev/null
	ok $? "$_nm: one process and processes, byte-identical (exit $_s1 $_sp)"
}
both crop-j1 -j 1 "$c"
both crop-j2 -j 2 "$c"
both crop-3d-j1 -3 -j 1 "$c"
both crop-3d-j2 -3 -j 2 "$c"
/usr/bin/python3 -c 'import sys, numpy as np; from osgeo import gdal
d = gdal.Open(sys.argv[1]); z = d.GetRasterBand(1).ReadAsArray()
print(int((np.signbit(z) & (z == 0)).sum()))' "$T/negz.tif" >"$T/nz"
[ "$(cat "$T/nz")" -gt 1000 ]; ok $? "the float DEM has samples -0 ($(cat "$T/nz"))"
both negz "$T/negz.tif"
both negz-3d -3 "$T/negz.tif"
# one level: level 0 alone, nothing to wait for but the chain's end
both one "$T/one.tif"
both one-3d -3 "$T/one.tif"
[ -z "$(ls -A "$TMPDIR")" ]; ok $? "no scratch left ($(ls -A "$TMPDIR"))"

# stages P: the chain's threads (named after their programs) alive in P
stages() {
	cat /proc/"$1"/task/*/comm 2>/dev/null |
	    grep -c '^dem2fqm$\|^fqmfilter$\|^fqmsolve$'
}
# at_block0 PID: waits for level 0's first block in the pyramid's
# temporary; the chain's threads alive then
at_block0() {
	_i=0
	while [ $_i -lt 3000 ] && kill -0 "$1" 2>/dev/null; do
		find "$T/D" -path '*/.p.*/0/*' -name '*.exr' 2>/dev/null |
		    grep -q . && break
		sleep 0.01; _i=$((_i + 1))
	done
	stages "$1"
}

# level 0's blocks while the chain runs (QEM-3D: its chain is long);
# SIGTERM then: the run dies of it, nothing left
rm -rf "$T/D"; mkdir "$T/D"
dem2vgis -q -3 "$DATA/N44W072.hgt" "$T/D/p" 2>"$T/e1" & pid=$!
a=$(at_block0 $pid)
kill -TERM $pid; wait $pid; s=$?
[ "$a" -gt 0 ]
ok $? "level 0's first block written while the chain runs ($a of its threads alive)"
[ $s -eq 143 ] && [ -z "$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$')" ]
ok $? "SIGTERM beside the chain: exit $s, nothing left ($(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$' | tr '\n' ' '))"

# SIGKILL then: the temporary and the scratch stay, the next run sweeps
rm -rf "$T/D"; mkdir "$T/D"
dem2vgis -q -3 "$DATA/N44W072.hgt" "$T/D/p" 2>/dev/null & pid=$!
at_block0 $pid >/dev/null
kill -KILL $pid; wait $pid 2>/dev/null
n1=$(ls -A "$T/D" "$TMPDIR" | grep -c '^\.p\.\|^dem2vgis\.' || true)
dem2vgis -q "$c" "$T/D/p"; s=$?
[ "$n1" -eq 2 ] && [ $s -eq 0 ] && [ "$(ls -A "$T/D")" = p ] &&
    [ -z "$(ls -A "$TMPDIR")" ]
ok $? "SIGKILL beside the chain: its temporary and scratch ($n1) swept by the next run (exit $s)"

# the chain fails while level 0 is packed (a vertex map over ulimit -f,
# 512-byte blocks: the crop's level 0 map is 4.8 MiB): its message alone,
# as the processes' route says it, nothing left
for r in "" --processes; do
	rm -rf "$T/D"; mkdir "$T/D"
	sh -c 'ulimit -f 6000; exec "$@"' sh dem2vgis -q $r "$c" "$T/D/p" \
	    2>"$T/e$r"; echo $? >"$T/s$r"
done
[ "$(cat "$T/s")" -eq 1 ] && [ "$(wc -l <"$T/e")" -eq 1 ] &&
    grep -q '^fqmsolve: .*File too large' "$T/e" && cmp -s "$T/e" "$T/e--processes" &&
    [ -z "$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$')" ]
ok $? "the chain's failure beside level 0: exit $(cat "$T/s"), its one message, nothing left ($(head -c 120 "$T/e"))"
# one level: level 0 (its one block) done long before the chain fails
# (its vertex map, 64 KB, over 100 blocks): no pyramid is made
rm -rf "$T/D"; mkdir "$T/D"
sh -c 'ulimit -f 100; exec "$@"' sh dem2vgis -q "$T/one.tif" "$T/D/p" 2>"$T/e"
s=$?
[ $s -eq 1 ] && grep -q '^fqmsolve: .*File too large' "$T/e" &&
    [ -z "$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$')" ]
ok $? "one level, the chain's failure after level 0's block: exit $s, nothing left ($(ls -A "$T/D" | tr '\n' ' '))"
done_testing
