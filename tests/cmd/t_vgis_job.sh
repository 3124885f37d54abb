# t_vgis_job - vgis-job, the one program of a plan's inner steps: each
# step gives what the filter it stands for gives, byte for byte (the
# fill's windows as the DEM's, the chain as dem2vgis -M, the pieces,
# parts and gather as tilepack's pyramid); the stamp fails a changed DEM;
# the guard refuses an output over the DEM; a plan's jobs call vgis-job
# only; and the filters a person scripts refuse the plan's options.
. "$(dirname "$0")/../lib.sh"
PATH=$B:$PATH

gdal_translate -q -srcwin 2600 2900 700 300 "$DATA/N48W125.hgt" "$T/dem.tif"
dem2fqm -II "$T/dem.tif" | grep -q "^voids [1-9]"
ok $? "a 700x300 crop of N48W125, with voids"
d=$T/dem.tif

# the program and its steps
fails "no step: usage" 2 "^usage: vgis-job " vgis-job
fails "an unknown step" 2 "^vgis-job: bogus: no such step" vgis-job bogus x
vgis-job --help >"$T/help" && for s in stamp check-stamp guard fill level0 \
    filter solve chain pieces piece part gather; do
	grep -q "^ *\(usage: \)\{0,1\}vgis-job $s " "$T/help" || echo "$s"
done >"$T/missing"
[ ! -s "$T/missing" ]; ok $? "--help lists every step ($(tr '\n' ' ' <"$T/missing"))"
vgis-job fill --help | grep -q "^usage: vgis-job fill .*" &&
    vgis-job fill --help | grep -q "^  -N nodata "
ok $? "a step's --help: its usage and the DEM options' lines"
fails "a step's bad option" 2 "^vgis-job level0: invalid option" \
    vgis-job level0 -Q "$d"

# stamp, check-stamp
cp "$d" "$T/s.tif"
vgis-job stamp "$T/s.stamp" "$T/s.tif" && vgis-job check-stamp "$T/s.stamp"
ok $? "stamp, then check-stamp of the same DEM: 0"
touch -d '2001-01-01' "$T/s.tif"
fails "check-stamp of a changed DEM: 1, saying to write the plan again" 1 \
    "^vgis-job check-stamp: .*s\.tif.*write the plan again" \
    vgis-job check-stamp "$T/s.stamp"

# guard
mkdir "$T/D" && cp "$d" "$T/D/dem.tif"
fails "guard: a path holding the DEM" 1 "D: contains the input DEM" \
    vgis-job guard "$T/D/dem.tif" "$T/D"
run "guard: a path apart" vgis-job guard "$T/D/dem.tif" "$T/apart"

# level0, fill: level 0 as dem2fqm's; its windows from the filled DEM
dem2fqm "$d" "$T/l0.fqm" && vgis-job level0 "$d" "$T/j0.fqm" &&
    cmp -s "$T/l0.fqm" "$T/j0.fqm"
ok $? "level0: dem2fqm's bytes"
vgis-job fill "$d" "$T/f.dem" &&
    vgis-job level0 -w 200,500 "$d" "$T/w1.fqm" &&
    vgis-job level0 -F "$T/f.dem" -w 200,500 "$d" "$T/w2.fqm" &&
    cmp -s "$T/w1.fqm" "$T/w2.fqm" && ! cmp -s "$T/w1.fqm" "$T/l0.fqm"
ok $? "fill, then level0 -F -w: the DEM's own window"
fails "level0 -w past the DEM" 1 "-w 600,800: not 3 or more of the DEM's 700" \
    vgis-job level0 -w 600,800 "$d" "$T/x.fqm"

# filter, solve: the filters' bytes without -C
fqmfilter "$T/l0.fqm" "$T/l1.fqm" && vgis-job filter "$T/l0.fqm" "$T/j1.fqm" &&
    cmp -s "$T/l1.fqm" "$T/j1.fqm" && fqmsolve "$T/l1.fqm" "$T/v1.fqm" &&
    vgis-job solve "$T/l1.fqm" "$T/jv1.fqm" && cmp -s "$T/v1.fqm" "$T/jv1.fqm"
ok $? "filter, solve: fqmfilter's and fqmsolve's bytes"
vgis-job solve -C 10,60 "$T/l1.fqm" "$T/c.fqm" &&
    [ "$(rsinfo "$T/c.fqm" | sed -n 's/^size //p')" = "50 151" ]
ok $? "solve -C 10,60: 50 columns ($(rsinfo "$T/c.fqm" | sed -n 's/^size //p'))"

# chain, pieces, parts, gather: dem2vgis -M's maps, dem2vgis's pyramid
dem2vgis -q "$d" "$T/ref" && dem2vgis -M "$d" "$T/vm" &&
    vgis-job chain "$d" "$T/jvm" && diff -r "$T/vm" "$T/jvm" >/dev/null
ok $? "chain: dem2vgis -M's vertex maps"
vm=$(ls "$T/jvm"/v*.fqm | sort -V)
# shellcheck disable=SC2086
vgis-job pieces -b 20000 "$d" $vm >"$T/jobs" &&
    grep -qE '(:.*){4}' "$T/jobs"
ok $? "pieces -b 20000: $(wc -l <"$T/jobs") jobs, parts among them"
st=0
while read -r p; do
	case $p in *:*:*:*:*) s=part ;; *) s=piece ;; esac
	# shellcheck disable=SC2086
	vgis-job $s -b 20000 "$p" "$d" "$T/work" $vm || st=1
done <"$T/jobs"
# shellcheck disable=SC2086
[ $st -eq 0 ] && vgis-job gather "$T/work" "$d" "$T/gathered" $vm &&
    diff -r "$T/ref" "$T/gathered" >/dev/null
ok $? "part, piece, gather: dem2vgis's pyramid, byte for byte"
first=$(grep -vE '(:.*){4}' "$T/jobs" | head -1)
# shellcheck disable=SC2086
fails "part given a piece's name" 2 "not a part" \
    vgis-job part "$first" "$d" "$T/work2" $vm

# a plan calls vgis-job for every step
dem2vgis --plan "$T/plan" --band-width 256 --fill-rows 100 "$d" "$T/pp" &&
    grep '^	' "$T/plan/Makefile" |
    grep -v '^	$(JOB) $@ \(env TMPDIR=. \)\{0,1\}\(sh mkpieces \)\{0,1\}$(B)/vgis-job ' >"$T/other"
[ ! -s "$T/other" ] && grep -q '"$b/vgis-job" check-stamp dem.stamp' "$T/plan/job"
ok $? "the plan's jobs are vgis-job steps ($(head -c 100 "$T/other"))"

# the filters a person scripts carry no plan option
for c in "dem2fqm -W f" "dem2fqm -F f" "dem2fqm -w 0,9" "dem2fqm --stamp f" \
    "dem2fqm --guard g" "dem2fqm --fill-pass 1" "fqmfilter -C 0,9" \
    "fqmsolve -C 0,9" "dem2vgis --check-stamp f" "dem2vgis --from f" \
    "dem2vgis --fill f"; do
	# shellcheck disable=SC2086
	$c "$d" "$T/none" >/dev/null 2>&1
	[ $? -eq 2 ] && [ ! -e "$T/none" ]; ok $? "$c: a usage error"
done
done_testing
