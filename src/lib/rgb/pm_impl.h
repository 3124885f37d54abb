/* pm_impl.h - the pieces of the PMTiles writer (pmtiles.h), shared by its
 * files and exposed for its unit test: varints and directories
 * (pm_dir.c), duplicate contents (pm_dedup.c), the archive (pm_write.c). */
#ifndef TL_PM_IMPL_H
#define TL_PM_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "base/util.h"
#include "rgb/pmtiles.h"

#define PM_HEADER 127   /* bytes of the header */
#define PM_ROOT_MAX (16384 - PM_HEADER) /* gzip'd root directory, at most */
#define PM_LEAF_MIN 4096 /* entries of a leaf directory, at least */

/* A tile as pm_add keeps it: 24 bytes. */
typedef struct {
	uint64_t id;    /* pm_tileid */
	uint64_t off;   /* in the spool */
	uint32_t len;
	uint32_t hash;  /* pm_hash of its bytes */
} pm_tile;

/* A directory entry (spec 4.1): run 0 points to a leaf directory. */
typedef struct {
	uint64_t id;
	uint64_t off;   /* in the tile data, or in the leaf directories */
	uint32_t len;
	uint32_t run;
} pm_entry;

/* A growing byte buffer. */
typedef struct {
	unsigned char *p;
	size_t n, cap;
} pm_buf;

int pm_buf_put(pm_buf *b, const void *src, size_t n, tl_err *e);
void pm_buf_free(pm_buf *b);

/* v as a little-endian base-128 varint (1 to 10 bytes) at p: its length. */
size_t pm_varint_put(unsigned char *p, uint64_t v);
/* The varint at p, n bytes there: its length, or 0 when it is cut short
 * or longer than 10 bytes. */
size_t pm_varint_get(const unsigned char *p, size_t n, uint64_t *v);

/* Entries read in order: the entry at position pos into *en, and the
 * position of the next one. A directory is encoded in four passes over
 * its entries (ids, runs, lengths, offsets: spec 4.2), each from its
 * first position. */
typedef size_t (*pm_next)(const void *src, size_t pos, pm_entry *en);
/* pm_next over an array of pm_entry (position = index). */
size_t pm_array_next(const void *src, size_t pos, pm_entry *en);

/* count entries of src from pos, encoded (spec 4.2, not compressed) and
 * appended to raw; *end: the position after them (may be NULL). */
int pm_dir_raw(pm_next next, const void *src, size_t pos, size_t count,
    pm_buf *raw, size_t *end, tl_err *e);
/* The same, gzip'd, appended to out. */
int pm_dir_encode(pm_next next, const void *src, size_t pos, size_t count,
    pm_buf *out, size_t *end, tl_err *e);
/* The directories of count entries of src (count > 0): every one in the
 * root when there are fewer than 16384 and the root then fits in
 * PM_ROOT_MAX bytes; otherwise leaves of L entries each (the last one
 * shorter), L = max(PM_LEAF_MIN, count / 3500) doubled until the root
 * of their pointers fits. root and leaves (the leaf section) filled;
 * *nleaves leaves. */
int pm_dirs(pm_next next, const void *src, size_t count, pm_buf *root,
    pm_buf *leaves, size_t *nleaves, tl_err *e);

/* 32 bits of hash of n bytes (FNV-1a 64, folded). */
uint32_t pm_hash(const void *p, size_t n);

/* The tiles t[0..n), sorted by id, as the archive stores them: doff[i],
 * tile i's offset in the tile data (a duplicate gets the offset of the
 * first tile of its content); *ncontents, the distinct contents; the
 * bytes read from spool (maxlen: the longest tile). */
int pm_dedup(const pm_tile *t, size_t n, int spool, uint32_t maxlen,
    uint64_t *doff, size_t *ncontents, tl_err *e);

/* The tiles t[0..n) with their data offsets as directory entries:
 * pm_next's source for pm_tiles_next, which merges a run of
 * consecutive ids of one content into one entry. */
typedef struct {
	const pm_tile *t;
	const uint64_t *doff;
	size_t n;
} pm_tiles;
size_t pm_tiles_next(const void *src, size_t pos, pm_entry *en);

#endif
