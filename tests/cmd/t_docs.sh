# t_docs - every program has a man page whose options are those --help
# lists, and the man pages render without warnings.
. "$(dirname "$0")/../lib.sh"

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
done_testing
