/* tr_plan.c - the terrain export as a plan's jobs (terrain.h): ranges of
 * a level's tiles made into a work directory, each with a record of the
 * try it holds at, then the gather, byte for byte tr_run's output.
 *
 * The rule, the same as one process's: a level's try is the first at
 * which every tile holds. Round 1: each range's job finds t_j, its own
 * first holding try; no tile holds everywhere before max t_j, so the
 * level's try is at least that. Round 2: each range behind max t_j (of
 * round 1) is made again from there, until it holds. The gather makes
 * again, in one process, any range still behind the largest try, until
 * all agree at one try T: every tile holds at T, and every try ever
 * taken is at most the level's first all-holding try (each range holds
 * there), so T is that try. Records are WORK.ranges/Z-I0.ROUND, beside
 * the work directory (which becomes the terrain, nothing more), text,
 * their doubles in C99's %a (exact), written under a temporary name and
 * renamed (outfile.h):
 * "tl-terrain-range 1", then "z i0 i1 t", "err direct", "tiles tris
 * bytes", and for the 3D Tiles profile a line of 9 doubles a tile, the
 * metadata of t3t.h, in range order. */
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"
#include "base/rmtree.h"
#include "terrain/tr_export.h"

#define RECORDS ".ranges" /* beside work: WORK.ranges */
#define NMETA 9

/* A range's record. */
typedef struct {
	tr_range r;
	tr_part p;
	double *meta;           /* 3D Tiles: NMETA a tile */
} record;

int
tr_plan_ranges(const tr_args *a, long long samples, tr_range **r, int *n,
    tl_err *e)
{
	tr_args q = *a;
	tr_export x;
	long long work;
	int cap = 0;

	q.jobs = 1;
	*r = NULL, *n = 0;
	if (tr_open(&x, &q, e) < 0)
		return -1;
	work = (long long)x.g.w0 * x.g.h0;
	for (int z = 0; z <= x.maxz; z++) {
		long long nt = tr_count(&x, z);
		long long k = samples > 0 ? (work + samples - 1) / samples : 1;
		k = k < 1 ? 1 : k > nt ? nt : k;
		for (long long j = 0; j < k; j++) {
			if (*n == cap) {
				tr_range *m = realloc(*r, (size_t)(cap = 2 *
				    cap + 16) * sizeof **r);
				if (m == NULL) {
					tr_close(&x);
					free(*r), *r = NULL;
					return tl_fail(e, "out of memory");
				}
				*r = m;
			}
			(*r)[(*n)++] = (tr_range){ z, (int)(nt * j / k),
			    (int)(nt * (j + 1) / k) };
		}
	}
	tr_close(&x);
	return 0;
}

static void
record_path(char *p, size_t n, const char *work, const tr_range *r,
    int round)
{
	snprintf(p, n, "%s" RECORDS "/%d-%d.%d", work, r->z, r->i0, round);
}

static int
record_write(const char *work, const record *rc, int round, tl_err *e)
{
	char path[4096];
	tl_outfile o;
	FILE *f;
	int bad;

	record_path(path, sizeof path, work, &rc->r, round);
	if (tl_out_begin(&o, path, e) < 0)
		return -1;
	if ((f = fdopen(dup(o.fd), "w")) == NULL) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	fprintf(f, "tl-terrain-range 2\n%d %d %d %d\n%a %a\n%lld %lld %lld "
	    "%lld %lld\n", rc->r.z, rc->r.i0, rc->r.i1, rc->p.t, rc->p.err,
	    rc->p.direct, rc->p.tiles, rc->p.tris, rc->p.bytes, rc->p.nsamp,
	    rc->p.nmeas);
	for (int i = 0; rc->meta && i < rc->r.i1 - rc->r.i0; i++)
		for (int k = 0; k < NMETA; k++)
			fprintf(f, "%a%c", rc->meta[NMETA * i + k],
			    k == NMETA - 1 ? '\n' : ' ');
	bad = ferror(f);
	if (fclose(f) != 0 || bad) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	return tl_out_commit(&o, e);
}

/* The record of range r (r->i1 < 0: any), round `round`, into *rc
 * (meta: when t3). 1 if there is none, 0 read. */
