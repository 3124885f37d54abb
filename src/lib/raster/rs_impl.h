/* rs_impl.h - private to raster/: the reader and writer objects, the
 * entry points of the backends (exr*.c, stream.c, rs_list.c) that the
 * front door raster.c dispatches to, and the size caps of rs_header.c. */
#ifndef TL_RS_IMPL_H
#define TL_RS_IMPL_H

#include "raster/raster.h"

/* Sanity caps shared by both forms, so that garbage cannot make a reader
 * allocate gigabytes before it notices. */
#define RS_MAXDIM (1 << 26)
#define RS_MAXROW (1 << 30) /* bytes: 4 x channels x width */
#define RS_MAXSTR 65535

struct rs_reader {
	rs_header h;
	char *name;  /* for messages: the path, or "stdin" */
	int fd;
	int ownfd;   /* close fd in rs_close */
	int y;       /* next row */
	int failed;  /* an error was reported: every later read fails */
	int (*row)(rs_reader *, float *, tl_err *);
	/* the next row where it lies (a ring's slot), held until the next
	 * read or the close; NULL: none, rows are copied (rs_read_row) */
	const float *(*view)(rs_reader *, tl_err *);
	/* columns x0 .. x0+n-1 of the next row, straight from the file;
	 * returns 1 when it cannot (not a complete stream file): the caller
	 * then reads whole rows. NULL: never. */
	int (*span)(rs_reader *, int x0, int n, float *dst, tl_err *);
	/* skips the next n rows of a reader read by spans by moving y
	 * alone (the caller does), when its spans come by pread; returns 1
	 * when it cannot: the caller reads and discards them. NULL: never. */
	int (*skip)(rs_reader *, int n);
	float *full; /* a whole row, for spans read as whole rows */
	void (*close)(rs_reader *);
	void *impl;
	unsigned char pre[8]; /* bytes rs_open read to find the magic */
	int npre;
};

struct rs_writer {
	rs_header h;
	char *name;  /* for messages */
	int y;       /* next row */
	int failed;
	int (*row)(rs_writer *, const float *, tl_err *);
	/* where the next row may be made in place (a ring's slot, taken
	 * until that row is written); NULL: none, rows are copied */
	float *(*slot)(rs_writer *, tl_err *);
	int (*finish)(rs_writer *, tl_err *);
	void (*abort)(rs_writer *);
	void *impl;
};

/* Size and channel count within the caps above; fills e ("name: ...")
 * (rs_header.c). */
int rs_check_size(const rs_header *h, const char *name, tl_err *e);

/* EXR (exr_read.c, exr_write.c): fd is a regular file (or scratch spool), read with pread from base. */
int rs_exr_open_read(rs_reader *r, long long base, tl_err *e);
/* How an EXR file is begun (outfile.h): tl_out_begin, tl_out_begin_fresh,
 * tl_out_begin_tree. */
enum rs_begin { RS_BEGIN, RS_BEGIN_FRESH, RS_BEGIN_TREE };
int rs_exr_create(rs_writer *w, const char *path, enum rs_compression c,
    enum rs_begin how, tl_err *e);

/* Stream (stream.c): r->pre holds the 8 magic bytes already consumed from r->fd. */
int rs_stream_open_read(rs_reader *r, tl_err *e);
int rs_stream_create(rs_writer *w, int fd, tl_err *e);

/* Band list (rs_list.c): r->pre holds the first 8 bytes of the list
 * file r->name, r->fd the rest. */
int rs_list_open_read(rs_reader *r, tl_err *e);
/* rs_open of one band: any form but a band list. */
rs_reader *rs_open_listed(const char *path, tl_err *e);

/* Ring (rs_ring.c): whether this thread's "-" is a ring (out: the
 * output), and the reader or writer on it. */
int rs_ring_bound(int out);
int rs_ring_outfd(void); /* the thread's stdout, or -1: STDOUT_FILENO */
int rs_ring_open_read(rs_reader *r, tl_err *e);
int rs_ring_create(rs_writer *w, tl_err *e);

extern const unsigned char rs_exr_magic[4];    /* exr_read.c */
extern const unsigned char rs_stream_magic[8]; /* stream.c */
extern const unsigned char rs_list_magic[8]; /* "fqm-band" */

#endif
