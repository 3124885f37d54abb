# t_terrain_edges - a geographic DEM whose samples lie on a tile edge
# (tr_grid.c's snap): 1" crops of N48W125 georeferenced so that sample
# column 256 is longitude -157.5 (an edge from level 3 on) and, apart,
# sample row 256 is latitude 67.5 (from level 4 on), each as pixel-is-
# area and as pixel-is-point. Far from the origin the affine map
# lon = ax + bx I misses that line by 1.1e-12 to 2.5e-12 degrees (bx
# carries the rounding of |ax|): the samples sat just inside one tile,
# quantised one unit from the edge the clip put their twins on, and the
# sliver between folded (holes along the edge at every level past 7, as
# on the 8193x8193 mosaic at -67.5). Now on the line: tilecheck --terrain
# --dem, the independent validator, finds no hole, no sample under no
# triangle, no tile over E_L, in both formats.
. "$(dirname "$0")/../lib.sh"

PY=/usr/bin/python3

# mk OUT AXIS LINE CONVENTION W H: a W x H crop whose sample column (x)
# or row (y) 256 is on longitude or latitude LINE
mk() {
	$PY - "$DATA/N48W125.hgt" "$@" <<'PY'
import sys
from osgeo import gdal, osr
gdal.UseExceptions()
src, dst, axis, line, conv, w, h = sys.argv[1:8]
line, w, h = float(line), int(w), int(h)
a = gdal.Open(src).ReadAsArray(1920, 2720, w, h)   # relief 21 - 644 m
s = 1 / 3600
# the geotransform is the corner whatever AREA_OR_POINT: the sample
# centres at origin + (i + 1/2) s
if axis == "x":
    ox, oy = (line - 256 * s) - s / 2, 48.9
else:
    ox, oy = -124.6, (line + 256 * s) + s / 2
d = gdal.GetDriverByName("GTiff").Create(dst, w, h, 1, gdal.GDT_Int16)
d.SetGeoTransform((ox, s, 0, oy, 0, -s))
r = osr.SpatialReference()
r.SetFromUserInput("EPSG:4326+5773")
d.SetProjection(r.ExportToWkt())
if conv == "point":
    d.SetMetadataItem("AREA_OR_POINT", "Point")
d.GetRasterBand(1).SetNoDataValue(-32768)
d.GetRasterBand(1).WriteArray(a)
PY
}

# off PYR AXIS LINE: the pyramid's georeference puts sample 256 on LINE
# (within 1e-13) while the affine map misses it by over 1e-12 (the case
# the old snap left): else this test would test nothing
off() {
	$PY - "$@" <<'PY'
import json, sys
p, axis, line = sys.argv[1], sys.argv[2], float(sys.argv[3])
g = json.load(open(p + "/index.json"))["georef"]
k = 0 if axis == "x" else 1
o, s = g["origin"][k], g["step"][k]
c = 0 if g["raster"] == "point" else 0.5
a = o + c * s
b = (o + (1 + c) * s) - a
sys.exit(not (abs(o + (256 + c) * s - line) < 1e-13 and
              abs(a + b * 256 - line) > 1e-12))
PY
}

for v in "x -157.5 area 320 160" "x -157.5 point 320 160" \
    "y 67.5 area 161 320" "y 67.5 point 161 320"; do
	set -- $v
	n=$1$3
	mk "$T/$n.tif" "$@"
	dem2vgis -q -H ellipsoid "$T/$n.tif" "$T/$n.pyr"
	what="$([ "$1" = x ] && echo column || echo row) 256 on $2 ($3)"
	off "$T/$n.pyr" "$1" "$2"
	ok $? "$what: the affine map misses the line by over 1e-12 degrees"
	for f in qm 3dtiles; do
		run "$what, -f $f: exported" vgis2terrain -q -j 2 -f $f \
		    "$T/$n.pyr" "$T/$n.$f" || continue
		tilecheck --terrain --dem "$T/$n.tif" -H ellipsoid "$T/$n.$f" \
		    >"$T/check" 2>&1
		s=$?
		grep -E '^violations' "$T/check" | sed 's/^/#   /'
		grep -E ': (hole|coverage|error):' "$T/check" | head -3 |
		    sed 's/^/#   /'
		[ $s -eq 0 ] && grep -q '^result: pass' "$T/check"
		ok $? "$what, -f $f: tilecheck --terrain --dem passes"
		grep -Eq '^violations: .* hole 0 .* coverage 0 error 0$' \
		    "$T/check"
		ok $? "$what, -f $f: hole 0, coverage 0, error 0"
	done
done
done_testing
