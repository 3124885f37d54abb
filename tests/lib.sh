# lib.sh - shared helpers for the shell tests (sourced). TAP lines on stdout.
set -u
TOP=$(cd "$(dirname "$0")/.." && pwd)
B="$TOP/build"
DATA=${DATA:-$TOP/../shared/data}
PATH="$B:$B/tools:$PATH"
export PATH
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
	d=$1; shift
	"$@" >"$T/out" 2>"$T/err"; s=$?
	[ $s -eq 0 ] || sed 's/^/#   /' "$T/err" | head -5
	ok $s "$d"
}

# fails DESCRIPTION STATUS PATTERN CMD...: CMD exits STATUS and its stderr
# matches the extended regex PATTERN.
fails() {
	d=$1; want=$2; pat=$3; shift 3
	"$@" >"$T/out" 2>"$T/err"; s=$?
	if [ $s -eq "$want" ] && grep -Eq -- "$pat" "$T/err"; then ok 0 "$d"
	else echo "#   exit $s, stderr: $(head -c 300 "$T/err")"; ok 1 "$d"; fi
}

done_testing() {
	echo "1..$_n"
	[ $_failed -eq 0 ]
}
