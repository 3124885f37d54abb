/* pack_parts.c - a tilepack piece in parts of DEM rows, and the piece
 * from its parts (pack.h, level.h: level_run_part, level_run_merged). */
#include "pack/pack_impl.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/outfile.h"

/* How many parts piece p of level pl runs in: enough runs of DEM rows of
 * nearly equal height that none holds more than a->part_samples DEM
 * samples of the piece's window (and a row more), at most a part a row;
 * 1, the piece whole, when it holds no more or part_samples is 0. */
int
pk_nparts(const work *w, int l, const level_piece *p)
{
	const georef *g = &w->ix->geo;
	long long n, bound = w->a->part_samples;
	level_window win;

	if (bound <= 0)
		return 1;
	pk_window(w, l, p, &win);
	n = ((long long)(win.d1 - win.d0) * g->height + bound - 1) / bound;
	return n < 1 ? 1 : n > g->height ? g->height : (int)n;
}

/* Part k of n: DEM rows [y0, y1). */
void
pk_part_rows(int height, int n, int k, int *y0, int *y1)
{
	*y0 = (int)((long long)height * k / n);
	*y1 = (int)((long long)height * (k + 1) / n);
}

static void
part_path(char *buf, size_t n, const char *dir, int l, const level_piece *p,
    int y0, const char *ext)
{
	snprintf(buf, n, "%s/" PARTS "/%d-%d-%d-%d%s", dir, l, p->b0, p->b1, y0,
	    ext);
}

/* The local errors of a part, into its EXR. */
static int
part_out(void *ctx, int g, float *err, tl_err *e)
{
	(void)g;
	return rs_write_row(ctx, err, e);
}

/* The part's record, written last: its rows, its samples, its blocks'
 * base errors (%.17g: exact). */
static int
part_record(const char *path, int l, const level_piece *p, int y0, int y1,
    const double *base, int by, long long samples, tl_err *e)
{
	tl_outfile o;
	FILE *f;

	if ((f = pk_record_open(&o, path, e)) == NULL)
		return -1;
	fprintf(f, "part %d %d %d %d %d\nsamples %lld\n", l, p->b0, p->b1, y0,
	    y1, samples);
	for (int bj = 0; bj < by; bj++)
		for (int bi = p->b0; bi < p->b1; bi++)
			fprintf(f, "%d %d %.17g\n", bi, bj,
			    base[(size_t)bj * (p->b1 - p->b0) + bi - p->b0]);
	return pk_record_close(&o, f, e);
}

/* Reads part (l, p, y0, y1)'s record: its base errors raised into base,
 * its samples added to *samples. */
static int
part_read(const char *dir, int l, const level_piece *p, int y0, int y1,
    double *base, int by, long long *samples, tl_err *e)
{
	char path[4096];
	int rl, r0, r1, ry0, ry1, n = 0, nb = p->b1 - p->b0;
	long long k;
	FILE *f;

	part_path(path, sizeof path, dir, l, p, y0, "");
	if ((f = fopen(path, "r")) == NULL)
		return errno == ENOENT ? tl_fail(e, "%s: piece %d:%d:%d: its "
		    "part of DEM rows %d..%d not made", dir, l, p->b0, p->b1,
		    y0, y1 - 1) : tl_failsys(e, "%s", path);
	if (fscanf(f, "part %d %d %d %d %d samples %lld", &rl, &r0, &r1, &ry0,
	    &ry1, &k) != 6 || rl != l || r0 != p->b0 || r1 != p->b1 ||
	    ry0 != y0 || ry1 != y1)
		goto bad;
	for (;;) {
		int bi, bj, m = 0;
		double b;
		if ((m = fscanf(f, "%d %d %lf", &bi, &bj, &b)) == EOF)
			break;
		if (m != 3 || bi < p->b0 || bi >= p->b1 || bj < 0 || bj >= by)
			goto bad;
		double *o = &base[(size_t)bj * nb + bi - p->b0];
		*o = b > *o ? b : *o;
		n++;
	}
	if (n != nb * by)
		goto bad;
	fclose(f);
	*samples += k;
	return 0;
bad:
	fclose(f);
	return tl_fail(e, "%s: not a record of part %d:%d:%d:%d:%d", path, l,
	    p->b0, p->b1, y0, y1);
}

/* Part (y0, y1) of piece p of level l: the DEM's window of its rows, the
 * vertex map from the part's first row, its local errors into an EXR
 * (channel E, level columns lo.., rows g0..), then its record. */
