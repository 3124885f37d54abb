/* dem_impl.h - inside the DEM reader (dem.h): the conversion of source
 * samples into the scratch file, which its format adapters share (GDAL in
 * dem_gdal.c, OpenImageIO for EXR in dem_oiio.c), and the void filling.
 * Not for users of dem.h. */
#ifndef TL_DEM_IMPL_H
#define TL_DEM_IMPL_H

#include "core/dem.h"
#include "core/oiio_plugin.h"

/* Sizes refused before anything is allocated or read: a side, the
 * samples (2^40 would need 4 TiB of float32 scratch), a row as read
 * (DEM_SAMPLEBYTES: float64, the widest buffer a row takes). */
#define DEM_MAXDIM (1 << 26)
#define DEM_MAXSAMPLES (1LL << 40)
#define DEM_MAXROW (1LL << 30)
#define DEM_SAMPLEBYTES 8
#define DEM_MAXABS 1e6   /* |z| beyond this (metres) is a void */

/* Source samples to metres in the scratch file: float32 rows, top row
 * first, NaN for a void. */
typedef struct {
	const char *what;        /* the file, for messages */
	int w, h, fd;
	enum dem_encoding enc;   /* resolved: never AUTO */
	int has_nodata, f32;     /* f32: compare nodata in float precision */
	double nodata;
	double scale, offset;    /* raw -> height in the file's unit */
	double zunit;            /* metres per height unit */
	int flip_x, flip_y;      /* source columns / rows run west / south */
	float *seg;              /* w floats */
	unsigned char *rowvoid;  /* one bit per row: the row has voids */
	long long voids;
	struct vdatum_shift *vd;     /* vertical datum conversion, or NULL */
	int info;                /* the header only (dem_open_info): no
	                          * scratch file, no samples read */
} dem_load;

/* Sets up the conversion once size, nodata and units are known (zunit,
 * scale, offset and the flips are set by the caller first; 0 scale = 1).
 * f32: the source is float32, so nodata compares in float. With L->info
 * it checks and describes only: the adapter then reads no sample. */
int dem_load_begin(dem_load *L, georef *g, const dem_opts *o, int w, int h,
    int f32, tl_err *e);

/* Resolves the encoding against the source: AUTO is Terrain-RGB for an
 * 8-bit image of 3 or more channels, grey otherwise. */
int dem_load_encoding(dem_load *L, const dem_opts *o, int type, int nch,
    tl_err *e);

/* Stores n samples of source row y from source column x0: p holds them
 * as enum tl_px type t, stride values apart (pixel k's channels at
 * k * stride); mask (may be NULL) 0 marks a void. */
int dem_load_put(dem_load *L, const void *p, int t, int stride, int x0,
    int y, int n, const unsigned char *mask, tl_err *e);

/* The adapters. Both return 1, not an error, when the file is not theirs
 * (the caller then says "not a raster"). The spooled name, if not NULL,
 * is the file's name for messages and format detection. */
int dem_read_gdal(dem_load *L, georef *g, const char *path,
    const dem_opts *o, tl_err *e);
int dem_read_oiio(dem_load *L, georef *g, const char *path, int known,
    const dem_opts *o, tl_err *e);

/* Fills the voids of the scratch file fd (w x h float32 rows, NaN for a
 * void; rowvoid marks the rows that have some) and appends a validity
 * mask per such row (dem_fill.c documents the method). */
int dem_fill(int fd, const unsigned char *rowvoid, int w, int h, tl_err *e);

#endif
