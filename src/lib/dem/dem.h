/* dem.h - DEM input: any raster GDAL reads (GeoTIFF, COG, SRTM .hgt and
 * .hgt.zip, Esri .asc, ENVI, VRT mosaics, NetCDF, PNG with a world file,
 * ...) and EXR (OpenImageIO, in the plugin tl_oiio.so, loaded only for
 * it); "-" for stdin (spooled to a file named by -n, so GDAL knows an
 * .hgt by its name). Georeferencing, nodata (NaN too), mask bands,
 * scale/offset and vertical units come from GDAL; heights come out in
 * metres, optionally converted to another vertical datum (vdatum.h).
 * South-up and east-left grids are turned north-up; rotated ones are
 * refused. Nothing is printed.
 *
 * The source is converted once, in row order, to float32 in an anonymous
 * scratch file; voids (declared nodata, masked, NaN, +-Inf, |z| > 1e6 m)
 * are then filled for geometry by 4-direction inverse-distance weighting
 * (see dem2fqm(1)). Afterwards any row can be read in any order with
 * bounded memory (a few rows), whatever the DEM's size. The filled
 * samples can be saved to a filled DEM file (filled(5)), from which jobs
 * read windows of the DEM without converting or filling it again. */
#ifndef TL_DEM_H
#define TL_DEM_H

#include <stdio.h>

#include "geo/georef.h"
#include "base/util.h"

enum dem_encoding {
	DEM_ENC_AUTO,       /* grey: value; 8-bit RGB(A): Terrain-RGB */
	DEM_ENC_GREY,       /* first channel, native value */
	DEM_ENC_TERRAINRGB, /* Mapbox: (R*65536 + G*256 + B) / 10 - 10000 */
	DEM_ENC_TERRARIUM   /* Mapzen: R*256 + G + B/256 - 32768 */
};

typedef struct {
	enum dem_encoding encoding;
	const char *hgt_name;  /* the name of a DEM on stdin (-n), or NULL */
	double cell[2];        /* -s: cell size in metres. Without a
	                        * geotransform it is the grid's step (0 = 1 m,
	                        * the program may warn: model GEO_NONE); with
	                        * one it overrides the CRS's metric (georef
	                        * cell). cell[1] 0 = cell[0] */
	int has_nodata;        /* override the file's nodata (the georef still
	                        * reports the file's) */
	double nodata;
	const char *heights;   /* -H: vertical datum to convert heights to
	                        * ("ellipsoid", "EPSG:5773"), NULL: as read */
	const char *vdatum;    /* -D: the DEM's vertical datum when it
	                        * declares none (or another), NULL: the file's */
	int resample;          /* --resample: a VRT's scaled or misplaced
	                        * sources resampled by GDAL, not refused */
} dem_opts;

typedef struct dem dem;

/* For programs reading a DEM: applies its option c, one of -e encoding,
 * -N nodata, -n name, -s dx[,dy], -H datum, -D datum (optstring DEM_OPTS),
 * with argument arg. Returns 1 when c is one of them, 0 when it is not,
 * -1 when arg is bad (e says why, as "-e x: unknown encoding"). */
#define DEM_OPTS "e:N:n:s:H:D:"
/* and --resample, a long option only (cli.c adds it): c is DEM_RESAMPLE */
#define DEM_RESAMPLE 0x7f00
int dem_option(dem_opts *o, int c, const char *arg, tl_err *e);

dem *dem_open(const char *path, const dem_opts *o, tl_err *e);
/* dem_open, returning once its rows can begin to be read: the void
 * fill's second pass (top-down) goes on in a thread beside the reader,
 * a read of a row it has not yet filled waits for it, and a failure of
 * the fill is told by the reads after it. For readers of rows mostly in
 * order (dem2fqm's level 0), so that they start sooner. */
dem *dem_open_streamed(const char *path, const dem_opts *o, tl_err *e);
/* Only columns x0 .. x1-1 of every row (north-up), for a job that needs a
 * window of a DEM larger than it should read (a tilepack piece): the
 * scratch file holds the window, the source is read only where its
 * blocks meet the window (all of a row for a striped file). Voids are not
 * filled (the fill reaches across the whole DEM): a void's z is NaN,
 * its valid 0. The georeferencing, the size and dem_read_span's column
 * numbers are the whole DEM's; a span outside the window fails. */
dem *dem_open_cols(const char *path, const dem_opts *o, int x0, int x1,
    tl_err *e);
/* dem_open_cols of rows y0 .. y1-1 only (a part of a piece, which scans
 * a band of the DEM's rows): the scratch file holds those rows of the
 * window (the others are holes), the source is read from the block
 * holding row y0; a span of another row fails. */
