# t_verify - the checker on real pyramids: tileplay --verify's usage (the
# alias), then every DEM's pyramids made by dem2vgis (1D and QEM-3D,
# projected and geographic with voids) passing every check of tilecheck
# against their DEM. (tests/verify/t_verify*.c test the checker itself
# on hand-built and corrupted pyramids, t_tilecheck.sh its program.)
. "$(dirname "$0")/../lib.sh"

run "--help exits 0" tileplay --help
grep -q '^usage: tileplay --verify dir' "$T/out"; ok $? "--help prints the usage"
run "--version exits 0" tileplay --version
grep -q '^tileplay [0-9]' "$T/out"; ok $? "--version prints the version"
fails "no --verify and no pyramid: exit 2" 2 'usage: tileplay' tileplay
fails "unknown option: exit 2" 2 'usage: tileplay' tileplay --verify x -Q
fails "an operand: exit 2" 2 'usage: tileplay' tileplay --verify x y
fails "--tau not numbers: exit 2" 2 '^tileplay: --tau 1,x: ' \
    tileplay --verify x --tau 1,x
fails "--tau negative: exit 2" 2 '^tileplay: --tau -1: ' \
    tileplay --verify x --tau -1
fails "no pyramid: exit 1" 1 "^tileplay: $T/none/index.json: " \
    tileplay --verify "$T/none"

if [ ! -x "$B/tilepack" ] || [ ! -x "$B/tilecheck" ] ||
    [ ! -x "$B/dem2vgis" ]; then
	echo "ok $((_n + 1)) - # SKIP tilepack, tilecheck or dem2vgis not built"
	_n=$((_n + 1))
	done_testing
	exit
fi

# verify NAME DEM [dem2vgis options]: make the pyramid, tilecheck it
verify() {
	_name=$1 _dem=$2; shift 2
	_vo=""; case $* in *"-s 60"*) _vo="-s 60" ;; esac
	if ! "$B/dem2vgis" -q "$@" "$_dem" "$T/$_name" \
	    >"$T/mk.out" 2>&1; then
		sed 's/^/#   /' "$T/mk.out" | head -5
		ok 1 "$_name: dem2vgis $*"
		return
	fi
	_t0=$(date +%s)
	# shellcheck disable=SC2086
	tilecheck --dem "$_dem" $_vo "$T/$_name" >"$T/$_name.txt" 2>&1
	_s=$?
	[ $_s -eq 0 ] && : || { grep '^result' "$T/$_name.txt"
	    grep '^  level' "$T/$_name.txt" | head -8; } | sed 's/^/#   /'
	ok $_s "$_name: every check passes against the DEM ($(grep -c \
	    '^level' "$T/$_name.txt") levels, $(( $(date +%s) - _t0 )) s)"
}

# Every DEM in ../shared/data, QEM-1D and QEM-3D levels, through the
# driver. (The .tif copies of the .hgt tiles give the same pyramids but
# for their vertical-datum attribute, t_pipeline proves their level-0
# quadrics identical: each checked once, in 1D, on a 601x601 crop, the
# container and its attributes being the subject, not the size; not
# N48W125.tif, 13 M samples whose .hgt twin is checked in both modes.)
# Under TL_QUICK (the sanitizers) N44W072.hgt is left out too: another
# 1201x1201 geographic tile, through N42E001's code paths (which has
# voids besides); make check runs it.
for f in N42E001.hgt N44W072.hgt N48W125.hgt bigtujunga.tif fuji.png; do
	big $f && { ok 0 "# SKIP $f under TL_QUICK"; continue; }
	[ -n "${TL_QUICK:-}" ] && [ $f = N44W072.hgt ] &&
	    { ok 0 "# SKIP $f under TL_QUICK (make check runs it)"; continue; }
	o=""; case $f in fuji.png) o="-s 60" ;; esac
	# shellcheck disable=SC2086
	verify "$f-1d" "$DATA/$f" $o
	# shellcheck disable=SC2086
	verify "$f-3d" "$DATA/$f" -3 $o
	rm -rf "$T/$f-1d" "$T/$f-3d"
done
for f in N42E001.tif N44W072.tif; do
	gdal_translate -q -srcwin 300 300 601 601 "$DATA/$f" "$T/$f" ||
	    { ok 1 "$f: a crop"; continue; }
	verify "$f-1d" "$T/$f"
	rm -rf "$T/$f-1d" "$T/$f"
done
done_testing
