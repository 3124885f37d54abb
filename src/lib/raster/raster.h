/* raster.h - row-streaming float32 rasters: OpenEXR scanline files at rest,
 * the fqm(5) stream on pipes. Every reader accepts either form (detected by
 * magic), and a band list, a text file naming rasters that are column
 * bands of one, read as that one (fqm(5) BAND LISTS); a writer makes EXR
 * for a file name and the stream for "-".
 *
 * A row is channel-planar: channel c of row y occupies row[c*width ..
 * c*width + width - 1], channels in the header's (sorted) order. Rows are
 * read and written strictly in order 0 .. height-1; only a few rows are ever
 * held (one EXR chunk), whatever the raster's size. */
#ifndef TL_RASTER_H
#define TL_RASTER_H

#include "base/util.h"
#include "geo/georef.h"

enum rs_type { RS_INT, RS_DOUBLE, RS_STRING, RS_V2I, RS_V2D };

typedef struct {
	char name[64];
	enum rs_type type;
	union {
		int i;
		double d;
		int v2i[2];
		double v2d[2];
	} v;
	char *s; /* RS_STRING value, owned */
} rs_attr;

#define RS_MAXCH 16
#define RS_MAXATTR 64

/* int: a raster that is a window of a wider one: its column 0 is column
 * x0 of that one (absent: 0). A band list's bands are such windows. */
#define RS_ATTR_X0 "fqm:x0"

typedef struct {
	int width, height;
	int nch;
	char ch[RS_MAXCH][32]; /* ascending strcmp order, as EXR stores them */
	int nattr;
	rs_attr attr[RS_MAXATTR]; /* in insertion order; names unique */
} rs_header;

void rs_header_init(rs_header *h, int width, int height);
void rs_header_free(rs_header *h); /* frees strings; h can be re-inited */
/* dst is overwritten (not freed first). */
int rs_header_copy(rs_header *dst, const rs_header *src, tl_err *e);

/* Adds a channel keeping the list sorted; -1 if full, too long or present. */
int rs_add_channel(rs_header *h, const char *name, tl_err *e);
void rs_clear_channels(rs_header *h);
int rs_channel(const rs_header *h, const char *name); /* index, or -1 */
/* Index of a channel that must exist; fills e ("what: no channel NAME"). */
int rs_need_channel(const rs_header *h, const char *name, const char *what,
    tl_err *e);

/* Attribute setters replace a same-named attribute; they fail only when the
 * table is full or the name longer than 63 bytes. */
int rs_set_int(rs_header *h, const char *name, int v, tl_err *e);
int rs_set_double(rs_header *h, const char *name, double v, tl_err *e);
int rs_set_string(rs_header *h, const char *name, const char *v, tl_err *e);
int rs_set_v2i(rs_header *h, const char *name, int x, int y, tl_err *e);
int rs_set_v2d(rs_header *h, const char *name, double x, double y, tl_err *e);
void rs_unset(rs_header *h, const char *name);
/* Getters return 0, or -1 when absent or of another type. */
int rs_get_int(const rs_header *h, const char *name, int *v);
int rs_get_double(const rs_header *h, const char *name, double *v);
const char *rs_get_string(const rs_header *h, const char *name); /* or NULL */
int rs_get_v2i(const rs_header *h, const char *name, int v[2]);
int rs_get_v2d(const rs_header *h, const char *name, double v[2]);
/* The attribute called name, or NULL. */
const rs_attr *rs_find_attr(const rs_header *h, const char *name);
/* 1 when a and b hold the same type and value, bit for bit (a NaN equals
 * the same NaN, -0 is not 0); names are not compared. */
int rs_attr_same(const rs_attr *a, const rs_attr *b);

/* --- reading ---------------------------------------------------------- */

typedef struct rs_reader rs_reader;

