# t_plan_bands - dem2vgis --plan with the chain split into column bands
# (--band-width): the fill job, a job per band, the chain from the bands'
# FQMs, then the pieces read the bands' vertex maps through band lists;
# the pyramid byte for byte the one dem2vgis builds in one run, on a
# geographic DEM with voids across the bands' borders (rows and columns
# stored backwards) and on a UTM DEM (a metric that varies along the rows)
# with the widest kernel. Killed in the middle and run again; GNU
# parallel; and the halo shown to be needed.
. "$(dirname "$0")/../lib.sh"
quick_skip "a banded plan run by make"
PATH=$B:$PATH

gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" "$T/crop.tif"
/usr/bin/python3 "$TOP/tests/tools/mkgdal.py" flipped "$T/crop.tif" "$T/flip.tif"
ok $? "a 2200x400 crop of N48W125 flipped both ways, with voids"
no_tmp() { [ "$(find "$1" -name '.*.??????' | wc -l)" -eq 0 ]; }

# plan NAME DEM BANDWIDTH FILLROWS [OPTIONS]: the plan, run by make -j2,
# against dem2vgis in one run
plan() {
	n=$1 d=$2 bw=$3 fr=$4; shift 4
	dem2vgis -q "$@" "$d" "$T/ref-$n" &&
	    dem2vgis "$@" --band-width "$bw" --fill-rows "$fr" \
	    --plan "$T/plan-$n" "$d" "$T/out-$n"
	ok $? "$n: dem2vgis in one run; the plan in bands of $bw columns"
	nb=$(wc -l <"$T/plan-$n/bands/targets")
	nf=$(cat "$T/plan-$n/bands/fill1" 2>/dev/null | wc -l)
	[ "$nb" -ge 3 ]; ok $? "$n: $nb band jobs, the fill in $nf row bands"
	make -s -C "$T/plan-$n" -j2 >"$T/make.log" 2>&1 &&
	    diff -r "$T/ref-$n" "$T/out-$n" >/dev/null
	s=$?
	[ $s -eq 0 ] || sed 's/^/#   /' "$T/make.log" | head -5
	ok $s "$n: make -j2: the pyramid dem2vgis makes, byte for byte"
	no_tmp "$T/plan-$n" && no_tmp "$T/out-$n"
	ok $? "$n: no temporary left"
}
plan flip "$T/flip.tif" 256 70
[ "$nf" -eq 6 ]; ok $? "flip: 400 rows in fill bands of 70: 6 (the last 50)"
# the bands' vertex maps, read as one, are the single chain's
dem2vgis -M "$T/flip.tif" "$T/vm"
for l in 0 1 2 3; do
	[ "$(rsinfo -c "$T/vm/v$l.fqm" | grep hash)" = \
	    "$(rsinfo -c "$T/plan-flip/bands/v$l.bands" | grep hash)" ]
	ok $? "flip: level $l's vertex maps in bands hash as the whole level's"
done
plan utm "$DATA/bigtujunga.tif" 128 0 -k binomial5
[ "$nf" -eq 0 ] && grep -q '^done/fill:$' "$T/plan-utm/Makefile"
ok $? "utm: --fill-rows 0: the fill one job"
# 2200 columns in bands of 1088: the third would be 24 wide, narrower
# than a halo (48), so the second takes it
dem2vgis --band-width 1088 --plan "$T/plan-m" "$T/flip.tif" "$T/out-m" &&
    [ "$(wc -l <"$T/plan-m/bands/targets")" -eq 2 ] &&
    grep -q 'band 1088,2200 ' "$T/plan-m/Makefile" &&
    make -s -C "$T/plan-m" -j2 >/dev/null 2>&1 &&
    diff -r "$T/ref-flip" "$T/out-m" >/dev/null
ok $? "a last band narrower than the halo joins the one before: 2 bands, byte for byte"

# QEM-3D stays one chain job: its fold fix has no bounded reach
dem2vgis -3 --band-width 256 --plan "$T/plan-3d" "$T/flip.tif" "$T/out-3d" &&
    [ ! -e "$T/plan-3d/bands" ] && ! grep -q '^done/fill:' "$T/plan-3d/Makefile"
ok $? "qem3d: no bands, the chain one job"

# killed while the bands run (SIGKILL to the whole process group), run
# again: it finishes, identical
dem2vgis --band-width 256 --fill-rows 70 --plan "$T/plan-k" "$T/flip.tif" "$T/out-k"
setsid make -s -C "$T/plan-k" -j2 >/dev/null 2>&1 & mk=$!
i=0	# until a band has started
while [ $i -lt 1200 ] && [ -z "$(ls "$T/plan-k/done" 2>/dev/null | grep b-)" ]
do sleep 0.02; i=$((i + 1)); done
/bin/kill -KILL -- -"$mk" 2>/dev/null; wait "$mk" 2>/dev/null
# the jobs' stages run in their own process groups and end on SIGTERM
# when their supervisor dies (graph_child.c): the killed run is over
# when the last of them has cleaned up (plan-[k]: not grep itself)
i=0
while [ $i -lt 1500 ] &&
    grep -qs -- "$T/plan-[k]" /proc/[0-9]*/cmdline 2>/dev/null
do sleep 0.02; i=$((i + 1)); done
[ ! -e "$T/out-k" ] && [ ! -e "$T/plan-k/done/chain" ]
ok $? "killed while the bands ran: no chain, no pyramid yet"
make -s -C "$T/plan-k" -j2 >"$T/rerun.err" 2>&1 &&
    diff -r "$T/ref-flip" "$T/out-k" >"$T/rerun.diff" 2>&1 && no_tmp "$T/plan-k"
