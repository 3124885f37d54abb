# t_rgb_plan - dem2rgb --plan: the raster-dem tiles as jobs (the warp,
# parts of tile columns, then the gather; t_rgb_plan_split shows the
# split itself) run by
# make -j2 and GNU parallel, byte for byte what dem2rgb makes in one
# process: the tree (diff -r, tiles.json and its measured error
# included) and the PMTiles archive (cmp), with other options (Terrain-RGB,
# WebP, 256 px, -m average). The DEM: a 257x257 crop of SRTM N48W125 with
# voids, and a UTM variant of it. Killed while its jobs run, then run again: it finishes,
# identical, no temporary left. The Slurm script submits the parts as an
# array and the gather after them (sbatch faked). A DEM changed since
# the plan was written is refused.
. "$(dirname "$0")/../lib.sh"
quick_skip "dem2rgb's plan run by make and GNU parallel"

gdal_translate -q -srcwin 2816 3080 257 257 "$DATA/N48W125.hgt" "$T/srtm.tif"
run "dem2rgb in one process" dem2rgb -j 2 "$T/srtm.tif" "$T/ref"
sed 's/^[^:]*: //' "$T/err" >"$T/rep1"

# no temporary: nothing like ".NAME.XXXXXX" under DIR
no_tmp() { [ "$(find "$1" -name '.*.??????' | wc -l)" -eq 0 ]; }

P=$T/plan
dem2rgb --plan "$P" --part-tiles 1 "$T/srtm.tif" "$T/tree" 2>/dev/null &&
    [ -f "$P/Makefile" ] && [ -x "$P/job" ] && [ -f "$P/dem.stamp" ] &&
    [ ! -e "$T/tree" ]
ok $? "the plan is written, nothing made yet"
n=$(wc -l <"$P/targets1")
[ "$n" -ge 2 ]; ok $? "$n parts, a job each"
# the parts cut the deepest zoom's tiles: each holds some of them
z=$(sed -n 's/^zoom \([0-9]*\): .*/\1/p' "$T/rep1" | tail -1)

# killed (SIGKILL to the whole process group) once a part is recorded:
# stopped first (SIGSTOP), and where every part had ended by then (the
# parts run together and may end within a look on a loaded machine), the
# check is skipped, saying so
setsid make -s -C "$P" -j2 >/dev/null 2>&1 & mk=$!
i=0
while [ $i -lt 6000 ] && [ -z "$(ls "$P/work.parts" 2>/dev/null)" ]; do
	sleep 0.01; i=$((i + 1))
done
/bin/kill -STOP -- -"$mk" 2>/dev/null
made=$(ls "$P/done" 2>/dev/null | grep -c '^p-')
/bin/kill -KILL -- -"$mk" 2>/dev/null
/bin/kill -CONT -- -"$mk" 2>/dev/null; wait "$mk" 2>/dev/null
if [ "$made" -lt "$n" ]; then
	[ ! -e "$T/tree" ]
	ok $? "killed among the parts ($made of $n made): no tree yet"
else
	ok 0 "killed among the parts: skipped, all $n parts had ended"
fi
# the parts alone: each holds tiles of the deepest zoom, all of them;
# per zoom each tile in work is a part's, written once (the gather
# writes those across parts)
# shellcheck disable=SC2046
make -s -C "$P" -j2 $(cat "$P/targets1") >/dev/null 2>&1
ok $? "the parts run again alone: the rest of them"
bad=0
for k in $(seq 0 $((n - 1))); do
	awk -v z="$z" '$1 == z && NF == 6 && $2 > 0 { f = 1 } END { exit !f }' \
	    "$P/work.parts/$k" || bad=1
