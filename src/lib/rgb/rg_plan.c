/* rg_plan.c - dem2rgb as a plan's jobs (rgb.h): the parts, each writing
 * its tiles into the shared work tree and a record of its counts, and
 * the gather that joins the records into one process's report and makes
 * the tree (or the archive) appear.
 *
 * The work split (QEM-1D, subsample): a part is rg_split.c's band, and
 * the gather joins the parts' pieces there before the rest (why that is
 * identical: rg_split.c). -m average: a part runs rg_run itself, the
 * warp and the means whole, and only leaves out the encoding of the
 * tiles of other ranges, so every tile it writes holds the bytes one
 * process writes, and the n ranges of a zoom cover its tiles once; the
 * error and the datum are part 0's, which measured as one process does.
 *
 * Records are WORK.parts/K, beside the work tree (which becomes OUT,
 * nothing more), text, written under a temporary name and renamed
 * (outfile.h): "tl-rgb-part 1", then "k n minzoom maxzoom segments
 * padx pady", the vertical datum on a line of its own, per zoom
 * "z tiles bytes samples max rms", the doubles in C99's %a (exact), and
 * for the split work "window x0 x1 of w" (the level-0 columns read). */
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rgb/rg_impl.h"
#include "base/outfile.h"
#include "base/rmtree.h"

#define RECORDS ".parts" /* beside work: WORK.parts */

static long long
floordiv(long long a, int b)
{
	return a >= 0 ? a / b : -((-a + b - 1) / b);
}

int
rg_plan_parts(const rg_args *a, long long tiles, int *n, tl_err *e)
{
	double ll[4], cell;
	long long pad[2], nt, nx, ny;
	dem_mgrid g;
	int z;

	if (rg_check_out(a, e) < 0 ||
	    dem_extent_wgs84(a->dem, ll, &cell, e) < 0)
		return -1;
	z = a->maxzoom >= 0 ? a->maxzoom :
	    rg_maxzoom((ll[1] + ll[3]) / 2, cell, a->dim);
	rg_grid_of(&g, z, a->dim, ll, 0, pad);
	nx = floordiv(g.x0 + g.w - 1, a->dim) - floordiv(g.x0, a->dim) + 1;
	ny = floordiv(g.y0 + g.h - 1, a->dim) - floordiv(g.y0, a->dim) + 1;
	if (RG_SPLIT(a)) { /* bands of whole tile columns */
		long long c = tiles / ny > 0 ? tiles / ny : 1;
		nt = tiles > 0 ? (nx + c - 1) / c : 1;
	} else
		nt = tiles > 0 ? (nx * ny + tiles - 1) / tiles : 1;
	*n = (int)(nt < 1 ? 1 : nt > RG_MAXPARTS ? RG_MAXPARTS : nt);
	return 0;
}

