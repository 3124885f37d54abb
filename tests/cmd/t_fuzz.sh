# t_fuzz - every fuzz target (tests/fuzz/fz_*.c) replayed, on this build,
# over its seeds (made from ../shared/data) and its regression inputs
# (tests/fuzz/regress/TARGET: what fuzzing found, each once a crash, a
# hang or an allocation out of all proportion). make fuzz runs them under
# libFuzzer; here they must simply all end, without a crash.
. "$(dirname "$0")/../lib.sh"

if ! sh "$TOP/tests/fuzz/seeds" "$B" "$T/seeds" >"$T/seeds.log" 2>&1; then
	sed 's/^/#   /' "$T/seeds.log" | head -5
	ok 1 "seeds made from ../shared/data"
	done_testing; exit 1
fi
# the targets' scratch (fuzz.c: $TMPDIR/tlfuzz.*, kept for the process's
# life, as libFuzzer needs) in $T, not left in /tmp
mkdir "$T/tmp" && TMPDIR=$T/tmp && export TMPDIR
for f in "$TOP"/tests/fuzz/fz_*.c; do
	t=$(basename "$f" .c); t=${t#fz_}
	set -- "$T/seeds/$t"/* "$TOP/tests/fuzz/regress/$t"/*
	n=0; for x in "$@"; do [ -f "$x" ] && n=$((n + 1)); done
	[ $n -gt 0 ] || { ok 1 "fuzz target $t has inputs"; continue; }
	# an allocation out of proportion fails here as in libFuzzer (not
	# under AddressSanitizer, whose shadow memory is virtual)
	( [ -n "${ASAN_OPTIONS:-}" ] || ulimit -v 4000000 2>/dev/null; "$B/tests/fuzz/fz_$t" $(for x in "$@"; do [ -f "$x" ] && echo "$x"; done) ) \
	    >"$T/$t.out" 2>&1
	s=$?
	[ $s -eq 0 ] || tail -3 "$T/$t.out" | sed 's/^/#   /'
	ok $s "fuzz target $t: $n seed and regression inputs replayed, no crash"
done
done_testing
