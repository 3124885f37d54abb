/* tr_grid.c - the DEM on the globe: its grid's longitudes and latitudes
 * (affine for a geographic DEM, PROJ for a projected one), the rectangle
 * of the terrain made from it, each block's longitude-latitude box, and
 * a thread's cache of blocks with their vertices' longitudes and
 * latitudes (a projected DEM's through PROJ as they are read, shared
 * through a scratch file). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include "terrain/tr_impl.h"

/* A block's record in g->zs: its heights, errors, then base, zmin,
 * zmax, emax (an undisplaced block: the terrain refuses others). */
#define ZREC (2 * PYRAMID_N * sizeof(float) + 4 * sizeof(double))


/* A geographic grid line the DEM means to lie on a line of the tiles
 * (a tile's edge, a lattice line: multiples of 180 / 2^24 degrees from
 * -180, -90) but reaches off it by rounding is put on it: off, it is a
 * vertex just inside one tile and missing from its neighbour, a sliver
 * that quantisation folds (a crack). v is the affine map's value, whose
 * step b = (a + step) - a carries the rounding of a (up to 1.4e-14
 * degrees for |a| in 64 .. 128) times the place I: 4e-12 at I = 5400
 * (the 8193x8193 mosaic's column at -67.5, holes); t is the same place from
 * the georeference directly (origin + (I + c) step), a few ulps of 180
 * off whatever I. Snapped: v within 1e-12 of a line (as ever), or t
 * within 1e-10 (a grid of whole 1/36000 degrees off a line is at least
 * 2e-10 from it, 1" at least 1e-9: no real grid line is that near one
 * it is not on). */
static double
snap(double v, double t, double o)
{
	double s = ldexp(180, -24), l = o + rint((v - o) / s) * s;

	if (fabs(v - l) < 1e-12)
		return l;
	l = o + rint((t - o) / s) * s;
	return fabs(t - l) < 1e-10 ? l : v;
}

int
tr_lonlat(const tr_grid *g, geo_proj *p, const georef *geo, double *x,
    double *y, int n, tl_err *e)
{
	double *z;
	int r;

	if (!g->projected) {
		for (int i = 0; i < n; i++) {
			double tx, ty;
			geo_vertex_crs(geo, 0, x[i], y[i], &tx, &ty);
			x[i] = snap(g->ax + g->bx * x[i], tx, -180);
			y[i] = snap(g->ay + g->by * y[i], ty, -90);
		}
		return 0;
	}
	if ((z = calloc((size_t)n, sizeof *z)) == NULL)
		return tl_fail(e, "grid: out of memory");
	for (int i = 0; i < n; i++)
		geo_grid_crs(geo, x[i], y[i], &x[i], &y[i]);
	r = geo_proj_lonlat(p, x, y, z, n, e);
	free(z);
	return r;
}

