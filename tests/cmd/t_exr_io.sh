# t_exr_io - EXR files go through a window in memory (raster/exr.c): a
# small file is written with one write(2) at its end and read with one
# read(2); a larger one goes out in pieces. What that must not change: a
# write that fails (ulimit -f) ends the program with a message and leaves
# nothing, before or at the end; a file cut short is refused as before;
# bytes past the end change nothing; what is read back equals the stream
# the same program gives. With strace, the system calls per small file.
. "$(dirname "$0")/../lib.sh"

dem=$DATA/N44W072.hgt
gdal_translate -q -srcwin 0 0 100 100 "$dem" "$T/s.tif" &&
    gdal_translate -q -srcwin 0 0 1201 1201 "$dem" "$T/m.tif" &&
    dem2fqm "$T/s.tif" "$T/s.exr" && dem2fqm "$T/m.tif" "$T/m.exr" &&
    dem2vgis -q "$T/s.tif" "$T/p" ||
    { ok 1 "fixtures"; done_testing; exit 1; }
ssz=$(wc -c <"$T/s.exr") msz=$(wc -c <"$T/m.exr")
[ "$ssz" -lt 1048576 ] && [ "$msz" -gt 4194304 ]
ok $? "fixtures: a small file ($ssz bytes) and a large one ($msz)"

# --- a failed write: exit 1, the message, nothing left -----------------
# limit BLOCKS WHERE FILE: dem2fqm FILE under ulimit -f BLOCKS, where the
# write fails at WHERE ("finish": the window's one write; "row N": a
# piece of a large file)
limit() {
	rm -rf "$T/u" "$T/tmp"; mkdir "$T/u" "$T/tmp"
	TMPDIR=$T/tmp sh -c 'trap "" XFSZ; ulimit -f "$0"; exec "$@"' "$1" \
	    dem2fqm "$3" "$T/u/o.exr" >"$T/out" 2>"$T/err"; _s=$?
	[ $_s -eq 1 ] &&
	    grep -Eq "^dem2fqm: .*u/o.exr: $2: write: File too large" \
	    "$T/err" && [ -z "$(ls -A "$T/u" "$T/tmp" | grep -v :)" ]
	ok $? "ulimit -f $1, $(basename "$3"): exit $_s, fails at $2, \
nothing left ($(head -c 100 "$T/err"))"
}
limit 100 finish "$T/s.tif"
limit 30000 "row [0-9]+" "$T/m.tif"

# --- reading: the window against the stream, cut short, grown -----------
for f in s m; do
	fqmsolve "$T/$f.exr" "$T/$f.v.exr" &&
	    dem2fqm "$T/$f.tif" - | fqmsolve - "$T/$f.w.exr" &&
	    cmp -s "$T/$f.v.exr" "$T/$f.w.exr"
	ok $? "$f: solved from the EXR file = from the stream"
done
head -c $((ssz - 1000)) "$T/s.exr" >"$T/cut.exr"
fails "a small file cut short: refused" 1 \
    '^fqmsolve: .*cut.exr: truncated or corrupt EXR' \
    fqmsolve "$T/cut.exr" "$T/o.exr"
head -c 300 "$T/s.exr" >"$T/cut.exr"
fails "a header cut short: refused" 1 \
    '^fqmsolve: .*cut.exr: truncated or corrupt EXR header' \
    fqmsolve "$T/cut.exr" "$T/o.exr"
cp "$T/s.exr" "$T/grown.exr" && head -c 5000 /dev/zero >>"$T/grown.exr" &&
    fqmsolve "$T/grown.exr" "$T/o.exr" && cmp -s "$T/o.exr" "$T/s.v.exr"
ok $? "bytes past the end change nothing"
blk=$(find "$T/p" -name '*.exr' | sort | head -1)
bsz=$(wc -c <"$blk")
head -c $((bsz / 2)) "$blk" >"$T/b" && mv "$T/b" "$blk"
tilecheck "$T/p" >"$T/out" 2>&1
[ $? -eq 1 ] && grep -q "$(basename "$blk"): truncated or corrupt EXR" "$T/out"
ok $? "a pyramid's block cut short: tilecheck exits 1 and says which"

# --- system calls per small file -----------------------------------------
# count CALLS PATTERN: the calls in $T/st on files whose name matches
count() {
	grep -E "^[0-9]+ +($1)\([0-9]+<[^>]*$2[^>]*>" "$T/st" | wc -l
}
if command -v strace >/dev/null 2>&1 &&
    strace -f -y -o "$T/st" -e trace=write,pwrite64,pwritev,pwritev2 \
    dem2fqm "$T/s.tif" "$T/st.exr" 2>/dev/null; then
	n=$(count 'write|pwrite64|pwritev|pwritev2' '/\.st\.exr\.')
	[ "$n" -eq 1 ]
	ok $? "a small EXR file written with 1 write ($n)"
	strace -f -y -o "$T/st" -e trace=read,pread64,preadv,preadv2 \
	    fqmsolve "$T/s.exr" "$T/o.exr"
	n=$(count 'read|pread64|preadv|preadv2' '/s\.exr')
	[ "$n" -le 3 ]
	ok $? "a small EXR file read with at most 3 reads: the program's \
look, the magic, the whole file ($n)"
else
	echo "# skipped: no strace (or it cannot trace here)"
fi
done_testing
