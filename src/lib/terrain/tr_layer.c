/* tr_layer.c - layer.json, the TileJSON that CesiumJS's
 * CesiumTerrainProvider and cesium-native read (quantized-mesh(5)):
 * format, scheme, tile URL template, projection, zoom range, extensions
 * and the available tiles per level, as inclusive rectangles that match
 * the files written exactly. */
#include <jansson.h>
#include <stdio.h>

#include "base/outfile.h"
#include "terrain/tr_impl.h"

static json_t *
bounds(void)
{
	return json_pack("[f,f,f,f]", -180.0, -90.0, 180.0, 90.0);
}

static json_t *
available(int maxzoom, const int (*avail)[4])
{
	json_t *a = json_array();

	for (int z = 0; a && z <= maxzoom; z++)
		json_array_append_new(a, json_pack("[{s:i,s:i,s:i,s:i}]",
		    "startX", avail[z][0], "startY", avail[z][1], "endX",
		    avail[z][2], "endY", avail[z][3]));
	return a;
}

int
tr_layer_write(const char *dir, const tr_args *a, int maxzoom,
    const int (*avail)[4], const char *datum, tl_err *e)
{
	char path[4096], desc[1024];
	json_t *j;
	FILE *f;
	int r;

	snprintf(desc, sizeof desc, "quantized-mesh terrain made by "
	    "vgis2terrain from a VGIS pyramid; heights in metres above the "
	    "WGS 84 ellipsoid (%s); every tile of level L within "
	    "77067.34 m / 2^L of every DEM sample it covers, measured on the "
	    "decoded mesh; the ellipsoid (height 0) past the DEM", datum);
	j = json_pack("{s:s,s:s,s:s,s:s,s:s,s:s,s:[s],s:s,s:o,s:i,s:i,"
	    "s:[s],s:o}", "tilejson", "2.1.0", "name", "vgis2terrain",
	    "description", desc, "version", "1.0.0", "format",
	    "quantized-mesh-1.0", "scheme", "tms", "tiles",
	    "{z}/{x}/{y}.terrain?v={version}", "projection", "EPSG:4326",
	    "bounds", bounds(), "minzoom", 0, "maxzoom", maxzoom,
	    "extensions", "octvertexnormals", "available",
	    available(maxzoom, avail));
	if (j == NULL)
		return tl_fail(e, "layer.json: out of memory");
	if (a->attrib)
		json_object_set_new(j, "attribution", json_string(a->attrib));
	if (a->parent)
		json_object_set_new(j, "parentUrl", json_string(a->parent));
	snprintf(path, sizeof path, "%s/layer.json", dir);
	if ((f = fopen(path, "w")) == NULL) {
		json_decref(j);
		return tl_failsys(e, "%s", path);
	}
	r = json_dumpf(j, f, JSON_INDENT(1) | JSON_PRESERVE_ORDER |
	    JSON_REAL_PRECISION(17));
	json_decref(j);
	if (fputc('\n', f) == EOF)
		r = -1;
	if (fclose(f) != 0 || r != 0)
		return tl_failsys(e, "%s", path);
	return 0;
}
