/* tr_store.c - a run's store of fixed-size records in a scratch file,
 * for what every thread would otherwise make again each time its cache
 * comes back to a block (tr_grid.c: a block's decoded heights and
 * errors; an EXR's inflate and checks cost twenty times a read back).
 *
 * Record k has a fixed place in an anonymous scratch file (tl_scratch:
 * unlinked at once, so that no end of the run, SIGKILL included, leaves
 * it behind); in memory, per record, its state and a hash of the bytes
 * written. No lock: two threads may put one record at once, with the
 * same bytes (a record depends only on what it is made from), so the
 * file holds them in any order; each sets the hash and then the state
 * only after its whole write returned (release; a reader that sees the
 * state (acquire) reads after a write returned, which POSIX's
 * read-after-write lets it see). A record is used only when its read is
 * whole and its hash agrees; else (a read error, bytes the disk lost)
 * the caller makes it again. A failed write (ENOSPC, EIO, EFBIG) stops
 * all writes, as does reaching half the space the file system had free
 * when the store was made (the output may share it); no file, no store:
 * every get fails. The caller's results are the same in every case. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include "terrain/tr_impl.h"

enum { ST_NONE, ST_WRITTEN };

struct tr_store {
	int fd;
	size_t size;            /* bytes a record */
	long long room;         /* bytes it may still take (atomic); -1
	                         * after a failed write */
	unsigned char *state;   /* per record (atomic) */
	uint64_t *sum;          /* per record: hash of its bytes (atomic) */
};

uint64_t
tr_hash(const void *p, size_t n)
{
	const unsigned char *b = p;
	uint64_t h[4] = { 1, 2, 3, 4 }, u;
	size_t i = 0;

	for (; 8 * i + 8 <= n; i++) {
		memcpy(&u, b + 8 * i, sizeof u);
		h[i & 3] = (h[i & 3] ^ u) * 0x100000001b3u;
		h[i & 3] ^= h[i & 3] >> 29;
	}
	if (8 * i < n) { /* the last word, padded with zeros */
		u = 0;
		memcpy(&u, b + 8 * i, n - 8 * i);
		h[i & 3] = (h[i & 3] ^ u) * 0x100000001b3u;
		h[i & 3] ^= h[i & 3] >> 29;
	}
	return (h[0] * 0x9e3779b97f4a7c15u ^ h[1]) * 0x9e3779b97f4a7c15u ^
	    (h[2] * 0x9e3779b97f4a7c15u ^ h[3]);
}

struct tr_store *
tr_store_new(long long n, size_t size)
{
	struct tr_store *s = calloc(1, sizeof *s);
	struct statvfs fs;
	tl_err ignored;

	if (s == NULL)
		return NULL;
	s->fd = -1, s->size = size;
	s->state = calloc((size_t)(n > 0 ? n : 1), sizeof *s->state);
	s->sum = calloc((size_t)(n > 0 ? n : 1), sizeof *s->sum);
	if (s->state == NULL || s->sum == NULL ||
	    (s->fd = tl_scratch(&ignored)) < 0 || fstatvfs(s->fd, &fs) < 0) {
		tr_store_free(s);
		return NULL;
	}
	s->room = (long long)(fs.f_bavail / 2 * fs.f_frsize);
	return s;
}

void
tr_store_free(struct tr_store *s)
{
	if (s == NULL)
		return;
	if (s->fd >= 0)
		close(s->fd);
	free(s->state), free(s->sum), free(s);
}

int
tr_store_get(struct tr_store *s, long long k, void *buf)
{
	tl_err ignored;

	if (s == NULL ||
	    __atomic_load_n(&s->state[k], __ATOMIC_ACQUIRE) != ST_WRITTEN)
		return -1;
	if (tl_pread(s->fd, buf, s->size, k * (long long)s->size, "scratch",
	    &ignored) < 0 || tr_hash(buf, s->size) !=
	    __atomic_load_n(&s->sum[k], __ATOMIC_RELAXED))
		return -1;
	return 0;
}

void
tr_store_put(struct tr_store *s, long long k, const void *buf)
{
	tl_err ignored;

	if (s == NULL || __atomic_load_n(&s->state[k], __ATOMIC_RELAXED) ==
	    ST_WRITTEN)
		return;
	if (__atomic_load_n(&s->room, __ATOMIC_RELAXED) < (long long)s->size ||
	    __atomic_sub_fetch(&s->room, (long long)s->size,
	    __ATOMIC_RELAXED) < 0)
		return;
	if (tl_pwrite(s->fd, buf, s->size, k * (long long)s->size, "scratch",
	    &ignored) < 0) {
		__atomic_store_n(&s->room, -1, __ATOMIC_RELAXED);
		return;
	}
	__atomic_store_n(&s->sum[k], tr_hash(buf, s->size), __ATOMIC_RELAXED);
	__atomic_store_n(&s->state[k], ST_WRITTEN, __ATOMIC_RELEASE);
}
