# t_pmtiles - PMTiles archives written by the project's own writer
# (rgb/pmtiles.h, through the test tool pmpack) and read back by the
# independent npm pmtiles reader (tests/js/pmtiles_read.mjs): every tile
# byte-identical to its tree's file and the directories listing exactly
# the tree's tiles; the header's zooms, bounds, centre, tile type and
# the metadata. (a) a synthetic tree of zooms 0..9 over a region, big
# enough for leaf directories, with duplicates and runs of one content;
# (b) PNG and WebP trees gdal2tiles makes from a real DEM. The archive
# is the same bytes for any order of the tiles and on a rerun; a failure
# or a killed run leaves nothing at the output.
. "$(dirname "$0")/../lib.sh"

JS=$TOP/tests/js
if ! command -v node >/dev/null || [ ! -d "$JS/node_modules/pmtiles" ]; then
	ok 0 "npm pmtiles # SKIP no node or no tests/js/node_modules (make tests)"
	done_testing
	exit
fi

# read ARCHIVE TREE NAME: npm pmtiles reads it all; its report in NAME.json
read_back() {
	node "$JS/pmtiles_read.mjs" "$1" "$2" >"$T/$3.json" 2>"$T/err"
	_s=$?
	[ $_s -eq 0 ] || { head -c 600 "$T/$3.json"; head -3 "$T/err"; } | sed 's/^/#   /'
	return $_s
}
# checks NAME < LINES: each line "EXPR | DESCRIPTION", a Python
# expression on the report NAME.json (r; its header h, its metadata m),
# passing when true; {...} in DESCRIPTION are Python expressions too.
# One Python for all the lines of a report.
checks() {
	python3 -c 'import json, sys
r = json.load(open(sys.argv[1])); h = r["header"]; m = r["metadata"]
for line in sys.stdin:
	e, d = line.rstrip("\n").split(" | ", 1)
	try:
		good = eval(e) is True
		d = eval("f" + repr(d))
	except Exception as x:
		good, d = False, "%s (%s)" % (d, x)
	print("%d\t%s" % (0 if good else 1, d))' "$T/$1.json" >"$T/checks"
	while IFS='	' read -r _st _d; do
		ok "$_st" "$_d"
		[ "$_st" -eq 0 ] || echo "#   $(head -c 400 "$T/$1.json")"
	done <"$T/checks"
}
# list TREE [sort options]: the tree's tiles, relative, in that order
list() {
	_d=$1; shift
	(cd "$_d" && find . -type f | sed 's|^\./||' | sort "$@")
}

# (a) zooms 0..9: at zoom 9 the 64 x 80 tiles x 256..319, y 128..207,
# above them their parents; tiles of random bytes and lengths, 7 in 10
# drawn from a pool of 1000 (duplicates, stored once, offsets pointing
# back: directories too big for the root), and a 16 x 16 block of zoom
# 9 one content (256 consecutive tile ids: one entry)
python3 - "$T/syn" <<'EOF'
import os, random, sys
rnd = random.Random(24)
top = sys.argv[1]
pool = [rnd.randbytes(rnd.randint(20, 400)) for _ in range(1000)]
for z in range(10):
	s = 9 - z
	for x in range(256 >> s, (319 >> s) + 1):
		d = os.path.join(top, str(z), str(x))
		os.makedirs(d)
		for y in range(128 >> s, (207 >> s) + 1):
			if z == 9 and 288 <= x < 304 and 160 <= y < 176:
				b = b"sea" * 100
			elif rnd.random() < 0.7:
				b = pool[rnd.randrange(len(pool))]
			else:
				b = rnd.randbytes(rnd.randint(20, 400))
			with open(os.path.join(d, "%d.png" % y), "wb") as f:
				f.write(b)