/* Opens path ("-" = stdin) as EXR or fqm stream. An EXR arriving on a pipe
 * is spooled to an anonymous scratch file first (EXR needs seeking).
 *
 * Or as a band list ("fqm-bands 1", then a path a line, left to right,
 * relative to the list's directory): a file only, whose bands are regular
 * files of either form, of the same height, channels and attributes
 * (RS_ATTR_X0 apart), their columns contiguous by RS_ATTR_X0. It reads as
 * one raster: the first band's header, widths summed, RS_ATTR_X0 the
 * first band's (unset when 0). It holds one file descriptor and one
 * reader per band, and one band's row; each band's reader checks its own
 * data as it goes, so a damaged band is reported by the row that reaches
 * it. Spans read only the bands they overlap. */
rs_reader *rs_open(const char *path, tl_err *e);
/* The same for an input that must be a regular file (a pyramid's block,
 * vgis(5)): a FIFO, device or directory is refused at once ("path: not a
 * regular file (a FIFO)"), never waited on; band lists are refused. */
rs_reader *rs_open_regular(const char *path, tl_err *e);
const rs_header *rs_header_of(const rs_reader *r);
/* Reads the next row; after the last row of a stream it also checks the
 * trailer, so truncation is reported before the caller commits output. */
int rs_read_row(rs_reader *r, float *row, tl_err *e);
/* The same row without a copy where the reader has it in memory (a ring
 * of rows between threads, rs_ring.h): a pointer to it, valid until the
 * next read or rs_close; else read into buf (a row's floats) and buf.
 * NULL on failure. */
const float *rs_read_row_view(rs_reader *r, float *buf, tl_err *e);
/* Reads columns x0 .. x0+n-1 of the next row of every channel, channel c
 * at dst + c n. From a complete stream file (its size and trailer checked
 * once) each row is read by position, whole, for its checksum covers
 * the whole row (a damaged row is reported by its number), and only the
 * span is copied out; otherwise whole rows are read in sequence and
 * verified. Of a band list, each band overlapped is read so, a band left
 * behind by earlier spans first skipping the rows it missed (by position
 * in a complete stream file, otherwise read and verified). A reader is
 * read by rows or by spans, not both. */
int rs_read_span(rs_reader *r, int x0, int n, float *dst, tl_err *e);
void rs_close(rs_reader *r);

/* --- writing ---------------------------------------------------------- */

enum rs_compression { RS_ZIP, RS_NONE, RS_RLE, RS_ZIPS, RS_PIZ };

/* Parses "zip", "none", "rle", "zips", "piz"; -1 if unknown. */
int rs_compression_parse(const char *s, enum rs_compression *c);

typedef struct rs_writer rs_writer;

/* path "-": the fqm stream on stdout. Otherwise an EXR scanline file, built
 * under a temporary name and renamed by rs_finish. */
rs_writer *rs_create(const char *path, const rs_header *h,
    enum rs_compression c, tl_err *e);
/* rs_create of an EXR file in a directory swept once, or that no dead
 * writer's temporaries can be in (tl_out_begin_fresh). */
rs_writer *rs_create_fresh(const char *path, const rs_header *h,
    enum rs_compression c, tl_err *e);
/* rs_create of a new EXR file inside a tree this process builds, under
 * its final name (tl_out_begin_tree). */
rs_writer *rs_create_tree(const char *path, const rs_header *h,
    enum rs_compression c, tl_err *e);
int rs_write_row(rs_writer *w, const float *row, tl_err *e);
/* Where to make the next row so that rs_write_row need not copy it: the
 * ring's slot itself (rs_ring.h), or own (a row's floats). NULL on
 * failure. */
float *rs_write_row_buffer(rs_writer *w, float *own, tl_err *e);
/* All rows written: stream trailer, or EXR offsets + rename (in a tree,
 * rs_create_tree, + close). Always frees w; on failure the output is
 * discarded as by rs_abort. */
int rs_finish(rs_writer *w, tl_err *e);
/* Discards: removes the temporary file; a stream gets no trailer, so its
 * reader reports truncation. Safe on NULL. */
void rs_abort(rs_writer *w);

/* Writes / reads a grid's georeferencing as the geo:* attributes
 * documented in fqm(5) (rs_georef.c). */
int rs_put_georef(const georef *g, rs_header *h, tl_err *e);
int rs_get_georef(georef *g, const rs_header *h, tl_err *e);

#endif
