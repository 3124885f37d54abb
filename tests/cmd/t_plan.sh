# t_plan - dem2vgis --plan: the job graph built by make (-j2), by GNU
# parallel when it is installed, killed in the middle and run again; the
# pyramid byte for byte the one dem2vgis builds in one run. The Slurm
# script is parsed here (sh -n), run in t_plan_slurm.sh.
. "$(dirname "$0")/../lib.sh"
quick_skip "a plan run by make and GNU parallel"
PATH=$B:$PATH

# A crop of N48W125 wide enough for two pieces at level 0 in QEM-1D (more
# than 16 block columns) and in QEM-3D (12).
gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" "$T/dem.tif"
ok $? "a 2200x400 crop of N48W125"
# no temporary: nothing like ".NAME.XXXXXX" under DIR
no_tmp() { [ "$(find "$1" -name '.*.??????' | wc -l)" -eq 0 ]; }

# (3D again with pieces in parts of rows, tilepack -b: the parts are
# jobs before their pieces)
for m in "" -3 "-3 --part-samples 300000"; do
	name=1d; [ "$m" = -3 ] && name=3d
	case $m in *part*) name=3d-parts ;; esac
	# shellcheck disable=SC2086
	if [ $name = 3d-parts ]; then
		cp -R "$T/ref-3d" "$T/ref-$name"
	else
		dem2vgis -q $m "$T/dem.tif" "$T/ref-$name"
	fi
	ok $? "$name: dem2vgis in one run"
	# shellcheck disable=SC2086
	dem2vgis $m --plan "$T/plan-$name" "$T/dem.tif" "$T/out-$name" &&
	    [ -f "$T/plan-$name/Makefile" ] && [ ! -e "$T/out-$name" ]
	ok $? "$name: the plan is written, nothing built yet"
	make -s -C "$T/plan-$name" -j2 >"$T/make.log" 2>&1 &&
	    diff -r "$T/ref-$name" "$T/out-$name" >/dev/null
	ok $? "$name: make -j2: the pyramid dem2vgis makes, byte for byte"
	n=$(wc -l <"$T/plan-$name/done/targets")
	q=$(wc -l <"$T/plan-$name/done/parts")
	[ "$n" -ge 2 ] && case $name in *parts) [ "$q" -ge 2 ] ;;
	    *) [ "$q" -eq 0 ] ;; esac
	ok $? "$name: $n pieces and $q parts of pieces, each a job"
	make -s -C "$T/plan-$name" >"$T/make2.log" 2>&1 && [ ! -s "$T/make2.log" ]
	ok $? "$name: make again: nothing to do"
done

# Killed in the middle (SIGKILL to the whole process group) while the
# pieces run, then run again: it finishes, identical; no half-written file
# anywhere. N48W125 whole: its pieces take seconds.
big N48W125 || {
dem2vgis -q "$DATA/N48W125.hgt" "$T/ref-k"
dem2vgis --plan "$T/plan-k" --part-samples 3000000 "$DATA/N48W125.hgt" "$T/out-k"
setsid make -s -C "$T/plan-k" -j2 >/dev/null 2>&1 & mk=$!
i=0	# until a piece has started (it makes work/)
while [ $i -lt 1200 ] && [ ! -e "$T/plan-k/work" ]; do sleep 0.05; i=$((i + 1)); done
sleep 0.2
/bin/kill -KILL -- -"$mk" 2>/dev/null; wait "$mk" 2>/dev/null
made=$(ls "$T/plan-k/done" | grep -c '^[pq]-')
all=$(cat "$T/plan-k/done/parts" "$T/plan-k/done/targets" | wc -l)
[ ! -e "$T/out-k" ] && [ "$made" -lt "$all" ]
ok $? "killed while the pieces and their parts ran ($made of $all made): no pyramid yet"
make -s -C "$T/plan-k" -j2 >/dev/null 2>&1 &&
    diff -r "$T/ref-k" "$T/out-k" >/dev/null
ok $? "run again: it finishes, the pyramid byte for byte"
no_tmp "$T/plan-k" && no_tmp "$T/out-k"
ok $? "no temporary left in the plan or the pyramid"
}

if command -v parallel >/dev/null; then
	dem2vgis --plan "$T/plan-p" --part-samples 300000 "$T/dem.tif" \
	    "$T/out-p"
	PARALLEL=-j2 sh "$T/plan-p/parallel.sh" >/dev/null 2>&1 &&
	    diff -r "$T/ref-1d" "$T/out-p" >/dev/null &&
	    [ "$(wc -l <"$T/plan-p/done/parts")" -ge 2 ]
	ok $? "GNU parallel (local, -j2), pieces in parts: the pyramid byte for byte"
else
	ok 0 "GNU parallel # SKIP not installed"
fi
sh -n "$T/plan-1d/slurm.sh"; ok $? "the Slurm script parses (sh -n)"
sh -n "$T/plan-1d/parallel.sh"; ok $? "the parallel script parses (sh -n)"
fails "--plan onto an existing plan: refused" 1 "plan-1d: exists" \
    dem2vgis --plan "$T/plan-1d" "$T/dem.tif" "$T/out-x"
fails "--plan with the DEM on stdin: refused" 2 "stdin" \
    dem2vgis --plan "$T/plan-x" - "$T/out-x"
done_testing
