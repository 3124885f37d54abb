/* pool.c - a loop's iterations on several threads (pool.h). */
#include "base/pool.h"

#include <assert.h>
#include <pthread.h>
#include <stdlib.h>

struct tl_pool {
	pthread_mutex_t mu;
	pthread_cond_t go, done;
	long gen;           /* bumped for each loop */
	int quit, pending;
	int nthreads;       /* started, besides the caller */
	pthread_t th[TL_POOL_MAXTHREADS];
	/* the loop */
	int n;
	void (*fn)(void *arg, int k, int i0, int i1);
	void *arg;
};

typedef struct {
	tl_pool *p;
	int k;      /* this thread's range: k of nthreads + 1 */
} member;

static void
range(const tl_pool *p, int k)
{
	int m = p->nthreads + 1;
	int i0 = (int)((long)p->n * k / m), i1 = (int)((long)p->n * (k + 1) / m);

	if (i0 < i1)
		p->fn(p->arg, k, i0, i1);
}

static void *
member_run(void *arg)
{
	tl_pool *p = ((member *)arg)->p;
	int k = ((member *)arg)->k;
	long seen = 0;

	free(arg);
	for (;;) {
		int quit;
		pthread_mutex_lock(&p->mu);
		while (p->gen == seen && !p->quit)
			pthread_cond_wait(&p->go, &p->mu);
		seen = p->gen, quit = p->quit;
		pthread_mutex_unlock(&p->mu);
		if (quit)
			return NULL;
		range(p, k);
		pthread_mutex_lock(&p->mu);
		if (--p->pending == 0)
			pthread_cond_signal(&p->done);
		pthread_mutex_unlock(&p->mu);
	}
}

tl_pool *
tl_pool_new(int threads, tl_err *e)
{
	tl_pool *p = tl_alloc(1, sizeof *p, e);

	assert(threads >= 1 && threads <= TL_POOL_MAXTHREADS);
	if (p == NULL)
		return NULL;
	pthread_mutex_init(&p->mu, NULL);
	pthread_cond_init(&p->go, NULL);
	pthread_cond_init(&p->done, NULL);
	for (int k = 1; k < threads; k++) {
		member *m = malloc(sizeof *m);
		if (m == NULL)
			break;
		*m = (member){ p, k };
		if (pthread_create(&p->th[p->nthreads], NULL, member_run, m)) {
			free(m);
			break; /* fewer threads: the caller's ranges are wider */
		}
		p->nthreads++;
	}
	return p;
}

int
tl_pool_threads(const tl_pool *p)
{
	return p->nthreads + 1;
}

void
tl_pool_for(tl_pool *p, int n, void (*fn)(void *arg, int k, int i0, int i1),
    void *arg)
{
	if (p->nthreads == 0) {
		if (n > 0)
			fn(arg, 0, 0, n);
		return;
	}
	pthread_mutex_lock(&p->mu);
	p->n = n, p->fn = fn, p->arg = arg;
	p->pending = p->nthreads, p->gen++;
	pthread_cond_broadcast(&p->go);
	pthread_mutex_unlock(&p->mu);
	range(p, 0);
	pthread_mutex_lock(&p->mu);
	while (p->pending > 0)
		pthread_cond_wait(&p->done, &p->mu);
	pthread_mutex_unlock(&p->mu);
}

void
tl_pool_free(tl_pool *p)
{
	if (p == NULL)
		return;
	pthread_mutex_lock(&p->mu);
	p->quit = 1;
	pthread_cond_broadcast(&p->go);
	pthread_mutex_unlock(&p->mu);
	for (int k = 0; k < p->nthreads; k++)
		pthread_join(p->th[k], NULL);
	pthread_mutex_destroy(&p->mu);
	pthread_cond_destroy(&p->go);
	pthread_cond_destroy(&p->done);
	free(p);
}