/* Level-0 places along the DEM's four sides, every step samples. */
static int
sides(const tr_grid *g, geo_proj *p, const georef *geo, double lo[4],
    tl_err *e)
{
	int step = (g->w0 > g->h0 ? g->w0 : g->h0) / 1024 + 1, n = 0, r;
	int cap = 2 * (g->w0 / step + g->h0 / step + 4);
	double *x = malloc((size_t)cap * sizeof *x), *y = malloc((size_t)cap *
	    sizeof *y);
	int *side = malloc((size_t)cap * sizeof *side);

	lo[0] = -INFINITY, lo[2] = INFINITY, lo[1] = -INFINITY, lo[3] = INFINITY;
	if (!x || !y || !side) {
		free(x), free(y), free(side);
		return tl_fail(e, "grid: out of memory");
	}
	for (int i = 0; i < g->w0; i += step) /* rows 0 and h0-1 */
		for (int k = 0; k < 2; k++)
			x[n] = i, y[n] = k ? g->h0 - 1 : 0, side[n++] = k;
	for (int j = 0; j < g->h0; j += step) /* columns 0 and w0-1 */
		for (int k = 0; k < 2; k++)
			x[n] = k ? g->w0 - 1 : 0, y[n] = j, side[n++] = 2 + k;
	for (int k = 0; k < 4; k++) /* the corners themselves */
		x[n] = k & 1 ? g->w0 - 1 : 0, y[n] = k & 2 ? g->h0 - 1 : 0,
		side[n++] = 4 + k;
	r = tr_lonlat(g, p, geo, x, y, n, e);
	/* lo: the innermost longitude of the west side, of the east, the
	 * innermost latitude of the south and the north (north-up grids:
	 * row 0 the north) */
	for (int i = 0; r == 0 && i < n; i++) {
		int s = side[i], west = s == 2 || s == 4 || s == 6;
		int east = s == 3 || s == 5 || s == 7;
		int north = s == 0 || s == 4 || s == 5;
		int south = s == 1 || s == 6 || s == 7;
		if (west)
			lo[0] = fmax(lo[0], x[i]);
		if (east)
			lo[2] = fmin(lo[2], x[i]);
		if (south)
			lo[1] = fmax(lo[1], y[i]);
		if (north)
			lo[3] = fmin(lo[3], y[i]);
	}
	free(x), free(y), free(side);
	return r;
}

double
tr_rim_band(const tr_grid *g, int z)
{
	double q = ldexp(180, -z) / QM_MAX * 111320.0; /* m: a latitude's */

	return 0.25 + 8 * q / g->cell;
}

/* A projected DEM's footprint: the box of every sample on its four
 * sides (the image of its inside is within that of its sides), west,
 * south, east, north, into g->fp; r, the terrain's rectangle: that box
 * widened by the band of level 0 (the widest, tr_rim_band) and a
 * hundredth of a cell for the curve of a side between two samples. */
static int
footprint(tr_grid *g, geo_proj *p, const georef *geo, double r[4],
    tl_err *e)
{
	int n = 2 * (g->w0 + g->h0), k = 0, ret;
	double *x = malloc((size_t)n * sizeof *x), *y = malloc((size_t)n *
	    sizeof *y), *f = g->fp;

	r[0] = r[1] = INFINITY, r[2] = r[3] = -INFINITY;
	if (!x || !y) {
		free(x), free(y);
		return tl_fail(e, "grid: out of memory");
	}
	for (int i = 0; i < g->w0; i++)
		x[k] = i, y[k++] = 0, x[k] = i, y[k++] = g->h0 - 1;
	for (int j = 0; j < g->h0; j++)
		x[k] = 0, y[k++] = j, x[k] = g->w0 - 1, y[k++] = j;
	ret = tr_lonlat(g, p, geo, x, y, k, e);
	f[0] = f[1] = INFINITY, f[2] = f[3] = -INFINITY;
	for (int i = 0; ret == 0 && i < k; i++) {
		f[0] = fmin(f[0], x[i]), f[2] = fmax(f[2], x[i]);
		f[1] = fmin(f[1], y[i]), f[3] = fmax(f[3], y[i]);
	}
	free(x), free(y);
	if (ret < 0)
		return -1;
	double m = (tr_rim_band(g, 0) + 0.01) * g->cell / 111000.0;
	double c = cos(fmin(89, fmax(fabs(f[1]), fabs(f[3]))) * M_PI / 180);
	r[0] = f[0] - m / c, r[2] = f[2] + m / c;
	r[1] = f[1] - m, r[3] = f[3] + m;
	return 0;
}

/* Per block of each level: the box of its vertices' longitudes and
 * latitudes, from its border (a block's image is convex enough: the
 * border holds the extremes up to the chord of one level step). */
