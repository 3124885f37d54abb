/* dem_gdal.h - inside the DEM reader, the GDAL side: what the files that
 * talk to GDAL share (dem_gdal_env.c, dem_pam.cpp, dem_gdal.c, dem_vrt.c,
 * dem_mosaic.c, dem_warp.c, dem_warp_list.c). Only they include it, and
 * only they include GDAL's headers: the rest of the reader reaches GDAL
 * through the adapter's methods (dem_gdal_adapter, dem_impl.h). */
#ifndef TL_DEM_GDAL_H
#define TL_DEM_GDAL_H

#include <gdal.h>
#include <ogr_srs_api.h>

#include "dem/dem_impl.h"

#define DEM_GRID_TOL 1e-6  /* of a pixel: "on one grid" */

/* --- GDAL itself (dem_gdal_env.c, dem_pam.cpp) --------------------------- */

/* GDAL set up once per process: drivers, a small block cache. */
void dem_gdal_init(void);

/* path opened by GDAL, raster, read-only, with its .aux.xml sidecar read
 * (PAM) but never written: every dataset the reader opens is opened so
 * (dem_pam.cpp). NULL when GDAL does not open it (its message is
 * GDAL's error). */
GDALDatasetH dem_gdal_open(const char *path);

/* GDAL's messages caught for ours instead of printed: between
 * dem_gdal_catch and dem_gdal_release (a stack, per thread), the first
 * failure lands in m->msg, the first warning in m->warning. */
typedef struct {
	char msg[512];
	char warning[512];
} dem_gdal_msg;
void dem_gdal_catch(dem_gdal_msg *m);
void dem_gdal_release(void);

/* --- a dataset read (dem_gdal.c) ------------------------------------------ */

/* What a VRT mosaic does not carry of its tiles but the reader needs:
 * GDALBuildVRT drops the dataset's metadata (AREA_OR_POINT, which moves
 * the georeferencing by half a pixel) and the band's unit, and the VRT's
 * driver hides the tiles' (an .hgt's heights are EGM96). Each field is
 * filled only when every tile agrees, "" (0) otherwise; the dataset's
 * own value, when it has one, wins. */
typedef struct {
	char driver[32];   /* the tiles' GDAL driver */
	char aop[16];      /* their AREA_OR_POINT */
	char unit[64];     /* their band's unit type */
	int signed_byte;   /* Byte with PIXELTYPE=SIGNEDBYTE (GDAL 3.6) */
	int rows;          /* the tallest block of a tile, rows per read */
} dem_tiles;

/* Reads the DEM from the open dataset ds, which stays open. t, if not
 * NULL, is what its tiles agree on; a VRT without it has its sources
 * asked (dem_vrt_tiles). */
int dem_read_dataset(dem_load *L, georef *g, GDALDatasetH ds,
    const dem_tiles *t, const dem_opts *o, tl_err *e);

/* --- mosaics (dem_mosaic.c) and dem2rgb's input (dem_warp_list.c) ------- */

/* The n DEM files paths as one in-memory VRT, after the checks of
 * dem_read_mosaic (dem_impl.h: one CRS, one grid, samples that agree;
 * with samples, their overlaps compared sample by sample); dt: what
 * the tiles agree on. what names the mosaic in messages. NULL with e
 * set naming the file at fault. The reader of a list reads this VRT;
 * dem2rgb(1) warps it. */
GDALDatasetH dem_mosaic_vrt(char *const *paths, int n, const dem_opts *o,
    int samples, const char *what, dem_tiles *dt, tl_err *e);

/* The DEM path as one GDAL dataset, for dem2rgb(1)'s warp and extent
 * (dem_warp.c): what GDAL opens, else a list of DEM files (dem2fqm(1),
 * MOSAICS) as the VRT the reader makes of it (dem_mosaic_vrt: the same
 * entries, checks, order and nodata; o: -N). GDAL's messages are kept
 * from the caller's catch. NULL with e set. */
GDALDatasetH dem_warp_open(const char *path, const dem_opts *o, int samples,
    tl_err *e);

/* --- tiles and VRT sources (dem_vrt.c) ------------------------------------ */

/* A tile's header: what every tile of a mosaic must share with the
 * first, and what the sources of a VRT are compared by. */
typedef struct {
	const char *path;
	char name[DEM_NAME];       /* path for messages (dem_name) */
	OGRSpatialReferenceH srs;  /* a clone (the file closes), NULL: none */
	double gt[6];
	int w, h, bh;              /* size, block height */
	int nbands, i8, point, has_nodata;
	GDALDataType type;
	double nodata, scale, offset;
	char driver[32], aop[16], unit[64];
} dem_head;

/* The header of the open dataset ds, of the file path, into h (zeroed
 * first; h->srs the caller's to destroy): refused when its
 * geotransform is missing, rotated, or does not run east and south. */
int dem_head_read(GDALDatasetH ds, const char *path, dem_head *h,
    tl_err *e);
/* What a VRT's own sources say, where the VRT h says nothing; depth:
 * the VRTs already looked into. */
int dem_head_vrt(GDALDatasetH ds, dem_head *h, const dem_opts *o,
    int depth, tl_err *e);
/* h noted in t, what the tiles agree on: an empty field once two
 * differ; first: t is set from h. */
void dem_tiles_note(dem_tiles *t, const dem_head *h, int first);

/* What the sources of the VRT ds agree on, each opened in turn (its
 * header only), a source that is a VRT by what its own sources say (to
 * VRT_DEPTH); t is zeroed first, and left so when a source does not open
 * (reading the VRT then says why). Refused, naming the VRT and the
 * source: a source GDAL would resample (scaled, or at a fractional
 * offset) unless o->resample, one that is not a regular file (a FIFO),
 * pixel-is-point and pixel-is-area sources in one VRT. */
int dem_vrt_tiles(GDALDatasetH ds, dem_tiles *t, const dem_opts *o,
    tl_err *e);

#endif
