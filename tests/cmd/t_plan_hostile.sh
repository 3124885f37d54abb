# t_plan_hostile - dem2vgis --plan with hostile names: every shell and
# make metacharacter (space ' " $ \ ; # & | * ? ` and a leading -) in the
# plan directory, the DEM and the pyramid, each name also trying to run
# "touch PWNED". For each character, the plan's jobs get the names
# exactly (make and sh); each runner (make, GNU parallel, Slurm faked and
# the one-node Slurm of t_plan_slurm), on three groups of names that hold
# every character, builds the pyramid byte for byte the one dem2vgis
# builds; nothing is ever run from a name (no PWNED anywhere). A
# newline, which make cannot carry, is refused at --plan time, naming
# what holds it, and no plan is left. The programs' directory (TL_BIN)
# has a hostile name too.
. "$(dirname "$0")/../lib.sh"
quick_skip "hostile names through make, GNU parallel and Slurm"
. "$TOP/tests/slurm.sh"
PATH=$B:$PATH

gdal_translate -q -srcwin 0 0 257 257 "$DATA/N44W072.hgt" "$T/dem.tif"
ok $? "a 257x257 crop of N44W072"
dem2vgis -q "$T/dem.tif" "$T/ref"; ok $? "dem2vgis in one run"

# name K: the K-th hostile name (1..13), its character's description in $desc
name() {
	case $1 in
	1) desc=space n='a b' ;;
	2) desc=quote n="a';touch PWNED;'" ;;
	3) desc=dquote n='a";touch PWNED;"' ;;
	4) desc=dollar n='a$(touch PWNED)$HOME' ;;
	5) desc=backslash n='a\b\' ;;
	6) desc=semicolon n='a;touch PWNED;' ;;
	7) desc=hash n='a#b\#c' ;;
	8) desc=ampersand n='a&touch PWNED&' ;;
	9) desc=pipe n='a|touch PWNED|' ;;
	10) desc=star n='a*' ;;
	11) desc=question n='a?' ;;
	12) desc=backtick n='a`touch PWNED`' ;;
	13) desc=dash n='-a' ;;
	esac
}
# the three groups: every character in one of them, each a name that a
# shell parsing it unquoted would run "touch PWNED" from
group() {
	case $1 in
	1) n="a b'c'\"d\";touch PWNED;" ;;
	2) n='a$(touch PWNED)\b#c&touch PWNED|touch PWNED|' ;;
	3) n='-a*?`touch PWNED`' ;;
	esac
}
# plan RUNNER NAME: in $T/RUNNER, the plan NAMEp of the DEM NAMEd.tif (a
# copy), for the pyramid NAMEo, all relative
plan() {
	mkdir -p "$T/$1" && cd "$T/$1" && cp "$T/dem.tif" "./$2d.tif" &&
	    dem2vgis --plan "$2p" -- "$2d.tif" "$2o" >"$T/plan.err" 2>&1
	_s=$?
	[ $_s -eq 0 ] || sed 's/^/#   /' "$T/plan.err"
	return $_s
}
same() { diff -r "$T/ref" "$1" >/dev/null; }

# --- each character: the names as make and sh give them to the jobs ----
# (a rule added to the plan's Makefile prints them through the shell)
# (a file, not make -f -: GNU make 4.3 leaves its copy of stdin in /tmp)
printf 'show:\n\t@printf "[%%s]\\n" $(DEM) $(OUT)\n' >"$T/show.mk"
k=1
while [ $k -le 13 ]; do
	name $k
	plan each "$n" &&
	    make -s -C "./${n}p" -f Makefile -f "$T/show.mk" show >"$T/names" 2>&1 &&
	    printf '[%s]\n' "$T/each/${n}d.tif" "$T/each/${n}o" |
	    cmp -s - "$T/names"
	s=$?
	[ $s -eq 0 ] || sed 's/^/#   /' "$T/names"
	ok $s "$desc in every name ($n): make and sh give the jobs the names"
	k=$((k + 1))
done
cd "$T/each" && grep -q '\\\\\\#' "./a#b\\#cp/Makefile"
ok $? "a '#' after a backslash escaped as make reads it (\\\\\\#)"

