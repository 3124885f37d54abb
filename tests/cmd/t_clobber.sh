# t_clobber - no program writes over what it reads (issue 21, class 1): an
# output that is an input, contains one or lies inside one is refused
# before any work, exit 1, with a message naming both, for every program
# and mode, however the paths are spelled (a symbolic link, "..", a hard
# link, a list entry, a VRT source). Each refusal leaves the work
# directory as it was, byte for byte, and no scratch behind.
. "$(dirname "$0")/../lib.sh"

W=$T/w
mkdir -p "$W" "$T/tmp"
TMPDIR=$T/tmp
export TMPDIR
gdal_translate -q -srcwin 0 0 257 257 "$DATA/N44W072.hgt" "$T/dem.tif" ||
    exit 1

# the fixtures: a DEM in D, a list and a VRT naming it, a pyramid, the
# vertex maps of the DEM, a tileset holding a pyramid (the issue's site)
mkdir "$W/D"
cp "$T/dem.tif" "$W/D/dem.tif"
cp "$T/dem.tif" "$W/dem.tif"
printf '# one tile\n  D/dem.tif\n' >"$W/list.txt"
(cd "$W" && gdalbuildvrt -q m.vrt D/dem.tif) || exit 1
ln -s D "$W/L"
run "fixture: the pyramid" dem2vgis -q "$W/dem.tif" "$W/pyr"
run "fixture: the vertex maps (dem2vgis -M)" dem2vgis -M "$W/dem.tif" "$W/vm"
V=$(ls "$W"/vm/v*.fqm | sort -V)
ln "$W/D/dem.tif" "$W/hard.tif"
ln "$W/vm/v0.fqm" "$W/vh.fqm"
mkdir "$W/site"
cp -r "$W/pyr" "$W/site/pyr"
run "fixture: the old tileset" vgis2tiles -q "$W/pyr" "$W/tiles"
cp "$W/tiles/tileset.json" "$W/site/"
ln -s site "$W/sl"
dem2fqm "$W/dem.tif" "$W/f0.fqm" && ln "$W/f0.fqm" "$W/f0h.fqm" &&
    ln -s f0.fqm "$W/f0l.fqm" && fqmfilter "$W/f0.fqm" "$W/f1.fqm" ||
    exit 1
printf 'fqm-bands 1\nf1.fqm\n' >"$W/bands.txt"
cp "$T/dem.tif" "$W/F.raw"
mkdir "$W/work" "$W/elsewhere"
cp -r "$W/pyr" "$W/pyr2"
mv "$W/pyr2/0" "$W/elsewhere/0"
ln -s ../elsewhere/0 "$W/pyr2/0"

snap() {
	(cd "$W" && find . | LC_ALL=C sort &&
	    find . -type f -exec md5sum {} + | LC_ALL=C sort)
}

# refused DESCRIPTION PATTERN CMD...: exit 1, stderr matching PATTERN
# (both paths), the work directory and the DEM byte for byte as they
# were, no scratch left.
refused() {
	_d=$1 _p=$2; shift 2
	snap >"$T/before"
	"$@" >"$T/out" 2>"$T/err"; _s=$?
	snap >"$T/after"
	_bad=""
	[ $_s -eq 1 ] || _bad="$_bad exit $_s;"
	grep -Eq -- "$_p" "$T/err" || _bad="$_bad message;"
	cmp -s "$T/before" "$T/after" || _bad="$_bad work directory changed;"
	cmp -s "$T/dem.tif" "$W/D/dem.tif" || _bad="$_bad DEM changed;"
	[ -z "$(ls -A "$TMPDIR")" ] || _bad="$_bad scratch left;"
	if [ -n "$_bad" ]; then
		echo "#  $_bad stderr: $(head -c 300 "$T/err")"
		diff "$T/before" "$T/after" | head -5 | sed 's/^/#   /'
	fi
	[ -z "$_bad" ]; ok $? "$_d"
}