static int
boxes(tr_grid *g, const pyramid_index *ix, geo_proj *p, tl_err *e)
{
	double x[4 * BT_CELLS], y[4 * BT_CELLS];

	if ((g->box = calloc((size_t)ix->nlevels, sizeof *g->box)) == NULL)
		return tl_fail(e, "grid: out of memory");
	for (int l = 0; l < ix->nlevels; l++) {
		const pyramid_level *L = &ix->lev[l];
		int nb = L->blocks[0] * L->blocks[1], s = 1 << l;
		if ((g->box[l] = malloc((size_t)nb * 4 * sizeof **g->box)) == NULL)
			return tl_fail(e, "grid: out of memory");
		for (int b = 0; b < nb; b++) {
			int bi = b % L->blocks[0], bj = b / L->blocks[0], n = 0;
			double *o = g->box[l] + 4 * b;
			for (int k = 0; k < BT_CELLS; k++) {
				double c0 = bi * BT_CELLS, r0 = bj * BT_CELLS;
				double c1 = c0 + BT_CELLS, r1 = r0 + BT_CELLS;
				x[n] = c0 + k, y[n++] = r0;
				x[n] = c1, y[n++] = r0 + k;
				x[n] = c1 - k, y[n++] = r1;
				x[n] = c0, y[n++] = r1 - k;
			}
			for (int i = 0; i < n; i++)
				x[i] *= s, y[i] *= s;
			if (tr_lonlat(g, p, &ix->geo, x, y, n, e) < 0)
				return -1;
			o[0] = o[1] = INFINITY, o[2] = o[3] = -INFINITY;
			for (int i = 0; i < n; i++) {
				o[0] = fmin(o[0], x[i]), o[2] = fmax(o[2], x[i]);
				o[1] = fmin(o[1], y[i]), o[3] = fmax(o[3], y[i]);
			}
			/* a margin for the sides' bulge between border points */
			double m = g->projected ? 1e-4 * s : 0;
			o[0] -= m, o[1] -= m, o[2] += m, o[3] += m;
		}
	}
	return 0;
}

/* A projected DEM's blocks' vertex longitudes and latitudes, each vertex
 * through PROJ when first read (tr_ll_need): of the 13 M vertices of the
 * UTM warp of N48W125's level-0 blocks the selections read under 1 M (a
 * deep level's tile walks its blocks whole but reads only the triangles
 * near it: tr_far) and tr_far's boxes 25 a block; the measure reads its
 * blocks whole (tr_block_all). A slot's vertex not yet converted holds
 * NaN (a converted one is finite: geo_proj_lonlat). A thread's cache
 * holds 32 blocks, and the levels come back to blocks it dropped, the
 * threads to the same blocks; so every block of every level has a fixed
 * place in an anonymous scratch file (tl_scratch: unlinked at once, so
 * that no end of the run, SIGKILL included, leaves it behind), LLBLOCK
 * bytes: its 129 x 129 longitudes, then its latitudes, NaN where not
 * converted; in memory, per block, the vertices its bytes hold (0: not
 * written) and a hash of them. A slot is loaded from it, and written
 * to it once it converted many at once (a whole block, at once for the
 * other threads) or when dropped, with those another thread wrote there
 * since (the hash changed). Both when LLMIN vertices or more are at
 * stake: a block's read or write costs about as much as converting a
 * few hundred vertices, and the selections come back to few of theirs
 * once the cache dropped them (alone, they ran 3 % faster without the
 * file than with every block read and written); a whole block's 16641
 * far more.
 *
 * No lock. Every buffer ever written holds, per vertex, NaN or its one
 * conversion (which depends only on its grid place: the same PROJ
 * operation, deterministic, point by point, on the same doubles, in
 * any batch), so the file holds NaN or the right doubles per vertex
 * whatever writes go in whatever order. Each writer sets hash and count
 * only after its whole write returned, the count last (release: a
 * reader that sees it (acquire) reads after a write returned, which a
 * read sees, POSIX's read-after-write). A block is used only when the
 * read is whole and its hash agrees; else (two writers at once who set
 * their hashes in the other order, a read across a write, a read error,
 * a short file, bytes the disk lost after a failed writeback) it is
 * taken as holding nothing, its vertices converted again: the same
 * doubles, the work lost, never wrong doubles. A write that fails
 * (ENOSPC, EIO, EFBIG) stops all writes (a partial one put NaN or right
 * doubles, its hash stale): the run goes on, converting what the file
 * lacks. So does a file whose blocks reach half the space its file
 * system had free when it was made, which the output may be sharing. A
 * file that cannot be made, no file: every block loads with no vertex
 * converted. The tiles are the same bytes in every case. */
