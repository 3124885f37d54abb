# t_terrain_plan - vgis2terrain --plan: the terrain export as jobs of
# tile ranges (two rounds a level, then the gather) run by make -j2 and
# GNU parallel, byte for byte the terrain vgis2terrain makes in one
# process, in both formats. The DEM: an ellipsoidal 513x513 crop of
# N48W125 with a 5.5 km spike, so that at some levels the spike's tiles
# hold only at a later try than the others: after round 1 that level's
# ranges are at different tries, and round 2 brings the others to the
# spike's, as one process does. Killed while its jobs run, then run
# again: it finishes, identical, no temporary left. The Slurm script
# parses and submits round 1, round 2 after it, the gather after that
# (sbatch faked). A pyramid changed since the plan was written is refused.
. "$(dirname "$0")/../lib.sh"
quick_skip "the terrain plan run by make and GNU parallel"
PY=/usr/bin/python3

gdal_translate -q -a_srs EPSG:4326+5773 -srcwin 1696 2176 513 513 \
    "$DATA/N48W125.hgt" "$T/srtm.tif"
$PY "$TOP/tests/tools/ellipsoidal.py" "$T/srtm.tif" "$T/geo.tif"
$PY "$TOP/tests/tools/spike.py" "$T/geo.tif" "$T/spike.tif" 100 400
dem2vgis -q "$T/spike.tif" "$T/pyr"; ok $? "a pyramid of the crop with a spike"
run "vgis2terrain in one process (qm)" vgis2terrain -j 2 "$T/pyr" "$T/ref-qm"
grep 'vgis2terrain: level ' "$T/err" | sed 's/^[^:]*: //' >"$T/rep1"
later=$(grep -c 'try [2-9]' "$T/rep1")
[ "$later" -ge 1 ]; ok $? "one process: $later levels held only at a later try"
vgis2terrain -q -j 2 -f 3dtiles "$T/pyr" "$T/ref-3d"
ok $? "vgis2terrain in one process (3dtiles)"

# no temporary: nothing like ".NAME.XXXXXX" under DIR
no_tmp() { [ "$(find "$1" -name '.*.??????' | wc -l)" -eq 0 ]; }

P=$T/plan-qm
vgis2terrain --plan "$P" --part-samples 140000 "$T/pyr" "$T/out-qm" 2>/dev/null &&
    [ -f "$P/Makefile" ] && [ -x "$P/job" ] && [ -f "$P/pyramid.stamp" ] &&
    [ ! -e "$T/out-qm" ]
ok $? "the plan is written, nothing made yet"
n=$(wc -l <"$P/targets1")
[ "$n" -ge 20 ] && [ "$(wc -l <"$P/targets2")" -eq "$n" ]
ok $? "$n ranges, a job each in round 1 and in round 2"

# killed (SIGKILL to the whole process group) once a range is recorded
setsid make -s -C "$P" -j2 >/dev/null 2>&1 & mk=$!
i=0
while [ $i -lt 1200 ] && [ -z "$(ls "$P/work.ranges" 2>/dev/null)" ]; do
	sleep 0.05; i=$((i + 1))
done
/bin/kill -KILL -- -"$mk" 2>/dev/null; wait "$mk" 2>/dev/null
made=$(ls "$P/done" 2>/dev/null | grep -c '^t1-')
[ ! -e "$T/out-qm" ] && [ "$made" -lt "$n" ]
ok $? "killed in round 1 ($made of $n made): no terrain yet"

# round 1 alone: the spike's ranges at a later try than their level's others
# shellcheck disable=SC2046
make -s -C "$P" -j2 $(cat "$P/targets1") >"$T/make.log" 2>&1
ok $? "round 1 run again: the rest of it"
awk 'FNR == 2 { t[$1] = t[$1] " " $4 } END { for (z in t) {
    split(t[z], a, " "); for (k in a) if (a[k] != a[1]) { d++; break } }
    exit !(d >= 1) }' "$P"/work.ranges/*.1
ok $? "after round 1 a level's ranges are at different tries"
make -s -C "$P" -j2 >"$T/make.log" 2>&1 &&
    diff -r "$T/ref-qm" "$T/out-qm" >/dev/null
ok $? "make -j2 again: round 2 and the gather; the terrain byte for byte one process's"
[ ! -e "$P/work" ] && [ ! -e "$P/work.ranges" ] && no_tmp "$P" && no_tmp "$T/out-qm"
ok $? "no temporary left in the plan or the terrain"
grep 'terrain-gather: level ' "$T/make.log" | sed 's/^[^:]*: //' |
    diff - "$T/rep1" >/dev/null
ok $? "the gather's report is one process's: per level tiles, triangles, bytes, try, bound"
make -s -C "$P" >"$T/make2.log" 2>&1 && [ ! -s "$T/make2.log" ]
ok $? "make again: nothing to do"

if command -v parallel >/dev/null; then
	vgis2terrain -q -f 3dtiles --plan "$T/plan-3d" --part-samples 140000 \
	    "$T/pyr" "$T/out-3d" &&
	    PARALLEL=-j2 sh "$T/plan-3d/parallel.sh" >/dev/null 2>&1 &&
	    diff -r "$T/ref-3d" "$T/out-3d" >/dev/null
	ok $? "-f 3dtiles, GNU parallel (-j2): the tileset byte for byte one process's"
else
	ok 0 "GNU parallel # SKIP not installed"
fi

# Slurm: the script parses; submitted to a fake sbatch (the plan done, so
# each job finds its target made): round 1 an array of n, round 2 one of n
# after it, the gather after that
sh -n "$P/slurm.sh" && sh -n "$P/parallel.sh"
ok $? "slurm.sh and parallel.sh parse (sh -n)"
. "$TOP/tests/slurm.sh"
mkdir "$T/bin" && fake_sbatch "$T/bin"
SBATCH_OPTS='' PATH=$T/bin:$PATH sh "$P/slurm.sh" >/dev/null 2>&1 &&
    awk -v n="$n" '{ j[NR] = $2 " " $3 " " $4 }
    END { exit !(NR == 3 && j[1] == "round1 - " n && j[2] == "round2 1 " n &&
        j[3] == "gather 2 -") }' "$T/bin/jobs" && [ ! -s "$T/bin/failed" ]
ok $? "slurm.sh: round 1 (array 1-$n), round 2 (afterok), gather (afterok)"

# the pyramid changed after the plan was written: every job refuses it
cp -R "$T/pyr" "$T/pyr2" &&
    vgis2terrain -q --plan "$T/plan-c" "$T/pyr2" "$T/out-c" &&
    touch "$T/pyr2/index.json"
! make -s -C "$T/plan-c" >"$T/make3.log" 2>&1 &&
    grep -q 'index.json.*write the plan again' "$T/make3.log" &&
    [ ! -e "$T/out-c" ] && [ ! -e "$T/plan-c/work.ranges" ]
ok $? "the pyramid changed since the plan: its jobs refuse it, say to write the plan again"

fails "--plan onto an existing directory: refused" 1 "exists" \
    vgis2terrain --plan "$P" "$T/pyr" "$T/out-x"
fails "--plan with -z and 3dtiles: usage" 2 "usage" \
    vgis2terrain -z -f 3dtiles --plan "$T/plan-x" "$T/pyr" "$T/out-x"
fails "a range outside the tileset: refused" 1 "not in the tileset" \
    vgis-job terrain-part 30:0:1 "$T/pyr" "$T/w"
done_testing
