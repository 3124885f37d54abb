# lib.sh - shared helpers for the shell tests in tests/*/ (sourced). TAP
# lines on stdout.
set -u
# the tests run make themselves (plans): not as jobs of the make that runs
# the suite, whose jobserver they would not reach (make -j check)
unset MAKEFLAGS MFLAGS MAKELEVEL
TOP=$(cd "$(dirname "$0")/../.." && pwd)
# the build to test: build/, or another (TL_BUILD=build-x, e.g. make B=build-x)
B=$(cd "$TOP" && cd "${TL_BUILD:-build}" && pwd)
TL_BIN=$B	# dem2vgis runs this build's programs
export TL_BIN
DATA=${DATA:-$TOP/../shared/data}
PATH="$B:$B/tools:$PATH"
TL_OIIO_PLUGIN=$B/tl_oiio.so	# for the tools in build/tools
export PATH TL_OIIO_PLUGIN
T=$(mktemp -d "${TMPDIR:-/tmp}/tltest.XXXXXX")
trap 'rm -rf "$T"' EXIT
_n=0
_failed=0

ok() {	# ok CONDITION-EXIT-STATUS DESCRIPTION
	_n=$((_n + 1))
	if [ "$1" -eq 0 ]; then echo "ok $_n - $2"
	else echo "not ok $_n - $2"; _failed=$((_failed + 1)); fi
}

# run DESCRIPTION CMD...: passes when CMD exits 0.
run() {
	_d=$1; shift
	"$@" >"$T/out" 2>"$T/err"; _s=$?
	[ $_s -eq 0 ] || sed 's/^/#   /' "$T/err" | head -5
	ok $_s "$_d"
	return $_s
}

# fails DESCRIPTION STATUS PATTERN CMD...: CMD exits STATUS and its stderr
# matches the extended regex PATTERN.
fails() {
	_d=$1; _want=$2; _pat=$3; shift 3
	"$@" >"$T/out" 2>"$T/err"; _s=$?
	if [ $_s -eq "$_want" ] && grep -Eq -- "$_pat" "$T/err"; then ok 0 "$_d"
	else echo "#   exit $_s, stderr: $(head -c 300 "$T/err")"; ok 1 "$_d"; fi
}

# TL_QUICK=1 (make check-asan, whose build runs several times slower):
# big NAME is true for the largest DEM (N48W125, 13 M samples), which the
# heaviest tests then leave out; every other DEM and every check runs.
big() {
	[ -n "${TL_QUICK:-}" ] || return 1
	case $1 in *N48W125*|n48*) return 0 ;; esac
	return 1
}

# browser_test NAME: a test of a browser (CesiumJS in Chromium) goes on
# only where node and chromium are, and not under TL_QUICK: the browser,
# not our code, is what such a test spends its minutes in, and the
# programs it runs are run under the sanitizers by the other tests.
browser_test() {
	if ! command -v node >/dev/null || [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ]; then
		ok 0 "$1 # SKIP no node or no chromium (scripts/install-deps)"
	elif [ -n "${TL_QUICK:-}" ]; then
		ok 0 "$1 # SKIP under the sanitizers (make check runs it)"
	else
		return 0
	fi
	done_testing
	exit
}

# quick_skip WHAT: under TL_QUICK (the sanitizer run) a test whose
# subject is no code path of ours that the other tests leave out (a
# plan's jobs through make, GNU parallel and Slurm run the steps that
# t_vgis_job and the programs' tests run under the sanitizers; static
# checks of the sources and the archives; two routes giving the same
# bytes, both run by other tests) ends here; make check runs it.
quick_skip() {
	[ -n "${TL_QUICK:-}" ] || return 0
	ok 0 "# SKIP under the sanitizers: $1 (make check runs it)"
	done_testing
	exit
}

# mid_run PID OUT: waits until PID's temporary for OUT (.NAME.XXXXXX in
# OUT's directory; a tree's with its .lock) is there, then stops PID; 0
# when PID is then stopped before its rename (the caller sends its
# signal, then CONT), 1 when the run ended first: a signal then tests
# nothing (a fast machine). A fixed sleep before the kill raced the
# run's end (CI, stop 30).
mid_run() {
	_md=$(dirname "$2") _mb=$(basename "$2") _mi=0
	while [ $_mi -lt 3000 ] && [ ! -e "$2" ]; do
		_mt=$(ls -A "$_md" | grep "^\.$_mb\.......\$" | head -1)
		# a tree's temporary once it holds its lock file: before
		# that a killed run's is swept only a minute later (sweep.c)
		if [ -n "$_mt" ] && { [ ! -d "$_md/$_mt" ] ||
		    [ -e "$_md/$_mt/.lock" ]; }; then
			kill -STOP "$1" 2>/dev/null || return 1
			[ ! -e "$2" ] && return 0
			kill -CONT "$1"; return 1
		fi
		sleep 0.01; _mi=$((_mi + 1))
	done
	return 1
}

# skip DESCRIPTION: a check that could not be made this time
skip() {
	echo "ok $((_n + 1)) - # SKIP $1"
	_n=$((_n + 1))
}

done_testing() {
	echo "1..$_n"
	[ $_failed -eq 0 ]
}
