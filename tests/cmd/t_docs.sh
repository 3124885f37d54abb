# t_docs - every program has a man page whose options are those --help
# lists, and the man pages render without warnings; the README and the
# overview page terrain-lod(7) agree with the Makefile and the source tree.
. "$(dirname "$0")/../lib.sh"
quick_skip "the man pages against --help"

PATH=$B:$PATH
for p in $(sed -n 's/^\(PROGS\|SCRIPTS\) *:= *//p' "$TOP/Makefile"); do
	m=$TOP/man/$p.1
	[ -f "$m" ]; ok $? "$p: man/$p.1 exists"
	# option letters: "[-k kernel]" in usage, ".Fl k" in the SYNOPSIS
	# "[-fq]" and ".Op Fl fq" list two options each
	help=$($p --help | sed -n '1,/^  -/p' | grep -o '\[-[a-zA-Z]*' | tr -d '[-' | fold -w1 | sort | tr -d '\n')
	man=$(sed -n '/^\.Sh SYNOPSIS/,/^\.Sh DESCRIPTION/p' "$m" | grep -o '^\.Op Fl [a-zA-Z]*' | sed 's/.* //' | fold -w1 | sort | tr -d '\n')
	[ -n "$help" ] && [ "$help" = "$man" ]
	ok $? "$p: --help options ($help) = man SYNOPSIS options ($man)"
	for o in $(echo "$help" | sed 's/./& /g'); do
		grep -qE "^\.It (.* )?Fl $o( |$)" "$m"
		ok $? "$p: man page describes -$o"
	done
done
for m in "$TOP"/man/*.[1-9]; do
	groff -mandoc -ww -Tutf8 "$m" >/dev/null 2>"$T/w"
	[ ! -s "$T/w" ]; ok $? "$(basename "$m") renders without warnings"
done
# mandoc's lint, where installed (man pages not installed aside)
if command -v mandoc >/dev/null; then
	mandoc -Tlint "$TOP/man/terrain-lod.7" 2>&1 |
	    grep -v 'referenced manual not found\|mandoc.db' >"$T/lint"
	[ ! -s "$T/lint" ]; ok $? "terrain-lod.7: mandoc -Tlint is clean"
	sed 's/^/#   /' "$T/lint"
fi

# ARCHITECTURE in terrain-lod(7): a subsection ".Ss src/lib/L" per folder,
# with "Uses: ..." and "Packages: ..." lines as the Makefile has them, a
# "Prefix: ..." line, and its files, one ".It Pa FILE..." line each,
# relative to the subsection.
M7=$TOP/man/terrain-lod.7
awk '/^\.Sh /{on = ($2 == "ARCHITECTURE")} on' "$M7" >"$T/arch"
[ -s "$T/arch" ]; ok $? "terrain-lod.7 has an ARCHITECTURE section"
sub() {	# sub DIR: the subsection of DIR
	awk -v d="$1" '/^\.Ss /{on = ($2 == d)} on' "$T/arch"
}
layers=$(sed -n 's/^LAYERS *:= *//p' "$TOP/Makefile")
dirs=$(cd "$TOP/src/lib" && ls -d */ | tr -d /)
for l in $(printf '%s\n' $layers $dirs | sort -u); do
	[ -d "$TOP/src/lib/$l" ] && echo " $layers " | grep -q " $l "
	ok $? "$l: a folder of src/lib and a layer of the Makefile"
	sub "src/lib/$l" >"$T/sub"
	[ -s "$T/sub" ]; ok $? "$l: described in terrain-lod.7 (.Ss src/lib/$l)"
	grep -q '^Prefix: ' "$T/sub"; ok $? "$l: terrain-lod.7 gives its prefix"
	for v in uses pkgs; do
		case $v in uses) k=Uses n=nothing ;; pkgs) k=Packages n=none ;; esac
		want=$(sed -n "s/^${v}_$l *:= *//p" "$TOP/Makefile" | tr ' ' '\n' | sort | xargs)
		got=$(sed -n "s/^$k: \(.*\)\.$/\1/p" "$T/sub" | tr ' ' '\n' | grep -v "^$n\$" | sort | xargs)
		[ "$want" = "$got" ]
		ok $? "$l: terrain-lod.7 says $k: ${got:-$n}; the Makefile's ${v}_$l: ${want:-(empty)}"
	done
done
awk '/^\.Ss /{d = $2} /^\.It Pa /{for (i = 3; i <= NF && $i ~ /^[A-Za-z0-9_.+-]+$/; i++) print d "/" $i}' \
    "$T/arch" | sort >"$T/named"
(cd "$TOP" && find src/lib src/cmd -type f \( -name '*.c' -o -name '*.h' -o -name '*.cpp' \)) | sort >"$T/files"
comm -23 "$T/files" "$T/named" >"$T/unnamed"
[ ! -s "$T/unnamed" ]; ok $? "every file of src/lib and src/cmd is named in terrain-lod.7 ARCHITECTURE"
sed 's/^/#   not named: /' "$T/unnamed"
comm -13 "$T/files" "$T/named" >"$T/ghosts"
[ ! -s "$T/ghosts" ]; ok $? "every file terrain-lod.7 ARCHITECTURE names exists"
sed 's/^/#   no such file: /' "$T/ghosts"
grep -q 'raster\.c$' "$T/arch" && grep -q 'rs_list\.c' "$T/arch" &&
    grep -q 'one allowed call loop' "$T/arch"
ok $? "terrain-lod.7 names the one allowed call loop (raster.c, rs_list.c)"

# the README: short, a line per program, a row per folder, and only man
# pages that exist
R=$TOP/README.md
n=$(wc -l <"$R")
[ "$n" -lt 350 ]; ok $? "README.md is under 350 lines ($n)"
for p in $(sed -n 's/^\(PROGS\|SCRIPTS\) *:= *//p' "$TOP/Makefile"); do
	grep -q "^| \`$p\` |.*($p(1))\|^| \`$p\` |.*man/$p\.1" "$R"
	ok $? "$p: a line in the README's program table, with its man page"
done
for l in $dirs; do
	grep -q "^| \`src/lib/$l/\` |" "$R"
	ok $? "$l: a row in the README's layout table"
done
{ grep -o '[a-z0-9][a-z0-9-]*([1-9])' "$R" | sed 's/\(.*\)(\(.\))/\1.\2/'
  grep -o 'man/[a-z0-9-]*\.[1-9]' "$R" | sed 's#man/##'; } | sort -u >"$T/pages"
grep -qx 'terrain-lod.7' "$T/pages"; ok $? "the README links terrain-lod(7)"
for pg in $(cat "$T/pages"); do
	[ -f "$TOP/man/$pg" ]; ok $? "README names $pg: man/$pg exists"
done
for m in "$TOP"/man/*.[1-6]; do
	sed -n '/^\.Sh SEE ALSO/,/^\.Sh /p' "$m" | grep -q '^\.Xr terrain-lod 7'
	ok $? "$(basename "$m"): SEE ALSO names terrain-lod(7)"
done
done_testing