#define LLBLOCK (2 * (size_t)PYRAMID_N * sizeof(double))
#define LLMIN 4096

struct tr_llfile {
	int fd;
	long long room;         /* bytes it may still take (atomic); -1
	                         * after a failed write: no more writes */
	long long *first;       /* per level: the place of its block 0 */
	int *held;              /* per block: vertices written (atomic) */
	uint64_t *sum;          /* per block: tr_hash of its bytes (atomic) */
};

static void
llfile_free(struct tr_llfile *f)
{
	if (f == NULL)
		return;
	if (f->fd >= 0)
		close(f->fd);
	free(f->first), free(f->held), free(f->sum), free(f);
}

/* g->ll for a projected DEM, or NULL when it cannot be made (memory,
 * no scratch file in TMPDIR): the run converts at each load. */
static void
llfile(tr_grid *g, const pyramid_index *ix)
{
	struct tr_llfile *f = calloc(1, sizeof *f);
	long long n = 0;
	tl_err ignored;
	struct statvfs fs;

	if (f == NULL)
		return;
	f->fd = -1;
	if ((f->first = calloc((size_t)ix->nlevels, sizeof *f->first)) ==
	    NULL)
		goto none;
	for (int l = 0; l < ix->nlevels; l++)
		f->first[l] = n, n += (long long)ix->lev[l].blocks[0] *
		    ix->lev[l].blocks[1];
	f->held = calloc((size_t)n, sizeof *f->held);
	f->sum = calloc((size_t)n, sizeof *f->sum);
	if (f->held == NULL || f->sum == NULL ||
	    (f->fd = tl_scratch(&ignored)) < 0 || fstatvfs(f->fd, &fs) < 0)
		goto none;
	f->room = (long long)(fs.f_bavail / 2 * fs.f_frsize);
	g->ll = f;
	return;
none:
	llfile_free(f);
}

int
tr_grid_init(tr_grid *g, const pyramid_index *ix, geo_proj *p, tl_err *e)
{
	const georef *geo = &ix->geo;
	double x0, y0, x1, y1, lo[4];

	memset(g, 0, sizeof *g);
	g->projected = geo->model != GEO_GEOGRAPHIC;
	g->w0 = ix->size0[0], g->h0 = ix->size0[1];
	geo_vertex_crs(geo, 0, 0, 0, &x0, &y0);
	geo_vertex_crs(geo, 0, 1, 1, &x1, &y1);
	g->ax = x0, g->bx = x1 - x0, g->ay = y0, g->by = y1 - y0;
	g->cell = g->projected ? fmax(fabs(g->bx), fabs(g->by)) * geo->unit :
	    fmax(fabs(g->bx), fabs(g->by)) * 111700.0;
	if ((g->projected ? footprint(g, p, geo, lo, e) : sides(g, p, geo, lo,
	    e)) < 0)
		return -1;
	g->r[0] = fmin(lo[0], lo[2]), g->r[2] = fmax(lo[0], lo[2]);
	g->r[1] = fmin(lo[1], lo[3]), g->r[3] = fmax(lo[1], lo[3]);
	if (!(g->r[0] >= -180 && g->r[2] <= 180 && g->r[1] >= -90 &&
	    g->r[3] <= 90))
		return tl_fail(e, "the DEM's longitudes %.9g .. %.9g, latitudes "
		    "%.9g .. %.9g: not a rectangle within -180 .. 180, "
		    "-90 .. 90", lo[0], lo[2], lo[1], lo[3]);
	if (boxes(g, ix, p, e) < 0)
		return -1;
	if (g->projected)
		tr_curve(g, p, geo), llfile(g, ix);
	long long n = 0;
	for (int l = 0; l < ix->nlevels; l++)
		n += (long long)ix->lev[l].blocks[0] * ix->lev[l].blocks[1];
	g->zs = tr_store_new(n, ZREC);
	return 0;
}

