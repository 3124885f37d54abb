# t_layers - the library's layers depend one way, as the Makefile's one
# table says (make print-layers: each layer, what it may use, its
# packages). Checked on the sources (project #includes by layer path,
# foreign headers only in the layer owning their package, each package
# owned by one layer), on the archives (no symbol a lower layer needs is
# defined by a higher one) and on the programs (each links only its
# layers' libraries: no GL or JSON where no layer asks for it).
. "$(dirname "$0")/../lib.sh"
quick_skip "the layers of the sources and archives"

L=$TOP/src/lib
make -s -C "$TOP" print-layers >"$T/layers" 2>/dev/null
[ -s "$T/layers" ]; ok $? "make print-layers: the layer table ($(wc -l <"$T/layers") layers)"
layers=$(cut -d: -f1 "$T/layers")
uses() { grep "^$1:" "$T/layers" | cut -d: -f2; }
pkgs() { grep "^$1:" "$T/layers" | cut -d: -f3; }

# every folder of src/lib is a layer of the table
for d in "$L"/*/; do
	d=$(basename "$d")
	echo "$layers" | grep -qx "$d"; ok $? "src/lib/$d is a layer of the table"
done

# A package's headers, as the sources include them.
headers() {
	case $1 in
	proj) echo 'proj\.h|proj_experimental\.h' ;;
	geographiclib) echo 'GeographicLib/' ;;
	OpenEXR) echo 'openexr[a-z_]*\.h|Imf[A-Za-z]*\.h' ;;
	libdeflate) echo 'libdeflate\.h' ;;
	gdal) echo 'gdal[a-z_]*\.h|cpl_[a-z_]*\.h|ogr_[a-z_]*\.h' ;;
	jansson) echo 'jansson\.h' ;;
	zlib) echo 'zlib\.h' ;;
	egl) echo 'EGL/' ;;
	epoxy) echo 'epoxy/' ;;
	glfw3) echo 'GLFW/' ;;
	glu) echo 'GL/glu\.h' ;;
	stb) echo 'stb_[a-z_]*\.h' ;;
	libpng) echo 'png\.h|pngconf\.h' ;;
	libwebp) echo 'webp/' ;;
	OpenImageIO) echo 'OpenImageIO/' ;;
	*) echo "unknown-package-$1" ;;
	esac
}
allpkgs=$(cut -d: -f3 "$T/layers" | tr ' ' '\n' | sed '/^$/d')
dup=$(echo "$allpkgs" | sort | uniq -d | tr '\n' ' ')
[ -z "$dup" ]; ok $? "each foreign package is owned by one layer only ($dup)"

for layer in $layers; do
	bad="" foreign=""
	for f in "$L/$layer"/*.[ch] "$L/$layer"/*.cpp; do
		[ -e "$f" ] || continue
		for inc in $(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$f"); do
			case " $(uses "$layer") " in
			*" ${inc%%/*} "*) ;;
			*) bad="$bad $(basename "$f"):$inc" ;;
			esac
		done
		# the OIIO plugin is built apart, linked by nothing
		case $f in */oiio_plugin.cpp) continue ;; esac
		for p in $allpkgs; do
			case " $(pkgs "$layer") " in *" $p "*) continue ;; esac
			grep -qE "^#include <($(headers "$p"))" "$f" &&
			    foreign="$foreign $(basename "$f"):$p"
		done
	done
	[ -z "$bad" ] || echo "#   $layer includes:$bad"
	[ -z "$bad" ]; ok $? "src/lib/$layer includes only $(uses "$layer" | sed 's/^ //; s/ /,/g') headers, by layer path"
	[ -z "$foreign" ] || echo "#   $layer includes foreign headers:$foreign"
	[ -z "$foreign" ]; ok $? "src/lib/$layer includes no other layer's foreign package"
done
# the programs: cli.c and the layers they use; no foreign header
foreign=$(grep -lE "^#include <($(for p in $allpkgs; do headers "$p"; done | tr '\n' '|' | sed 's/|$//'))" \
    "$TOP"/src/cmd/*.c | tr '\n' ' ')
[ -z "$foreign" ]; ok $? "src/cmd includes no foreign package ($foreign)"

# A header named in a folder it is not in would not resolve: every project
# include names an existing file.
missing=$(cd "$TOP/src" && grep -ho '^#include "[^"]*"' lib/*/*.[ch] lib/*/*.cpp cmd/*.[ch] |
    sed 's/#include "\(.*\)"/\1/' | sort -u | while read -r h; do
	[ -f "lib/$h" ] || [ -f "cmd/$h" ] || echo "$h"; done)
[ -z "$missing" ]; ok $? "every project #include names a file under src/lib or src/cmd ($missing)"

# archives: symbols each layer leaves undefined are not defined by a
# layer it may not use
defined() { nm -g --defined-only "$1" 2>/dev/null | awk 'NF == 3 { print $3 }' | sort -u; }
undef() { nm -g --undefined-only "$1" 2>/dev/null | awk '{ print $NF }' | sort -u; }
for layer in $layers; do
	a=$B/lib$layer.a
	[ -f "$a" ]; ok $? "$B/lib$layer.a exists"
	defined "$a" >"$T/d.$layer"
	undef "$a" >"$T/u.$layer"
done
for low in $layers; do
	bad=""
	for high in $layers; do
		case " $(uses "$low") " in *" $high "*) continue ;; esac
		up=$(comm -12 "$T/u.$low" "$T/d.$high" | head -3 | tr '\n' ' ')
		[ -z "$up" ] || bad="$bad lib$high.a($up)"
	done
	[ -z "$bad" ] || echo "#   lib$low.a needs:$bad"
	[ -z "$bad" ]; ok $? "lib$low.a needs nothing from a layer it may not use"
done

# programs: the shared libraries they need
needs() { readelf -d "$B/$1" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p'; }
for p in dem2fqm fqmfilter fqmsolve; do
	n=$(needs $p | grep -E 'jansson|glfw|epoxy|EGL|GL\.' | tr '\n' ' ')
	[ -z "$n" ]; ok $? "$p links no JSON or GL library ($n)"
done
# dem2vgis runs the stages' and tilepack's work as threads (one process):
# it links what they link (GDAL, JSON), never the viewer's GL
n=$(needs dem2vgis | grep -E 'glfw|epoxy|EGL|GL\.' | tr '\n' ' ')
[ -z "$n" ]; ok $? "dem2vgis links no GL library ($n)"
for p in tilepack tilecheck; do
	n=$(needs $p | grep -E 'glfw|epoxy|EGL|GL\.' | tr '\n' ' ')
	[ -z "$n" ]; ok $? "$p links no GL library ($n)"
done
needs tileplay | grep -q glfw; ok $? "tileplay (play) links GLFW"
n=$(needs vgis2tiles | grep -E 'glfw|epoxy|EGL|GL\.|gdal' | tr '\n' ' ')
[ -z "$n" ]; ok $? "vgis2tiles (tiles3d) links no GL library and no GDAL ($n)"
for p in dem2fqm fqmfilter fqmsolve tilepack tilecheck tileplay dem2vgis vgis2tiles; do
	n=$(needs $p | grep -i OpenImageIO | tr '\n' ' ')
	[ -z "$n" ]; ok $? "$p does not link OpenImageIO (a plugin: $n)"
done
done_testing
