/* dem_impl.h - inside the DEM reader (dem.h): the conversion of source
 * samples into the scratch file, which its format adapters share (GDAL in
 * dem_gdal.c, OpenImageIO for EXR in dem_oiio.c), the mosaics of several
 * files (dem_mosaic.c, lists of them in dem_list.c), the void filling, and
 * filled DEM files (dem_filled.c). Not for users of dem.h. */
#ifndef TL_DEM_IMPL_H
#define TL_DEM_IMPL_H

#include <gdal.h>
#include <stdint.h>

#include "dem/dem.h"
#include "raster/oiio_plugin.h"

/* Sizes refused before anything is allocated or read: a side, the
 * samples (2^40 would need 4 TiB of float32 scratch), a row as read
 * (DEM_SAMPLEBYTES: float64, the widest buffer a row takes). */
#define DEM_MAXDIM (1 << 26)
#define DEM_MAXSAMPLES (1LL << 40)
#define DEM_MAXROW (1LL << 30)
#define DEM_SAMPLEBYTES 8
#define DEM_MAXABS 1e6   /* |z| beyond this (metres) is a void */

/* A path as messages name it: whole up to DEM_NAME - 1 bytes, else its
 * head and tail around "...", so that a list entry of 5000 characters
 * does not fill the screen; returns buf (DEM_NAME bytes). */
#define DEM_NAME 100
const char *dem_name(const char *path, char *buf);

/* Bit i of a per-row bitmap (which rows have voids), and setting it. */
static inline int
dem_bit(const unsigned char *b, long long i)
{
	return b[i >> 3] >> (i & 7) & 1;
}

static inline void
dem_setbit(unsigned char *b, long long i)
{
	b[i >> 3] |= (unsigned char)(1 << (i & 7));
}

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
	int cx0, cx1;            /* the columns kept (dem_open_cols), in
	                          * north-up order; cx1 0: all, until
	                          * dem_load_begin resolves it */
	int cy0, cy1;            /* the rows kept (dem_open_rows), north-up;
	                          * cy1 0: all, until dem_load_begin */
	uint64_t print;          /* dem_fingerprint, by dem_load_begin */
} dem_load;

/* The dem of dem.h (dem.c), also opened on a filled DEM file
 * (dem_filled.c). */
struct dem {
	georef g;
	int fd;                  /* filled rows, then masks of void rows;
	                          * of a window (cols): its rows, unfilled;
	                          * or a filled DEM file (file) */
	int cx0, cw;             /* the columns in fd (all but dem_open_cols) */
	int cy0, cy1;            /* the rows read (dem_open_rows,
	                          * dem_open_window), or 0, 0: all */
	int unfilled;            /* dem_open_cols: NaN marks a void */
	long long voids;
	double zunit;            /* metres per height unit of the file */
	unsigned char *rowvoid;  /* one bit per row: the row has voids */
	uint64_t print;          /* dem_fingerprint of how it was read */
	struct dem_file *file;   /* where fd's rows and masks are, when fd
	                          * is a filled DEM file; else NULL */
	char what[DEM_NAME];     /* the file, for messages (dem_name) */
};

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
 * k * stride); mask (may be NULL) 0 marks a void. Samples outside the
 * kept columns are skipped, so an adapter may hand over more. */
int dem_load_put(dem_load *L, const void *p, int t, int stride, int x0,
    int y, int n, const unsigned char *mask, tl_err *e);

/* The adapters. Both return 1, not an error, when the file is not theirs
 * (the caller then says "not a raster"). The spooled name, if not NULL,
 * is the file's name for messages and format detection. */
int dem_read_gdal(dem_load *L, georef *g, const char *path,
    const dem_opts *o, tl_err *e);

/* --- GDAL, shared by the adapter and the mosaics (dem_gdal.c) --------- */

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

/* --- mosaics (dem_mosaic.c, dem_list.c) ------------------------------- */

/* The n DEM files paths, checked to lie on one grid and to agree where
 * they overlap (not with L->info, which reads no sample), read as one DEM
 * through an in-memory VRT. A refusal names the file at fault. */
int dem_read_mosaic(dem_load *L, georef *g, char *const *paths, int n,
    const dem_opts *o, tl_err *e);

