# t_loops - no call loop between object files. Read from the built
# archives with nm: object A calls object B when A leaves undefined a
# global symbol that B alone defines (strongly: weak and common
# definitions, C++'s inline copies, say nothing of who calls whom). Every
# cycle of that graph (a strongly connected component of more than one
# object) fails, printing its members; the one allowed case is the band
# list of raster (raster.o <-> rs_list.o: a band list is a raster made of
# rasters, so it opens its column files through the front door).
# The programs' objects are read too (cli.o beside the programs);
# TL_LOOPS_OBJS="a.o b.a ...": check those files instead. Last, that
# GDAL is seen by the DEM reader's GDAL adapter only.
. "$(dirname "$0")/../lib.sh"
quick_skip "call loops in the archives"

if [ -n "${TL_LOOPS_OBJS:-}" ]; then
	objs=$TL_LOOPS_OBJS
else
	# the layers' archives (the Makefile's table: no stale archive of
	# an old layout in a reused build folder), and the programs' own
	# objects (cli.o and each main)
	objs=$(for l in $(make -s -C "$TOP" print-layers 2>/dev/null | cut -d: -f1); do
		ls "$B/lib$l.a"; done 2>/dev/null; ls "$B"/cmd/*.o 2>/dev/null)
fi
[ -n "$objs" ]; ok $? "archives to read ($(echo $objs | wc -w))"
# nm -A: "archive:member: value type name", or "archive:member: U name"
# (one file: "file: value type name")
# shellcheck disable=SC2086
nm -A -g $objs 2>/dev/null >"$T/nm"
[ -s "$T/nm" ]; ok $? "nm reads them ($(wc -l <"$T/nm") symbols)"

python3 - "$T/nm" >"$T/loops" <<'EOF'
import sys
# the one allowed loop: the band list (see the head of raster/rs_list.c)
ALLOWED = [{"libraster.a:raster.o", "libraster.a:rs_list.o"}]

defs, undefs, objs = {}, {}, set()
for line in open(sys.argv[1]):
	f = line.split()
	if len(f) not in (2, 3):
		continue
	# "path/lib.a:member.o:VALUE" -> "lib.a:member.o"
	obj = f[0].rsplit(":", 1)[0].rsplit("/", 1)[-1]
	objs.add(obj)
	typ, sym = f[-2], f[-1]
	if typ == "U":
		undefs.setdefault(obj, set()).add(sym)
	elif typ in "TDBRG" and typ.isupper():
		defs.setdefault(sym, set()).add(obj)
calls = {o: set() for o in objs}
for a, syms in undefs.items():
	for s in syms:
		d = defs.get(s, ())
		if len(d) == 1:
			b = next(iter(d))
			if b != a:
				calls[a].add(b)

# Tarjan's strongly connected components, iterative
index, low, on, stack, sccs, n = {}, {}, set(), [], [], 0
for root in sorted(objs):
	if root in index:
		continue
	work = [(root, iter(sorted(calls[root])))]
	index[root] = low[root] = n; n += 1
	stack.append(root); on.add(root)
	while work:
		v, it = work[-1]
		w = next(it, None)
		if w is not None:
			if w not in index:
				index[w] = low[w] = n; n += 1
				stack.append(w); on.add(w)
				work.append((w, iter(sorted(calls[w]))))
			elif w in on:
				low[v] = min(low[v], index[w])
			continue
		work.pop()
		if work:
			low[work[-1][0]] = min(low[work[-1][0]], low[v])
		if low[v] == index[v]:
			c = set()
			while True:
				w = stack.pop(); on.discard(w); c.add(w)
				if w == v:
					break
			if len(c) > 1:
				sccs.append(c)
print("edges %d objects %d" % (sum(len(v) for v in calls.values()), len(objs)))
for c in sorted(sccs, key=lambda c: sorted(c)):
	tag = "allowed" if c in ALLOWED else "loop"
	# the calls inside the loop, with one symbol each, to say why
	why = []
	for a in sorted(c):
		for b in sorted(calls[a] & c):
			s = sorted(x for x in undefs.get(a, ()) if defs.get(x) == {b})
			why.append("%s -> %s (%s%s)" % (a.split(":")[-1], b.split(":")[-1],
			    s[0], ", +%d" % (len(s) - 1) if len(s) > 1 else ""))
	print("%s %s" % (tag, " ".join(sorted(c))))
	for w in why:
		print("  " + w)
EOF
ok $? "the call graph of the object files ($(head -1 "$T/loops"))"
grep -q '^edges [1-9]' "$T/loops"; ok $? "some object calls another (nm read them)"

sed -n 's/^allowed //p' "$T/loops" | while read -r c; do
	echo "# allowed: $c (the band list: a raster made of rasters)"
done
loops=$(grep -c '^loop ' "$T/loops")
[ "$loops" -eq 0 ] || awk '/^loop /{ p = 1 } /^[a-z]/ && !/^loop /{ p = 0 } p { print "#   " $0 }' "$T/loops"
[ "$loops" -eq 0 ]; ok $? "no call loop between object files but the band list ($loops found)"

# The DEM reader reaches GDAL through its adapter's table of methods
# (dem_impl.h): in libdem.a only the GDAL side (dem_gdal.h) calls GDAL,
# and only its files include GDAL's headers (dem_warp.c: dem2rgb's warp).
gdal_side="dem_gdal.o dem_gdal_env.o dem_pam.o dem_vrt.o dem_mosaic.o dem_mosaic_overlap.o dem_mosaic_tile.o dem_warp.o"
bad=$(awk '$1 ~ /libdem\.a:/ && $2 == "U" &&
    $3 ~ /^(GDAL|CPL|CSL|OGR|OSR|VSI)/ {
	split($1, p, ":"); print p[2] }' "$T/nm" | sort -u |
    while read -r o; do
	case " $gdal_side " in *" $o "*) ;; *) echo "$o" ;; esac
    done | tr '\n' ' ')
[ -z "$bad" ]; ok $? "libdem.a: only the GDAL adapter's objects call GDAL ($bad)"
awk '$1 ~ /libdem\.a:dem_gdal\.o:/ && $2 == "U" && $3 ~ /^GDAL/' "$T/nm" |
    grep -q .
ok $? "libdem.a: dem_gdal.o calls GDAL (the check above reads GDAL's symbols)"
inc=$(cd "$TOP/src" && grep -lE '^#include <(gdal|cpl_|ogr_)' lib/*/* cmd/* |
    grep -vE '^lib/dem/(dem_gdal(_env)?\.[ch]|dem_pam\.cpp|dem_vrt\.c|dem_mosaic(_overlap|_tile)?\.[ch]|dem_warp\.c)$' |
    tr '\n' ' ')
[ -z "$inc" ]; ok $? "GDAL's headers included by the GDAL adapter's files only ($inc)"
done_testing
