/* rs_ring.c - the ring backend (rs_ring.h): a reader and a writer whose
 * rows are a ring's slots, and the thread's binding of "-" to them. */
#include "raster/rs_impl.h"
#include "raster/rs_ring.h"
#include "base/ring.h"

#include <stdlib.h>
#include <string.h>

struct rs_ring {
	tl_ring *q;
	rs_header h; /* the writer's, copied: the ring outlives it */
	void *taken; /* the writer's slot from ring_slot, not yet put */
};

/* this thread's "-" */
static _Thread_local struct {
	rs_ring *in, *out;
	int k, outfd;
} bound = { .outfd = -1 };

rs_ring *
rs_ring_new(int readers, int rows, tl_err *e)
{
	rs_ring *r = tl_alloc(1, sizeof *r, e);

	if (r == NULL)
		return NULL;
	rs_header_init(&r->h, 0, 0);
	if ((r->q = tl_ring_new(readers, rows, e)) == NULL) {
		free(r);
		return NULL;
	}
	return r;
}

void
rs_ring_free(rs_ring *r)
{
	if (r == NULL)
		return;
	tl_ring_free(r->q);
	rs_header_free(&r->h);
	free(r);
}

void
rs_ring_cancel(rs_ring *r)
{
	tl_ring_cancel(r->q);
}

void
rs_ring_bind(rs_ring *in, int k, rs_ring *out, int outfd)
{
	bound.in = in, bound.k = k, bound.out = out, bound.outfd = outfd;
}

int
rs_ring_bound(int out)
{
	return (out ? bound.out : bound.in) != NULL;
}

int
rs_ring_outfd(void)
{
	return bound.outfd;
}

static size_t
rowbytes(const rs_header *h)
{
	return (size_t)h->width * (size_t)h->nch * sizeof(float);
}

/* --- reading ---------------------------------------------------------- */

typedef struct {
	rs_ring *ring;
	int k;
	int held;   /* a slot given by ring_view, not yet released */
} rd;

static int
stopped(const char *name, tl_err *e)
{
	return tl_fail(e, "%s: stopped", name);
}

/* The next slot, the one ring_view gave released first. */
static const void *
next_slot(rs_reader *r, tl_err *e)
{
	rd *d = r->impl;
	const void *p;

	if (d->held)
		tl_ring_get_end(d->ring->q, d->k);
	d->held = 0;
	if ((p = tl_ring_get_begin(d->ring->q, d->k)) == NULL)
		return tl_ring_cancelled(d->ring->q) ? stopped(r->name, e),
		    NULL : (tl_fail(e, "%s: truncated at row %d of %d",
		    r->name, r->y, r->h.height), NULL);
	return p;
}

static int
ring_read_row(rs_reader *r, float *row, tl_err *e)
{
	rd *d = r->impl;
	const void *p = next_slot(r, e);

	if (p == NULL)
		return -1;
	memcpy(row, p, rowbytes(&r->h));
	tl_ring_get_end(d->ring->q, d->k);
	return 0;
}

/* The slot itself, held until the next read or the close (its leave):
 * a reader that decodes the row as it goes copies nothing. */
static const float *
ring_view(rs_reader *r, tl_err *e)
{
	rd *d = r->impl;
	const void *p = next_slot(r, e);

	d->held = p != NULL;
	return p;
}

static void
ring_close_read(rs_reader *r)
{
	rd *d = r->impl;

	if (d != NULL)
		tl_ring_leave(d->ring->q, d->k);
	free(d);
	r->impl = NULL;
}

int
rs_ring_open_read(rs_reader *r, tl_err *e)
{
	rd *d;

	if ((d = tl_alloc(1, sizeof *d, e)) == NULL)
		return -1;
	d->ring = bound.in, d->k = bound.k;
	r->impl = d;
	r->row = ring_read_row;
	r->view = ring_view;
	r->close = ring_close_read;
	if (tl_ring_wait_start(d->ring->q) == NULL)
		return stopped(r->name, e);
	return rs_header_copy(&r->h, &d->ring->h, e);
}

/* --- writing ---------------------------------------------------------- */

static int
ring_write_row(rs_writer *w, const float *row, tl_err *e)
{
	rs_ring *q = w->impl;
	void *p = q->taken != NULL ? q->taken : tl_ring_put_begin(q->q);

	if (p == NULL)
		return stopped(w->name, e);
	if (p != row)
		memcpy(p, row, rowbytes(&w->h));
	q->taken = NULL;
	tl_ring_put_end(q->q);
	return 0;
}

/* The next slot, taken: the row made in it is not copied. */
static float *
ring_slot(rs_writer *w, tl_err *e)
{
	rs_ring *q = w->impl;

	if (q->taken == NULL && (q->taken = tl_ring_put_begin(q->q)) == NULL)
		return stopped(w->name, e), NULL;
	return q->taken;
}

static int
ring_finish(rs_writer *w, tl_err *e)
{
	rs_ring *q = w->impl;

	tl_ring_close(q->q);
	return 0;
}

int
rs_ring_create(rs_writer *w, tl_err *e)
{
	rs_ring *q = bound.out;

	w->impl = q;
	w->row = ring_write_row;
	w->slot = ring_slot;
	w->finish = ring_finish;
	w->abort = NULL; /* the readers wait for the cancel */
	if (rs_header_copy(&q->h, &w->h, e) < 0)
		return -1;
	return tl_ring_start(q->q, rowbytes(&w->h), q, e);
}
