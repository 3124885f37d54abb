/* pm_dedup.c - the PMTiles writer's tile data: each distinct content
 * once, in tile-id order (clustered), every duplicate pointing to the
 * first tile of its content; and the entries with runs merged
 * (pm_impl.h). Contents are equal when hash, length and bytes are. */
#define _GNU_SOURCE /* qsort_r */
#include "rgb/pm_impl.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

uint32_t
pm_hash(const void *p, size_t n)
{
	const unsigned char *b = p;
	uint64_t h = UINT64_C(14695981039346656037);

	for (size_t i = 0; i < n; i++) {
		h ^= b[i];
		h *= UINT64_C(1099511628211);
	}
	return (uint32_t)(h ^ (h >> 32));
}

/* Tile indices by hash, length, then index: the candidates for one
 * content side by side, the first of each content first. */
static int
by_content(const void *a, const void *b, void *arg)
{
	const pm_tile *t = arg;
	uint32_t i = *(const uint32_t *)a, j = *(const uint32_t *)b;

	if (t[i].hash != t[j].hash)
		return t[i].hash < t[j].hash ? -1 : 1;
	if (t[i].len != t[j].len)
		return t[i].len < t[j].len ? -1 : 1;
	return (i > j) - (i < j);
}

/* The reading of tiles for comparison: one held (buf[0], tile held) and
 * the one compared with it (buf[1]). */
struct cmp {
	const pm_tile *t;
	int spool;
	unsigned char *buf[2];
	size_t held;
};

static int
same(struct cmp *c, size_t rep, size_t k, int k_read, tl_err *e)
{
	const pm_tile *t = c->t;

	if (c->held != rep) {
		if (tl_pread(c->spool, c->buf[0], t[rep].len,
		    (long long)t[rep].off, "pmtiles: spool", e) < 0)
			return -1;
		c->held = rep;
	}
	if (!k_read && tl_pread(c->spool, c->buf[1], t[k].len,
	    (long long)t[k].off, "pmtiles: spool", e) < 0)
		return -1;
	return memcmp(c->buf[0], c->buf[1], t[k].len) == 0;
}

/* One group g[0..m) of equal hash and length (indices ascending): each
 * tile's first tile of equal bytes into doff (as an index). */
static int
group(struct cmp *c, const uint32_t *g, size_t m, uint64_t *doff,
    tl_err *e)
{
	size_t nrep = 0, *rep;
	int r = 0;

	if (m == 1) {
		doff[g[0]] = g[0];
		return 0;
	}
	if ((rep = tl_alloc(m, sizeof *rep, e)) == NULL)
		return -1;
	for (size_t k = 0; r == 0 && k < m; k++) {
		size_t q;
		int s = 0;

		for (q = 0; q < nrep; q++)
			if ((s = same(c, rep[q], g[k], q > 0, e)) != 0)
				break;
		if (s < 0)
			r = -1;
		else if (q < nrep)
			doff[g[k]] = rep[q];
		else
			doff[g[k]] = rep[nrep++] = g[k];
	}
	free(rep);
	return r;
}

int
pm_dedup(const pm_tile *t, size_t n, int spool, uint32_t maxlen,
    uint64_t *doff, size_t *ncontents, tl_err *e)
{
	struct cmp c = { t, spool, { NULL, NULL }, (size_t)-1 };
	uint32_t *perm = tl_alloc(n, sizeof *perm, e);
	uint64_t at = 0;
	int r = -1;

	assert(n <= UINT32_MAX);
	c.buf[0] = tl_alloc(maxlen, 1, e);
	c.buf[1] = tl_alloc(maxlen, 1, e);
	if (perm == NULL || c.buf[0] == NULL || c.buf[1] == NULL)
		goto out;
	for (size_t i = 0; i < n; i++)
		perm[i] = (uint32_t)i;
	qsort_r(perm, n, sizeof *perm, by_content, (void *)t);
	for (size_t a = 0, b; a < n; a = b) {
		for (b = a + 1; b < n && t[perm[b]].hash == t[perm[a]].hash &&
		    t[perm[b]].len == t[perm[a]].len; b++)
			;
		if (group(&c, perm + a, b - a, doff, e) < 0)
			goto out;
	}
	/* in id order a content's first tile comes before its duplicates */
	*ncontents = 0;
	for (size_t i = 0; i < n; i++) {
		if (doff[i] == i) {
			doff[i] = at, at += t[i].len;
			++*ncontents;
		} else {
			assert(doff[i] < i);
			doff[i] = doff[doff[i]];
		}
	}
	r = 0;
out:
	free(perm), free(c.buf[0]), free(c.buf[1]);
	return r;
}

size_t
pm_tiles_next(const void *src, size_t pos, pm_entry *en)
{
	const pm_tiles *s = src;
	size_t j = pos + 1;

	en->id = s->t[pos].id, en->off = s->doff[pos];
	en->len = s->t[pos].len, en->run = 1;
	while (j < s->n && s->t[j].id == s->t[j - 1].id + 1 &&
	    s->doff[j] == en->off && en->run < UINT32_MAX)
		en->run++, j++;
	return j;
}
