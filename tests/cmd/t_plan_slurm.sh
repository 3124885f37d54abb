# t_plan_slurm - dem2vgis --plan's slurm.sh run, the pyramid byte for byte
# the one dem2vgis builds in one run: first by a fake sbatch that runs each
# job at once, in order (no Slurm needed); then, as root with Debian's
# munge and slurmctld, slurmd, slurm-client installed, on a real Slurm
# cluster of one node started here (munged, slurmctld, slurmd on
# 127.0.0.1, every file of theirs under $T, stopped at the end whatever
# happens). A plan whose first job fails: the jobs after it are cancelled,
# none left pending; submitted again once the DEM is back, it finishes.
. "$(dirname "$0")/../lib.sh"
quick_skip "a plan run by Slurm"
PATH=$B:$PATH:/usr/sbin:/sbin

gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" "$T/dem.tif"
ok $? "a 2200x400 crop of N48W125"
dem2vgis -q "$T/dem.tif" "$T/ref"; ok $? "dem2vgis in one run"

# --- dry run: sbatch faked ---------------------------------------------
. "$TOP/tests/slurm.sh"
mkdir "$T/bin" && fake_sbatch "$T/bin"

# the plan in a directory whose name has a space and a quote
P="$T/plan it's" O="$T/out it's"
dem2vgis --plan "$P" "$T/dem.tif" "$O"
ok $? "the plan, in a directory named with a space and a quote"
sh -n "$P/slurm.sh" && { ! command -v bash >/dev/null || bash -n "$P/slurm.sh"; }
ok $? "slurm.sh parses (sh -n, bash -n)"
SBATCH_OPTS='' PATH=$T/bin:$PATH sh "$P/slurm.sh" >"$T/dry.out" 2>&1 &&
    diff -r "$T/ref" "$O" >/dev/null
ok $? "dry run (sbatch faked, SBATCH_OPTS empty): the pyramid byte for byte"
n=$(wc -l <"$P/done/targets")
# chain; submit after it; the pieces, an array of n; gather after them
awk -v n="$n" '{ j[NR] = $2 " " $3 " " $4 }
    END { exit !(NR == 4 && j[1] == "chain - -" && j[2] == "submit 1 -" &&
        j[3] == "pieces - " n && j[4] == "gather 3 -") }' "$T/bin/jobs" &&
    [ "$(ls "$P" | grep -c '^slurm-3_[0-9]*\.out$')" -eq "$n" ] &&
    [ ! -s "$T/bin/failed" ]
ok $? "dry run: chain, submit (afterok chain), $n pieces (array 1-$n), gather (afterok pieces)"

# a plan whose chain fails (its DEM gone): the rest is not run; the DEM
# back, submitted again, it finishes
cp "$T/dem.tif" "$T/gone.tif"
dem2vgis --plan "$T/plan-f" "$T/gone.tif" "$T/out-f"
mv "$T/gone.tif" "$T/away.tif" && rm "$T/bin/jobs" "$T/bin/n"
SBATCH_OPTS='-p test -t 5' PATH=$T/bin:$PATH sh "$T/plan-f/slurm.sh" \
    >/dev/null 2>&1 && [ ! -e "$T/out-f" ] &&
    [ "$(cut -d' ' -f2 "$T/bin/jobs" | tr '\n' ' ')" = "chain submit " ] &&
    grep -q 'gone.tif' "$T/plan-f/slurm-1.out"
ok $? "dry run, the chain failing: the rest not run, the error in slurm-1.out"
# the same file back (a copy would be another DEM to the plan: t_plan_dem)
mv "$T/away.tif" "$T/gone.tif"
SBATCH_OPTS='-p test -t 5' PATH=$T/bin:$PATH sh "$T/plan-f/slurm.sh" \
    >/dev/null 2>&1 && diff -r "$T/ref" "$T/out-f" >/dev/null
ok $? "dry run, submitted again with the DEM back: the pyramid byte for byte"
# (and pieces in parts: tilepack -b)
dem2vgis --band-width 512 --fill-rows 150 --part-samples 200000 \
    --plan "$T/plan-db" "$T/dem.tif" "$T/out-db"