static int
record_read(const char *work, const tr_range *r, int round, int t3,
    record *rc, tl_err *e)
{
	char path[4096];
	int v, ok, n = 0;
	FILE *f;

	record_path(path, sizeof path, work, r, round);
	if ((f = fopen(path, "r")) == NULL)
		return errno == ENOENT ? 1 : tl_failsys(e, "%s", path);
	rc->meta = NULL;
	ok = fscanf(f, "tl-terrain-range %d %d %d %d %d %la %la %lld %lld "
	    "%lld %lld %lld", &v, &rc->r.z, &rc->r.i0, &rc->r.i1, &rc->p.t,
	    &rc->p.err, &rc->p.direct, &rc->p.tiles, &rc->p.tris, &rc->p.bytes,
	    &rc->p.nsamp, &rc->p.nmeas) == 12 && v == 2 && rc->r.z == r->z && rc->r.i0 == r->i0 &&
	    (r->i1 < 0 || rc->r.i1 == r->i1) && (n = rc->r.i1 - rc->r.i0) > 0 &&
	    rc->p.t >= 0 && rc->p.t < TR_TRIES;
	if (ok && t3)
		ok = (rc->meta = malloc((size_t)n * NMETA *
		    sizeof *rc->meta)) != NULL;
	for (int i = 0; ok && t3 && i < n * NMETA; i++)
		ok = fscanf(f, "%la", &rc->meta[i]) == 1;
	fclose(f);
	if (!ok) {
		free(rc->meta), rc->meta = NULL;
		return tl_fail(e, "%s: not a record of tiles from %d of level "
		    "%d (a plan's file: write the plan again)", path, r->i0,
		    r->z);
	}
	rc->p.held = 1;
	return 0;
}

/* The metadata of the range's tiles between x->t3 and rc->meta: out 1
 * copies the set's into the record. */
static void
meta_copy(tr_export *x, record *rc, int out)
{
	const tr_range *r = &rc->r;
	int nx = x->av[r->z][2] - x->av[r->z][0] + 1;

	for (int i = r->i0; i < r->i1; i++) {
		double *m = t3t_meta(x->t3, r->z, x->av[r->z][0] + i % nx,
		    x->av[r->z][1] + i / nx);
		double *q = rc->meta + NMETA * (size_t)(i - r->i0);
		memcpy(out ? q : m, out ? m : q, NMETA * sizeof *m);
	}
}

/* A set for the range's rows only (levels above: one tile each). */
static t3t_set *
range_set(const tr_export *x, const tr_range *r, tl_err *e)
{
	int av[TR_MAXZ + 1][4] = { { 0 } };
	int nx = x->av[r->z][2] - x->av[r->z][0] + 1;

	memcpy(av[r->z], x->av[r->z], sizeof av[r->z]);
	av[r->z][1] = x->av[r->z][1] + r->i0 / nx;
	av[r->z][3] = x->av[r->z][1] + (r->i1 - 1) / nx;
	return t3t_new(r->z, (const int (*)[4])av, e);
}

/* The largest try of the round-1 records of level z in work (unreadable
 * ones are the gather's to refuse). */
static int
level_try(const char *work, int z, tl_err *e)
{
	char dir[4096], path[4400], tail[8];
	struct dirent *d;
	int best = 0, v, lz, i0, i1, t;
	DIR *dp;
	FILE *f;

	snprintf(dir, sizeof dir, "%s" RECORDS, work);
	if ((dp = opendir(dir)) == NULL)
		return tl_failsys(e, "%s", dir);
	while ((d = readdir(dp)) != NULL) {
		if (sscanf(d->d_name, "%d-%d.%7s", &lz, &i0, tail) != 3 ||
		    lz != z || strcmp(tail, "1") != 0)
			continue;
		snprintf(path, sizeof path, "%s/%s", dir, d->d_name);
		if ((f = fopen(path, "r")) == NULL)
			continue;
		if (fscanf(f, "tl-terrain-range %d %d %d %d %d", &v, &lz, &i0,
		    &i1, &t) == 5 && v == 1 && t > best && t < TR_TRIES)
			best = t;
		fclose(f);
	}
	closedir(dp);
	return best;
}

