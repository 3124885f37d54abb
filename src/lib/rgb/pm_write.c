/* pm_write.c - one PMTiles v3 archive, from tiles in any order
 * (pmtiles.h): the spool of tiles, the 127-byte header, and the
 * sections in the specification's order (header, root directory, gzip'd
 * metadata, leaf directories, tile data), written under a temporary name
 * and renamed. The format is the PMTiles v3 specification
 * (protomaps/PMTiles spec/v3/spec.md): chapter 3 (header), 5 (metadata). */
#include "rgb/pm_impl.h"

#include <assert.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "base/byteorder.h"
#include "base/gzip.h"
#include "base/json.h"
#include "base/outfile.h"

struct pm_writer {
	tl_outfile out;   /* the archive, under its temporary name */
	tl_outfile spool; /* the tiles as they came, beside it */
	pthread_mutex_t lock;
	pm_tile *t;       /* n of cap */
	size_t n, cap;
	uint64_t end;     /* bytes in the spool */
	uint32_t maxlen;
	int failed;       /* a pm_add failed: only pm_abort remains */
};

pm_writer *
pm_open(const char *path, tl_err *e)
{
	pm_writer *w = tl_alloc(1, sizeof *w, e);

	if (w == NULL)
		return NULL;
	if (tl_out_begin(&w->out, path, e) < 0) {
		free(w);
		return NULL;
	}
	/* a second temporary of the same name: swept as the first is */
	if (tl_out_begin_fresh(&w->spool, path, e) < 0) {
		tl_out_abort(&w->out);
		free(w);
		return NULL;
	}
	pthread_mutex_init(&w->lock, NULL);
	return w;
}

/* Room for one more tile; under the lock. */
static int
grow(pm_writer *w, tl_err *e)
{
	size_t cap = w->cap ? w->cap * 2 : 1024;
	pm_tile *t;

	if (w->n < w->cap)
		return 0;
	if (w->n >= UINT32_MAX)
		return tl_fail(e, "%s: more than %u tiles", w->out.path,
		    UINT32_MAX);
	if (cap > SIZE_MAX / sizeof *t ||
	    (t = realloc(w->t, cap * sizeof *t)) == NULL)
		return tl_fail(e, "%s: out of memory", w->out.path);
	w->t = t, w->cap = cap;
	return 0;
}

static int
check_tile(const pm_writer *w, int z, unsigned x, unsigned y, size_t n,
    tl_err *e)
{
	const char *p = w->out.path;

	if (z < 0 || z > PM_MAXZOOM)
		return tl_fail(e, "%s: tile %d/%u/%u: zoom not in 0 .. %d", p,
		    z, x, y, PM_MAXZOOM);
	if ((uint64_t)x >> z != 0 || (uint64_t)y >> z != 0)
		return tl_fail(e, "%s: tile %d/%u/%u: x or y past 2^%d", p,
		    z, x, y, z);
	if (n == 0)
		return tl_fail(e, "%s: tile %d/%u/%u: empty", p, z, x, y);
	if (n > UINT32_MAX)
		return tl_fail(e, "%s: tile %d/%u/%u: %zu bytes, more than "
		    "%u", p, z, x, y, n, UINT32_MAX);
	return 0;
}

int
pm_add(pm_writer *w, int z, unsigned x, unsigned y, const void *bytes,
    size_t n, tl_err *e)
{
	pm_tile t;
	int r;

	if ((r = check_tile(w, z, x, y, n, e)) == 0) {
		t.id = pm_tileid(z, x, y);
		t.len = (uint32_t)n;
		t.hash = pm_hash(bytes, n);
	}
	pthread_mutex_lock(&w->lock);
	if (r == 0 && w->failed)
		r = tl_fail(e, "%s: a tile failed before", w->out.path);
	if (r == 0 && (r = grow(w, e)) == 0) {
		t.off = w->end, w->end += n;
		w->t[w->n++] = t;
		if (t.len > w->maxlen)
			w->maxlen = t.len;
	}
	if (r < 0)
		w->failed = 1;
	pthread_mutex_unlock(&w->lock);
	/* the tile's place is its own: written outside the lock */
	if (r == 0 && tl_pwrite(w->spool.fd, bytes, n, (long long)t.off,
	    w->out.path, e) < 0) {
		pthread_mutex_lock(&w->lock);
		w->failed = 1;
		pthread_mutex_unlock(&w->lock);
		r = -1;
	}
	return r;
}