static int
put_record(const char *work, int k, int n, const rg_report *r,
    const int win[3], tl_err *e)
{
	char path[4200];
	tl_outfile o;
	FILE *f;

	snprintf(path, sizeof path, "%s" RECORDS, work);
	if (mkdir(path, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", path);
	snprintf(path, sizeof path, "%s" RECORDS "/%d", work, k);
	if (tl_out_begin(&o, path, e) < 0)
		return -1;
	if ((f = fdopen(dup(o.fd), "w")) == NULL) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	fprintf(f, "tl-rgb-part 1\n%d %d %d %d %d %lld %lld\n%s\n", k, n,
	    r->minzoom, r->maxzoom, r->segments, r->pad[0], r->pad[1],
	    r->vdatum);
	for (int z = r->minzoom; z <= r->maxzoom; z++)
		fprintf(f, "%d %lld %lld %lld %a %a\n", z, r->tiles[z],
		    r->bytes[z], r->n[z], r->max[z], r->rms[z]);
	if (win != NULL) /* the split work: the columns the part read */
		fprintf(f, "window %d %d of %d\n", win[0], win[1], win[2]);
	if (fclose(f) != 0) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	return tl_out_commit(&o, e);
}

int
rg_part(const rg_args *a, const char *work, int k, int n, tl_err *e)
{
	rg_args b = *a;
	rg_report r;

	if (n < 1 || n > RG_MAXPARTS || k < 0 || k >= n)
		return tl_fail(e, "%d:%d: not a part k:n, 0 <= k < n <= %d", k,
		    n, RG_MAXPARTS);
	if (mkdir(work, 0777) < 0 && errno != EEXIST)
		return tl_failsys(e, "%s", work);
	b.work = work, b.part = k, b.nparts = n;
	b.sink = NULL, b.dump = NULL;
	if (RG_SPLIT(a)) {
		int win[3];
		if (rg_split_part(&b, work, k, n, &r, win, e) < 0)
			return -1;
		return put_record(work, k, n, &r, win, e);
	}
	if (rg_run(&b, &r, e) < 0)
		return -1;
	return put_record(work, k, n, &r, NULL, e);
}

/* Record k into r (part 0) or its tiles and bytes added to r's; n:
 * the parts record 0 says, checked against every other. */
static int
get_record(const char *work, int k, int *n, rg_report *r, tl_err *e)
{
	char path[4200], line[512];
	int kk, nn, z0, z1, seg, z, ok;
	long long px, py, t, b, s;
	double mx, rms;
	FILE *f;

	snprintf(path, sizeof path, "%s" RECORDS "/%d", work, k);
	if ((f = fopen(path, "r")) == NULL)
		return errno == ENOENT ? tl_fail(e, "%s: no record: run the "
		    "plan's part %d first", path, k) :
		    tl_failsys(e, "%s", path);
	ok = fgets(line, sizeof line, f) != NULL &&
	    strcmp(line, "tl-rgb-part 1\n") == 0 &&
	    fscanf(f, "%d %d %d %d %d %lld %lld", &kk, &nn, &z0, &z1, &seg,
	    &px, &py) == 7 && kk == k && (k == 0 || nn == *n) &&
	    (k == 0 || (z0 == r->minzoom && z1 == r->maxzoom)) &&
	    z0 >= 0 && z0 <= z1 && z1 <= RG_MAXZOOM && fgetc(f) == '\n' &&
	    fgets(line, sizeof line, f) != NULL;
	if (ok && k == 0) {
		*n = nn, r->minzoom = z0, r->maxzoom = z1, r->segments = seg;
		r->pad[0] = px, r->pad[1] = py;
		line[strcspn(line, "\n")] = '\0';
		snprintf(r->vdatum, sizeof r->vdatum, "%.255s", line);
	}
	for (int zz = z0; ok && zz <= z1; zz++) {
		ok = fscanf(f, "%d %lld %lld %lld %la %la", &z, &t, &b, &s, &mx,
		    &rms) == 6 && z == zz;
		r->tiles[zz] += t, r->bytes[zz] += b;
		if (ok && k == 0)
			r->n[zz] = s, r->max[zz] = mx, r->rms[zz] = rms;
	}
	fclose(f);
	return ok ? 0 : tl_fail(e, "%s: not a part's record of this plan",
	    path);
}

/* The bytes of file path, malloc'd, in *p (n of them). */
static int
read_file(const char *path, unsigned char **p, size_t *n, tl_err *e)
{
	FILE *f = fopen(path, "rb");
	long len;

	*p = NULL;
	if (f == NULL || fseek(f, 0, SEEK_END) < 0 || (len = ftell(f)) < 0 ||
	    fseek(f, 0, SEEK_SET) < 0) {
		if (f != NULL)
			fclose(f);
		return tl_failsys(e, "%s", path);
	}
	*n = (size_t)len;
	if ((*p = tl_alloc(*n ? *n : 1, 1, e)) == NULL) {
		fclose(f);
		return -1;
	}
	if (fread(*p, 1, *n, f) != *n) {
		fclose(f);
		free(*p);
		*p = NULL;
		return tl_fail(e, "%s: short read", path);
	}
	fclose(f);
	return 0;
}

/* Every tile file of the work tree (z/x/y.ext) into the archive w; the
 * count in *nt. */
static int
add_tiles(pm_writer *w, const char *work, const rg_report *r,
    const char *ext, long long *nt, tl_err *e)
{
	char path[4400];
	int rv = 0;

	*nt = 0;
	for (int z = r->minzoom; rv == 0 && z <= r->maxzoom; z++) {
		DIR *dx, *dy;
		struct dirent *x, *y;
		snprintf(path, sizeof path, "%s/%d", work, z);
		if ((dx = opendir(path)) == NULL)
			continue; /* a zoom with no tile */
		while (rv == 0 && (x = readdir(dx)) != NULL) {
			if (x->d_name[0] == '.')
				continue;
			snprintf(path, sizeof path, "%s/%d/%s", work, z,
			    x->d_name);
			if ((dy = opendir(path)) == NULL) {
				rv = tl_failsys(e, "%s", path);
				break;
			}
			while (rv == 0 && (y = readdir(dy)) != NULL) {
				char *dot = strrchr(y->d_name, '.');
				unsigned char *p;
				size_t n = 0;
				if (y->d_name[0] == '.' || dot == NULL ||
				    strcmp(dot + 1, ext) != 0)
					continue;
				snprintf(path, sizeof path, "%s/%d/%s/%s", work,
				    z, x->d_name, y->d_name);
				if ((rv = read_file(path, &p, &n, e)) < 0)
					break;
				rv = pm_add(w, z, (unsigned)strtoul(x->d_name,
				    NULL, 10), (unsigned)strtoul(y->d_name,
				    NULL, 10), p, n, e);
				free(p);
				(*nt)++;
			}
			closedir(dy);
		}
		closedir(dx);
	}
	return rv;
}

/* -o: the archive from the work tree's tiles, which must be the tiles
 * the parts recorded. */
static int
gather_archive(const rg_job *j, const char *work, const rg_report *r,
    const double ll[4], tl_err *e)
{
	long long want = 0, nt;
	pm_writer *w;

	for (int z = r->minzoom; z <= r->maxzoom; z++)
		want += r->tiles[z];
	if ((w = pm_open(j->a->out, e)) == NULL)
		return -1;
	if (add_tiles(w, work, r, rg_format_ext(j->a->fmt), &nt, e) < 0) {
		pm_abort(w);
		return -1;
	}
	if (nt != want) {
		pm_abort(w);
		return tl_fail(e, "%s: %lld tiles, the parts recorded %lld: "
		    "run the plan again", work, nt, want);
	}
	return rg_pmtiles_close(w, j, r, ll, e);
}

int
rg_gather(const rg_args *a, const char *work, rg_report *r, tl_err *e)
{
	rg_job j = { 0 };
	char path[4200];
	double ll[4], cell;
	struct stat st;
	int n = 1, rv;

	memset(r, 0, sizeof *r);
	if (stat(work, &st) < 0 || !S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: no work directory: run the plan's "
		    "parts first", work);
	for (int k = 0; k < n; k++)
		if (get_record(work, k, &n, r, e) < 0)
			return -1;
	if (rg_check_out(a, e) < 0 ||
	    dem_extent_wgs84(a->dem, ll, &cell, e) < 0)
		return -1;
	if (RG_SPLIT(a) && rg_split_gather(a, work, n, r, e) < 0)
		return -1;
	j.a = a, j.tree = work;
	if (a->pmtiles)
		rv = gather_archive(&j, work, r, ll, e);
	else if ((rv = rg_tilejson(&j, r, ll, e)) == 0)
		rv = tl_dir_install(work, a->out, e);
	if (rv < 0)
		return -1;
	/* the records first: a gather killed before work is gone has the
	 * plan's sweep run the parts again */
	snprintf(path, sizeof path, "%s" RECORDS, work);
	tl_rmtree(path);
	snprintf(path, sizeof path, "%s.grid", work);
	tl_rmtree(path);
	if (a->pmtiles)
		tl_rmtree(work);
	return 0;
}