dem *dem_open_window(const char *path, const dem_opts *o, int x0, int x1,
    int y0, int y1, tl_err *e);
/* Saves d's converted, void-filled samples and validity (what
 * dem_read_row gives for every row; d from dem_open or dem_open_filled)
 * to path as a filled DEM file (filled(5)), streamed a row at a time,
 * atomically: built under a hidden temporary name beside path and renamed
 * when complete, nothing left behind on failure. A job that needs a
 * window of a DEM too large to fill per job reads it back with
 * dem_open_filled. */
int dem_save_filled(dem *d, const char *path, tl_err *e);
/* dem_save_filled's file made in row bands by several jobs (filled(5),
 * PARTS), byte for byte the same: pass 1 per band of rows y0 .. y1-1
 * converts them, unfilled, into filled.raw and writes the band's state
 * filled.s.Y0; the join, once all pass 1 are done, reads the states of
 * the bands [k band_rows, (k+1) band_rows) (band_rows: --band-rows)
 * and writes each band's edges filled.e.Y0 and filled.tmp's header;
 * pass 2 per band (after the join) fills its rows into filled.tmp and
 * marks it done, filled.d.Y0;
 * the commit, once every pass 2 is done, checks and renames filled.tmp
 * to filled and removes the rest. Each part takes the DEM and the same
 * options o (the parts are checked to match), bands may run at once on
 * any hosts sharing the directory, and any part may be run again. */
int dem_fill_pass1(const char *dem_path, const dem_opts *o,
    const char *filled, int y0, int y1, tl_err *e);
int dem_fill_join(const char *dem_path, const dem_opts *o,
    const char *filled, int band_rows, tl_err *e);
int dem_fill_pass2(const char *dem_path, const dem_opts *o,
    const char *filled, int y0, int y1, tl_err *e);
int dem_fill_commit(const char *dem_path, const dem_opts *o,
    const char *filled, int band_rows, tl_err *e);
/* The DEM at dem_path (its header only, as dem_open_info reads it, with
 * options o) whose samples are read from the filled DEM file that
 * dem_save_filled wrote for it: dem_read_row and dem_read_span give
 * exactly what they give on dem_open(dem_path, o), bit for bit, reading
 * only the bytes asked for (pread); dem_voids is the file's count. Fails,
 * naming the file, when it is not such a file, is truncated or damaged,
 * or was made from another DEM or with other options (its size and a
 * fingerprint of what makes the values: dem_impl.h, dem_fingerprint).
 * Neither path may be "-": a DEM on stdin cannot be opened again. */
dem *dem_open_filled(const char *dem_path, const dem_opts *o,
    const char *filled, tl_err *e);
/* The DEM's header only (dem2fqm -I): georeferencing, size, nodata,
 * vertical datum (-H, -D checked as dem_open does) and unit, read
 * through GDAL (or OpenImageIO) without reading a sample nor making a
 * scratch file, so it answers at once whatever the DEM's size. Its voids
 * are unknown (-1) and dem_read_row fails. */
dem *dem_open_info(const char *path, const dem_opts *o, tl_err *e);
const georef *dem_georef(const dem *d); /* width, height inside */
long long dem_voids(const dem *d);      /* void samples (of a window: its
                                         * own); -1: unknown */
double dem_zunit(const dem *d);         /* metres per unit of the file */
/* Row j (any order): z gets heights with voids filled, valid (if not NULL)
 * gets 1 for a real sample and 0 for a void. Both have width entries. */
int dem_read_row(dem *d, int j, float *z, unsigned char *valid, tl_err *e);
/* Columns x0 .. x0+n-1 of row j, likewise (n entries each). Both read
 * with pread(2) only: threads may read one dem at once. */
int dem_read_span(dem *d, int j, int x0, int n, float *z,
    unsigned char *valid, tl_err *e);
void dem_close(dem *d);

/* Adds to s the files the DEM at path is read from, for its reader's
 * outputs to keep off (paths.h): path, a list's entries, and what GDAL
 * reads for path and for a list's VRTs (a VRT's sources, followed into
 * VRTs). Nothing but a regular file is opened. "-" adds none. */
struct tl_paths;
int dem_paths(struct tl_paths *s, const char *path, tl_err *e);

/* dem2fqm -I: what a user needs to trust the result and a script to plan
 * a pyramid, as "key value" lines on f (dem2fqm(1)); "voids N" only when
 * they are known (a DEM from dem_open, not dem_open_info). */
int dem_info_print(const dem *d, FILE *f, tl_err *e);
/* A grid without a CRS has no known unit: fills buf with what was
 * assumed (and how to say otherwise) and returns 1, or returns 0. name
 * names the DEM. */
int dem_ground_note(const dem *d, const dem_opts *o, const char *name,
    char *buf, size_t n);

#endif
