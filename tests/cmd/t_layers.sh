# t_layers - the library's layers depend one way: core <- pyramid <- play,
# pyramid <- tiles3d (the 3D Tiles export), core <- jobs (the supervisor),
# and the programs above them. Checked on the sources (project #includes), on the
# archives (no symbol a lower layer needs is defined by a higher one) and on
# the programs (each links only its layers' libraries: no GL or JSON where
# no layer asks for it).
. "$(dirname "$0")/../lib.sh"

L=$TOP/src/lib
allowed() {	# allowed LAYER: the layers its files may include
	case $1 in
	core) echo "core" ;;
	pyramid) echo "core pyramid" ;;
	play) echo "core pyramid play" ;;
	jobs) echo "core jobs" ;;
	tiles3d) echo "core pyramid tiles3d" ;;
	esac
}
for layer in core pyramid play jobs tiles3d; do
	bad=""
	for f in "$L/$layer"/*.[ch] "$L/$layer"/*.cpp; do
		[ -e "$f" ] || continue
		for inc in $(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$f"); do
			case " $(allowed $layer) " in
			*" ${inc%%/*} "*) ;;
			*) bad="$bad $(basename "$f"):$inc" ;;
			esac
		done
	done
	[ -z "$bad" ] || echo "#   $layer includes:$bad"
	[ -z "$bad" ]; ok $? "src/lib/$layer includes only $(allowed $layer | tr ' ' ',') headers, by layer path"
done

# A header named in a folder it is not in would not resolve: every project
# include names an existing file.
missing=$(cd "$TOP/src" && grep -ho '^#include "[^"]*"' lib/*/*.[ch] lib/*/*.cpp cmd/*.c |
    sed 's/#include "\(.*\)"/\1/' | sort -u | while read -r h; do
	[ -f "lib/$h" ] || echo "$h"; done)
[ -z "$missing" ]; ok $? "every project #include names a file under src/lib ($missing)"

# archives: symbols each layer leaves undefined are not defined above it
defined() { nm -g --defined-only "$1" 2>/dev/null | awk 'NF == 3 { print $3 }' | sort -u; }
undef() { nm -g --undefined-only "$1" 2>/dev/null | awk '{ print $NF }' | sort -u; }
check_up() {	# check_up LOWER HIGHER...
	low=$1; shift
	for high in "$@"; do
		up=$(comm -12 "$T/u.$low" "$T/d.$high" | head -5 | tr '\n' ' ')
		[ -z "$up" ] || echo "#   lib$low.a needs from lib$high.a: $up"
		[ -z "$up" ]; ok $? "lib$low.a needs nothing from lib$high.a"
	done
}
for layer in core pyramid play jobs tiles3d; do
	a=$B/lib$layer.a
	[ -f "$a" ]; ok $? "build/lib$layer.a exists"
	defined "$a" >"$T/d.$layer"
	undef "$a" >"$T/u.$layer"
done
check_up core pyramid play jobs tiles3d
check_up pyramid play jobs tiles3d
check_up jobs pyramid play tiles3d
check_up tiles3d play jobs

# programs: the shared libraries they need
needs() { readelf -d "$B/$1" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p'; }
for p in dem2fqm fqmfilter fqmsolve dem2vgis; do
	n=$(needs $p | grep -E 'jansson|glfw|epoxy|EGL|GL\.' | tr '\n' ' ')
	[ -z "$n" ]; ok $? "$p (core) links no JSON or GL library ($n)"
done
for p in tilepack tilecheck; do
	n=$(needs $p | grep -E 'glfw|epoxy|EGL|GL\.' | tr '\n' ' ')
	[ -z "$n" ]; ok $? "$p (pyramid) links no GL library ($n)"
done
needs tileplay | grep -q glfw; ok $? "tileplay (play) links GLFW"
n=$(needs vgis2tiles | grep -E 'glfw|epoxy|EGL|GL\.|gdal' | tr '\n' ' ')
[ -z "$n" ]; ok $? "vgis2tiles (tiles3d) links no GL library and no GDAL ($n)"
for p in dem2fqm fqmfilter fqmsolve tilepack tilecheck tileplay dem2vgis vgis2tiles; do
	n=$(needs $p | grep -i OpenImageIO | tr '\n' ' ')
	[ -z "$n" ]; ok $? "$p does not link OpenImageIO (a plugin: $n)"
done
done_testing