static void
writer_free(pm_writer *w)
{
	tl_out_abort(&w->spool);
	tl_out_abort(&w->out); /* nothing after a commit */
	pthread_mutex_destroy(&w->lock);
	free(w->t);
	free(w);
}

void
pm_abort(pm_writer *w)
{
	if (w != NULL)
		writer_free(w);
}

static int
lonlat_ok(double lon, double lat)
{
	return isfinite(lon) && isfinite(lat) && fabs(lon) <= 180 &&
	    fabs(lat) <= 90;
}

static int
check_meta(const char *p, const pm_meta *m, tl_err *e)
{
	json_error_t je;
	json_t *j;
	int oom = 0, obj;

	if (m->type != PM_PNG && m->type != PM_JPEG && m->type != PM_WEBP)
		return tl_fail(e, "%s: tile type %d: not PNG, JPEG or WebP",
		    p, m->type);
	if (m->minzoom < 0 || m->minzoom > m->maxzoom ||
	    m->maxzoom > PM_MAXZOOM || m->center_zoom < m->minzoom ||
	    m->center_zoom > m->maxzoom)
		return tl_fail(e, "%s: zooms %d .. %d, centre %d: not 0 <= "
		    "min <= centre <= max <= %d", p, m->minzoom, m->maxzoom,
		    m->center_zoom, PM_MAXZOOM);
	if (!lonlat_ok(m->bounds[0], m->bounds[1]) ||
	    !lonlat_ok(m->bounds[2], m->bounds[3]) ||
	    m->bounds[1] > m->bounds[3] ||
	    !lonlat_ok(m->center[0], m->center[1]))
		return tl_fail(e, "%s: bounds or centre not in longitude "
		    "-180 .. 180, latitude -90 .. 90 (south <= north)", p);
	if (m->json == NULL)
		return tl_fail(e, "%s: no metadata", p);
	j = tl_json_parse(m->json, strlen(m->json), &je, &oom);
	obj = json_is_object(j);
	json_decref(j);
	if (j == NULL)
		return tl_fail(e, "%s: metadata: %s", p, oom ? "out of memory" :
		    je.text);
	return obj ? 0 : tl_fail(e, "%s: metadata: not a JSON object", p);
}

static int
by_id(const void *a, const void *b)
{
	uint64_t i = ((const pm_tile *)a)->id, j = ((const pm_tile *)b)->id;

	return (i > j) - (i < j);
}

/* The tiles in id order, each once, within the header's zooms. */
static int
sort_tiles(pm_writer *w, const pm_meta *m, tl_err *e)
{
	const char *p = w->out.path;
	uint32_t x, y;
	int z, z1;

	if (w->n == 0)
		return tl_fail(e, "%s: no tile", p);
	qsort(w->t, w->n, sizeof *w->t, by_id);
	for (size_t i = 1; i < w->n; i++)
		if (w->t[i].id == w->t[i - 1].id) {
			pm_tile_zxy(w->t[i].id, &z, &x, &y);
			return tl_fail(e, "%s: tile %d/%u/%u given twice", p,
			    z, x, y);
		}
	pm_tile_zxy(w->t[w->n - 1].id, &z1, &x, &y);
	pm_tile_zxy(w->t[0].id, &z, &x, &y);
	if (z < m->minzoom || z1 > m->maxzoom)
		return tl_fail(e, "%s: tiles of zooms %d .. %d, not within "
		    "the header's %d .. %d", p, z, z1, m->minzoom, m->maxzoom);
	return 0;
}

/* The header's numbers besides the sections' places. */
struct counts {
	uint64_t tiles, entries, contents;
};

/* A position (spec 3.4): longitude then latitude, each times 10^7 to
 * the nearest integer, little-endian 32-bit signed. */
static void
put_pos(unsigned char *p, double lon, double lat)
{
	le_put32(p, (uint32_t)(int32_t)llround(lon * 1e7));
	le_put32(p + 4, (uint32_t)(int32_t)llround(lat * 1e7));
}

/* The header (spec 3.1): sec[] the offsets and lengths of root,
 * metadata, leaves, tile data, in that order. */
