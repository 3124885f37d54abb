/* ring.c - the bounded ring of slots between threads (ring.h): one lock
 * and one condition; counters of slots put and got, never wrapped.
 *
 * A waiter is woken a batch at a time, not at every slot: a reader once
 * the writer is a batch ahead of it, the writer once a batch of slots is
 * free; and whoever goes to
 * sleep first wakes the other side's waiters, so that no one sleeps on
 * a batch that cannot come. A row's wake-up and context switch cost
 * about as much as a cheap stage's work on it. */
#include "base/ring.h"

#include <assert.h>
#include <pthread.h>
#include <stdlib.h>

struct tl_ring {
	pthread_mutex_t mu;
	pthread_cond_t cv;
	int nslots, nreaders;
	size_t slotbytes;
	unsigned char *buf;       /* nslots x slotbytes, at the start */
	const void *meta;
	int started, closed, cancelled;
	int batch;                /* slots a waiter is woken for */
	int wwait, rwait;         /* the writer waits; readers that wait */
	unsigned char waits[TL_RING_MAXREADERS]; /* reader k waits */
	long long put;            /* slots written */
	long long got[TL_RING_MAXREADERS]; /* slots released by each reader;
	                           * LLONG_MAX once it has left */
};

#define GONE 0x7fffffffffffffffLL

tl_ring *
tl_ring_new(int readers, int slots, tl_err *e)
{
	tl_ring *q;

	assert(readers >= 1 && readers <= TL_RING_MAXREADERS && slots >= 1);
	if ((q = tl_alloc(1, sizeof *q, e)) == NULL)
		return NULL;
	pthread_mutex_init(&q->mu, NULL);
	pthread_cond_init(&q->cv, NULL);
	q->nslots = slots, q->nreaders = readers;
	q->batch = slots / 4 > 1 ? slots / 4 : 1;
	return q;
}

void
tl_ring_free(tl_ring *q)
{
	if (q == NULL)
		return;
	pthread_mutex_destroy(&q->mu);
	pthread_cond_destroy(&q->cv);
	free(q->buf);
	free(q);
}

int
tl_ring_start(tl_ring *q, size_t slotbytes, const void *meta, tl_err *e)
{
	unsigned char *b = tl_alloc((size_t)q->nslots, slotbytes, e);

	if (b == NULL)
		return -1;
	pthread_mutex_lock(&q->mu);
	assert(!q->started);
	q->buf = b, q->slotbytes = slotbytes, q->meta = meta;
	q->started = 1;
	pthread_cond_broadcast(&q->cv);
	pthread_mutex_unlock(&q->mu);
	return 0;
}

/* The slowest attached reader's count (GONE when none is left). */
static long long
slowest(const tl_ring *q)
{
	long long m = GONE;

	for (int k = 0; k < q->nreaders; k++)
		m = q->got[k] < m ? q->got[k] : m;
	return m;
}

/* Whether a waiting reader has a batch to read. */
static int
readers_due(const tl_ring *q)
{
	for (int k = 0; k < q->nreaders; k++)
		if (q->waits[k] && q->put - q->got[k] >= q->batch)
			return 1;
	return 0;
}

/* Sleeps on the condition, *count counting the sleepers, the other
 * side's (n of them) woken first. */
static void
sleep_on(tl_ring *q, int *count, int n)
{
	if (n > 0)
		pthread_cond_broadcast(&q->cv);
	(*count)++;
	pthread_cond_wait(&q->cv, &q->mu);
	(*count)--;
}

void *
tl_ring_put_begin(tl_ring *q)
{
	void *p = NULL;

	pthread_mutex_lock(&q->mu);
	while (!q->cancelled && q->put - slowest(q) >= q->nslots)
		sleep_on(q, &q->wwait, q->rwait);
	if (!q->cancelled)
		p = q->buf + (size_t)(q->put % q->nslots) * q->slotbytes;
	pthread_mutex_unlock(&q->mu);
	return p;
}

void
tl_ring_put_end(tl_ring *q)
{
	pthread_mutex_lock(&q->mu);
	q->put++;
	if (q->rwait > 0 && readers_due(q))
		pthread_cond_broadcast(&q->cv);
	pthread_mutex_unlock(&q->mu);
}

void
tl_ring_close(tl_ring *q)
{
	pthread_mutex_lock(&q->mu);
	q->closed = 1;
	pthread_cond_broadcast(&q->cv);
	pthread_mutex_unlock(&q->mu);
}

const void *
tl_ring_wait_start(tl_ring *q)
{
	const void *m = NULL;

	pthread_mutex_lock(&q->mu);
	while (!q->cancelled && !q->started)
		pthread_cond_wait(&q->cv, &q->mu);
	if (!q->cancelled)
		m = q->meta;
	pthread_mutex_unlock(&q->mu);
	return m;
}

const void *
tl_ring_get_begin(tl_ring *q, int k)
{
	const void *p = NULL;

	assert(k >= 0 && k < q->nreaders);
	pthread_mutex_lock(&q->mu);
	while (!q->cancelled && q->got[k] >= q->put && !q->closed) {
		q->waits[k] = 1;
		sleep_on(q, &q->rwait, q->wwait);
		q->waits[k] = 0;
	}
	if (!q->cancelled && q->got[k] < q->put)
		p = q->buf + (size_t)(q->got[k] % q->nslots) * q->slotbytes;
	pthread_mutex_unlock(&q->mu);
	return p;
}

void
tl_ring_get_end(tl_ring *q, int k)
{
	pthread_mutex_lock(&q->mu);
	q->got[k]++;
	if (q->wwait > 0 && q->nslots - (q->put - slowest(q)) >= q->batch)
		pthread_cond_broadcast(&q->cv);
	pthread_mutex_unlock(&q->mu);
}

void
tl_ring_leave(tl_ring *q, int k)
{
	pthread_mutex_lock(&q->mu);
	q->got[k] = GONE;
	pthread_cond_broadcast(&q->cv);
	pthread_mutex_unlock(&q->mu);
}

void
tl_ring_cancel(tl_ring *q)
{
	pthread_mutex_lock(&q->mu);
	q->cancelled = 1;
	pthread_cond_broadcast(&q->cv);
	pthread_mutex_unlock(&q->mu);
}

int
tl_ring_cancelled(tl_ring *q)
{
	int c;

	pthread_mutex_lock(&q->mu);
	c = q->cancelled;
	pthread_mutex_unlock(&q->mu);
	return c;
}
