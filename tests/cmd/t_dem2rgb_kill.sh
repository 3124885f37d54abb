# t_dem2rgb_kill - a dem2rgb killed by SIGTERM or SIGINT (in the warp,
# in the chain; a tree, an archive) dies of the signal and leaves
# nothing: no OUT, no temporary beside it, no scratch directory in
# $TMPDIR; one killed by SIGKILL leaves its scratch, which the next run
# removes; a live run's scratch is not taken by another run's sweep.
. "$(dirname "$0")/../lib.sh"

gdal_translate -q -srcwin 2560 2824 513 513 "$DATA/N48W125.hgt" "$T/srtm.tif"
mkdir "$T/tmp" "$T/o"
TMPDIR=$T/tmp
export TMPDIR

# scratch: the scratch directories in $TMPDIR
scratch() {
	ls -a "$TMPDIR" | grep '^dem2rgb\.'
}

# until WHAT PID: waits (10 s at most) until the run PID has a scratch
# directory (WHAT dir) or a zoom's scratch file in it (WHAT zoom); 1 when
# the run ended first
until_has() {
	_k=0
	while [ $_k -lt 200 ] && kill -0 "$2" 2>/dev/null; do
		case $1 in
		dir) [ -n "$(scratch)" ] && return 0 ;;
		zoom) ls "$TMPDIR"/dem2rgb.*/z[0-9]* >/dev/null 2>&1 &&
		    return 0 ;;
		esac
		sleep 0.05
		_k=$((_k + 1))
	done
	return 1
}

# killed DESC SIG STATUS WHAT OUT DEM2RGB-ARGS...: the run killed by SIG
# once it has WHAT; it exits STATUS, and nothing is left
killed() {
	_d=$1 _sig=$2 _st=$3 _what=$4 _out=$5
	shift 5
	dem2rgb -q "$@" &
	_p=$!
	if until_has "$_what" $_p; then
		kill -"$_sig" $_p
		wait $_p
		ok $(($? != _st)) "$_d: dies of SIG$_sig"
		if [ ! -e "$_out" ] &&
		    [ -z "$(ls -a "$T/o" | grep -v '^\.\.\?$')" ]; then
			ok 0 "$_d: no output and no temporary left"
		else	# what was left, for the next failure's reader
			ok 1 "$_d: no output and no temporary left"
			ls -laR "$T/o" | sed 's/^/#   /'
		fi
		[ -z "$(scratch)" ]; ok $? "$_d: no scratch left in TMPDIR"
	else
		wait $_p
		for _k in 1 2 3; do
			ok 0 "$_d # SKIP the run ended before the kill"
		done
	fi
	rm -rf "$T/o"/* "$T/o"/.??* "$TMPDIR"/*
}

killed "TERM in the chain, a tree" TERM 143 zoom "$T/o/tree" \
    -j 1 "$T/srtm.tif" "$T/o/tree"
killed "INT in the chain, an archive" INT 130 zoom "$T/o/a.pmtiles" \
    -j 2 -f webp -o "$T/o/a.pmtiles" "$T/srtm.tif"
killed "TERM from the start (the warp)" TERM 143 dir "$T/o/tree" \
    -j 2 -e mapbox "$T/srtm.tif" "$T/o/tree"
killed "HUP in the chain" HUP 129 zoom "$T/o/tree" \
    -j 2 "$T/srtm.tif" "$T/o/tree"

# KILL: the scratch stays, locked by no one; the next run removes it
dem2rgb -q -j 1 "$T/srtm.tif" "$T/o/tree" &
p=$!
if until_has zoom $p; then
	kill -KILL $p
	wait $p
	[ -n "$(scratch)" ]; ok $? "KILL: the dead run's scratch is there"
	dead=$(scratch)
	run "KILL: the next run" dem2rgb -q -z 8 "$T/srtm.tif" "$T/o/next"
	[ -z "$(scratch)" ]; ok $? "KILL: the next run removed $dead"
	[ -f "$T/o/next/tiles.json" ]; ok $? "KILL: the next run's tree"
else
	wait $p
	for k in 1 2 3 4; do
		ok 0 "KILL # SKIP the run ended before the kill"
	done
fi
rm -rf "$T/o"/* "$T/o"/.??*

# a live run's scratch is not swept by another run
dem2rgb -q -j 1 "$T/srtm.tif" "$T/o/long" &
p=$!
if until_has zoom $p; then
	live=$(scratch)
	run "beside a live run" dem2rgb -q -z 6 "$T/srtm.tif" "$T/o/short"
	[ -n "$live" ] && [ -d "$TMPDIR/$live" ]
	ok $? "the live run's scratch kept"
	wait $p
	ok $? "the live run ends well"
	[ -f "$T/o/long/tiles.json" ] && [ -z "$(scratch)" ]
	ok $? "its tree made, its scratch gone"
else
	wait $p
	for k in 1 2 3 4; do
		ok 0 "live # SKIP the run ended before the other began"
	done
fi
done_testing
