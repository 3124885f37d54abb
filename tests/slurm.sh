# slurm.sh - a real Slurm cluster of one node for the plan tests, sourced
# after lib.sh: as root with Debian's munge, slurmctld, slurmd and
# slurm-client installed, munged, slurmctld and slurmd on 127.0.0.1,
# every file of theirs under $T/slurm, stopped at the end whatever
# happens. slurm_start: 0 once the node is idle; 1 with $why set when it
# cannot run here (the caller skips), 2 when it did not come up (shown).
# Then: up, drained SECONDS, stop, alive, and SLURM_CONF exported.
PATH=$PATH:/usr/sbin:/sbin

# fake_sbatch DIR: DIR/sbatch, a fake that runs each job at once (no
# Slurm needed)
fake_sbatch() {
cat >"$1/sbatch" <<'EOF'
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
chmod +x "$1/sbatch"
}
slurm_start() {
why=
if [ "$(id -u)" -ne 0 ]; then
	why="not root (slurmd runs the jobs here as root)"
else
	for c in mungekey munged slurmctld slurmd sbatch squeue sinfo scontrol \
	    scancel; do
		command -v $c >/dev/null || { why="no $c (Debian: munge slurmctld slurmd slurm-client)"; break; }
	done
fi
[ -z "$why" ] || return 1

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
	return 2
fi
}

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
