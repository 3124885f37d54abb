# t_globe - DEMs that cover the globe, touch a pole or cross the
# antimeridian, made from a real tile with GDAL: each one through
# dem2vgis (ellipsoidal heights), tilecheck --dem, vgis2tiles (regions
# on the globe, west > east only across the antimeridian, errors finite
# and under the Earth's radius, every glb vertex inside its tile's
# volume, the 3D Tiles and glTF validators) and tileplay --shot (some
# terrain in the picture: a cut near a pole is a sliver a few km wide).
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3
JS=$TOP/tests/js
SRC=$DATA/N44W072.tif
tr() {	# NAME GDAL_TRANSLATE-OPTIONS...: a variant of the real tile
	_o=$1; shift
	gdal_translate -q -a_srs EPSG:4326 "$@" "$SRC" "$T/$_o.tif"
}
# (a) the globe: 1-degree cells, pixel-is-area (centres 89.5S..89.5N) and
# pixel-is-point (centres on both poles, 180W and 180E both present)
tr area -outsize 360 180 -a_ullr -180 90 180 -90
tr point -outsize 361 181 -a_ullr -180.5 90.5 180.5 -90.5 \
    -mo AREA_OR_POINT=Point
# and pixel-is-area whose edges reach 90.5 (half a pixel past the poles)
# with rows of centres on both poles
tr polearea -outsize 360 181 -a_ullr -180 90.5 180 -90.5
# (b) a pole: a cut reaching 90N (its edge), one with a row on 90S, one
# whose last row misses 90S by rounding (-90.00000000000001: the pole)
tr round -srcwin 0 0 301 301 -a_ullr -72.15 0.15 18.15 -90.15 \
    -mo AREA_OR_POINT=Point
tr north -srcwin 0 0 300 300 -a_ullr -72 90 -70 88
tr south -srcwin 0 0 301 301 -a_ullr -72.00333333333333 -87.99666666666667 \
    -69.99666666666667 -90.00333333333333 -mo AREA_OR_POINT=Point
# (c) the antimeridian, from either side
tr east -srcwin 0 0 300 300 -a_ullr 179.5 45 180.5 44
tr west -srcwin 0 0 300 300 -a_ullr -180.5 45 -179.5 44
# (d) polar stereographic (NSIDC north, EPSG:3413) of a cut
gdal_translate -q -srcwin 0 0 400 400 "$SRC" "$T/cut.tif"
gdalwarp -q -t_srs EPSG:3413 -ts 300 300 -r bilinear "$T/cut.tif" \
    "$T/polar.tif"
# and a cut re-georeferenced across the south pole, Antarctic polar
# stereographic (EPSG:3031), 1 km cells
gdal_translate -q -a_srs EPSG:3031 -srcwin 0 0 300 300 \
    -a_ullr -150000 150000 150000 -150000 "$SRC" "$T/spole.tif"

H="-D EPSG:5773 -H ellipsoid"
names=
for d in area:any point:any polearea:any north:0 south:0 round:0 east:1 \
    west:1 polar:0 spole:0; do
	n=${d%:*} cross=${d#*:}
	run "$n: dem2vgis $H" dem2vgis $H "$T/$n.tif" "$T/$n.pyr"
	run "$n: tilecheck --dem passes" tilecheck $H --dem "$T/$n.tif" \
	    "$T/$n.pyr"
	run "$n: vgis2tiles" vgis2tiles -q "$T/$n.pyr" "$T/$n.3d"
	run "$n: regions on the globe, errors sane, every vertex in its volume" \
	    $PY "$TOP/tests/tools/tiles3d_globe.py" "$T/$n.3d" $cross
	sed 's/^/#   /' "$T/out"
	run "$n: tileplay --shot" tileplay "$T/$n.pyr" --shot "$T/$n.png" \
	    --size 160x120 --background 255,0,255
	names="$names $n"
done
# the validators once over every tileset (node starts slowly)
run "every glb passes the glTF validator" \
    node "$JS/validate.js" glb "$T"/*.3d/*/*.glb
run "every tileset.json passes the 3D Tiles 1.1 schema" \
    node "$JS/validate.js" tileset "$T"/*.3d/tileset.json
# terrain in every shot (not the background's magenta)
$PY -c "from osgeo import gdal; import sys
for f in sys.argv[1:]:
	a = gdal.Open(f).ReadAsArray()
	bg = (a[0] == 255) & (a[1] == 0) & (a[2] == 255)
	print(int((~bg).sum()))" $(for n in $names; do echo "$T/$n.png"; done) \
    >"$T/px"
set -- $(cat "$T/px")
for n in $names; do
	[ "${1:-0}" -ge 20 ]; ok $? "$n: the shot shows terrain (${1:-no} pixels)"
	shift
done

# a row past a pole (centres to 90.1S) is refused, saying so
tr past -srcwin 0 0 100 100 -a_ullr -72.1 -88.1 -69.9 -90.2 \
    -mo AREA_OR_POINT=Point
fails "a row past the pole: refused" 1 'latitude -90.1.*past the pole' \
    dem2vgis $H "$T/past.tif" "$T/past.pyr"
[ ! -e "$T/past.pyr" ]; ok $? "a row past the pole: nothing written"
fails "... also with no datum shift" 1 'latitude -90.*past the pole' \
    dem2vgis "$T/past.tif" "$T/past.pyr"
# QEM-3D on a grid with rows on both poles: offsets along a pole's row
# move nothing (it is one point), so the checker passes
run "point, QEM-3D: dem2vgis -3" dem2vgis -3 $H "$T/point.tif" "$T/p3.pyr"
run "point, QEM-3D: tilecheck --dem passes" tilecheck $H --dem \
    "$T/point.tif" "$T/p3.pyr"
run "point, QEM-3D: vgis2tiles" vgis2tiles -q "$T/p3.pyr" "$T/p3.3d"
run "point, QEM-3D: regions, errors, volumes" \
    $PY "$TOP/tests/tools/tiles3d_globe.py" "$T/p3.3d" any
done_testing