void
tr_grid_free(tr_grid *g, int nlevels)
{
	llfile_free(g->ll);
	tr_store_free(g->zs);
	g->ll = NULL, g->zs = NULL;
	for (int l = 0; g->box && l < nlevels; l++)
		free(g->box[l]);
	free(g->box);
	g->box = NULL;
}

/* A geographic block (l, bi, bj)'s longitude per column and latitude
 * per row into x, y. */
static int
convert(tr_work *w, int l, int bi, int bj, double *x, double *y, tl_err *e)
{
	for (int k = 0; k < BT_SIZE; k++) {
		x[k] = (double)(bi * BT_CELLS + k) * (1 << l);
		y[k] = (double)(bj * BT_CELLS + k) * (1 << l);
	}
	return tr_lonlat(w->g, &w->proj, &w->ix->geo, x, y, BT_SIZE, e);
}

/* The file's block (l, bi, bj). */
static long long
llindex(const tr_work *w, int l, int bi, int bj)
{
	return w->g->ll->first[l] + (long long)bj * w->ix->lev[l].blocks[0] +
	    bi;
}

/* Slot s's block (l, bi, bj) from the run's file, or with no vertex
 * converted. */
static void
ll_load(tr_work *w, int s, int l, int bi, int bj)
{
	struct tr_llfile *f = w->g->ll;
	double *x = w->clon[s];
	long long k;
	uint64_t h;
	tl_err ignored;

	w->cnll[s] = 0, w->cnew[s] = 0, w->csum[s] = 0;
	if (f != NULL) {
		k = llindex(w, l, bi, bj);
		if (__atomic_load_n(&f->held[k], __ATOMIC_ACQUIRE) >= LLMIN &&
		    tl_pread(f->fd, x, LLBLOCK, k * (long long)LLBLOCK,
		    "scratch", &ignored) == 0 &&
		    (h = tr_hash(x, LLBLOCK)) == __atomic_load_n(&f->sum[k],
		    __ATOMIC_RELAXED)) {
			for (int v = 0; v < PYRAMID_N; v++)
				w->cnll[s] += !isnan(x[v]);
			w->csum[s] = h;
			return;
		}
	}
	for (size_t v = 0; v < 2 * (size_t)PYRAMID_N; v++)
		x[v] = NAN;
}

/* Into slot s the vertices file block k holds that it lacks, when the
 * block was written since the slot was loaded. */
static void
ll_merge(tr_work *w, int s, long long k)
{
	struct tr_llfile *f = w->g->ll;
	double *x = w->clon[s], *t;
	tl_err ignored;

	if (__atomic_load_n(&f->sum[k], __ATOMIC_RELAXED) == w->csum[s] ||
	    (t = malloc(LLBLOCK)) == NULL)
		return;
	if (tl_pread(f->fd, t, LLBLOCK, k * (long long)LLBLOCK, "scratch",
	    &ignored) == 0 && tr_hash(t, LLBLOCK) ==
	    __atomic_load_n(&f->sum[k], __ATOMIC_RELAXED))
		for (int v = 0; v < PYRAMID_N; v++)
			if (isnan(x[v]) && !isnan(t[v])) {
				x[v] = t[v], x[PYRAMID_N + v] = t[PYRAMID_N + v];
				w->cnll[s]++;
			}
	free(t);
}

/* Slot s's conversions into the run's file, with those another thread
 * wrote there since the slot was loaded or saved. */
