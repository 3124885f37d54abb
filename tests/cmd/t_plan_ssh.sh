# t_plan_ssh - dem2vgis --plan's parallel.sh over ssh, the README's way
# (PARALLEL='--sshloginfile hosts -j N'): an sshd of the test's own on
# 127.0.0.1 (its host keys, config, authorized key, pid and log in $T;
# the system's /etc/ssh untouched, no system sshd needed), a client key
# made here, GNU parallel running every job through it; the pyramid byte
# for byte the one dem2vgis builds in one run. That the jobs really went
# through ssh: sshd's SetEnv puts a make in PATH that logs its targets,
# which only the sessions of this sshd see. Needs root (sshd's privilege
# separation) and openssh-server; else a skip.
. "$(dirname "$0")/../lib.sh"
PATH=$B:$PATH
SSHD=/usr/sbin/sshd

skip() { ok 0 "GNU parallel over ssh # SKIP $1"; done_testing; exit; }
[ "$(id -u)" -eq 0 ] || skip "not root (sshd needs it)"
[ -x "$SSHD" ] || skip "no $SSHD (openssh-server)"
for c in ssh ssh-keygen parallel make; do
	command -v "$c" >/dev/null || skip "no $c"
done
case $T in *[!A-Za-z0-9/._-]*) skip "\$T ($T) has characters an sshlogin cannot carry" ;; esac

sshd_pid=
stop_sshd() {
	[ -n "$sshd_pid" ] || return 0
	/bin/kill -TERM "$sshd_pid" 2>/dev/null
	i=0	# its children (the sessions) end with the connections
	while [ $i -lt 100 ] && /bin/kill -0 "$sshd_pid" 2>/dev/null; do
		sleep 0.05; i=$((i + 1))
	done
	/bin/kill -KILL "$sshd_pid" 2>/dev/null
	wait "$sshd_pid" 2>/dev/null
	sshd_pid=
}
trap 'stop_sshd; rm -rf "$T"' EXIT
trap 'exit 129' HUP
trap 'exit 130' INT
trap 'exit 143' TERM

# Keys: the host's and the client's, throwaway, in $T.
ssh-keygen -q -t ed25519 -N '' -C tl-host -f "$T/host_key" &&
    ssh-keygen -q -t ed25519 -N '' -C tl-client -f "$T/id" &&
    cp "$T/id.pub" "$T/authorized_keys"
ok $? "a host key and a client key made in \$T"

# The remote jobs' make: logs its arguments (the job's target), then the
# real make. In PATH only for the sessions of this sshd (SetEnv).
mkdir "$T/rbin"
printf '#!/bin/sh\necho "$*" >>%s/remote.log\nexec %s "$@"\n' \
    "$T" "$(command -v make)" >"$T/rbin/make"
chmod +x "$T/rbin/make"

# sshd on a free port of 127.0.0.1: a few tried from a range until one
# listens (sshd exits when it cannot bind).
mkdir -p /run/sshd	# its privilege separation directory
# The sessions' environment (SetEnv: one line, every NAME=VALUE on it):
# the logging make first in PATH, and the sanitizers' options of make
# check-asan, which GNU parallel does not carry to a remote job.
env="\"PATH=$T/rbin:/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin\""
for v in ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
	eval "x=\${$v:-}"
	[ -n "$x" ] && env="$env \"$v=$x\""
done
base=$((20000 + $$ % 20000))
port=
for try in 0 1 2 3 4 5 6 7 8 9; do
	p=$((base + try * 7))
	cat >"$T/sshd_config" <<EOF
Port $p
ListenAddress 127.0.0.1
HostKey $T/host_key
PidFile $T/sshd.pid
AuthorizedKeysFile $T/authorized_keys
PermitRootLogin prohibit-password
PubkeyAuthentication yes
PasswordAuthentication no
KbdInteractiveAuthentication no
UsePAM no
StrictModes no
X11Forwarding no
AllowTcpForwarding no
PrintMotd no
LogLevel VERBOSE
MaxStartups 100
MaxSessions 100
SetEnv $env
EOF
	: >"$T/sshd.log"
	"$SSHD" -D -f "$T/sshd_config" -E "$T/sshd.log" & sshd_pid=$!
	i=0	# up to 30 s: listening, or gone
	while [ $i -lt 600 ]; do
		grep -q "Server listening on 127.0.0.1 port $p" "$T/sshd.log" &&
		    { port=$p; break 2; }
		/bin/kill -0 "$sshd_pid" 2>/dev/null || break
		sleep 0.05; i=$((i + 1))
	done
	stop_sshd
