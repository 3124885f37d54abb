# t_pipeline - dem2fqm | fqmfilter ... | fqmsolve on every DEM in
# ../shared/data: every level's size and georeferencing against gdalinfo's
# values (literals below, not read by our code), pipe and file routes
# byte-identical, reruns byte-identical, level 0 reproducing the DEM. A
# GeoTIFF copy of a .hgt tile: its level 0's size and georeferencing, and
# its quadrics identical to the .hgt's, from which on all is the same.
. "$(dirname "$0")/../lib.sh"

# file W0 H0 epsg gdal-origin-x gdal-origin-y pixel-x pixel-y valid-samples
# (gdalinfo 3.6: "Size is", "Origin =", "Pixel Size =", voids from
# ../shared/data/README.md)
cat >"$T/dems" <<'END'
N42E001.hgt 1201 1201 4326 0.999583333333333 43.000416666666666 0.000833333333333 -0.000833333333333 1434749
N42E001.tif 1201 1201 4326 0.999583333333333 43.000416666666666 0.000833333333333 -0.000833333333333 1434749
N44W072.hgt 1201 1201 4326 -72.000416666666666 45.000416666666666 0.000833333333333 -0.000833333333333 1442401
N44W072.tif 1201 1201 4326 -72.000416666666666 45.000416666666666 0.000833333333333 -0.000833333333333 1442401
N48W125.hgt 3601 3601 4326 -125.000138888888884 49.000138888888891 0.000277777777778 -0.000277777777778 6483325
N48W125.tif 3601 3601 4326 -125.000138888888884 49.000138888888891 0.000277777777778 -0.000277777777778 6483325
bigtujunga.tif 1197 643 32611 376313.655454263498541 3807917.827628375496715 30 -30 769671
fuji.png 512 512 0 0 0 1 -1 262144
END

# size of level l of an n0 extent: ceil((n0-1)/2^l)+1 (the spec's formula)
lsize() { echo $(( ($1 - 1 + (1 << $2) - 1) / (1 << $2) + 1 )); }

# attr FILE NAME: the value(s) of an attribute
attr() { rsinfo "$1" | awk -v n="$2" '$1 == "attr" && $2 == n { $1 = $2 = $3 = ""; print substr($0, 4) }'; }

# near A B TOL: |A - B| <= TOL
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(d <= t && -d <= t) }'; }