static void
ll_save(tr_work *w, int s)
{
	struct tr_llfile *f = w->g->ll;
	long long k, off;
	tl_err ignored;

	if (f == NULL || w->cnew[s] < LLMIN ||
	    __atomic_load_n(&f->room, __ATOMIC_RELAXED) < 0)
		return;
	k = llindex(w, w->ckey[s][0], w->ckey[s][1], w->ckey[s][2]);
	off = k * (long long)LLBLOCK;
	if (__atomic_load_n(&f->held[k], __ATOMIC_ACQUIRE) > 0)
		ll_merge(w, s, k);
	else if (__atomic_load_n(&f->room, __ATOMIC_RELAXED) <
	    (long long)LLBLOCK || __atomic_sub_fetch(&f->room, LLBLOCK,
	    __ATOMIC_RELAXED) < 0)
		return; /* a new block past the room */
	w->cnew[s] = 0;
	if (tl_pwrite(f->fd, w->clon[s], LLBLOCK, off, "scratch",
	    &ignored) < 0) {
		__atomic_store_n(&f->room, -1, __ATOMIC_RELAXED);
		return;
	}
	w->csum[s] = tr_hash(w->clon[s], LLBLOCK);
	__atomic_store_n(&f->sum[k], w->csum[s], __ATOMIC_RELAXED);
	__atomic_store_n(&f->held[k], w->cnll[s], __ATOMIC_RELEASE);
}

/* Slot s's vertices v[0 .. n-1] (v NULL: all) through PROJ where not
 * yet converted, in one batch; a vertex listed twice is converted once. */
static int
need(tr_work *w, int s, const int *v, int n, tl_err *e)
{
	double *lon = w->clon[s], *lat = w->clat[s], sx[2 * 64], *x = sx;
	int sa[64], *at = sa, m = 0, r = 0, l = w->ckey[s][0];
	int bi = w->ckey[s][1], bj = w->ckey[s][2];

	if (w->cnll[s] == PYRAMID_N)
		return 0;
	if (v == NULL)
		n = PYRAMID_N;
	if (n > 64 && ((x = malloc(2 * (size_t)n * sizeof *x)) == NULL ||
	    (at = malloc((size_t)n * sizeof *at)) == NULL)) {
		if (x != sx)
			free(x);
		return tl_fail(e, "grid: out of memory");
	}
	for (int i = 0; i < n; i++) {
		int k = v ? v[i] : i;
		if (!isnan(lon[k]))
			continue;
		lon[k] = 0; /* taken */
		at[m] = k;
		x[m] = (double)(bi * BT_CELLS + k % BT_SIZE) * (1 << l);
		x[n + m++] = (double)(bj * BT_CELLS + k / BT_SIZE) * (1 << l);
	}
	if (m > 0)
		r = tr_lonlat(w->g, &w->proj, &w->ix->geo, x, x + n, m, e);
	for (int i = 0; i < m; i++)
		lon[at[i]] = r < 0 ? NAN : x[i], lat[at[i]] = r < 0 ? NAN :
		    x[n + i];
	if (r == 0 && m > 0)
		w->cnll[s] += m, w->cnew[s] += m;
	if (x != sx)
		free(x), free(at);
	if (m >= LLMIN)
		ll_save(w, s); /* a whole block at once: shared at once */
	return r;
}

int
tr_ll_need(tr_work *w, const pyramid_block *b, const int *v, int n,
    tl_err *e)
{
	if (!w->g->projected)
		return 0;
	return need(w, (int)(b - w->cache), v, n, e);
}

/* Block b (level, bi, bj set) as decoded: from the run's store, or
 * loaded (pyramid_block_load: read and checked) and put there. */
