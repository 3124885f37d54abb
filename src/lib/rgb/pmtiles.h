/* pmtiles.h - one PMTiles version 3 archive written from tiles that
 * arrive in any order: the PMTiles writer's one interface (pm_*). The
 * format is the PMTiles v3 specification (protomaps/PMTiles,
 * spec/v3/spec.md); pmtiles(5) says which part of it is written.
 *
 * Contract:
 * - pm_open creates the archive under a hidden temporary name beside
 *   path and a spool file beside it (base/outfile.h): nothing appears at
 *   path before pm_close succeeds; a failure, pm_abort or a fatal signal
 *   removes both, and after a killed run the next output begun in that
 *   directory does.
 * - pm_add copies a tile's bytes to the spool and keeps 24 bytes of it
 *   in memory (tile id, spool offset, length, hash): tiles come in any
 *   order, from any number of threads at once (pm_add locks; the bytes
 *   are copied before it returns). After a pm_add that failed only
 *   pm_abort remains. Disk: the spool holds every tile given until
 *   pm_close has copied each distinct content into the archive.
 * - pm_close sorts the tiles by tile id, stores each distinct content
 *   once (equal hash and length, then equal bytes), merges a run of
 *   consecutive tile ids of one content into one entry, and writes the
 *   archive clustered: header, root directory, metadata, leaf
 *   directories, tile data; directories and metadata gzip'd (base/gzip.h),
 *   tiles stored as given (tile compression none). While it runs it holds
 *   12 more bytes a tile (data offsets, and a permutation while it finds
 *   duplicates) and the gzip'd leaf directories. It frees the writer,
 *   whether it succeeds or not.
 * - The archive depends only on the set of (z, x, y, bytes) and on the
 *   pm_meta: byte-identical whatever the order of the pm_add calls.
 * - Refused: a zoom past PM_MAXZOOM, x or y past the zoom's 2^z, an
 *   empty tile, a tile given twice, a tile outside the header's zooms,
 *   no tile at all, metadata that is not a JSON object; each "path: why".
 */
#ifndef TL_PMTILES_H
#define TL_PMTILES_H

#include <stddef.h>
#include <stdint.h>

#include "base/util.h"

#define PM_MAXZOOM 31 /* the deepest zoom a 64-bit tile id holds */

/* The header's tile types (spec 3.2, Tile Type). */
enum { PM_PNG = 2, PM_JPEG = 3, PM_WEBP = 4 };

/* What the header and the metadata section say besides the tiles. */
typedef struct {
	int type;              /* PM_PNG, PM_JPEG or PM_WEBP */
	int minzoom, maxzoom;  /* every tile's zoom lies within them */
	double bounds[4];      /* west, south, east, north (degrees) */
	double center[2];      /* longitude, latitude (degrees) */
	int center_zoom;       /* minzoom .. maxzoom */
	const char *json;      /* the metadata: a JSON object in UTF-8
	                        * ("encoding": "terrarium", ...), stored
	                        * as given */
} pm_meta;

typedef struct pm_writer pm_writer;

/* The writer of the archive path: NULL with "path: why" when it cannot
 * be created (an unwritable directory fails here, not at the end). */
pm_writer *pm_open(const char *path, tl_err *e);
/* Tile z/x/y (XYZ: rows from the north), n bytes: 0, or -1. */
int pm_add(pm_writer *w, int z, unsigned x, unsigned y, const void *bytes,
    size_t n, tl_err *e);
/* The archive written and renamed onto its path: 0, or -1 (nothing
 * left). Frees w in both cases. */
int pm_close(pm_writer *w, const pm_meta *m, tl_err *e);
/* Drops the archive and frees w; never fails. NULL does nothing. */
void pm_abort(pm_writer *w);

/* The tile id of z/x/y: the tiles of the zooms above z, then z/x/y's
 * place on zoom z's Hilbert curve (spec 4.1, TileID). z <= PM_MAXZOOM,
 * x, y < 2^z. */
uint64_t pm_tileid(int z, uint32_t x, uint32_t y);
/* Its inverse: 0, or -1 for an id past zoom PM_MAXZOOM. */
int pm_tile_zxy(uint64_t id, int *z, uint32_t *x, uint32_t *y);

#endif
