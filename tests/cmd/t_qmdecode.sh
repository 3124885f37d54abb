# t_qmdecode - tilecheck --terrain from the command line, and its decoder
# against a third party's: on the tileset tests/verify/t_qm encodes by
# hand (heights all over 0..32767, a gzip'd tile, a tile of 32-bit
# indices), loaders.gl's decoder (tests/js/qmdecode.js, which checks
# QuantizedMeshLoader against it too) prints per tile the same vertex
# and triangle counts and checksum of u, v, heights and indices as
# tilecheck --terrain --dump; exit statuses on damage and usage.
. "$(dirname "$0")/../lib.sh"

JS=$TOP/tests/js
"$B/tests/verify/t_qm" --write "$T/qm"
ok $? "t_qm --write: the hand-encoded tileset"
run "tilecheck --terrain: it passes" tilecheck --terrain "$T/qm"
grep -q '^result: pass$' "$T/out"; ok $? "the report ends in result: pass"
run "tilecheck --terrain --dump" tilecheck --terrain --dump "$T/qm"
mv "$T/out" "$T/c.txt"
run "qmdecode.js (loaders.gl) decodes every tile" node "$JS/qmdecode.js" "$T/qm"
mv "$T/out" "$T/js.txt"
[ "$(wc -l <"$T/c.txt")" -eq 6 ] && cmp -s "$T/c.txt" "$T/js.txt"
ok $? "both decoders: the same vertices, triangles and checksums for the 6 tiles"
diff "$T/c.txt" "$T/js.txt" | sed 's/^/#   /' | head -5

# a tile cut short fails both, and the check
f=$(ls "$T"/qm/3/*/*.terrain)
head -c 1000 "$f" >"$T/cut" && cp "$T/cut" "$f"
tilecheck --terrain "$T/qm" >"$T/out" 2>"$T/err"
[ $? -eq 1 ] && grep -q '^3/.*: decode: truncated' "$T/out"
ok $? "a tile cut short: exit 1, decode: truncated"
tilecheck --terrain --dump "$T/qm" >"$T/out" 2>"$T/err"
[ $? -eq 1 ] && grep -q 'truncated' "$T/err"
ok $? "--dump of it: exit 1, truncated on stderr"
node "$JS/qmdecode.js" "$T/qm" >"$T/out" 2>"$T/err"
[ $? -eq 1 ]; ok $? "qmdecode.js on it: exit 1 ($(head -c 100 "$T/err"))"

rm "$T/qm/layer.json"
fails "no layer.json: cannot check (3)" 3 'layer.json' tilecheck --terrain "$T/qm"
fails "two directories: usage (2)" 2 'usage' tilecheck --terrain "$T/qm" "$T/qm"
done_testing