static int
mkdir_ok(const char *p, tl_err *e)
{
	if (mkdir(p, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", p);
	return 0;
}

/* Range r of the open x into work at tries from `from` on, recorded for
 * round `round`. */
static int
make_range(tr_export *x, const char *work, const tr_range *r, int from,
    int round, tl_err *e)
{
	record rc = { *r, { 0 }, NULL };
	int rv = -1;

	if (x->a->format && ((x->t3 = range_set(x, r, e)) == NULL ||
	    (rc.meta = malloc((size_t)(r->i1 - r->i0) * NMETA *
	    sizeof *rc.meta)) == NULL)) {
		tl_fail(e, "out of memory");
		goto done;
	}
	if (tr_dirs(x, work, r->z, e) < 0 || tr_settle(x, work, r->z, r->i0,
	    r->i1, from, &rc.p, e) < 0)
		goto done;
	if (rc.meta)
		meta_copy(x, &rc, 1);
	rv = record_write(work, &rc, round, e);
done:
	free(rc.meta);
	t3t_free(x->t3);
	x->t3 = NULL;
	return rv;
}

/* The range's own round-1 record copied as its round-2 one. */
static int
copy_round(tr_export *x, const char *work, const tr_range *r, tl_err *e)
{
	record rc = { 0 };
	int rv;

	if ((rv = record_read(work, r, 1, x->a->format, &rc, e)) != 0)
		return rv < 0 ? -1 : tl_fail(e, "tiles %d..%d of level %d: "
		    "no round-1 record: run its round 1 first", r->i0,
		    r->i1 - 1, r->z);
	rv = record_write(work, &rc, 2, e);
	free(rc.meta);
	return rv;
}

int
tr_plan_part(const tr_args *a, const char *work, const tr_range *r,
    int round, tl_err *e)
{
	char path[4096];
	tr_export x;
	record rc = { 0 };
	int rv = -1, from = 0, own;

	if (tr_open(&x, a, e) < 0)
		return -1;
	if (r->z < 0 || r->z > x.maxz || r->i0 < 0 || r->i1 <= r->i0 ||
	    r->i1 > tr_count(&x, r->z)) {
		tl_fail(e, "tiles %d..%d of level %d: not in the tileset "
		    "(levels 0..%d)", r->i0, r->i1 - 1, r->z, x.maxz);
		goto done;
	}
	snprintf(path, sizeof path, "%s" RECORDS, work);
	if (mkdir_ok(work, e) < 0 || mkdir_ok(path, e) < 0)
		goto done;
	tl_out_sweep_dir(path);
	if (round == 1) {
		/* its tiles are remade: a round-2 record no longer holds */
		record_path(path, sizeof path, work, r, 2);
		if (unlink(path) < 0 && errno != ENOENT) {
			tl_failsys(e, "%s", path);
			goto done;
		}
		rv = make_range(&x, work, r, 0, 1, e);
		goto done;
	}
	if ((from = level_try(work, r->z, e)) < 0 ||
	    (own = record_read(work, r, 1, 0, &rc, e)) < 0)
		goto done;
	rv = own == 0 && rc.p.t == from ? copy_round(&x, work, r, e) :
	    make_range(&x, work, r, from, 2, e);
done:
	tr_close(&x);
	return rv;
}

/* The records of level z in work into *out (*n, by i0; a range's round-2
 * record when it has one), covering the level exactly. */
static int
level_records(tr_export *x, const char *work, int z, record **out, int *n,
    tl_err *e)
{
	char dir[4096], tail[8];
	struct dirent *d;
	record *rc = NULL;
	int cap = 0, lz, i0, at = 0;
	DIR *dp;

	*n = 0;
	snprintf(dir, sizeof dir, "%s" RECORDS, work);
	if ((dp = opendir(dir)) == NULL)
		return tl_failsys(e, "%s", dir);
	while ((d = readdir(dp)) != NULL) {
		if (sscanf(d->d_name, "%d-%d.%7s", &lz, &i0, tail) != 3 ||
		    lz != z || strcmp(tail, "1") != 0)
			continue;
		if (*n == cap && (rc = realloc(*out, (size_t)(cap = 2 * cap +
		    8) * sizeof *rc)) == NULL)
			break;
		*out = rc;
		(*out)[(*n)++] = (record){ .r = { z, i0, -1 } };
	}
	closedir(dp);
	if (d != NULL)
		return tl_fail(e, "out of memory");
	for (int k = 0; k < *n; k++) {
		record *c = &(*out)[k];
		tr_range r = c->r;
		int st = record_read(work, &r, 2, x->a->format, c, e);
		if (st < 0 || (st == 1 &&
		    record_read(work, &r, 1, x->a->format, c, e) != 0))
			return -1;
	}
	for (int k = 1; k < *n; k++) /* by i0: few, nearly sorted */
		for (int m = k; m > 0 && (*out)[m].r.i0 < (*out)[m - 1].r.i0;
		    m--) {
			record t = (*out)[m];
			(*out)[m] = (*out)[m - 1], (*out)[m - 1] = t;
		}
	for (int k = 0; k < *n && (*out)[k].r.i0 == at; k++)
		at = (*out)[k].r.i1;
	if (at != tr_count(x, z))
		return tl_fail(e, "level %d: tiles from %d on have no record in "
		    "%s: run their jobs first", z, at, work);
	return 0;
}

/* Level z gathered: its records' metadata into x->t3, the ranges
 * behind the largest try made again until all agree; its report. */
static int
gather_level(tr_export *x, const char *work, int z, tr_report *rep,
    tl_err *e)
{
	record *rc = NULL;
	int n = 0, rv = -1, top, behind = 1;
	tr_part sum = { 0 };

	if (level_records(x, work, z, &rc, &n, e) < 0)
		goto done;
	for (int k = 0; x->t3 && k < n; k++)
		meta_copy(x, &rc[k], 0);
	if (tr_dirs(x, work, z, e) < 0)
		goto done;
	while (behind) {
		behind = 0, top = 0;
		for (int k = 0; k < n; k++)
			top = rc[k].p.t > top ? rc[k].p.t : top;
		for (int k = 0; k < n; k++)
			if (rc[k].p.t < top) {
				behind = 1;
				if (tr_settle(x, work, z, rc[k].r.i0,
				    rc[k].r.i1, top, &rc[k].p, e) < 0)
					goto done;
			}
	}
	for (int k = 0; k < n; k++) {
		sum.t = rc[k].p.t;
		sum.err = fmax(sum.err, rc[k].p.err);
		sum.direct = fmax(sum.direct, rc[k].p.direct);
		sum.tiles += rc[k].p.tiles, sum.tris += rc[k].p.tris;
		sum.bytes += rc[k].p.bytes;
		sum.nsamp += rc[k].p.nsamp, sum.nmeas += rc[k].p.nmeas;
	}
	tr_report_level(x, z, &sum, rep);
	rv = 0;
done:
	for (int k = 0; k < n; k++)
		free(rc[k].meta);
	free(rc);
	return rv;
}

int
tr_plan_gather(const tr_args *a, const char *work, tr_report *rep,
    tl_err *e)
{
	char path[4096];
	struct stat st;
	tr_export x;
	int rv = -1;

	memset(rep, 0, sizeof *rep);
	/* never a work directory made here: no range job has run */
	snprintf(path, sizeof path, "%s" RECORDS, work);
	if (stat(work, &st) < 0 || !S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: no work directory: run the plan's "
		    "range jobs first", work);
	if (tr_open(&x, a, e) < 0)
		return -1;
	rep->maxzoom = x.maxz;
	if (tr_check_out(a->out, e) < 0 || (a->format && (x.t3 =
	    t3t_new(x.maxz, (const int (*)[4])x.av, e)) == NULL))
		goto done;
	for (int z = 0; z <= x.maxz; z++)
		if (gather_level(&x, work, z, rep, e) < 0)
			goto done;
	if (tr_finish(&x, work, e) < 0)
		goto done;
	if ((rv = tl_dir_install(work, a->out, e)) == 0)
		tl_rmtree(path);
done:
	tr_close(&x);
	return rv;
}
