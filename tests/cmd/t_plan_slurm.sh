# t_plan_slurm - dem2vgis --plan's slurm.sh run, the pyramid byte for byte
# the one dem2vgis builds in one run: first by a fake sbatch that runs each
# job at once, in order (no Slurm needed); then, as root with Debian's
# munge and slurmctld, slurmd, slurm-client installed, on a real Slurm
# cluster of one node started here (munged, slurmctld, slurmd on
# 127.0.0.1, every file of theirs under $T, stopped at the end whatever
# happens). A plan whose first job fails: the jobs after it are cancelled,
# none left pending; submitted again once the DEM is back, it finishes.
. "$(dirname "$0")/../lib.sh"
PATH=$B:$PATH:/usr/sbin:/sbin

gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" "$T/dem.tif"
ok $? "a 2200x400 crop of N48W125"
dem2vgis -q "$T/dem.tif" "$T/ref"; ok $? "dem2vgis in one run"

# --- dry run: sbatch faked ---------------------------------------------
mkdir "$T/bin"
cat >"$T/bin/sbatch" <<'EOF'
#!/bin/sh
# sbatch, faked: the job runs now, to its end (an array's tasks one after
# the other), its output in DIR/slurm-ID.out (slurm-ID_I.out) as Slurm
# names it; a job whose afterok dependency failed is not run. Each call a
# line "ID NAME DEPENDENCY ARRAY" in jobs beside this file.
d=$(cd "$(dirname "$0")" && pwd)
id=$(($(cat "$d/n" 2>/dev/null || echo 0) + 1)); echo "$id" >"$d/n"
name=- dir=. dep= arr= wrap=
while [ $# -gt 0 ]; do
	case $1 in
	--parsable|--kill-on-invalid-dep=yes) ;;
	-p|-t) shift ;;
	-J) name=$2; shift ;;
	-D) dir=$2; shift ;;
	--dependency=afterok:*) dep=${1#--dependency=afterok:} ;;
	--array=1-*) arr=${1#--array=1-} ;;
	--wrap) wrap=$2; shift ;;
	*) echo "sbatch (fake): $1: not known" >&2; exit 1 ;;
	esac
	shift
done
echo "$id $name ${dep:--} ${arr:--}" >>"$d/jobs"
echo "$id"
bad=0
for x in $(echo "$dep" | tr : ' '); do
	grep -qx "$x" "$d/failed" 2>/dev/null && bad=1
done
cd "$dir" || exit 1
if [ $bad -eq 0 ] && [ -n "$arr" ]; then
	i=1
	while [ $i -le "$arr" ]; do
		SLURM_JOB_ID=$id SLURM_ARRAY_TASK_ID=$i sh -c "$wrap" \
		    >"slurm-${id}_$i.out" 2>&1 || bad=1
		i=$((i + 1))
	done
elif [ $bad -eq 0 ]; then
	SLURM_JOB_ID=$id sh -c "$wrap" >"slurm-$id.out" 2>&1 || bad=1
fi
[ $bad -eq 0 ] || echo "$id" >>"$d/failed"
exit 0
EOF
chmod +x "$T/bin/sbatch"

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
rm "$T/gone.tif" "$T/bin/jobs" "$T/bin/n"
SBATCH_OPTS='-p test -t 5' PATH=$T/bin:$PATH sh "$T/plan-f/slurm.sh" \
    >/dev/null 2>&1 && [ ! -e "$T/out-f" ] &&
    [ "$(cut -d' ' -f2 "$T/bin/jobs" | tr '\n' ' ')" = "chain submit " ] &&
    grep -q 'gone.tif' "$T/plan-f/slurm-1.out"
ok $? "dry run, the chain failing: the rest not run, the error in slurm-1.out"
cp "$T/dem.tif" "$T/gone.tif"
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
why=
if [ "$(id -u)" -ne 0 ]; then
	why="not root (slurmd runs the jobs here as root)"
else
	for c in mungekey munged slurmctld slurmd sbatch squeue sinfo scontrol \
	    scancel; do
		command -v $c >/dev/null || { why="no $c (Debian: munge slurmctld slurmd slurm-client)"; break; }
	done
fi
if [ -n "$why" ]; then
	ok 0 "Slurm (one-node cluster on localhost) # SKIP $why"
	done_testing; exit
fi