static int
block_load(tr_work *w, pyramid_block *b, tl_err *e)
{
	const pyramid_index *ix = w->ix;
	long long k = (long long)b->bj * ix->lev[b->level].blocks[0] + b->bi;
	unsigned char *r;
	double v[4];

	if (b->level < 0 || b->level >= ix->nlevels || b->bi < 0 ||
	    b->bj < 0 || b->bi >= ix->lev[b->level].blocks[0] ||
	    b->bj >= ix->lev[b->level].blocks[1])
		return pyramid_block_load(w->dir, ix, b, e); /* it says */
	for (int l = 0; l < b->level; l++)
		k += (long long)ix->lev[l].blocks[0] * ix->lev[l].blocks[1];
	if (w->zrec == NULL && w->g->zs && (w->zrec = malloc(ZREC)) == NULL)
		return tl_fail(e, "block cache: out of memory");
	r = w->zrec;
	if (r && tr_store_get(w->g->zs, k, r) == 0) {
		memcpy(b->z, r, PYRAMID_N * sizeof(float));
		memcpy(b->e, r + PYRAMID_N * sizeof(float), PYRAMID_N *
		    sizeof(float));
		memcpy(v, r + 2 * PYRAMID_N * sizeof(float), sizeof v);
		b->base = v[0], b->zmin = v[1], b->zmax = v[2], b->emax = v[3];
		return 0;
	}
	if (pyramid_block_load(w->dir, ix, b, e) < 0)
		return -1;
	if (r) {
		v[0] = b->base, v[1] = b->zmin, v[2] = b->zmax, v[3] = b->emax;
		memcpy(r, b->z, PYRAMID_N * sizeof(float));
		memcpy(r + PYRAMID_N * sizeof(float), b->e, PYRAMID_N *
		    sizeof(float));
		memcpy(r + 2 * PYRAMID_N * sizeof(float), v, sizeof v);
		tr_store_put(w->g->zs, k, r);
	}
	return 0;
}

const pyramid_block *
tr_block(tr_work *w, int l, int bi, int bj, const double **lon,
    const double **lat, tl_err *e)
{
	int s = 0;
	pyramid_block *b;

	/* the block held, else the slot used least recently (a strip's
	 * blocks stay while the next strip, going the other way, comes
	 * back past them: tr_tile_at) */
	for (int k = 0; k < w->ncache; k++) {
		if (w->cused[k] == 1 && w->ckey[k][0] == l &&
		    w->ckey[k][1] == bi && w->ckey[k][2] == bj) {
			w->cstamp[k] = ++w->clock;
			*lon = w->clon[k], *lat = w->clat[k];
			return &w->cache[k];
		}
		if (w->cstamp[k] < w->cstamp[s])
			s = k;
	}
	b = &w->cache[s];
	w->cstamp[s] = ++w->clock;
	if (w->cused[s] == 1 && w->g->projected)
		ll_save(w, s);
	if (w->cused[s] == 0) {
		if (pyramid_block_alloc(b, 0, e) < 0)
			return NULL;
		w->cused[s] = 2; /* allocated, holding nothing */
		/* one allocation: y follows x (lonlat) */
		size_t nv = w->g->projected ? PYRAMID_N : BT_SIZE;
		if ((w->clon[s] = malloc(2 * nv * sizeof *w->clon[s])) == NULL)
			return tl_fail(e, "block cache: out of memory"), NULL;
		w->clat[s] = w->clon[s] + nv;
	}
	*lon = w->clon[s], *lat = w->clat[s];
	w->cused[s] = 2, w->cboxok[s] = 0;
	if (w->ix->lev[l].displaced)
		return tl_fail(e, "%s: level %d is displaced (QEM-3D): not "
		    "exported", w->dir, l), NULL;
	b->level = l, b->bi = bi, b->bj = bj, b->displaced = 0;
	if (block_load(w, b, e) < 0)
		return NULL;
	if (w->g->projected)
		ll_load(w, s, l, bi, bj);
	else if (convert(w, l, bi, bj, w->clon[s], w->clat[s], e) < 0)
		return NULL;
	w->cused[s] = 1;
	w->ckey[s][0] = l, w->ckey[s][1] = bi, w->ckey[s][2] = bj;
	return b;
}

const pyramid_block *
tr_block_all(tr_work *w, int l, int bi, int bj, const double **lon,
    const double **lat, tl_err *e)
{
	const pyramid_block *b = tr_block(w, l, bi, bj, lon, lat, e);

	if (b != NULL && tr_ll_need(w, b, NULL, 0, e) < 0)
		return NULL;
	return b;
}
