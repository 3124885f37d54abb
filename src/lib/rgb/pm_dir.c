/* pm_dir.c - PMTiles directories: varints, the encoding of a directory
 * (delta-coded tile ids, run lengths, lengths, offsets with 0 for "right
 * after the previous one"), gzip'd, and the split of the entries between
 * the root directory and leaf directories (pm_impl.h). The format is the
 * PMTiles v3 specification (protomaps/PMTiles spec/v3/spec.md, chapter 4
 * and appendix A.1); the split follows the reference writers'. */
#include "rgb/pm_impl.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "base/gzip.h"

int
pm_buf_put(pm_buf *b, const void *src, size_t n, tl_err *e)
{
	if (n > b->cap - b->n) {
		size_t cap = b->cap ? b->cap : 4096;
		unsigned char *p;

		while (n > cap - b->n) {
			if (cap > SIZE_MAX / 2)
				return tl_fail(e, "pmtiles: directory too large");
			cap *= 2;
		}
		if ((p = realloc(b->p, cap)) == NULL)
			return tl_fail(e, "pmtiles: out of memory");
		b->p = p, b->cap = cap;
	}
	if (n > 0)
		memcpy(b->p + b->n, src, n);
	b->n += n;
	return 0;
}

void
pm_buf_free(pm_buf *b)
{
	free(b->p);
	memset(b, 0, sizeof *b);
}

size_t
pm_varint_put(unsigned char *p, uint64_t v)
{
	size_t k = 0;

	while (v >= 0x80) {
		p[k++] = (unsigned char)(v | 0x80);
		v >>= 7;
	}
	p[k++] = (unsigned char)v;
	return k;
}

size_t
pm_varint_get(const unsigned char *p, size_t n, uint64_t *v)
{
	uint64_t r = 0;

	for (size_t k = 0; k < n && k < 10; k++) {
		r |= (uint64_t)(p[k] & 0x7f) << (7 * k);
		if (p[k] < 0x80) {
			*v = r;
			return k + 1;
		}
	}
	return 0;
}

size_t
pm_array_next(const void *src, size_t pos, pm_entry *en)
{
	*en = ((const pm_entry *)src)[pos];
	return pos + 1;
}

static int
put_varint(pm_buf *b, uint64_t v, tl_err *e)
{
	unsigned char tmp[10];

	return pm_buf_put(b, tmp, pm_varint_put(tmp, v), e);
}

/* One column of the encoding (spec 4.2): 0 ids, 1 runs, 2 lengths, 3
 * offsets. */
static int
column(int c, pm_next next, const void *src, size_t pos, size_t count,
    pm_buf *raw, size_t *end, tl_err *e)
{
	uint64_t last = 0, v = 0;
	pm_entry en;

	for (size_t k = 0; k < count; k++) {
		pos = next(src, pos, &en);
		switch (c) {
		case 0:
			assert(k == 0 || en.id > last);
			v = en.id - last, last = en.id;
			break;
		case 1:
			v = en.run;
			break;
		case 2:
			assert(en.len > 0);
			v = en.len;
			break;
		case 3: /* last: where the previous entry ends */
			v = k > 0 && en.off == last ? 0 : en.off + 1;
			last = en.off + en.len;
			break;
		}
		if (put_varint(raw, v, e) < 0)
			return -1;
	}
	if (end != NULL)
		*end = pos;
	return 0;
}

int
pm_dir_raw(pm_next next, const void *src, size_t pos, size_t count,
    pm_buf *raw, size_t *end, tl_err *e)
{
	assert(count > 0);
	if (put_varint(raw, count, e) < 0)
		return -1;
	for (int c = 0; c < 4; c++)
		if (column(c, next, src, pos, count, raw, end, e) < 0)
			return -1;
	return 0;
}

int
pm_dir_encode(pm_next next, const void *src, size_t pos, size_t count,
    pm_buf *out, size_t *end, tl_err *e)
{
	pm_buf raw = { 0 };
	unsigned char *z = NULL;
	size_t zn = 0;
	int r;

	r = pm_dir_raw(next, src, pos, count, &raw, end, e);
	if (r == 0)
		r = tl_gzip(raw.p, raw.n, &z, &zn, e);
	if (r == 0)
		r = pm_buf_put(out, z, zn, e);
	free(z);
	pm_buf_free(&raw);
	return r;
}

/* Leaves of l entries each into leaves, their pointers into root:
 * *nleaves of them. */
static int
split(pm_next next, const void *src, size_t count, size_t l, pm_buf *root,
    pm_buf *leaves, size_t *nleaves, tl_err *e)
{
	size_t nl = (count + l - 1) / l, pos = 0;
	pm_entry *ptr = tl_alloc(nl, sizeof *ptr, e), first;
	int r = ptr == NULL ? -1 : 0;

	for (size_t k = 0; r == 0 && k < nl; k++) {
		size_t m = k + 1 < nl ? l : count - k * l, at = leaves->n;

		next(src, pos, &first);
		r = pm_dir_encode(next, src, pos, m, leaves, &pos, e);
		ptr[k].id = first.id, ptr[k].off = at;
		ptr[k].len = (uint32_t)(leaves->n - at), ptr[k].run = 0;
		if (r == 0 && leaves->n - at > UINT32_MAX)
			r = tl_fail(e, "pmtiles: leaf directory too large");
	}
	if (r == 0)
		r = pm_dir_encode(pm_array_next, ptr, 0, nl, root, NULL, e);
	*nleaves = nl;
	free(ptr);
	return r;
}

int
pm_dirs(pm_next next, const void *src, size_t count, pm_buf *root,
    pm_buf *leaves, size_t *nleaves, tl_err *e)
{
	size_t l = count / 3500 > PM_LEAF_MIN ? count / 3500 : PM_LEAF_MIN;

	assert(count > 0);
	root->n = leaves->n = 0, *nleaves = 0;
	if (count < 16384) {
		if (pm_dir_encode(next, src, 0, count, root, NULL, e) < 0)
			return -1;
		if (root->n <= PM_ROOT_MAX)
			return 0;
	}
	for (;;) {
		root->n = leaves->n = 0;
		if (split(next, src, count, l, root, leaves, nleaves, e) < 0)
			return -1;
		if (root->n <= PM_ROOT_MAX)
			return 0;
		if (l >= count)
			return tl_fail(e, "pmtiles: the root directory does "
			    "not fit in %d bytes", PM_ROOT_MAX);
		l *= 2;
	}
}