# --- vgis2tiles ------------------------------------------------------------
refused "vgis2tiles pyr site, site holding pyr (the issue's example)" \
    "^vgis2tiles: $W/site: contains the input pyramid $W/site/pyr\$" \
    vgis2tiles -q "$W/site/pyr" "$W/site"
refused "vgis2tiles: OUTDIR the pyramid itself" \
    "$W/pyr: is the input pyramid $W/pyr" vgis2tiles -q "$W/pyr" "$W/pyr"
refused "vgis2tiles: OUTDIR inside the pyramid" \
    "$W/pyr/tiles: is inside the input pyramid $W/pyr" \
    vgis2tiles -q "$W/pyr" "$W/pyr/tiles"
refused "vgis2tiles: OUTDIR a symbolic link to the directory holding it" \
    "$W/sl: contains the input pyramid $W/site/pyr" \
    vgis2tiles -q "$W/site/pyr" "$W/sl"
refused "vgis2tiles: OUTDIR through .." \
    "$W/site/pyr/../../site: contains the input pyramid" \
    vgis2tiles -q "$W/site/pyr" "$W/site/pyr/../../site"
refused "vgis2tiles: OUTDIR holding a level the pyramid links to" \
    "$W/elsewhere: contains the input pyramid $W/pyr2" \
    vgis2tiles -q "$W/pyr2" "$W/elsewhere"

# --- dem2vgis --------------------------------------------------------------
refused "dem2vgis -f DIR/dem.tif DIR (the issue's example)" \
    "^dem2vgis: $W/D: contains the input DEM $W/D/dem.tif\$" \
    dem2vgis -q -f "$W/D/dem.tif" "$W/D"
refused "dem2vgis: OUT the DEM itself" \
    "$W/D/dem.tif: is the input DEM $W/D/dem.tif" \
    dem2vgis -q -f "$W/D/dem.tif" "$W/D/dem.tif"
refused "dem2vgis: OUT a symbolic link to the DEM's directory" \
    "$W/L: contains the input DEM $W/D/dem.tif" \
    dem2vgis -q -f "$W/D/dem.tif" "$W/L"
refused "dem2vgis: the DEM through a symbolic link" \
    "$W/D: contains the input DEM $W/L/dem.tif" \
    dem2vgis -q -f "$W/L/dem.tif" "$W/D"
refused "dem2vgis: OUT through .. past a missing directory" \
    "$W/none/../D: contains the input DEM $W/D/dem.tif" \
    dem2vgis -q -f "$W/D/dem.tif" "$W/none/../D"
refused "dem2vgis: OUT holding one DEM of a mosaic" \
    "$W/D: contains the input DEM $W/D/dem.tif" \
    dem2vgis -q -f "$W/dem.tif" "$W/D/dem.tif" "$W/D"
refused "dem2vgis: OUT holding a list's entry" \
    "$W/D: contains $W/D/dem.tif, an entry of the input DEM list $W/list.txt" \
    dem2vgis -q -f "$W/list.txt" "$W/D"
refused "dem2vgis: OUT holding a VRT's source" \
    "$W/D: contains .*D/dem.tif, a file of the input DEM $W/m.vrt" \
    dem2vgis -q -f "$W/m.vrt" "$W/D"
refused "dem2vgis -M: the vertex maps' directory holding the DEM" \
    "$W/D: contains the input DEM $W/D/dem.tif" \
    dem2vgis -M "$W/D/dem.tif" "$W/D"
refused "dem2vgis -M: a VRT's source" \
    "$W/D: contains .*D/dem.tif, a file of the input DEM $W/m.vrt" \
    dem2vgis -M "$W/m.vrt" "$W/D"
refused "dem2vgis --plan: PLANDIR holding the DEM" \
    "$W/D: contains the input DEM $W/D/dem.tif" \
    dem2vgis -f --plan "$W/D" "$W/D/dem.tif" "$W/out"
