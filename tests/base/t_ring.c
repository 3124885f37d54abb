/* t_ring - the ring of slots between threads (ring.h): every reader sees
 * every slot in order whatever the speeds (a writer, readers, each now
 * fast, now slow, sleeping at random), though a waiter is woken only a
 * batch of slots at a time; a reader that leaves early no longer holds
 * the writer; the close ends the readers, the cancel everyone. */
#include "base/ring.h"
#include "tap.h"

#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SLOTS 1000

typedef struct {
	tl_ring *q;
	int k, slow, leave_at;  /* leave_at: leaves after so many (-1: never) */
	unsigned seed;
	long long seen, bad;
} reader;

/* Now and then a pause of up to 200 us, more often when slow. */
static void
dawdle(unsigned *seed, int slow)
{
	*seed = *seed * 1103515245u + 12345u;
	if ((*seed >> 16) % 8 < (unsigned)(slow ? 3 : 1)) {
		struct timespec t = { 0, (long)((*seed >> 8) % 200) * 1000 };
		nanosleep(&t, NULL);
	}
}

static void *
read_all(void *arg)
{
	reader *r = arg;
	const int *p;

	if (tl_ring_wait_start(r->q) == NULL)
		return NULL;
	while ((p = tl_ring_get_begin(r->q, r->k)) != NULL) {
		r->bad += *p != r->seen;
		r->seen++;
		dawdle(&r->seed, r->slow);
		tl_ring_get_end(r->q, r->k);
		if (r->seen == r->leave_at) {
			tl_ring_leave(r->q, r->k);
			break;
		}
	}
	return NULL;
}

/* A writer of n slots, its own speed, and readers of the given speeds:
 * every reader saw its slots in order. */
static void
run(const char *what, int slots, int nr, const int *slow, int wslow,
    const int *leave_at)
{
	tl_err e = { "" };
	tl_ring *q = tl_ring_new(nr, slots, &e);
	reader r[TL_RING_MAXREADERS];
	pthread_t th[TL_RING_MAXREADERS];
	unsigned seed = 7;
	int good = 1;

	for (int k = 0; k < nr; k++) {
		r[k] = (reader){ q, k, slow[k], leave_at ? leave_at[k] : -1,
		    (unsigned)k * 31 + 1, 0, 0 };
		pthread_create(&th[k], NULL, read_all, &r[k]);
	}
	tl_ring_start(q, sizeof(int), q, &e);
	for (int i = 0; i < SLOTS; i++) {
		int *p = tl_ring_put_begin(q);
		if (p == NULL)
			break;
		*p = i;
		dawdle(&seed, wslow);
		tl_ring_put_end(q);
	}
	tl_ring_close(q);
	for (int k = 0; k < nr; k++) {
		pthread_join(th[k], NULL);
		good &= r[k].bad == 0 && r[k].seen == (leave_at != NULL &&
		    leave_at[k] >= 0 ? leave_at[k] : SLOTS);
	}
	ok(good, "%s: every reader saw its slots, in order", what);
	tl_ring_free(q);
}

static void *
wait_one(void *arg)
{
	reader *r = arg;

	r->seen = tl_ring_get_begin(r->q, r->k) == NULL &&
	    tl_ring_cancelled(r->q);
	return NULL;
}

int
main(void)
{
	static const int fast[3] = { 0, 0, 0 }, mixed[3] = { 1, 0, 1 };
	static const int leave[2] = { 100, -1 };
	tl_err e = { "" };
	reader r = { 0 };
	pthread_t th;

	run("16 slots, one reader, a slow writer", 16, 1, fast, 1, NULL);
	run("16 slots, one slow reader, a fast writer", 16, 1, mixed, 0,
	    NULL);
	run("16 slots, three readers, mixed", 16, 3, mixed, 0, NULL);
	run("16 slots, three readers, mixed, a slow writer", 16, 3, mixed, 1,
	    NULL);
	run("3 slots (a batch of one), two readers", 3, 2, mixed, 0, NULL);
	run("1 slot, two readers", 1, 2, mixed, 1, NULL);
	run("16 slots, a reader leaves after 100", 16, 2, fast, 0, leave);
	/* a reader waiting on nothing: the cancel ends its wait */
	r.q = tl_ring_new(1, 16, &e);
	tl_ring_start(r.q, sizeof(int), r.q, &e);
	pthread_create(&th, NULL, wait_one, &r);
	usleep(20000);
	tl_ring_cancel(r.q);
	pthread_join(th, NULL);
	ok(r.seen == 1, "a waiting reader: the cancel wakes it, cancelled");
	tl_ring_free(r.q);
	return tap_done();
}