EOF
ok $? "a synthetic tree, zooms 0..9 ($(list "$T/syn" | wc -l) tiles)"
n=$(list "$T/syn" | wc -l)
printf '{"encoding":"terrarium","name":"synthetic","vertical_datum":"EGM2008","zooms":[0,9]}' >"$T/meta.json"
OPTS="-z 0,9 -b -0.5,-45.5,90.25,0.75 -c 45.125,-22.375,4 -m $T/meta.json"
list "$T/syn" | pmpack $OPTS "$T/syn" "$T/a.pmtiles"
ok $? "pmpack: the synthetic tree in path order"
list "$T/syn" -r | pmpack $OPTS "$T/syn" "$T/b.pmtiles"
ok $? "pmpack: in reverse order"
list "$T/syn" -t/ -k3 | pmpack $OPTS "$T/syn" "$T/c.pmtiles"
ok $? "pmpack: in order of the rows"
cmp -s "$T/a.pmtiles" "$T/b.pmtiles" && cmp -s "$T/a.pmtiles" "$T/c.pmtiles"
ok $? "the three orders: byte-identical archives"
list "$T/syn" | pmpack $OPTS "$T/syn" "$T/a2.pmtiles" && cmp -s "$T/a.pmtiles" "$T/a2.pmtiles"
ok $? "a rerun: byte-identical"

read_back "$T/a.pmtiles" "$T/syn" syn
ok $? "npm pmtiles: every tile byte-identical to the tree's, the directories list exactly the tree's tiles"
checks syn <<EOF
r['read'] == r['tree'] == r['listed'] == $n | npm pmtiles: $n tiles read, $n listed
r['leaves'] > 1 and h['leafDirectoryLength'] > 0 | {r['leaves']} leaf directories
h['minZoom'] == 0 and h['maxZoom'] == 9 and h['centerZoom'] == 4 | header: zooms 0..9, centre zoom 4
[h['minLon'], h['minLat'], h['maxLon'], h['maxLat'], h['centerLon'], h['centerLat']] == [-0.5, -45.5, 90.25, 0.75, 45.125, -22.375] | header: bounds and centre
h['tileType'] == 2 and h['tileCompression'] == 1 and h['internalCompression'] == 2 and h['clustered'] and h['specVersion'] == 3 | header: PNG, tiles uncompressed, directories gzip'd, clustered, version 3
h['numAddressedTiles'] == $n and h['numTileEntries'] <= $n - 255 and h['numTileContents'] < h['numTileEntries'] | header: $n tiles; runs merged ({h['numTileEntries']} entries), duplicates stored once ({h['numTileContents']} contents)
m == json.load(open('$T/meta.json')) | the metadata as given
EOF
# the reader's check can fail: one byte of the last tile changed
cp "$T/a.pmtiles" "$T/bad.pmtiles"
printf 'Z' | dd of="$T/bad.pmtiles" bs=1 seek=$(($(wc -c <"$T/a.pmtiles") - 1)) \
    conv=notrunc 2>/dev/null
node "$JS/pmtiles_read.mjs" "$T/bad.pmtiles" "$T/syn" >"$T/bad.json" 2>&1
[ $? -eq 1 ] && grep -q '"different":\["[0-9]' "$T/bad.json"
ok $? "a byte of a tile changed: the reader finds that tile different"

# (b) a real DEM through gdal2tiles: PNG (grey and alpha) and WebP
# (lossless, RGBA)
DEM=$DATA/N42E001.tif
gdal_translate -q -of VRT -ot Byte -a_nodata none -scale 0 3000 0 255 \
    "$DEM" "$T/grey.vrt" &&
    gdal2tiles.py -q --xyz -z 5-11 -w none --processes=1 "$T/grey.vrt" "$T/png" 2>"$T/err"
ok $? "gdal2tiles: PNG tiles of $(basename "$DEM"), zooms 5..11 ($(list "$T/png" | wc -l) tiles)"
gdal_translate -q -of VRT -ot Byte -a_nodata none -scale 0 3000 0 255 \
    -b 1 -b 1 -b 1 "$DEM" "$T/rgb.vrt" &&
    gdal2tiles.py -q --xyz -z 5-9 -w none --processes=1 --tiledriver=WEBP \
    --webp-lossless "$T/rgb.vrt" "$T/webp" 2>"$T/err"
