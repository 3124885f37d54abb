/* inproc.c - stages as threads joined by rings (inproc.h): the threads,
 * the first failure, the cancel, and the stop signals taken by the
 * thread that runs them. */
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "jobs/inproc.h"
#include "jobs/graph.h"

typedef struct {
	inproc *p;
	inproc_fn fn;
	void *arg;
	rs_ring *in, *out;
	int k, outfd;
	pthread_t th;
	int started;
	int ended;            /* fn returned, outfd closed, failure noted */
} task;

struct inproc {
	const char *prog;
	task t[INPROC_MAXTASKS];
	int n;
	rs_ring *ring[INPROC_MAXTASKS];
	int nring;
	pthread_mutex_t mu;
	pthread_cond_t cv;    /* a task ended (inproc_ended) */
	int running, failed;
	int stop;             /* failed or cancelled (inproc_stopped) */
	tl_err first;         /* the first failure's message */
};

static const int stops[3] = { SIGINT, SIGTERM, SIGHUP };

static void
stopset(sigset_t *s)
{
	sigemptyset(s);
	for (int i = 0; i < 3; i++)
		sigaddset(s, stops[i]);
}

void
inproc_block(sigset_t *old)
{
	sigset_t s;

	stopset(&s);
	pthread_sigmask(SIG_BLOCK, &s, old);
}

int
inproc_pending(void)
{
	struct timespec zero = { 0, 0 };
	sigset_t s;
	int sig;

	stopset(&s);
	sig = sigtimedwait(&s, NULL, &zero);
	return sig > 0 ? sig : graph_signal();
}

inproc *
inproc_new(const char *prog, tl_err *e)
{
	inproc *p = tl_alloc(1, sizeof *p, e);

	if (p == NULL)
		return NULL;
	p->prog = prog;
	pthread_mutex_init(&p->mu, NULL);
	pthread_cond_init(&p->cv, NULL);
	return p;
}

void
inproc_free(inproc *p)
{
	if (p == NULL)
		return;
	for (int i = 0; i < p->n; i++)
		if (p->t[i].outfd >= 0)
			close(p->t[i].outfd); /* a task never started */
	for (int i = 0; i < p->nring; i++)
		rs_ring_free(p->ring[i]);
	pthread_mutex_destroy(&p->mu);
	pthread_cond_destroy(&p->cv);
	free(p);
}

rs_ring *
inproc_ring(inproc *p, int readers, tl_err *e)
{
	rs_ring *q;

	if (p->nring == INPROC_MAXTASKS)
		return tl_fail(e, "more than %d rings", INPROC_MAXTASKS), NULL;
	/* rows the writer runs ahead: a filter's window (FILTER_MAX_RADIUS
	 * rows each side) and slack, so that neither side waits often */
	if ((q = rs_ring_new(readers, 16, e)) != NULL)
		p->ring[p->nring++] = q;
	return q;
}

int
inproc_task(inproc *p, inproc_fn fn, void *arg, rs_ring *in, int k,
    rs_ring *out, int outfd, tl_err *e)
{
	task *t;

	if (p->n == INPROC_MAXTASKS)
		return tl_fail(e, "more than %d tasks", INPROC_MAXTASKS);
	t = &p->t[p->n++];
	*t = (task){ .p = p, .fn = fn, .arg = arg, .in = in, .k = k,
	    .out = out, .outfd = outfd };
	return 0;
}

/* Every ring cancelled: each task stops at its next row. */
static void
cancel_all(inproc *p)
{
	__atomic_store_n(&p->stop, 1, __ATOMIC_RELEASE);
	pthread_mutex_lock(&p->mu);
	pthread_cond_broadcast(&p->cv);
	pthread_mutex_unlock(&p->mu);
	for (int i = 0; i < p->nring; i++)
		rs_ring_cancel(p->ring[i]);
}

