/* dem_impl.h - inside the DEM reader (dem.h), not for its users. The
 * reader (dem.c) opens a DEM through a table of format adapters
 * (dem_adapter: GDAL in dem_gdal.c, a list of DEM files in dem_list.c,
 * OpenImageIO for EXR in dem_oiio.c), each of which converts its source
 * samples through the sink they share (dem_load, dem_load.c); the GDAL
 * side's own interface is dem_gdal.h, the only one with GDAL's types.
 * Also here: the void filling (dem_voidfill.c) and filled DEM files
 * (dem_filled.c, dem_filled_jobs.c). */
#ifndef TL_DEM_IMPL_H
#define TL_DEM_IMPL_H

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
 * does not fill the screen; returns buf (DEM_NAME bytes) (dem_load.c). */
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
	float *band;             /* rows by0 .. by1-1 staged (dem_load_band),
	                          * bandcap floats (dem_map); by1 = by0:
	                          * none */
	size_t bandcap, staged;  /* staged: the samples put into it */
	int by0, by1;            /* north-up, within cy0 .. cy1 */
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
	/* the rows' source: NULL, fd as below (dem.c); else the method
	 * that reads row j, columns x0 .. x0+n-1 (checked by the caller),
	 * of a filled DEM file (dem_filled.c) */
	int (*span)(dem *d, int j, int x0, int n, float *z,
	    unsigned char *valid, tl_err *e);
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
	struct dem_async *fill;  /* the fill's second pass, running beside
	                          * the readers (dem.c); NULL: none */
	char what[DEM_NAME];     /* the file, for messages (dem_name) */
};

/* --- the sink the adapters call back (dem_load.c) ------------------- */

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

/* Scratch writes a band at a time: source rows y .. y+n-1, every kept
 * column of each, are staged in memory by the dem_load_put calls that
 * follow, and dem_load_flush writes them in one pwrite (the same bytes
 * at the same offsets as a pwrite per put). A band of more than
 * DEM_BANDBYTES (its kept rows x kept columns x 4 bytes) is not staged:
 * its puts write as they come. Every kept sample of the band must be put
 * before the flush. */
#define DEM_BANDBYTES (32LL << 20)

/* n bytes, zeroed, for a band or chunk of rows, and their release
 * (dem_load.c): mapped, not malloc'd, so that unmapping gives them back
 * to the system at once and leaves glibc's mmap threshold, which the
 * free of a large block raises for the rest of the run, where it was. */
void *dem_map(size_t n, tl_err *e);
void dem_unmap(void *p, size_t n);
int dem_load_band(dem_load *L, int y, int n, tl_err *e);
int dem_load_flush(dem_load *L, tl_err *e);

/* --- the adapters ------------------------------------------------- */

/* What the reader knows of an input before any adapter reads it: a path
 * in GDAL's virtual file systems (/vsizip/...), a file whose first bytes
 * say nothing, say EXR, or say a format GDAL reads. */
enum dem_input { DEM_IN_VSI, DEM_IN_NONE, DEM_IN_EXR, DEM_IN_KNOWN };

/* Refuses at once what is not a regular file (a FIFO is not waited on)
 * and tells an EXR, a GDAL format known by its magic, or nothing, by the
 * first bytes (dem.c); every way into a DEM file starts here. */
int dem_check_file(const char *path, enum dem_input *kind, tl_err *e);

/* A format adapter: its methods. The reader tries them in its table's
 * order (dem.c) on the inputs they take. */
typedef struct {
	const char *name;
	unsigned takes;  /* the inputs it is tried on: 1 << enum dem_input */
	/* Reads path into L (with L->info its header only): 0, -1, or 1
	 * when the file is not this adapter's (the next is tried). base: what
	 * a list's relative entries are relative to (NULL: its directory) */
	int (*read)(dem_load *L, georef *g, const char *path,
	    const char *base, enum dem_input in, const dem_opts *o, tl_err *e);
	/* The files reading path reads besides path itself, into *files (n,
	 * each malloc'd, the array too): 0, 1 when path is not this
	 * adapter's, -1. NULL: none. */
	int (*files)(const char *path, char ***files, int *n, tl_err *e);
} dem_adapter;