refused "dem2vgis --plan: PLANDIR holding a list's entry" \
    "$W/D: contains $W/D/dem.tif, an entry of the input DEM list" \
    dem2vgis -f --plan "$W/D" "$W/list.txt" "$W/out"
refused "dem2vgis --plan: OUT holding the DEM" \
    "$W/D: contains the input DEM $W/D/dem.tif" \
    dem2vgis --plan "$W/plan" "$W/D/dem.tif" "$W/D"
refused "dem2vgis --plan: PLANDIR holding OUT" \
    "$W/plan: contains the output directory $W/plan/out" \
    dem2vgis --plan "$W/plan" "$W/dem.tif" "$W/plan/out"
refused "dem2vgis --plan: PLANDIR inside OUT" \
    "$W/out/plan: is inside the output directory $W/out" \
    dem2vgis --plan "$W/out/plan" "$W/dem.tif" "$W/out"
refused "dem2vgis --plan: PLANDIR OUT itself" \
    "$W/pyr: is the output directory $W/pyr" \
    dem2vgis -f --plan "$W/pyr" "$W/dem.tif" "$W/pyr"

# --- dem2fqm ---------------------------------------------------------------
refused "dem2fqm: out a hard link of the DEM, named both" \
    "$W/hard.tif: is both the input and the output \\(the input $W/D/dem.tif\\)" \
    dem2fqm "$W/D/dem.tif" "$W/hard.tif"
refused "dem2fqm: out a VRT's source" \
    "$W/D/dem.tif: is .*D/dem.tif, a file of the input DEM $W/m.vrt" \
    dem2fqm "$W/m.vrt" "$W/D/dem.tif"
refused "dem2fqm: out a list's entry, through a symbolic link" \
    "$W/L/dem.tif: is $W/D/dem.tif, an entry of the input DEM list" \
    dem2fqm "$W/list.txt" "$W/L/dem.tif"
refused "vgis-job fill: the filled DEM onto the DEM" \
    "$W/D/dem.tif: is the input DEM $W/D/dem.tif" \
    vgis-job fill "$W/D/dem.tif" "$W/D/dem.tif"
refused "vgis-job fill: the filled DEM onto a VRT's source" \
    "$W/hard.tif: is .*D/dem.tif, a file of the input DEM $W/m.vrt" \
    vgis-job fill "$W/m.vrt" "$W/hard.tif"
refused "vgis-job level0 -F: out the filled DEM it reads" \
    "$W/f0.fqm: is the input filled DEM $W/f0.fqm" \
    vgis-job level0 -F "$W/f0.fqm" "$W/dem.tif" "$W/f0.fqm"
refused "vgis-job fill --pass 1: its FILLED.raw onto the DEM" \
    "$W/F.raw: is the input DEM $W/F.raw" \
    vgis-job fill --pass 1 --rows 0,128 "$W/F.raw" "$W/F"
refused "vgis-job guard: a path holding the DEM" \
    "$W/D: contains the input DEM $W/D/dem.tif" \
    vgis-job guard "$W/D/dem.tif" "$W/D"

# --- fqmfilter, fqmsolve ---------------------------------------------------
refused "fqmfilter: out a hard link of in, named both" \
    "$W/f0h.fqm: is both the input and the output \\(the input $W/f0.fqm\\)" \
    fqmfilter "$W/f0.fqm" "$W/f0h.fqm"
refused "fqmsolve: out a symbolic link to in" \
    "$W/f0l.fqm: is both the input and the output" \
    fqmsolve "$W/f0.fqm" "$W/f0l.fqm"
refused "fqmsolve: out a band of the band list in" \
    "$W/f1.fqm: is $W/f1.fqm, a band of the input FQM $W/bands.txt" \
    fqmsolve "$W/bands.txt" "$W/f1.fqm"
refused "fqmfilter: out a band, through .." \
    "$W/vm/../f1.fqm: is $W/f1.fqm, a band of the input FQM" \
    fqmfilter "$W/bands.txt" "$W/vm/../f1.fqm"