S=$T/slurm
SLURM_CONF=$S/slurm.conf
export SLURM_CONF
pids=	# the daemons started: munged, slurmctld, slurmd
cpid= dpid=
# the processes of our jobs: their scripts are in our spool
strays() {
	grep -l "$S/spoo[l]/job" /proc/[0-9]*/cmdline 2>/dev/null | cut -d/ -f3
}
alive() {
	for p in $pids $(strays); do kill -0 "$p" 2>/dev/null && return 0; done
	return 1
}
# stop the cluster: its jobs cancelled, then the daemons (TERM, then KILL)
stop() {
	[ -n "$pids" ] || return 0
	kill -0 "$cpid" 2>/dev/null && timeout 20 scancel -u root >/dev/null 2>&1
	i=0
	while [ $i -lt 100 ] && [ -n "$(strays)" ]; do sleep 0.2; i=$((i + 1)); done
	/bin/kill -TERM $pids 2>/dev/null
	i=0
	while [ $i -lt 100 ] && alive; do sleep 0.2; i=$((i + 1)); done
	for p in $(strays); do
		/bin/kill -KILL -- "-$(ps -o pgid= -p "$p" | tr -d ' ')" 2>/dev/null
	done
	/bin/kill -KILL $pids 2>/dev/null
	wait
	pids=
}
trap 'stop; rm -rf "$T"' EXIT
trap 'exit 129' HUP
trap 'exit 130' INT
trap 'exit 143' TERM

# the TCP ports listened on, 4 hex digits each
listening() {
	awk '$4 == "0A" { split($2, a, ":"); print a[2] }' /proc/net/tcp \
	    /proc/net/tcp6 2>/dev/null
}
port=$((20000 + $$ % 20000))
while listening | grep -Eqix "$(printf '%04X|%04X' $port $((port + 1)))"; do
	port=$((port + 2))
done
mkdir -p "$S/state" "$S/spool" && mungekey -c -k "$S/munge.key"
ok $? "a munge key"
# -F: in the foreground, its log on stderr; -f: though not every directory
# up to its socket is searchable by all (mktemp's 0700), a warning only
munged -F -f --key-file="$S/munge.key" --socket="$S/munge.sock" \
    --pid-file="$S/munged.pid" --log-file="$S/munged.log" \
    --seed-file="$S/munged.seed" >"$S/munged.err" 2>&1 &
pids="$pids $!"
node=$(slurmd -C 2>/dev/null | sed -n 's/^NodeName=\([^ ]*\).*/\1/p')
[ -n "$node" ] || node=$(uname -n | cut -d. -f1)
cat >"$SLURM_CONF" <<EOF
ClusterName=tltest
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$S/munge.sock
StateSaveLocation=$S/state
SlurmdSpoolDir=$S/spool
SlurmctldPidFile=$S/slurmctld.pid
SlurmdPidFile=$S/slurmd.pid
SlurmctldLogFile=$S/slurmctld.log
SlurmdLogFile=$S/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0
MpiDefault=none
ReturnToService=2
MinJobAge=3600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
i=0
while [ $i -lt 100 ] && [ ! -S "$S/munge.sock" ]; do sleep 0.1; i=$((i + 1)); done
slurmctld -D -f "$SLURM_CONF" >"$S/slurmctld.err" 2>&1 &
cpid=$!
slurmd -D -f "$SLURM_CONF" >"$S/slurmd.err" 2>&1 &
dpid=$!
pids="$pids $cpid $dpid"
# both daemons running; a client command given 10 s at most (sinfo,
# squeue: 9 s each to fail when slurmctld is not there)
up() { kill -0 "$cpid" 2>/dev/null && kill -0 "$dpid" 2>/dev/null; }
before() { [ "$(date +%s)" -lt "$1" ]; }
end=$(($(date +%s) + 60))	# up to 60 s for the node to be idle
while up && before $end &&
    [ "$(timeout 10 sinfo -h -o %T 2>/dev/null)" != idle ]; do
	sleep 0.5
done
up && [ "$(timeout 10 sinfo -h -o %T 2>/dev/null)" = idle ]; s=$?
ok $s "a cluster of one node ($node, ports $port, $((port + 1))): idle"
if [ $s -ne 0 ]; then
	for f in munged.err slurmctld.log slurmd.log; do
		tail -5 "$S/$f" 2>/dev/null | sed "s/^/#   $f: /"
	done
	done_testing; exit
fi

# squeue empty, up to $1 s; not waiting more than 10 s once every job left
# is one that can never run (DependencyNeverSatisfied)
drained() {
	_end=$(($(date +%s) + $1)) _stuck=0
	while up && before $_end && [ $_stuck -lt 20 ]; do
		_q=$(timeout 10 squeue -h -o %r 2>&1)
		[ -n "$_q" ] || break
		if echo "$_q" | grep -qvx DependencyNeverSatisfied; then _stuck=0
		else _stuck=$((_stuck + 1)); fi
		sleep 0.5
	done
	up && [ -z "$(timeout 10 squeue -h 2>&1)" ]
}
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