extern const dem_adapter dem_gdal_adapter;  /* dem_gdal.c: what GDAL reads */
extern const dem_adapter dem_list_adapter;  /* dem_list.c: a list of DEMs */
extern const dem_adapter dem_oiio_adapter;  /* dem_oiio.c: EXR */

/* The entries of the list of DEM files path, resolved and checked as
 * its reading checks them (a missing file, a directory, a FIFO refused,
 * naming the line), into *paths (n, each malloc'd, the array too): 0,
 * -1, or 1 when path is no list (dem_list.c). */
int dem_list_paths(const char *path, char ***paths, int *n, tl_err *e);

/* 1 when GDAL identifies the file path as a VRT (dem_gdal.c). */
int dem_gdal_is_vrt(const char *path);

/* The n DEM files paths, checked to lie on one grid and to agree where
 * they overlap (not with L->info, which reads no sample), read as one DEM
 * through an in-memory VRT (dem_mosaic.c). A refusal names the file at
 * fault. */
int dem_read_mosaic(dem_load *L, georef *g, char *const *paths, int n,
    const dem_opts *o, tl_err *e);

/* --- the reader, for the fill jobs (dem.c) -------------------------- */

/* Only rows y0 .. y1-1 of the DEM (north-up), converted unfilled into
 * fd (a dup of it is kept: the dem's own), row j at j W 4 bytes, NaN
 * for a void, as dem_open converts them; the source is read only where
 * its blocks meet those rows. dem_voids and the row bitmap count those
 * rows only; dem_read_row reads them (unfilled, valid 0 for a void). A
 * row band's first pass of a filled DEM file (dem_filled_jobs.c). */
dem *dem_open_rows(const char *path, const dem_opts *o, int y0, int y1,
    int fd, tl_err *e);

/* --- void filling (dem_voidfill.c) ---------------------------------- */

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
 * mask per such row (dem_voidfill.c documents the method), in two
 * passes: dem_fill_up reads every row (NULL on failure), dem_fill_down
 * then fills and writes them top-down, telling done(ctx, n) (may be
 * NULL) each time rows 0 .. n-1 are in place, filled, their masks too;
 * done returns -1 to stop it (which fails). dem_fill_free ends either. */
typedef struct dem_filling dem_filling;
dem_filling *dem_fill_up(int fd, const unsigned char *rowvoid, int w,
    int h, tl_err *e);
int dem_fill_down(dem_filling *f, int (*done)(void *, int), void *ctx,
    tl_err *e);
void dem_fill_free(dem_filling *f);

/* --- filled DEM files (dem_filled.c) ---------------------------------- */

/* 64-bit FNV-1a of p[0 .. n-1] from h, DEM_FNV0 to begin (dem_load.c). */
#define DEM_FNV0 0xcbf29ce484222325ULL
uint64_t dem_fnv(uint64_t h, const void *p, size_t n);

/* A fingerprint (64-bit FNV-1a, no cryptography) of what makes the values
 * a DEM's samples become: its size and georeferencing (g as the file
 * declares it, before the datum conversion), the resolved conversion of
 * L (encoding, nodata, scale, offset, unit, flips) and the datum options
 * of o. dem_load_begin takes it, the same for dem_open and
 * dem_open_info, so a filled DEM file can be matched to its DEM from the
 * DEM's header alone (dem_load.c). */
uint64_t dem_fingerprint(const dem_load *L, const georef *g,
    const dem_opts *o);

/* The header and row bitmap of a filled DEM file for a w x h DEM with
 * voids void samples, rows with voids marked in rowvoid, fingerprint
 * print, written to fd as dem_save_filled writes them; *zoff, *moff and
 * *size: where the heights and masks go, and the file's size. */
int dem_filled_head(int fd, const char *path, int w, int h,
    const unsigned char *rowvoid, long long voids, uint64_t print,
    long long *zoff, long long *moff, long long *size, tl_err *e);

#endif