s=$?
[ $s -eq 0 ] || { tail -5 "$T/rerun.err"; head -5 "$T/rerun.diff"
	find "$T/plan-k" -name '.*.??????'; } 2>/dev/null | sed 's/^/#   /'
ok $s "run again: it finishes, byte for byte, no temporary left"

# GNU parallel and Slurm run the stages as separate makes: each goal
# makes itself alone, not the chain after it
P=$T/plan-p
dem2vgis --band-width 256 --fill-rows 70 --plan "$P" "$T/flip.tif" "$T/out-p" &&
    make -s -C "$P" done/f1-2 >/dev/null 2>&1 && [ -e "$P/done/f1-2" ] &&
    [ "$(ls "$P/done")" = f1-2 ]
ok $? "make done/f1-2: that fill band's pass 1 alone"
make -s -C "$P" done/fill >/dev/null 2>&1 && [ -f "$P/fill.dem" ] &&
    [ -z "$(ls "$P/bands" | grep -v '[.a-z]')" ] && [ ! -e "$P/done/chain" ] &&
    [ -z "$(ls "$P" | grep -v '^bands$\|^done$\|^fill.dem$\|^Makefile$\|^mkpieces$\|^job$\|^dem.stamp$\|sh$')" ]
ok $? "make done/fill: the fill's parts, no band, no chain, no part left"
make -s -C "$P" done/b-1 >/dev/null 2>&1 && [ -f "$P/bands/1/f.fqm" ] &&
    [ ! -e "$P/bands/0" ] && [ ! -e "$P/done/chain" ]
ok $? "make done/b-1: that band alone"
if command -v parallel >/dev/null; then
	PARALLEL=-j2 sh "$T/plan-p/parallel.sh" >/dev/null 2>&1 &&
	    diff -r "$T/ref-flip" "$T/out-p" >/dev/null
	ok $? "GNU parallel (local, -j2): the pyramid byte for byte"
else
	ok 0 "GNU parallel # SKIP not installed"
fi
sh -n "$T/plan-flip/slurm.sh" && grep -q '^	b=$(array bands ' "$T/plan-flip/slurm.sh"
ok $? "the Slurm script parses (sh -n) and has the band array"

# The halo is needed: level 3's FQM of columns 64 .. 127 (level-0 columns
# 512 .. 1023) from a window 3 x 2^3 columns wider on either side is the
# whole level's; 2^3 wider, with binomial5, it is not.
# band DEM A B: level 3's FQM of level-0 columns A..B-1's window
band() {
	vgis-job level0 -w "$2,$3" "$1" - | fqmfilter -k binomial5 |
	    fqmfilter -k binomial5 | vgis-job filter -k binomial5 -C 64,128 -
}
dem2fqm "$T/flip.tif" - | fqmfilter -k binomial5 | fqmfilter -k binomial5 |
    vgis-job filter -k binomial5 -C 64,128 - >"$T/whole.fqm"
band "$T/flip.tif" 488 1048 >"$T/h24.fqm" && cmp -s "$T/whole.fqm" "$T/h24.fqm"
ok $? "halo 3 x 2^3: level 3's band is the whole level's"
band "$T/flip.tif" 504 1032 >"$T/h8.fqm" && ! cmp -s "$T/whole.fqm" "$T/h8.fqm"
ok $? "halo 2^3 with binomial5: it is not (the halo is needed)"

# the filled DEM: its windows give the FQM's windows; refused for
# another DEM's options
vgis-job fill "$T/flip.tif" "$T/f.dem" &&
    vgis-job level0 -w 700,1300 "$T/flip.tif" - |
    vgis-job filter -C 400,600 - >"$T/w1.fqm" &&
    vgis-job level0 -F "$T/f.dem" -w 700,1300 "$T/flip.tif" - |
    vgis-job filter -C 400,600 - >"$T/w2.fqm" && cmp -s "$T/w1.fqm" "$T/w2.fqm"
ok $? "vgis-job fill, then level0 -F -w: the window as from the DEM itself"
fails "vgis-job level0 -F with other DEM options: refused" 1 "f.dem: made from another DEM or other options" \
    vgis-job level0 -F "$T/f.dem" -N 0 -w 0,100 "$T/flip.tif" /dev/null
fails "vgis-job fill with a third operand: usage" 2 "usage" \
    vgis-job fill "$T/flip.tif" "$T/g.dem" "$T/out.fqm"
fails "--band-levels: vgis-job chain's, not dem2vgis's" 2 "usage" \
    dem2vgis --band-levels 2 --band 0,100 "$T/flip.tif" "$T/x"
fails "--band past the DEM's columns: refused" 2 "has 2200 columns and 6 levels" \
    vgis-job chain --band 2000,2300 --band-levels 2 "$T/flip.tif" "$T/x"
fails "--band-levels as many as the DEM's levels: refused" 2 "has 2200 columns and 6 levels" \
    vgis-job chain --band 0,1000 --band-levels 6 "$T/flip.tif" "$T/x"
fails "--from and --band together: refused" 2 "alone" \
    vgis-job chain --from x.bands --band 0,100 --band-levels 2 "$T/flip.tif" "$T/x"
fails "fqmfilter on a window from an odd column: refused" 1 "odd" \
    sh -c "vgis-job level0 -w 3,40 '$T/flip.tif' - | fqmfilter >/dev/null"
done_testing
