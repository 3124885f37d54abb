/* t_store.c - a run's store of records (terrain/tr_store.c): a record
 * reads back as put, one never put is not there, a put once made is not
 * replaced, two threads putting the same records at once leave them
 * whole; no store (NULL, as when TMPDIR cannot hold one) has nothing. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "tap.h"
#include "terrain/tr_impl.h"

#define N 64
#define SIZE 1001 /* not a whole number of 8-byte words */

static void
fill(unsigned char *b, int k, int salt)
{
	for (int i = 0; i < SIZE; i++)
		b[i] = (unsigned char)(k * 31 + i * 7 + salt);
}

struct arg {
	struct tr_store *s;
};

static void *
putter(void *p)
{
	struct arg *a = p;
	unsigned char b[SIZE];

	for (int r = 0; r < 20; r++)
		for (int k = 0; k < N; k++)
			fill(b, k, 0), tr_store_put(a->s, k, b);
	return NULL;
}

int
main(void)
{
	struct tr_store *s = tr_store_new(N, SIZE);
	unsigned char b[SIZE], want[SIZE];
	int bad = 0;

	ok(s != NULL, "a store of %d records of %d bytes", N, SIZE);
	if (s == NULL)
		return tap_done();
	ok(tr_store_get(s, 3, b) < 0, "a record never put: not there");
	fill(want, 3, 0);
	tr_store_put(s, 3, want);
	memset(b, 0, sizeof b);
	ok(tr_store_get(s, 3, b) == 0 && memcmp(b, want, SIZE) == 0,
	    "a record reads back as put");
	fill(b, 3, 1);
	tr_store_put(s, 3, b); /* a second put of another record 3 */
	ok(tr_store_get(s, 3, b) == 0 && memcmp(b, want, SIZE) == 0,
	    "a record put is kept (a second put is dropped)");
	ok(tr_store_get(s, 4, b) < 0, "its neighbour is not there");

	struct arg a = { s };
	pthread_t t[4];
	for (int i = 0; i < 4; i++)
		pthread_create(&t[i], NULL, putter, &a);
	for (int i = 0; i < 4; i++)
		pthread_join(t[i], NULL);
	for (int k = 0; k < N; k++) {
		fill(want, k, 0);
		if (tr_store_get(s, k, b) < 0 || memcmp(b, want, SIZE) != 0)
			bad++;
	}
	ok(bad == 0, "4 threads putting the same %d records at once: each "
	    "reads back whole (%d bad)", N, bad);
	tr_store_free(s);
	ok(tr_store_get(NULL, 0, b) < 0, "no store: nothing there");
	tr_store_put(NULL, 0, b);
	ok(1, "no store: a put is dropped");
	return tap_done();
}