/* What the sources of the VRT ds agree on, each opened in turn (its
 * header only), a source that is a VRT by what its own sources say (to
 * VRT_DEPTH); t is zeroed first, and left so when a source does not open
 * (reading the VRT then says why). Refused, naming the VRT and the
 * source: a source GDAL would resample (scaled, or at a fractional
 * offset) unless o->resample, one that is not a regular file (a FIFO),
 * pixel-is-point and pixel-is-area sources in one VRT. */
int dem_vrt_tiles(GDALDatasetH ds, dem_tiles *t, const dem_opts *o,
    tl_err *e);

/* The file path as a list of DEM files (dem2fqm(1) says what is one):
 * returns 1 when it is not one, else reads its mosaic. Relative entries
 * are relative to base, NULL for the list's own directory. */
int dem_read_list(dem_load *L, georef *g, const char *path,
    const char *base, const dem_opts *o, tl_err *e);
/* The entries of the list path, resolved as dem_read_list resolves
 * them, into *paths (n, each malloc'd, the array too): 0, 1 when path
 * is no list, -1. */
int dem_list_files(const char *path, char ***paths, int *n, tl_err *e);
int dem_read_oiio(dem_load *L, georef *g, const char *path, int known,
    const dem_opts *o, tl_err *e);

/* Only rows y0 .. y1-1 of the DEM (north-up), converted unfilled into
 * fd (a dup of it is kept: the dem's own), row j at j W 4 bytes, NaN
 * for a void, as dem_open converts them; the source is read only where
 * its blocks meet those rows. dem_voids and the row bitmap count those
 * rows only; dem_read_row reads them (unfilled, valid 0 for a void). A
 * row band's first pass of a filled DEM file (dem_filled_jobs.c). */
dem *dem_open_rows(const char *path, const dem_opts *o, int y0, int y1,
    int fd, tl_err *e);

/* The nearest valid sample in a column beyond a row (row -1: none). */
typedef struct {
	float v;
	int32_t row;
} dem_near;

/* Rows y0 .. y1-1 to fill: read unfilled from in (row j at zin + j W 4),
 * written filled to out (row j at zout + j W 4, little-endian) with the
 * validity masks of its rows with voids at moff + k W, k counting those
 * rows from rank; every row is written. above and below: per column the
 * nearest valid sample above y0 and below y1-1 (NULL: none), so that a
 * band of rows fills exactly as the whole DEM does. */
typedef struct {
	int in, out;
	long long zin, zout, moff, rank;
	int y0, y1;
	const dem_near *above, *below;
	const char *win, *wout;  /* in and out, for messages */
} dem_fill_band;
int dem_fill_rows(const dem_fill_band *b, const unsigned char *rowvoid,
    int w, int h, tl_err *e);

/* Fills the voids of the scratch file fd (w x h float32 rows, NaN for a
 * void; rowvoid marks the rows that have some) and appends a validity
 * mask per such row (dem_voidfill.c documents the method). */
int dem_fill(int fd, const unsigned char *rowvoid, int w, int h, tl_err *e);

/* --- filled DEM files (dem_filled.c) ---------------------------------- */

/* A fingerprint (64-bit FNV-1a, no cryptography) of what makes the values
 * a DEM's samples become: its size and georeferencing (g as the file
 * declares it, before the datum conversion), the resolved conversion of
 * L (encoding, nodata, scale, offset, unit, flips) and the datum options
 * of o. dem_load_begin takes it, the same for dem_open and
 * dem_open_info, so a filled DEM file can be matched to its DEM from the
 * DEM's header alone. */
uint64_t dem_fingerprint(const dem_load *L, const georef *g,
    const dem_opts *o);

/* The header and row bitmap of a filled DEM file for a w x h DEM with
 * voids void samples, rows with voids marked in rowvoid, fingerprint
 * print, written to fd as dem_save_filled writes them; *zoff, *moff and
 * *size: where the heights and masks go, and the file's size. */
int dem_filled_head(int fd, const char *path, int w, int h,
    const unsigned char *rowvoid, long long voids, uint64_t print,
    long long *zoff, long long *moff, long long *size, tl_err *e);

/* dem_read_span on a dem whose fd is a filled DEM file: row j, columns
 * x0 .. x0+n-1 (checked by the caller). */
int dem_file_span(dem *d, int j, int x0, int n, float *z,
    unsigned char *valid, tl_err *e);

#endif