# --- each runner: every character in three groups ----------------------
# (the programs too, from a directory with a hostile name: TL_BIN)
mkdir -p "$T/bin" && fake_sbatch "$T/bin"
TL_BIN=$T/'b d;touch PWNED;#$x' && ln -s "$B" "$TL_BIN"
ok $? "the programs from a directory named $TL_BIN"
for g in 1 2 3; do
	group $g
	plan make "$n" && make -s -C "./${n}p" -j2 >"$T/log" 2>&1 &&
	    same "./${n}o"
	s=$?
	[ $s -eq 0 ] || tail -3 "$T/log" | sed 's/^/#   /'
	ok $s "make, group $g ($n): the pyramid byte for byte"
	if command -v parallel >/dev/null; then
		plan par "$n" && PARALLEL=-j2 sh "./${n}p/parallel.sh" \
		    >"$T/log" 2>&1 && same "./${n}o"
		s=$?
		[ $s -eq 0 ] || tail -3 "$T/log" | sed 's/^/#   /'
		ok $s "GNU parallel, group $g ($n): the pyramid byte for byte"
	else
		ok 0 "GNU parallel, group $g # SKIP not installed"
	fi
	plan dry "$n" && SBATCH_OPTS='' PATH=$T/bin:$PATH \
	    sh "./${n}p/slurm.sh" >"$T/log" 2>&1 && same "./${n}o"
	s=$?
	[ $s -eq 0 ] || tail -3 "$T/log" | sed 's/^/#   /'
	ok $s "Slurm faked, group $g ($n): the pyramid byte for byte"
done

cd "$T/make" &&
    [ "$(grep -lF "B = '$T/b d;touch PWNED;\\#\$\$x'" ./*p/Makefile | wc -l)" -eq 3 ]
ok $? "the plans ran the programs from there (B in each Makefile)"

# a mosaic of two tiles with such names (the plan's list, dems.txt)
group 2
mkdir -p "$T/mosaic" && cd "$T/mosaic" &&
    gdal_translate -q -srcwin 0 0 128 257 "$T/dem.tif" "./${n}w.tif" &&
    gdal_translate -q -srcwin 128 0 129 257 "$T/dem.tif" "./${n}e.tif" &&
    dem2vgis -q -- "${n}w.tif" "${n}e.tif" ref &&
    dem2vgis --plan "${n}p" -- "${n}w.tif" "${n}e.tif" "${n}o" &&
    make -s -C "./${n}p" >"$T/log" 2>&1 && diff -r ref "./${n}o" >/dev/null
ok $? "make, a mosaic of two tiles named $n: the pyramid byte for byte"

# --- a newline: refused at once, naming what holds it ------------------
nl='
'
cd "$T" && cp dem.tif "d${nl}x.tif"
fails "a newline in the plan directory: refused" 1 \
    "plan directory .*p.nx: a newline cannot go into a plan" \
    dem2vgis --plan "p${nl}x" dem.tif o
fails "a newline in the DEM's name: refused" 1 \
    "the DEM .*d.nx.tif: a newline cannot go into a plan" \
    dem2vgis --plan p "d${nl}x.tif" o
fails "a newline in a DEM's name, of several: refused" 1 \
    "x.tif: a name holding a newline" \
    dem2vgis --plan p dem.tif "d${nl}x.tif" o
fails "a newline in the pyramid's name: refused" 1 \
    "the pyramid .*o.nx: a newline cannot go into a plan" \
    dem2vgis --plan p dem.tif "o${nl}x"
fails "a newline in an option (-n): refused" 1 \
    "the option a.nb: a newline" dem2vgis --plan p -n "a${nl}b" dem.tif o
[ ! -e p ] && [ ! -e "p${nl}x" ] && [ "$(ls -a | grep -c '^\.p')" -eq 0 ]
ok $? "a refused plan leaves nothing"

# --- the one-node Slurm cluster of t_plan_slurm ------------------------
slurm_start; s=$?
if [ $s -eq 1 ]; then
	ok 0 "Slurm (one-node cluster on localhost) # SKIP $why"
elif [ $s -eq 0 ]; then
	for g in 1 2 3; do
		group $g
		plan slurm "$n" && SBATCH_OPTS='' sh "./${n}p/slurm.sh" \
		    >"$T/log-$g" 2>&1
		ok $? "Slurm, group $g ($n): submitted"
	done
	drained 300; ok $? "the queue drained"
	for g in 1 2 3; do
		group $g
		cd "$T/slurm" && same "./${n}o"
		ok $? "Slurm, group $g ($n): the pyramid byte for byte"
	done
	stop
fi

found=$(find "$T" / -maxdepth 1 -name PWNED 2>/dev/null; find "$T" -name PWNED)
[ -z "$found" ]; ok $? "nothing run from a name: no PWNED ($found)"
done_testing