done
for d in "$T/ref"/*/; do
	zz=$(basename "$d")
	want=$(find "$d" -type f | wc -l)
	have=$(find "$P/work/$zz" -type f 2>/dev/null | wc -l)
	sum=$(cat "$P"/work.parts/* | awk -v z="$zz" \
	    '$1 == z && NF == 6 { s += $2 } END { print s + 0 }')
	[ "$have" -eq "$sum" ] && [ "$have" -le "$want" ] || bad=1
	[ "$zz" != "$z" ] || [ "$have" -eq "$want" ] || bad=1
done
[ $bad -eq 0 ]; ok $? "each part holds tiles of zoom $z, all of them; per zoom the parts' tiles are recorded"
make -s -C "$P" -j2 >"$T/make.log" 2>&1 && diff -r "$T/ref" "$T/tree" >/dev/null
ok $? "make -j2 again: the gather; the tree byte for byte one process's"
[ ! -e "$P/work" ] && [ ! -e "$P/work.parts" ] && no_tmp "$P" && no_tmp "$T/tree"
ok $? "no temporary left in the plan or the tree"
grep 'rgb-gather: zoom ' "$T/make.log" | sed 's/^[^:]*: //' |
    diff - "$T/rep1" >/dev/null
ok $? "the gather's report is one process's: per zoom tiles, bytes, error"
make -s -C "$P" >"$T/make2.log" 2>&1 && [ ! -s "$T/make2.log" ]
ok $? "make again: nothing to do"

# a part with no tile of its own at the coarse zooms writes none there
n1=$(find "$T/tree/0" -type f | wc -l)
[ "$n1" -eq 1 ]; ok $? "zoom 0: one tile, written by one part"

opts="-e mapbox -f webp -t 256 -Z 2 -z 11"
# shellcheck disable=SC2086
dem2rgb -q -j 2 $opts -o "$T/ref.pmtiles" "$T/srtm.tif"
ok $? "dem2rgb in one process: $opts, an archive"
if command -v parallel >/dev/null; then
	# shellcheck disable=SC2086
	dem2rgb $opts --plan "$T/plan-pm" --part-tiles 2 \
	    -o "$T/out.pmtiles" "$T/srtm.tif" &&
	    PARALLEL=-j2 sh "$T/plan-pm/parallel.sh" >/dev/null 2>&1 &&
	    cmp "$T/ref.pmtiles" "$T/out.pmtiles" &&
	    [ ! -e "$T/plan-pm/work" ] && [ ! -e "$T/plan-pm/work.parts" ]
	ok $? "$opts -o, GNU parallel (-j2): the archive byte for byte one process's"
else
	ok 0 "GNU parallel # SKIP not installed"
fi

dem2rgb -q -j 1 -m average -z 11 "$T/srtm.tif" "$T/ref-av" &&
    dem2rgb -m average -z 11 --plan "$T/plan-av" --part-tiles 1 \
    "$T/srtm.tif" "$T/out-av" && make -s -C "$T/plan-av" -j2 -q 2>/dev/null
[ $? -ne 0 ]; ok $? "make -q: a plan not run is not up to date"
make -s -C "$T/plan-av" -j2 >/dev/null 2>"$T/make-av.err" &&
    diff -r "$T/ref-av" "$T/out-av" >"$T/diff-av" 2>&1
s=$?
[ $s -eq 0 ] || head -5 "$T/make-av.err" "$T/diff-av" | sed 's/^/#   /'
ok $s "-m average, make -j2: the tree byte for byte one process's"

# a UTM DEM (reprojected by the warp): the same
gdalwarp -q -t_srs EPSG:32610 -tr 30 30 -r bilinear "$T/srtm.tif" "$T/utm.tif"
dem2rgb -q -j 2 -z 11 "$T/utm.tif" "$T/ref-utm" &&
    dem2rgb -q -z 11 --plan "$T/plan-utm" --part-tiles 1 "$T/utm.tif" \
    "$T/out-utm" && make -s -C "$T/plan-utm" -j2 >"$T/make4.log" 2>&1 &&
    [ ! -s "$T/make4.log" ] && diff -r "$T/ref-utm" "$T/out-utm" >/dev/null
ok $? "a UTM DEM, -q, make -j2: the tree byte for byte one process's, no report"

# Slurm: the script parses; submitted to a fake sbatch (the plan done, so
# each job finds its target made): the parts an array of n, the gather
# after it
sh -n "$P/slurm.sh" && sh -n "$P/parallel.sh"
ok $? "slurm.sh and parallel.sh parse (sh -n)"
. "$TOP/tests/slurm.sh"
mkdir "$T/bin" && fake_sbatch "$T/bin"
SBATCH_OPTS='' PATH=$T/bin:$PATH sh "$P/slurm.sh" >/dev/null 2>&1 &&
    awk -v n="$n" '{ j[NR] = $2 " " $3 " " $4 }
    END { exit !(NR == 3 && j[1] == "warp - -" && j[2] == "parts 1 " n &&
    j[3] == "gather 2 -") }' "$T/bin/jobs" && [ ! -s "$T/bin/failed" ]
ok $? "slurm.sh: the warp, the parts (array 1-$n, afterok), the gather (afterok)"

# the DEM changed after the plan was written: every job refuses it
cp "$T/srtm.tif" "$T/srtm2.tif" &&
    dem2rgb --plan "$T/plan-c" "$T/srtm2.tif" "$T/out-c" &&
    touch -d '2001-01-01' "$T/srtm2.tif"
! make -s -C "$T/plan-c" >"$T/make3.log" 2>&1 &&
    grep -q 'srtm2.tif.*write the plan again' "$T/make3.log" &&
    [ ! -e "$T/out-c" ] && [ ! -e "$T/plan-c/work.parts" ]
ok $? "the DEM changed since the plan: its jobs refuse it, say to write the plan again"

fails "--plan onto an existing directory: refused" 1 "exists" \
    dem2rgb --plan "$P" "$T/srtm.tif" "$T/out-x"
fails "--plan with --dump: usage" 2 "not with --plan" \
    dem2rgb --dump "$T/d" --plan "$T/plan-x" "$T/srtm.tif" "$T/out-x"
fails "a part past the count: refused" 1 "not a part" \
    vgis-job rgb-part 3:3 "$T/srtm.tif" "$T/w"
fails "the gather before the parts: refused" 1 "run the plan's parts" \
    vgis-job rgb-gather "$T/srtm.tif" "$T/w" "$T/out-x"
done_testing