static void
put_header(unsigned char h[PM_HEADER], const uint64_t sec[8],
    const struct counts *c, const pm_meta *m)
{
	memset(h, 0, PM_HEADER);
	memcpy(h, "PMTiles", 7);
	h[7] = 3;
	for (int k = 0; k < 8; k++)
		le_put64(h + 8 + 8 * k, sec[k]);
	le_put64(h + 72, c->tiles);
	le_put64(h + 80, c->entries);
	le_put64(h + 88, c->contents);
	h[96] = 1;                     /* clustered */
	h[97] = 2;                     /* internal compression: gzip */
	h[98] = 1;                     /* tile compression: none */
	h[99] = (unsigned char)m->type;
	h[100] = (unsigned char)m->minzoom;
	h[101] = (unsigned char)m->maxzoom;
	put_pos(h + 102, m->bounds[0], m->bounds[1]);
	put_pos(h + 110, m->bounds[2], m->bounds[3]);
	h[118] = (unsigned char)m->center_zoom;
	put_pos(h + 119, m->center[0], m->center[1]);
}

/* Each distinct content once, in id order, from base on: *len bytes. */
static int
copy_tiles(pm_writer *w, const uint64_t *doff, uint64_t base,
    uint64_t *len, tl_err *e)
{
	unsigned char *buf = tl_alloc(w->maxlen, 1, e);
	uint64_t at = 0;
	int r = buf == NULL ? -1 : 0;

	for (size_t i = 0; r == 0 && i < w->n; i++) {
		const pm_tile *t = &w->t[i];

		if (doff[i] != at) {
			assert(doff[i] < at); /* a duplicate */
			continue;
		}
		r = tl_pread(w->spool.fd, buf, t->len, (long long)t->off,
		    w->out.path, e);
		if (r == 0)
			r = tl_pwrite(w->out.fd, buf, t->len,
			    (long long)(base + at), w->out.path, e);
		at += t->len;
	}
	free(buf);
	*len = at;
	return r;
}

/* The sections after the header, then the header. */
static int
write_archive(pm_writer *w, const pm_meta *m, const uint64_t *doff,
    struct counts *c, tl_err *e)
{
	pm_tiles src = { w->t, doff, w->n };
	pm_buf root = { 0 }, leaves = { 0 };
	unsigned char h[PM_HEADER], *meta = NULL;
	uint64_t sec[8];
	size_t nmeta = 0, nleaves, pos = 0;
	pm_entry en;
	int r, fd = w->out.fd;

	for (c->entries = 0; pos < w->n; c->entries++)
		pos = pm_tiles_next(&src, pos, &en);
	r = pm_dirs(pm_tiles_next, &src, c->entries, &root, &leaves,
	    &nleaves, e);
	if (r == 0)
		r = tl_gzip(m->json, strlen(m->json), &meta, &nmeta, e);
	sec[0] = PM_HEADER, sec[1] = root.n;
	sec[2] = sec[0] + sec[1], sec[3] = nmeta;
	sec[4] = sec[2] + sec[3], sec[5] = leaves.n;
	sec[6] = sec[4] + sec[5];
	if (r == 0)
		r = tl_pwrite(fd, root.p, root.n, (long long)sec[0],
		    w->out.path, e);
	if (r == 0)
		r = tl_pwrite(fd, meta, nmeta, (long long)sec[2], w->out.path, e);
	if (r == 0)
		r = tl_pwrite(fd, leaves.p, leaves.n, (long long)sec[4],
		    w->out.path, e);
	if (r == 0)
		r = copy_tiles(w, doff, sec[6], &sec[7], e);
	put_header(h, sec, c, m);
	if (r == 0)
		r = tl_pwrite(fd, h, PM_HEADER, 0, w->out.path, e);
	free(meta);
	pm_buf_free(&root), pm_buf_free(&leaves);
	return r;
}

int
pm_close(pm_writer *w, const pm_meta *m, tl_err *e)
{
	struct counts c = { w->n, 0, 0 };
	uint64_t *doff = NULL;
	size_t ncontents;
	int r = -1;

	if (w->failed)
		tl_fail(e, "%s: a tile failed before", w->out.path);
	else if (check_meta(w->out.path, m, e) == 0 &&
	    sort_tiles(w, m, e) == 0 &&
	    (doff = tl_alloc(w->n, sizeof *doff, e)) != NULL &&
	    pm_dedup(w->t, w->n, w->spool.fd, w->maxlen, doff, &ncontents,
	    e) == 0) {
		c.contents = ncontents;
		if (write_archive(w, m, doff, &c, e) == 0)
			r = tl_out_commit(&w->out, e);
	}
	free(doff);
	writer_free(w);
	return r;
}