# --- tilepack --------------------------------------------------------------
# shellcheck disable=SC2086
refused "tilepack: dir holding the DEM" \
    "$W/D: contains the input DEM $W/D/dem.tif" \
    tilepack -q -f "$W/D/dem.tif" "$W/D" $V
# shellcheck disable=SC2086
refused "tilepack: dir holding a VRT's source" \
    "$W/D: contains .*D/dem.tif, a file of the input DEM $W/m.vrt" \
    tilepack -q -f "$W/m.vrt" "$W/D" $V
# shellcheck disable=SC2086
refused "tilepack: dir holding the vertex maps" \
    "$W/vm: contains the input vertex map $W/vm/v0.fqm" \
    tilepack -q -f "$W/dem.tif" "$W/vm" $V
# shellcheck disable=SC2086
refused "tilepack: dir a vertex map" \
    "$W/vm/v0.fqm: is the input vertex map $W/vm/v0.fqm" \
    tilepack -q "$W/dem.tif" "$W/vm/v0.fqm" $V
# shellcheck disable=SC2086
refused "tilepack: dir a hard link of a vertex map" \
    "$W/vh.fqm: is the input vertex map $W/vm/v0.fqm" \
    tilepack -q "$W/dem.tif" "$W/vh.fqm" $V
printf 'fqm-bands 1\n%s\n' "$W/f1.fqm" >"$T/bands.txt"
refused "tilepack: dir holding a band of a vertex map's band list" \
    "$W: contains $W/f1.fqm, a band of the input vertex map $T/bands.txt" \
    tilepack -q -f "$T/dem.tif" "$W" "$T/bands.txt"
# shellcheck disable=SC2086
refused "tilepack -p: the work directory holding the DEM" \
    "$W/D: contains the input DEM $W/D/dem.tif" \
    tilepack -q -p 0:0:1 "$W/D/dem.tif" "$W/D" $V
# shellcheck disable=SC2086
refused "tilepack -g: dir inside the work directory" \
    "$W/work/out: is inside the input work directory $W/work" \
    tilepack -q -g "$W/work" "$W/dem.tif" "$W/work/out" $V
# shellcheck disable=SC2086
refused "tilepack -g: dir the work directory, through a symbolic link" \
    "$W/wl: is the input work directory $W/work" \
    sh -c 'ln -s work "$1/wl" && trap "rm -f \"$1/wl\"" EXIT && shift &&
    "$@"' sh "$W" tilepack -q -g "$W/work" "$W/dem.tif" "$W/wl" $V

# --- tileplay --------------------------------------------------------------
refused "tileplay --shot: the picture inside the pyramid" \
    "$W/pyr/x.png: is inside the input pyramid $W/pyr" \
    tileplay --shot "$W/pyr/x.png" "$W/pyr"
refused "tileplay --shot: the picture a hard link of a block" \
    "$W/b.png: is inside the input pyramid $W/pyr" \
    sh -c 'ln "$1/pyr/0/0_0.exr" "$1/b.png" && trap "rm -f \"$1/b.png\"" EXIT &&
    tileplay --shot "$1/b.png" "$1/pyr"' sh "$W"
refused "tileplay --shot: into a level the pyramid links to" \
    "$W/elsewhere/0/x.png: is inside the input pyramid $W/pyr2" \
    tileplay --shot "$W/elsewhere/0/x.png" "$W/pyr2"

# --- what is apart still runs ----------------------------------------------
run "dem2vgis: OUT beside the DEM's directory" \
    dem2vgis -q "$W/D/dem.tif" "$T/pyr"
run "vgis2tiles: OUTDIR beside the pyramid" \
    vgis2tiles -q "$W/pyr" "$T/tileset"
run "fqmfilter: out beside in" fqmfilter "$W/f0.fqm" "$T/f1.fqm"
run "vgis-job guard: a path apart" \
    vgis-job guard "$W/list.txt" "$T/x"
done_testing