ok $? "gdal2tiles: WebP tiles, zooms 5..9 ($(list "$T/webp" | wc -l) tiles)"
printf '{"encoding":"terrarium","name":"N42E001","tileSize":256}' >"$T/meta2.json"
for f in png webp; do
	case $f in png) z=5,11 ;; webp) z=5,9 ;; esac
	o="-t $f -z $z -b 1,42,2,43 -c 1.5,42.5,8 -m $T/meta2.json"
	list "$T/$f" | pmpack $o "$T/$f" "$T/$f.pmtiles"
	ok $? "pmpack: the $f tree"
	list "$T/$f" -r | pmpack $o "$T/$f" "$T/$f.r.pmtiles" &&
	    cmp -s "$T/$f.pmtiles" "$T/$f.r.pmtiles"
	ok $? "$f: in reverse order, byte-identical"
	read_back "$T/$f.pmtiles" "$T/$f" $f
	ok $? "npm pmtiles: every $f tile byte-identical to gdal2tiles' file, none more"
	tt=2; [ $f = webp ] && tt=4
	checks $f <<EOF
r['read'] == r['listed'] == r['tree'] > 10 and h['tileType'] == $tt and h['minZoom'] == 5 and h['maxZoom'] == ${z#5,} | $f: {r['read']} tiles; header: tile type $tt, zooms $z
[h['minLon'], h['minLat'], h['maxLon'], h['maxLat'], h['centerLon'], h['centerLat'], h['centerZoom']] == [1, 42, 2, 43, 1.5, 42.5, 8] and m['encoding'] == 'terrarium' | $f: header bounds and centre; metadata encoding terrarium
EOF
done

# failures: nothing left at the output
list "$T/png" | pmpack "$T/png" "$T/meta2.json/x.pmtiles" >"$T/out" 2>"$T/err"
[ $? -eq 1 ] && grep -q 'meta2.json/x.pmtiles: cannot create' "$T/err"
ok $? "an output that cannot be created (its directory a file): exit 1, at once"
{ list "$T/png"; list "$T/png" | head -1; } | pmpack "$T/png" "$T/d.pmtiles" >"$T/out" 2>"$T/err"
[ $? -eq 1 ] && grep -q 'given twice' "$T/err" && [ ! -e "$T/d.pmtiles" ]
ok $? "a tile given twice: exit 1, no archive ($(cat "$T/err"))"
echo 12/1/2.png | pmpack "$T/png" "$T/d.pmtiles" >"$T/out" 2>"$T/err"
[ $? -eq 1 ] && grep -q 'cannot read' "$T/err" && [ ! -e "$T/d.pmtiles" ]
ok $? "a missing tile file: exit 1, no archive"
[ "$(ls -A "$T" | grep -c '^\.')" -eq 0 ]; ok $? "no temporary left"

# a killed run (SIGKILL, while it reads its list): no archive; the
# next run to that path removes its temporaries
mkfifo "$T/fifo"
pmpack "$T/png" "$T/k.pmtiles" <"$T/fifo" 2>/dev/null &
pid=$!
exec 3>"$T/fifo"
list "$T/png" | head -5 >&3
sleep 1
kill -KILL $pid; wait $pid 2>/dev/null
exec 3>&-
[ ! -e "$T/k.pmtiles" ] && [ "$(ls -A "$T" | grep -c '^\.k\.pmtiles\.')" -eq 2 ]
ok $? "killed: no archive, its two temporaries (archive and spool)"
list "$T/png" | pmpack -t png -z 5,11 -b 1,42,2,43 -c 1.5,42.5,8 \
    -m "$T/meta2.json" "$T/png" "$T/k.pmtiles" && cmp -s "$T/k.pmtiles" "$T/png.pmtiles"
ok $? "the next run: the archive, the same bytes"
[ "$(ls -A "$T" | grep -c '^\.')" -eq 0 ]; ok $? "and the killed run's temporaries are gone"
done_testing