static void *
run_task(void *arg)
{
	task *t = arg;
	inproc *p = t->p;
	tl_err e = { 0 };
	int r;

	rs_ring_bind(t->in, t->k, t->out, t->outfd);
	r = t->fn(t->arg, &e);
	if (t->outfd >= 0 && close(t->outfd) < 0 && r == 0)
		r = tl_failsys(&e, "%s: a vertex map", p->prog);
	t->outfd = -1;
	pthread_mutex_lock(&p->mu);
	if (r < 0 && !p->failed) { /* the first: the cause */
		p->failed = 1;
		p->first = e;
	}
	p->running--;
	t->ended = 1;
	pthread_cond_broadcast(&p->cv);
	pthread_mutex_unlock(&p->mu);
	if (r < 0)
		cancel_all(p);
	return NULL;
}

int
inproc_stopped(inproc *p)
{
	return __atomic_load_n(&p->stop, __ATOMIC_ACQUIRE);
}

int
inproc_ended(inproc *p, int n, int ms)
{
	struct timespec until;
	int r = 1, k;

	clock_gettime(CLOCK_REALTIME, &until);
	until.tv_sec += ms / 1000;
	until.tv_nsec += (long)(ms % 1000) * 1000000;
	if (until.tv_nsec >= 1000000000)
		until.tv_sec++, until.tv_nsec -= 1000000000;
	pthread_mutex_lock(&p->mu);
	for (;;) {
		for (k = 0; k < n && p->t[k].ended; k++)
			;
		if (p->failed || inproc_stopped(p))
			r = -1;
		else if (k == n)
			r = 0;
		if (r <= 0 ||
		    pthread_cond_timedwait(&p->cv, &p->mu, &until) != 0)
			break;
	}
	pthread_mutex_unlock(&p->mu);
	return r;
}

/* Dies of sig now: the tasks cannot be stopped (inproc.h). */
static void __attribute__((noreturn))
die(inproc *p, int sig, scratch *s)
{
	sigset_t set;

	fprintf(stderr, "%s: stopped by signal %d\n", p->prog, sig);
	if (s != NULL)
		scratch_end(s);
	/* the outputs' handler, if installed, removes the temporaries and
	 * dies of it; else the default action */
	sigemptyset(&set);
	sigaddset(&set, sig);
	pthread_sigmask(SIG_UNBLOCK, &set, NULL);
	raise(sig);
	signal(sig, SIG_DFL);
	raise(sig);
	_exit(128 + sig);
}

/* Waits for the tasks, a stop signal meanwhile: its number, or 0. The
 * tick, 5 ms, is how late the run goes on after its last task (50 ms
 * was a tenth of N48W125's one-process run's serial part). */
static int
watch(inproc *p, int stoppable, scratch *s)
{
	struct timespec tick = { 0, 5 * 1000 * 1000 };
	sigset_t set;
	int sig = 0, running;

	stopset(&set);
	for (;;) {
		pthread_mutex_lock(&p->mu);
		running = p->running;
		pthread_mutex_unlock(&p->mu);
		if (running == 0)
			return sig;
		int k = sigtimedwait(&set, NULL, &tick);
		if (k <= 0 || sig != 0)
			continue;
		if (!stoppable)
			die(p, k, s);
		sig = k;
		cancel_all(p);
	}
}

int
inproc_run(inproc *p, int stoppable, scratch *s, int *status, tl_err *e)
{
	int sig = inproc_pending(), started = 0;

	*status = 1;
	if (sig == 0)
		for (; started < p->n; started++) {
			task *t = &p->t[started];
			pthread_mutex_lock(&p->mu);
			p->running++;
			pthread_mutex_unlock(&p->mu);
			if ((errno = pthread_create(&t->th, NULL, run_task, t))) {
				pthread_mutex_lock(&p->mu);
				p->running--;
				if (!p->failed)
					p->failed = 1, tl_failsys(&p->first,
					    "%s: thread", p->prog);
				pthread_mutex_unlock(&p->mu);
				cancel_all(p);
				break;
			}
		}
	if (sig == 0)
		sig = watch(p, stoppable, s);
	for (int i = 0; i < started; i++)
		pthread_join(p->t[i].th, NULL);
	if (sig != 0) {
		*status = 128 + sig;
		return tl_fail(e, "%s: stopped by signal %d", p->prog, sig);
	}
	if (!p->failed)
		return *status = 0;
	*e = p->first;
	return -1;
}