done
[ -n "$port" ]; ok $? "sshd of the test's own listening on 127.0.0.1:${port:-none}"
[ -n "$port" ] || { sed 's/^/#   /' "$T/sshd.log" | tail -5; done_testing; exit; }

cat >"$T/ssh_config" <<EOF
Host *
	HostName 127.0.0.1
	Port $port
	User root
	IdentityFile $T/id
	IdentitiesOnly yes
	StrictHostKeyChecking no
	UserKnownHostsFile $T/known_hosts
	BatchMode yes
	ConnectTimeout 30
	LogLevel ERROR
EOF
# (the remote shell's startup files may put more in front: anywhere in it)
# shellcheck disable=SC2016
timeout 60 ssh -F "$T/ssh_config" tl-test \
    'echo ":$PATH:"; echo "${UBSAN_OPTIONS:-}"' >"$T/env" 2>"$T/err" &&
    sed -n 1p "$T/env" | grep -q ":$T/rbin:" &&
    [ "$(sed -n 2p "$T/env")" = "${UBSAN_OPTIONS:-}" ]
s=$?; [ $s -eq 0 ] || sed 's/^/#   /' "$T/err" "$T/env" | head -5
ok $s "ssh with the client key: in, with the sessions' environment"

# The crop of t_plan: two pieces at level 0 in QEM-1D.
gdal_translate -q -srcwin 1300 2900 2200 400 "$DATA/N48W125.hgt" "$T/dem.tif"
ok $? "a 2200x400 crop of N48W125"
no_tmp() { [ "$(find "$1" -name '.*.??????' | wc -l)" -eq 0 ]; }
dem2vgis -q "$T/dem.tif" "$T/ref"
ok $? "dem2vgis in one run"
dem2vgis --plan "$T/plan" --part-samples 400000 "$T/dem.tif" "$T/out"
ok $? "the plan is written (pieces in parts of rows: tilepack -b)"

# The README's form: a hosts file of sshlogins (here one machine, by the
# ssh command that reaches it; the host name is a name for ssh_config).
echo "ssh -F $T/ssh_config tl-test" >"$T/hosts"
: >"$T/remote.log"
in0=$(grep -c "Accepted publickey for root from 127.0.0.1" "$T/sshd.log")
PARALLEL="--sshloginfile $T/hosts -j 2" timeout 300 sh "$T/plan/parallel.sh" \
    >"$T/par.log" 2>&1
s=$?; [ $s -eq 0 ] || sed 's/^/#   /' "$T/par.log" | tail -5
ok $s "parallel.sh with PARALLEL='--sshloginfile hosts -j 2'"
diff -r "$T/ref" "$T/out" >/dev/null
ok $? "GNU parallel over ssh (sshd on localhost): the pyramid byte for byte"
no_tmp "$T/plan" && no_tmp "$T/out"
ok $? "no temporary left in the plan or the pyramid"

# Every job ran through ssh: each target once in the remote make's log.
n=$(wc -l <"$T/plan/done/targets") q=$(wc -l <"$T/plan/done/parts")
{ echo done/pieces.mk; cat "$T/plan/done/parts" "$T/plan/done/targets"
  echo done/gather; } | sed "s|^|-C $T/plan |" | sort >"$T/want"
sort "$T/remote.log" >"$T/got"
[ "$n" -ge 2 ] && [ "$q" -ge 2 ] && cmp -s "$T/want" "$T/got"
s=$?; [ $s -eq 0 ] || diff "$T/want" "$T/got" | head -5 | sed 's/^/#   /'
ok $s "each of the $((n + q + 2)) jobs ($n pieces, $q parts) made by a session of this sshd"
in1=$(grep -c "Accepted publickey for root from 127.0.0.1" "$T/sshd.log")
[ $((in1 - in0)) -ge $((n + q + 2)) ]
ok $? "sshd's log: $((in1 - in0)) logins by the client key for the $((n + q + 2)) jobs"

stop_sshd
! pgrep -f "$T/sshd_config" >/dev/null
ok $? "sshd stopped, none of its processes left"
done_testing
