# t_plane - a tilted plane (dx != dy) through the real programs and files:
# every level's QEM-1D and QEM-3D surface stays on the plane, within what
# float32 storage of quadrics and heights allows (the algebra alone, in
# double, is exact to 1e-9 m: t_filter).
. "$(dirname "$0")/../lib.sh"

/usr/bin/python3 "$TOP/tests/tools/mkbad.py" "$T" || { ok 1 "fixtures"; done_testing; exit 1; }
for k in binomial none box binomial5; do
	dem2fqm "$T/plane.tif" - | fqmfilter -k "$k" - "$T/l1.exr"
	worst=0
	for l in 1 2 3 4 5 6 7; do
		for m in qem1d qem3d; do
			fqmsolve -m $m "$T/l$l.exr" "$T/v.exr"
			set -- $(fqmeval "$T/plane.tif" "$T/v.exr") x x x x x x
			worst=$(awk -v a="$worst" -v b="$5" 'BEGIN { print (b > a ? b : a) }')
		done
		fqmfilter -k "$k" "$T/l$l.exr" "$T/l$((l + 1)).exr" 2>/dev/null || break
	done
	awk -v w="$worst" 'BEGIN { exit !(w < 1e-3) }'
	ok $? "kernel $k: tilted plane through files, levels 1-$l, 1D and 3D: max error $worst m (< 1e-3)"
done
done_testing