nb=$(wc -l <"$T/plan-db/bands/targets")
rm -f "$T/bin/jobs" "$T/bin/failed"
SBATCH_OPTS='' PATH=$T/bin:$PATH sh "$T/plan-db/slurm.sh" >"$T/dry.out" 2>&1 &&
    diff -r "$T/ref" "$T/out-db" >/dev/null
ok $? "dry run of a plan in $nb bands: the pyramid byte for byte"
j=$(awk '{ print $2, ($3 == "-" ? "-" : "dep"), $4 }' "$T/bin/jobs" | tr '\n' ';')
nq=$(wc -l <"$T/plan-db/done/parts")
[ "$j" = "fill1 - 3;join dep -;fill2 dep 3;fill dep -;bands dep $nb;chain dep -;submit dep -;parts - $nq;pieces dep $(wc -l <"$T/plan-db/done/targets");gather dep -;" ] &&
    [ "$nq" -ge 10 ]
ok $? "dry run in bands: the fill's passes (arrays of 3, join, commit), bands (array 1-$nb), chain, submit, $nq parts, pieces after them, gather ($j)"

# arrays of at most TL_SLURM_ARRAY tasks (Slurm's MaxArraySize): several
# arrays a stage, the next stage after all of them
dem2vgis --band-width 512 --fill-rows 150 --part-samples 200000 \
    --plan "$T/plan-dc" "$T/dem.tif" "$T/out-dc"
rm -f "$T/bin/jobs" "$T/bin/failed"
TL_SLURM_ARRAY=4 SBATCH_OPTS='' PATH=$T/bin:$PATH sh "$T/plan-dc/slurm.sh" \
    >"$T/dry.out" 2>&1 && diff -r "$T/ref" "$T/out-dc" >/dev/null
ok $? "dry run, arrays of at most 4 tasks: the pyramid byte for byte"
# per array stage: arrays, tasks, the largest array; the pieces' arrays
# wait for every parts' array
awk '{ n[$2]++; t[$2] += $4; if ($4 > m[$2]) m[$2] = $4 }
    END { split("fill1 fill2 bands parts pieces", s, " ")
    for (i = 1; i <= 5; i++) printf "%s %d %d %d;", s[i], n[s[i]], t[s[i]], m[s[i]] }' \
    "$T/bin/jobs" >"$T/arrays"
nq=$(wc -l <"$T/plan-dc/done/parts") np=$(wc -l <"$T/plan-dc/done/targets")
nb=$(wc -l <"$T/plan-dc/bands/targets")
want="fill1 1 3 3;fill2 1 3 3;bands 2 $nb 4;parts $(((nq + 3) / 4)) $nq 4;pieces $(((np + 3) / 4)) $np 4;"
qids=$(awk '$2 == "parts" { printf "%s%s", s, $1; s = ":" }' "$T/bin/jobs")
pdeps=$(awk '$2 == "pieces" { print $3 }' "$T/bin/jobs" | sort -u)
[ "$(cat "$T/arrays")" = "$want" ] && [ "$pdeps" = "$qids" ]
ok $? "dry run, arrays of at most 4: $(cat "$T/arrays") each pieces' array after every parts' array ($pdeps)"

# --- a real cluster of one node ----------------------------------------
slurm_start; s=$?
if [ $s -eq 1 ]; then
	ok 0 "Slurm (one-node cluster on localhost) # SKIP $why"
	done_testing; exit
fi
[ $s -eq 0 ] || { done_testing; exit; }

# the plan again, and the failing plan, both submitted at once
rm -rf "$P" "$O" "$T/plan-f" "$T/out-f" "$T/gone.tif"
dem2vgis --plan "$P" "$T/dem.tif" "$O" &&
    cp "$T/dem.tif" "$T/gone.tif" &&
    dem2vgis --plan "$T/plan-f" "$T/gone.tif" "$T/out-f" &&
    rm "$T/gone.tif"
ok $? "the plans (one with its DEM gone)"
start=$(date +%s)
SBATCH_OPTS='' sh "$P/slurm.sh" >"$T/sb.out" 2>&1 &&
    SBATCH_OPTS='-p test -t 5' sh "$T/plan-f/slurm.sh" >"$T/sbf.out" 2>&1