while read -r f W0 H0 epsg ox oy px py nvalid; do
	big $f && { ok 0 "# SKIP $f under TL_QUICK"; continue; }
	dem=$DATA/$f
	[ -f "$dem" ] || { ok 1 "$f: missing from $DATA"; continue; }
	o=""; case $f in fuji.png) o="-s 60" ;; esac
	twin=""; case $f in N*.tif) twin=$T/${f%.tif}.l0.exr ;; esac
	d=$T/$f; mkdir -p "$d"
	# shellcheck disable=SC2086
	run "$f: dem2fqm to EXR" dem2fqm $o "$dem" "$d/l0.exr" || continue
	l=0; levels_ok=0; geo_ok=0
	while :; do
		w=$(lsize "$W0" $l) h=$(lsize "$H0" $l)
		set -- $(rsinfo "$d/l$l.exr" | awk '$1 == "size" { print $2, $3 }')
		[ "$1 $2" = "$w $h" ] || { echo "# level $l: $1x$2, expected ${w}x$h"; levels_ok=1; }
		[ "$(attr "$d/l$l.exr" fqm:level)" = "$l" ] || levels_ok=1
		[ "$(attr "$d/l$l.exr" fqm:size0)" = "$W0 $H0" ] || levels_ok=1
		# GDAL's origin is the corner of pixel (0,0): our origin for
		# pixel-is-area, origin - step/2 for pixel-is-point.
		set -- $(attr "$d/l$l.exr" geo:origin) $(attr "$d/l$l.exr" geo:step)
		raster=$(attr "$d/l$l.exr" geo:raster)
		gx=$1 gy=$2
		if [ "$raster" = point ] && [ "$f" != fuji.png ]; then
			gx=$(awk -v a="$1" -v s="$3" 'BEGIN { printf "%.17g", a - s / 2 }')
			gy=$(awk -v a="$2" -v s="$4" 'BEGIN { printf "%.17g", a - s / 2 }')
		fi
		if [ "$f" != fuji.png ]; then
			near "$gx" "$ox" 1e-9 && near "$gy" "$oy" 1e-9 &&
			    near "$3" "$px" 1e-12 && near "$4" "$py" 1e-12 &&
			    [ "$(attr "$d/l$l.exr" geo:epsg)" = "$epsg" ] || {
				echo "# level $l: origin $gx $gy step $3 $4"; geo_ok=1; }
		else
			[ "$(attr "$d/l$l.exr" geo:model)" = none ] || geo_ok=1
		fi
		[ "$w" -le 129 ] && [ "$h" -le 129 ] && break
		[ -n "$twin" ] && break	# its levels are its twin's
		fqmfilter "$d/l$l.exr" "$d/l$((l + 1)).exr" 2>"$T/err" || {
			sed 's/^/#   /' "$T/err"; levels_ok=1; break; }
		l=$((l + 1))
	done
	top=$l
	ok $levels_ok "$f: sizes of levels 0..$top are ceil((W0-1)/2^l)+1"
	ok $geo_ok "$f: georeferencing of levels 0..$top matches gdalinfo"
	if [ -n "$twin" ]; then	# the .hgt row came first, kept its level 0
		[ -f "$twin" ] && [ "$(rsinfo -c "$d/l0.exr" | grep '^hash')" = \
		    "$(rsinfo -c "$twin" | grep '^hash')" ]
		ok $? "${f%.tif}: .hgt and .tif give identical level-0 quadric maps"
		rm -rf "$d" "$twin"
		continue
	fi
	case $f in N*.hgt) cp "$d/l0.exr" "$T/${f%.hgt}.l0.exr" ;; esac

	# The same pyramid through pipes, ending in EXR files: byte-identical.
	cmd="dem2fqm $o $dem -"
	l=0
	while [ $l -lt "$top" ]; do cmd="$cmd | fqmfilter - -"; l=$((l + 1)); done
	sh -c "$cmd | fqmfilter - $d/pipe-top1.exr" 2>"$T/err" || true
	[ "$top" -gt 0 ] && sh -c "$cmd | fqmsolve - $d/pipe-v.exr" 2>"$T/err"
	fqmsolve "$d/l$top.exr" "$d/file-v.exr" 2>>"$T/err"
	cmp -s "$d/pipe-v.exr" "$d/file-v.exr"
	ok $? "$f: pipe and file routes give byte-identical level-$top vertex maps"
	sh -c "dem2fqm $o $dem - | fqmfilter - $d/p1.exr" 2>"$T/err"
	cmp -s "$d/p1.exr" "$d/l1.exr"
	ok $? "$f: dem2fqm | fqmfilter - file.exr equals the file route"
	# shellcheck disable=SC2086
	dem2fqm $o "$dem" - >"$d/a.fqm" && dem2fqm $o "$dem" - >"$d/b.fqm" &&
	    dem2fqm $o "$dem" "$d/l0b.exr" &&
	    cmp -s "$d/a.fqm" "$d/b.fqm" && cmp -s "$d/l0.exr" "$d/l0b.exr"
	ok $? "$f: reruns are byte-identical (stream and EXR)"
	[ "$(rsinfo -c "$d/a.fqm" | grep -v '^attr')" = \
	    "$(rsinfo -c "$d/l0.exr" | grep -v '^attr')" ]
	ok $? "$f: stream and EXR hold the same pixels"

	# Level 0 solved is the DEM itself, at every valid sample.
	fqmsolve "$d/l0.exr" "$d/v0.exr" &&
	    set -- $(fqmeval $o "$dem" "$d/v0.exr") x x x x x x &&
	    [ "$1" = "$nvalid" ] && [ "$5" = 0.000000 ] && [ "$6" = 0 ]
	ok $? "$f: level 0 solved reproduces all $nvalid valid samples exactly (n=$1 max=$5)"
	rm -rf "$d"
done <"$T/dems"

# The driver of the pipeline runs the stages' work as threads of one
# process (t_oneproc): it reads the DEM, so GDAL is linked into it; the
# viewer's GL never is.
if command -v readelf >/dev/null; then
	readelf -d "$B/dem2vgis" >"$T/needed" &&
	    grep -Eq 'NEEDED.*libgdal' "$T/needed" &&
	    ! grep -Eq 'NEEDED.*lib(glfw|epoxy|EGL)' "$T/needed"
	ok $? "dem2vgis (one process) links GDAL, no GL ($(grep -o 'lib[a-zA-Z0-9_-]*' "$T/needed" | grep -E 'gdal|glfw|epoxy|EGL' | tr '\n' ' '))"
else
	ok 0 "# SKIP dem2vgis's libraries: no readelf"
fi
done_testing
