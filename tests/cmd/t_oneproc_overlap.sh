# t_oneproc_overlap - dem2vgis as one process converts the DEM once, in
# its chain (dem2fqm's work), and tilepack's work reads that conversion
# instead of making its own: the same pyramid as the processes' route
# (a DEM with voids, QEM-1D and QEM-3D, one from stdin); the
# conversion's failure is dem2fqm's one message, as the processes' route
# says it (a DEM all voids), a file that is no raster dem2fqm -I's;
# SIGTERM while it converts, or later, leaves nothing and the run dies
# of it.
. "$(dirname "$0")/../lib.sh"

GDAL_PAM_ENABLED=NO; export GDAL_PAM_ENABLED
TMPDIR=$T/tmp; export TMPDIR; mkdir "$TMPDIR"
c=$T/crop.tif
gdal_translate -q -srcwin 1500 1500 900 700 "$DATA/N48W125.hgt" "$c" &&
    /usr/bin/python3 -c 'import sys; from osgeo import gdal
s = gdal.Open(sys.argv[1]); d = gdal.Translate(sys.argv[2], s)
b = d.GetRasterBand(1); b.Fill(b.GetNoDataValue()); d = None' "$c" \
    "$T/void.tif" || { ok 1 "fixtures"; done_testing; exit 1; }
printf 'II*\0 not a TIFF at all\n' >"$T/junk.tif"

# both NAME ARGS...: the pyramid by either route, identical
both() {
	_nm=$1; shift
	dem2vgis -q "$@" "$T/$_nm.1" <"$c" 2>"$T/err1"; _s1=$?
	dem2vgis -q --processes "$@" "$T/$_nm.p" <"$c" 2>"$T/errp"; _sp=$?
	[ $_s1 -eq 0 ] && [ $_sp -eq 0 ] && [ -f "$T/$_nm.1/index.json" ] &&
	    diff -r "$T/$_nm.1" "$T/$_nm.p" >/dev/null
	ok $? "$_nm: one process and processes, byte-identical (exit $_s1 $_sp)"
}
both crop "$c"
both crop-3d -3 "$c"
both stdin -n crop.tif -
[ -z "$(ls -A "$TMPDIR")" ]; ok $? "no scratch left ($(ls -A "$TMPDIR"))"

# fail2 DESCRIPTION PATTERN DEM: both routes fail alike, one line each
fail2() {
	rm -rf "$T/D"; mkdir "$T/D"
	dem2vgis -q "$3" "$T/D/p" 2>"$T/e1"; _s1=$?
	dem2vgis -q --processes "$3" "$T/D/p" 2>"$T/ep"; _sp=$?
	[ $_s1 -eq 1 ] && [ $_sp -eq 1 ] && [ "$(wc -l <"$T/e1")" -eq 1 ] &&
	    grep -q "$2" "$T/e1" && cmp -s "$T/e1" "$T/ep" &&
	    [ -z "$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$')" ]
	ok $? "$1: exit $_s1 ($_sp), as the processes' route: $(head -c 150 "$T/e1")"
}
fail2 "a DEM all voids (the conversion's failure)" \
    '^dem2fqm: .*no valid samples' "$T/void.tif"
fail2 "no raster (dem2fqm -I's failure first)" '^dem2fqm: .*junk.tif' \
    "$T/junk.tif"

# SIGTERM once the run's scratch exists, and later (the conversion, the
# chain, tilepack): the run dies of it, nothing left (N48W125)
for k in 1 2 3; do
	rm -rf "$T/D"; mkdir "$T/D"
	dem2vgis -q "$DATA/N48W125.hgt" "$T/D/p" 2>"$T/e1" & pid=$!
	i=0
	while [ $i -lt 3000 ] && kill -0 $pid 2>/dev/null &&
	    ! ls -A "$TMPDIR" | grep -q '^dem2vgis\.'; do
		sleep 0.01; i=$((i + 1)); done
	[ $k -gt 1 ] && sleep 0.$((k * 2))
	kill -TERM $pid; wait $pid; s=$?
	[ $s -eq 143 ] && [ -z "$(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$')" ]
	ok $? "SIGTERM $k: exit $s, nothing left ($(ls -A "$T/D" "$TMPDIR" | grep -v '^/\|^$' | tr '\n' ' '))"
done
done_testing
