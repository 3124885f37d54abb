# t_dem2rgb_pmtiles - dem2rgb -o: the raster-dem tiles of the crop of
# SRTM N48W125 t_dem2rgb uses (513 x 513 samples with voids) as one
# PMTiles v3 archive, read back by the independent npm pmtiles reader
# (tests/js/pmtiles_read.mjs): exactly the tiles of the tree dem2rgb
# writes of the same DEM, byte-identical; the header's zooms, bounds,
# centre and tile type those of tiles.json; the metadata tiles.json's
# fields but tilejson and tiles (encoding, datum, error per zoom...).
# PNG and WebP; reruns and -j 1 / -j 2 byte-identical; an existing file
# that is not an archive, an output on the input refused; a killed run
# leaves no archive.
. "$(dirname "$0")/../lib.sh"

JS=$TOP/tests/js
if ! command -v node >/dev/null || [ ! -d "$JS/node_modules/pmtiles" ]; then
	ok 0 "npm pmtiles # SKIP no node or no tests/js/node_modules (make tests)"
	done_testing
	exit
fi

gdal_translate -q -srcwin 2560 2824 513 513 "$DATA/N48W125.hgt" "$T/srtm.tif"

# same TREE ARCHIVE FORMAT: npm pmtiles reads ARCHIVE against TREE; the
# header and metadata checked against TREE/tiles.json
same() {
	node "$JS/pmtiles_read.mjs" "$2" "$1" >"$T/read.json" 2>"$T/err"
	_s=$?
	[ $_s -eq 0 ] || { head -c 600 "$T/read.json"; head -3 "$T/err"; } | sed 's/^/#   /'
	ok $_s "$3: npm pmtiles reads every tile of the tree, byte-identical, and lists no other"
	python3 - "$1/tiles.json" "$T/read.json" "$3" >"$T/checks" <<'PY'
import json, sys
tj = json.load(open(sys.argv[1])); r = json.load(open(sys.argv[2]))
h, m, f = r["header"], r["metadata"], sys.argv[3]
e7 = lambda a, b: abs(a - b) <= 0.5e-7 + 1e-12
b, c = tj["bounds"], tj["center"]
for good, d in [
    (r["read"] == r["listed"] == r["tree"] == sum(z["tiles"] for z in tj["error"]) > 10,
     "%s: %d tiles, those tiles.json counts" % (f, r["read"])),
    (h["minZoom"] == tj["minzoom"] and h["maxZoom"] == tj["maxzoom"] and
     h["centerZoom"] == c[2], "%s: header zooms %d..%d, centre zoom %d as tiles.json" %
     (f, h["minZoom"], h["maxZoom"], h["centerZoom"])),
    (all(e7(x, y) for x, y in zip([h["minLon"], h["minLat"], h["maxLon"],
     h["maxLat"], h["centerLon"], h["centerLat"]], b + c[:2])),
     "%s: header bounds and centre those of tiles.json" % f),
    (h["tileType"] == {"png": 2, "webp": 4}[f] and h["tileCompression"] == 1,
     "%s: tile type %d, tiles stored as written" % (f, h["tileType"])),
    (m == {k: v for k, v in tj.items() if k not in ("tilejson", "tiles")},
     "%s: metadata = tiles.json but tilejson and tiles" % f),
    (m["encoding"] == tj["encoding"] and m["vertical_datum"] == "EPSG:5773",
     "%s: metadata encoding %s, vertical datum %s" % (f, m["encoding"],
     m["vertical_datum"]))]:
	print("%d\t%s" % (0 if good else 1, d))
PY
	while IFS='	' read -r _st _d; do ok "$_st" "$_d"; done <"$T/checks"
}

O="-q -D EPSG:5773"
run "png: the tree" dem2rgb $O -j 2 "$T/srtm.tif" "$T/tree"
run "png: the archive" dem2rgb $O -j 2 -o "$T/a.pmtiles" "$T/srtm.tif"
same "$T/tree" "$T/a.pmtiles" png
[ -z "$(ls -A "$T" | grep '^\.')" ]; ok $? "no temporary left"
cp "$T/a.pmtiles" "$T/first"
run "a rerun onto the archive" dem2rgb $O -j 2 -o "$T/a.pmtiles" "$T/srtm.tif" &&
    dem2rgb $O -j 1 -o "$T/a1.pmtiles" "$T/srtm.tif"
cmp -s "$T/first" "$T/a.pmtiles" && cmp -s "$T/a.pmtiles" "$T/a1.pmtiles"
ok $? "-j 1 and -j 2, rerun: byte-identical archives"

W="$O -f webp -e mapbox -Z 6"
run "webp, Terrain-RGB: the tree" dem2rgb $W "$T/srtm.tif" "$T/wtree"
run "webp, Terrain-RGB: the archive" dem2rgb $W -o "$T/w.pmtiles" "$T/srtm.tif"
same "$T/wtree" "$T/w.pmtiles" webp

# refusals: nothing written, nothing replaced
: >"$T/file"
fails "unwritable output" 1 "dem2rgb: .*file/x.pmtiles" \
    dem2rgb -q -z 8 -o "$T/file/x.pmtiles" "$T/srtm.tif"
fails "output equal to the input refused" 1 "is the input" \
    dem2rgb -q -z 8 -o "$T/srtm.tif" "$T/srtm.tif"
echo keep >"$T/other.pmtiles"
fails "a file that is not an archive is not replaced" 1 "not a PMTiles archive" \
    dem2rgb -q -z 8 -o "$T/other.pmtiles" "$T/srtm.tif"
[ "$(cat "$T/other.pmtiles")" = keep ]; ok $? "... and kept"
fails "usage: -o and a second operand" 2 "usage" \
    dem2rgb -o "$T/x.pmtiles" "$T/srtm.tif" "$T/tree"
fails "usage: -o and -u" 2 "-u" dem2rgb -u http://x/ -o "$T/x.pmtiles" "$T/srtm.tif"
[ ! -e "$T/x.pmtiles" ] && [ -z "$(ls -A "$T" | grep '^\.')" ]
ok $? "... no archive and no temporary left"

# killed: by TERM nothing is left; by KILL no archive, and the next run
# in that directory removes the dead run's temporaries
dem2rgb -q -j 1 -o "$T/k.pmtiles" "$T/srtm.tif" &
pid=$!
if mid_run $pid "$T/k.pmtiles"; then
	kill -TERM $pid; kill -CONT $pid; wait $pid
	[ ! -e "$T/k.pmtiles" ] && [ -z "$(ls -A "$T" | grep '^\.')" ]
	ok $? "TERM: no archive and no temporary left"
else
	wait $pid; skip "the run ended before the kill"
fi
rm -f "$T/k.pmtiles"
dem2rgb -q -j 1 -o "$T/k.pmtiles" "$T/srtm.tif" &
pid=$!
if mid_run $pid "$T/k.pmtiles"; then
	kill -KILL $pid; kill -CONT $pid 2>/dev/null; wait $pid
	[ ! -e "$T/k.pmtiles" ]; ok $? "KILL: no archive"
else
	wait $pid; skip "the run ended before the kill"
fi
dem2rgb $O -j 2 -o "$T/k.pmtiles" "$T/srtm.tif" && cmp -s "$T/k.pmtiles" "$T/a.pmtiles" &&
    [ -z "$(ls -A "$T" | grep '^\.')" ]
ok $? "KILL: the next run, the same archive; the dead run's temporaries gone"
done_testing