int
pk_run_part(work *w, int l, const level_piece *p, int y0, int y1, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	char exr[4096], rec[4096];
	int by = pyramid_nblocks(w->ix->lev[l].size[1]), r = -1;
	double *base = tl_alloc((size_t)(p->b1 - p->b0) * by, sizeof *base, e);
	rs_writer *out = NULL;
	level_args L;
	level_window win;
	level_part q;
	level_stats st;
	rs_header h;
	dem *d = NULL;
	vmap v = { 0 };
	sink k;

	rs_header_init(&h, 1, 1);
	if (base == NULL || pk_vmap_open(&v, w->a->levels[l], l, g, e) < 0)
		goto done;
	pk_level_setup(w, l, &v, &k, w->a->jobs, &L);
	level_piece_window(&L, g->width, p, &win);
	level_part_window(&L, p, y0, y1, &q);
	rs_header_init(&h, q.hi - q.lo, q.g1 - q.g0);
	part_path(exr, sizeof exr, w->tmp, l, p, y0, ".exr");
	part_path(rec, sizeof rec, w->tmp, l, p, y0, "");
	if ((d = dem_open_window(w->a->dem_path, &w->a->dem, (int)win.d0,
	    (int)win.d1, y0, y1, e)) == NULL ||
	    rs_add_channel(&h, "E", e) < 0 ||
	    rs_set_int(&h, RS_ATTR_X0, q.lo, e) < 0 ||
	    (out = rs_create(exr, &h, RS_ZIP, e)) == NULL)
		goto done;
	if (level_run_part(&L, p, &q, d, part_out, out, base, &st, e) < 0)
		goto done;
	r = rs_finish(out, e);
	out = NULL;
	if (r == 0)
		r = part_record(rec, l, p, y0, y1, base, by, st.samples, e);
done:
	rs_abort(out);
	rs_header_free(&h);
	dem_close(d);
	pk_vmap_close(&v);
	free(base);
	return r;
}

/* A piece's parts' local errors, read back: each part's EXR opened when
 * its first row is reached, closed after its last (parts come in order
 * of rows, overlapping by about 130 level rows), the maximum taken. */
typedef struct {
	const char *dir;
	int l;
	const level_piece *p;
	int n;             /* parts */
	level_part *q;     /* their windows */
	rs_reader **r;
	int first;         /* parts before it are done with */
	float *row;
} merge;

static int
merge_open(merge *m, int k, tl_err *e)
{
	const rs_header *h;
	char path[4096];
	int x0;

	part_path(path, sizeof path, m->dir, m->l, m->p, m->q[k].y0, ".exr");
	if ((m->r[k] = rs_open(path, e)) == NULL)
		return -1;
	h = rs_header_of(m->r[k]);
	if (h->width != m->q[k].hi - m->q[k].lo ||
	    h->height != m->q[k].g1 - m->q[k].g0 || h->nch != 1 ||
	    rs_get_int(h, RS_ATTR_X0, &x0) < 0 || x0 != m->q[k].lo)
		return tl_fail(e, "%s: not the local errors of part %d:%d:%d:"
		    "%d:%d", path, m->l, m->p->b0, m->p->b1, m->q[k].y0,
		    m->q[k].y1);
	return 0;
}

static int
merge_row(void *ctx, int g, float *err, tl_err *e)
{
	merge *m = ctx;
	int n = m->q[0].hi - m->q[0].lo;

	memset(err, 0, (size_t)n * sizeof *err);
	for (; m->first < m->n && m->q[m->first].g1 <= g; m->first++) {
		rs_close(m->r[m->first]);
		m->r[m->first] = NULL;
	}
	for (int k = m->first; k < m->n && m->q[k].g0 <= g; k++) {
		if ((m->r[k] == NULL && merge_open(m, k, e) < 0) ||
		    rs_read_row(m->r[k], m->row, e) < 0)
			return -1;
		for (int i = 0; i < n; i++)
			err[i] = m->row[i] > err[i] ? m->row[i] : err[i];
	}
	return 0;
}

/* Piece p of level l from its n parts in the work directory: their
 * records' base errors and samples, their local errors merged as the
 * piece's blocks are made. */
int
pk_run_merged(work *w, int l, const level_piece *p, int n, tl_err *e)
{
	const georef *g = dem_georef(w->d);
	int by = pyramid_nblocks(w->ix->lev[l].size[1]), r = -1;
	double *base = tl_alloc((size_t)(p->b1 - p->b0) * by, sizeof *base, e);
	merge m = { w->tmp, l, p, n, NULL, NULL, 0, NULL };
	long long samples = 0;
	level_args L;
	level_stats st;
	vmap v = { 0 };
	sink k;

	m.q = tl_alloc(n, sizeof *m.q, e);
	m.r = tl_alloc(n, sizeof *m.r, e);
	if (base == NULL || m.q == NULL || m.r == NULL ||
	    pk_vmap_open(&v, w->a->levels[l], l, g, e) < 0)
		goto done;
	pk_level_setup(w, l, &v, &k, w->a->jobs, &L);
	for (int i = 0; i < n; i++) {
		int y0, y1;
		pk_part_rows(g->height, n, i, &y0, &y1);
		level_part_window(&L, p, y0, y1, &m.q[i]);
		if (part_read(w->tmp, l, p, y0, y1, base, by, &samples, e) < 0)
			goto done;
	}
	if ((m.row = tl_alloc(m.q[0].hi - m.q[0].lo, sizeof *m.row,
	    e)) == NULL ||
	    level_run_merged(&L, p, g->width, merge_row, &m, base, &st, e) < 0)
		goto done;
	st.samples = samples;
	pk_merge_stats(w, l, &st);
	r = 0;
done:
	for (int i = 0; m.r != NULL && i < n; i++)
		rs_close(m.r[i]);
	pk_vmap_close(&v);
	free(m.q), free(m.r), free(m.row), free(base);
	return r;
}