ok $? "slurm.sh submits (SBATCH_OPTS empty; '-p test -t 5')"
drained 300; ok $? "the queue drained ($(($(date +%s) - start)) s)"
[ -z "$(timeout 10 squeue -h 2>&1)" ] || timeout 10 squeue 2>&1 | sed 's/^/#   /'
diff -r "$T/ref" "$O" >/dev/null
ok $? "Slurm (one-node cluster on localhost): the pyramid byte for byte"

# every job through Slurm: scontrol knows them (MinJobAge 3600 s)
scontrol -o show job >"$T/jobs" 2>&1
n=$(wc -l <"$P/done/targets")
# st NAME: the states of the jobs named NAME, "COUNT STATE" a line
st() {
	sed -n "s/.* JobName=$1 .* JobState=\([A-Z_]*\) .*/\1/p" "$T/jobs" |
	    sort | uniq -c | awk '{ print $1, $2 }'
}
bad=0
[ "$(st chain)" = "$(printf '1 COMPLETED\n1 FAILED')" ]; s=$?
ok $s "two chains: one completed, one failed"; bad=$((bad + s))
[ "$(st submit)" = "$(printf '1 CANCELLED\n1 COMPLETED')" ] &&
    grep -q 'JobName=submit .*JobState=CANCELLED Reason=DependencyNeverSatisfied' "$T/jobs"
s=$?; ok $s "the failing plan's next job cancelled, not left pending"
bad=$((bad + s))
[ "$(st pieces)" = "$n COMPLETED" ] && [ "$(st gather)" = "1 COMPLETED" ] &&
    [ "$(ls "$P" | grep -c '^slurm-[0-9]*_[0-9]*\.out$')" -eq "$n" ] &&
    [ "$(ls "$P" | grep -c '^slurm-[0-9]*\.out$')" -eq 3 ]
s=$?; ok $s "an array of $n pieces, then the gather: all completed, an output file each"
bad=$((bad + s))
[ ! -e "$T/out-f" ] && grep -q 'gone.tif' "$T"/plan-f/slurm-*.out
ok $? "the failing plan: no pyramid, the error in its chain's output"
grep -q 'JobName=chain .*JobState=FAILED.* TimeLimit=00:05:00' "$T/jobs"
s=$?; ok $s "SBATCH_OPTS reached sbatch (-t 5: TimeLimit=00:05:00)"
bad=$((bad + s))
[ $bad -eq 0 ] || sed 's/^/#   /' "$T/jobs"

# the chain in column bands: the fill, the bands as an array after it,
# the rest of the chain after them
dem2vgis --band-width 512 --fill-rows 150 --part-samples 200000 \
    --plan "$T/plan-b" "$T/dem.tif" "$T/out-b"
nb=$(wc -l <"$T/plan-b/bands/targets")
SBATCH_OPTS='' sh "$T/plan-b/slurm.sh" >"$T/sbb.out" 2>&1
ok $? "slurm.sh of a plan in $nb bands submits"
drained 300; ok $? "the queue drained"
diff -r "$T/ref" "$T/out-b" >/dev/null
ok $? "Slurm, in bands: the pyramid byte for byte"
nq=$(wc -l <"$T/plan-b/done/parts")
scontrol -o show job >"$T/jobs" 2>&1
[ "$(st fill1)" = "3 COMPLETED" ] && [ "$(st join)" = "1 COMPLETED" ] &&
    [ "$(st fill2)" = "3 COMPLETED" ] &&
    [ "$(st fill)" = "1 COMPLETED" ] && [ "$(st bands)" = "$nb COMPLETED" ] &&
    [ "$(st chain)" = "$(printf '2 COMPLETED\n1 FAILED')" ] &&
    [ "$(st parts)" = "$nq COMPLETED" ]
s=$?; ok $s "the fill's arrays of 3 and its join and commit, an array of $nb bands, the chain, an array of $nq parts of pieces: all completed"
[ $s -eq 0 ] || sed 's/^/#   /' "$T/jobs"

stop
! alive; ok $? "the cluster stopped: no daemon, no job left"
done_testing
