/* dem.h - DEM input: GeoTIFF (8/16/32-bit integers, 16/32/64-bit floats;
 * strip or tiled; any libtiff compression; first sample), 16-bit grey PNG,
 * Terrain-RGB and Terrarium PNG, EXR, SRTM .hgt; "-" for stdin (spooled to
 * a scratch file). TIFF pixels through libtiff, georeferencing and
 * GDAL_NODATA through libgeotiff, .hgt through our own reader, every other
 * format through OpenImageIO in the plugin tl_oiio.so (oiio_plugin.h),
 * loaded only when such a file is opened. Nothing is printed.
 *
 * The source is converted once, in row order, to float32 in an anonymous
 * scratch file; voids (declared nodata, NaN, +-Inf, |z| > 1e6 m) are then
 * filled for geometry by 4-direction inverse-distance weighting (see
 * dem2fqm(1)). Afterwards any row can be read in any order with bounded
 * memory (a few rows), whatever the DEM's size. */
#ifndef TL_DEM_H
#define TL_DEM_H

#include "georef.h"
#include "oiio_plugin.h"
#include "util.h"

enum dem_encoding {
	DEM_ENC_AUTO,       /* grey: value; 8-bit RGB(A): Terrain-RGB */
	DEM_ENC_GREY,       /* first channel, native value */
	DEM_ENC_TERRAINRGB, /* Mapbox: (R*65536 + G*256 + B) / 10 - 10000 */
	DEM_ENC_TERRARIUM   /* Mapzen: R*256 + G + B/256 - 32768 */
};

typedef struct {
	enum dem_encoding encoding;
	const char *hgt_name;  /* name giving an .hgt on stdin its tile, or NULL */
	double cell[2];        /* cell size in metres for ungeoreferenced DEMs;
	                        * 0 = 1 m (the program may warn: model is
	                        * GEO_NONE); cell[1] 0 = cell[0] */
	int has_nodata;        /* override the file's nodata (the georef still
	                        * reports the file's) */
	double nodata;
} dem_opts;

typedef struct dem dem;

/* For programs reading a DEM: applies its option c, one of -e encoding,
 * -N nodata, -n name, -s dx[,dy] (optstring DEM_OPTS), with argument arg.
 * Returns 1 when c is one of them, 0 when it is not, -1 when arg is bad
 * (e says why, as "-e x: unknown encoding"). */
#define DEM_OPTS "e:N:n:s:"
int dem_option(dem_opts *o, int c, const char *arg, tl_err *e);

dem *dem_open(const char *path, const dem_opts *o, tl_err *e);
const georef *dem_georef(const dem *d); /* width, height inside */
long long dem_voids(const dem *d);      /* void samples */
/* Row j (any order): z gets heights with voids filled, valid (if not NULL)
 * gets 1 for a real sample and 0 for a void. Both have width entries. */
int dem_read_row(dem *d, int j, float *z, unsigned char *valid, tl_err *e);
void dem_close(dem *d);

/* The OpenImageIO plugin that reads the other formats, for other users
 * (tileplay writes its PNGs through it): $TL_OIIO_PLUGIN, else beside the
 * program, else ../lib/terrain-lod from it, else TL_LIBDIR; loaded once
 * and kept. NULL with the reason in why. */
const tl_oiio_api *dem_oiio_plugin(char *why, size_t n);

#endif
