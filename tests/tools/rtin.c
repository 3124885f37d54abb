/*
 * rtin - a reference for scripts/bench-terrain: per level of a
 * quantized-mesh tileset, the triangles a right-triangulated irregular
 * network (RTIN: longest-edge bisection, as Martini and MapLibre use) of
 * each tile needs to be within E_L = 77067.34 m / 2^L of every valid DEM
 * sample in the tile, measured as the renderer draws it: flat triangles
 * in ECEF (WGS 84), vertical distance. Independent of the writer: it reads only the DEM
 * (GDAL) and the names of the tile files, never their bytes.
 *
 * usage: rtin DEM TERRAINDIR [F]   (a geographic DEM, heights as the
 * tiles'; F: hold F E_L instead, default 1)
 * prints: "level L tiles N triangles T forced F" per level present.
 *
 * The lattice is the DEM's own sample grid (vertices on samples; outside
 * the DEM and on voids a vertex has height 0, the ellipsoid), a square
 * window of 2^k + 1 samples from the sample at or west/north of the
 * tile's corner, covering the tile. A triangle splits while some valid
 * sample inside the tile and under it (in the grid) is more than E_L,
 * vertically, from its plane in ECEF (no quantisation, no skirts). Splits
 * are then closed so that the mesh is conforming (a split hypotenuse is
 * split on both sides, the 4-8 mesh rule), the new triangles retested,
 * until nothing changes. Counted: the triangles that meet the tile's
 * rectangle. A leaf of legs 1 holds only its 3 vertices, so E_L is
 * always met, one-sample cliffs included.
 */
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gdal.h>

#define EL0	77067.34
#define WGS_A	6378137.0
#define WGS_E2	(1 / 298.257223563 * (2 - 1 / 298.257223563))
#define D2R	(M_PI / 180)
#define MAXLEV	32

static double frac = 1;	/* the fraction of E_L held */

struct dem {
	float	*z;		/* w * h, NaN where no valid sample */
	int	 w, h;
	double	 gt[6];
	double	*clat, *slat, *nrad;	/* per row: cos, sin, prime vertical */
	double	*clon, *slon;		/* per column */
};

struct tile {
	const struct dem *d;
	long	 ox, oy;	/* window origin, DEM sample indices */
	long	 s;		/* window side, a power of two */
	double	 rx0, rx1, ry0, ry1;	/* tile rectangle, sample index space */
	long	 vx0, vx1, vy0, vy1;	/* samples checked (inclusive) */
	double	 e;
};

/* a set of window points (split midpoints), open addressing */
struct set {
	uint64_t *k;
	size_t	 n, cap;
};

static int
set_has(const struct set *s, uint64_t key)
{
	size_t i;

	if (s->cap == 0)
		return 0;
	for (i = (key * 0x9e3779b97f4a7c15ULL) >> 20 & (s->cap - 1);
	    s->k[i] != 0; i = (i + 1) & (s->cap - 1))
		if (s->k[i] == key)
			return 1;
	return 0;
}

static int
set_add(struct set *s, uint64_t key)
{
	size_t i, j, oc;
	uint64_t *ok;

	if (set_has(s, key))
		return 0;
	if (2 * (s->n + 1) > s->cap) {
		ok = s->k;
		oc = s->cap;
		s->cap = oc ? 2 * oc : 1024;
		if ((s->k = calloc(s->cap, 8)) == NULL)
			abort();
		s->n = 0;
		for (j = 0; j < oc; j++)
			if (ok[j] != 0)
				set_add(s, ok[j]);
		free(ok);
	}
	for (i = (key * 0x9e3779b97f4a7c15ULL) >> 20 & (s->cap - 1);
	    s->k[i] != 0; i = (i + 1) & (s->cap - 1))
		;
	s->k[i] = key;
	s->n++;
	return 1;
}

static uint64_t
key(long x, long y)
{
	return ((uint64_t)y << 32 | (uint64_t)x) + 1;
}

/* height of window point (x, y): the sample, 0 outside or on a void */
static double
height(const struct tile *t, long x, long y)
{
	long i = t->ox + x, j = t->oy + y;
	float v;

	if (i < 0 || j < 0 || i >= t->d->w || j >= t->d->h)
		return 0;
	v = t->d->z[(size_t)j * t->d->w + i];
	return isnan(v) ? 0 : v;
}

/* ECEF of the window point (x, y) at height z (WGS 84) */
static void
ecef(const struct tile *t, long x, long y, double z, double *p)
{
	const double *g = t->d->gt;
	double lon = (g[0] + (t->ox + x + 0.5) * g[1]) * D2R;
	double lat = (g[3] + (t->oy + y + 0.5) * g[5]) * D2R, n;

	lat = fmax(-M_PI / 2, fmin(M_PI / 2, lat));
	n = WGS_A / sqrt(1 - WGS_E2 * sin(lat) * sin(lat));
	p[0] = (n + z) * cos(lat) * cos(lon);
	p[1] = (n + z) * cos(lat) * sin(lon);
	p[2] = (n * (1 - WGS_E2) + z) * sin(lat);
}

/* vertical distance from DEM sample (i, j) of height v to the plane
 * through pa with normal nn, in ECEF, as the renderer draws it */
static double
vdist(const struct dem *d, long i, long j, double v, const double *pa,
    const double *nn)
{
	double q[3], u[3], r = d->nrad[j], den;

	u[0] = d->clat[j] * d->clon[i];
	u[1] = d->clat[j] * d->slon[i];
	u[2] = d->slat[j];
	q[0] = (r + v) * u[0];
	q[1] = (r + v) * u[1];
	q[2] = (r * (1 - WGS_E2) + v) * u[2];
	den = nn[0] * u[0] + nn[1] * u[1] + nn[2] * u[2];
	if (fabs(den) < 1e-12)
		return INFINITY;
	return fabs((nn[0] * (pa[0] - q[0]) + nn[1] * (pa[1] - q[1]) +
	    nn[2] * (pa[2] - q[2])) / den);
}

/* largest vertical distance (ECEF) from the triangle abc's plane to the
 * checked samples under it (in the grid), stopping once over t->e */
static double
tri_error(const struct tile *t, const long *a, const long *b, const long *c)
{
	long x, y, x0, x1, y0, y1, i, j;
	double pa[3], pb[3], pc[3], nn[3], den, l1, l2, e, worst = 0;
	float v;

	ecef(t, a[0], a[1], height(t, a[0], a[1]), pa);
	ecef(t, b[0], b[1], height(t, b[0], b[1]), pb);
	ecef(t, c[0], c[1], height(t, c[0], c[1]), pc);
	nn[0] = (pb[1] - pa[1]) * (pc[2] - pa[2]) - (pb[2] - pa[2]) * (pc[1] - pa[1]);
	nn[1] = (pb[2] - pa[2]) * (pc[0] - pa[0]) - (pb[0] - pa[0]) * (pc[2] - pa[2]);
	nn[2] = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
	x0 = fmax(fmin(a[0], fmin(b[0], c[0])) + t->ox, t->vx0);
	x1 = fmin(fmax(a[0], fmax(b[0], c[0])) + t->ox, t->vx1);
	y0 = fmax(fmin(a[1], fmin(b[1], c[1])) + t->oy, t->vy0);
	y1 = fmin(fmax(a[1], fmax(b[1], c[1])) + t->oy, t->vy1);
	den = (double)(b[1] - c[1]) * (a[0] - c[0]) +
	    (double)(c[0] - b[0]) * (a[1] - c[1]);
	for (j = y0; j <= y1; j++)
		for (i = x0; i <= x1; i++) {
			v = t->d->z[(size_t)j * t->d->w + i];
			if (isnan(v))
				continue;
			x = i - t->ox;
			y = j - t->oy;
			l1 = ((double)(b[1] - c[1]) * (x - c[0]) +
			    (double)(c[0] - b[0]) * (y - c[1])) / den;
			l2 = ((double)(c[1] - a[1]) * (x - c[0]) +
			    (double)(a[0] - c[0]) * (y - c[1])) / den;
			if (l1 < -1e-9 || l2 < -1e-9 || l1 + l2 > 1 + 1e-9)
				continue;
			e = vdist(t->d, i, j, v, pa, nn);
			if (e > worst && (worst = e) > t->e)
				return worst;
		}
	return worst;
}

/* does triangle abc meet the tile's rectangle (positive area)? */
static int
tri_meets(const struct tile *t, const long *a, const long *b, const long *c)
{
	double ox = t->ox, oy = t->oy, nx, ny, lo = INFINITY, hi = -INFINITY;
	double tl, th, q;
	double rx[4] = { t->rx0, t->rx1, t->rx0, t->rx1 };
	double ry[4] = { t->ry0, t->ry0, t->ry1, t->ry1 };
	int k;

	if (fmax(a[0], fmax(b[0], c[0])) + ox <= t->rx0 ||
	    fmin(a[0], fmin(b[0], c[0])) + ox >= t->rx1 ||
	    fmax(a[1], fmax(b[1], c[1])) + oy <= t->ry0 ||
	    fmin(a[1], fmin(b[1], c[1])) + oy >= t->ry1)
		return 0;
	/* the hypotenuse's normal, pointing away from c */
	nx = -(double)(b[1] - a[1]);
	ny = (double)(b[0] - a[0]);
	tl = nx * (a[0] + ox) + ny * (a[1] + oy);
	th = nx * (c[0] + ox) + ny * (c[1] + oy);
	for (k = 0; k < 4; k++) {
		q = nx * rx[k] + ny * ry[k];
		lo = fmin(lo, q);
		hi = fmax(hi, q);
	}
	return fmax(lo, fmin(tl, th)) < fmin(hi, fmax(tl, th));
}

/*
 * Top-down: triangle (a, b, c), hypotenuse ab, right angle c, splits at
 * the midpoint m if m is in `split' or it is over E_L (then m is added).
 * Returns the leaves meeting the tile; *added counts new splits.
 */
static long
walk(const struct tile *t, struct set *split, const long *a, const long *b,
    const long *c, long *added)
{
	long m[2];

	if (labs(a[0] - b[0]) + labs(a[1] - b[1]) <= 2 &&
	    labs(a[0] - b[0]) == labs(a[1] - b[1]))
		return tri_meets(t, a, b, c);	/* legs of 1: a leaf */
	m[0] = (a[0] + b[0]) / 2;
	m[1] = (a[1] + b[1]) / 2;
	if (!set_has(split, key(m[0], m[1]))) {
		if (tri_error(t, a, b, c) <= t->e)
			return tri_meets(t, a, b, c);
		set_add(split, key(m[0], m[1]));
		(*added)++;
	}
	return walk(t, split, c, a, m, added) + walk(t, split, b, c, m, added);
}

static int
tz(long v, int k)
{
	int n = 0;

	if (v == 0)
		return k;
	while ((v & 1) == 0) {
		v >>= 1;
		n++;
	}
	return n;
}

/* the right-angle vertices of the two triangles whose hypotenuse has
 * midpoint (x, y) (the 4-8 mesh, first diagonal from (0, 0)): 2 points */
static void
parents(long s, int k, long x, long y, long *p)
{
	int j = tz(x, k) < tz(y, k) ? tz(x, k) : tz(y, k);
	long h = 1L << j, cx, cy;

	(void)s;
	if ((x >> j & 1) && (y >> j & 1)) {
		/* diagonal: from the cell corner that is a multiple of 4h */
		cx = ((x - h) % (4 * h) == 0) ? x - h : x + h;
		cy = ((y - h) % (4 * h) == 0) ? y - h : y + h;
		p[0] = 2 * x - cx;
		p[1] = cy;
		p[2] = cx;
		p[3] = 2 * y - cy;
	} else if (x >> j & 1) {
		p[0] = x;
		p[1] = y - h;
		p[2] = x;
		p[3] = y + h;
	} else {
		p[0] = x - h;
		p[1] = y;
		p[2] = x + h;
		p[3] = y;
	}
}

/* close `split' under the parents rule; returns the splits added */
static long
close_splits(long s, int k, struct set *split)
{
	uint64_t *todo, q;
	size_t nt = 0, ct, i;
	long p[4], added = 0, x, y;
	int e;

	ct = split->n + 1024;
	if ((todo = malloc(ct * 8)) == NULL)
		abort();
	for (i = 0; i < split->cap; i++)
		if (split->k[i] != 0)
			todo[nt++] = split->k[i];
	while (nt > 0) {
		q = todo[--nt] - 1;
		x = (long)(q & 0xffffffff);
		y = (long)(q >> 32);
		parents(s, k, x, y, p);
		for (e = 0; e < 2; e++) {
			x = p[2 * e];
			y = p[2 * e + 1];
			if (x < 0 || y < 0 || x > s || y > s ||
			    ((x == 0 || x == s) && (y == 0 || y == s)))
				continue;
			if (!set_add(split, key(x, y)))
				continue;
			added++;
			if (nt == ct && (todo = realloc(todo, (ct *= 2) * 8)) == NULL)
				abort();
			todo[nt++] = key(x, y);
		}
	}
	free(todo);
	return added;
}

/* triangles of tile z/x/y's conforming RTIN; *forced: closure splits */
static long
tile_rtin(const struct dem *d, int z, long tx, long ty, long *forced)
{
	struct tile t;
	struct set split = { NULL, 0, 0 };
	double span = 180.0 / (1L << z), w = -180 + tx * span, so = -90 + ty * span;
	long n = 0, add, fx;
	long r0[2], r1[2], r2[2], r3[2];
	int k = 0;

	t.d = d;
	t.e = frac * EL0 / (double)(1L << z);
	t.rx0 = (w - d->gt[0]) / d->gt[1] - 0.5;
	t.rx1 = (w + span - d->gt[0]) / d->gt[1] - 0.5;
	t.ry0 = (so + span - d->gt[3]) / d->gt[5] - 0.5;
	t.ry1 = (so - d->gt[3]) / d->gt[5] - 0.5;
	t.ox = (long)floor(t.rx0);
	t.oy = (long)floor(t.ry0);
	while ((1L << k) < (long)ceil(t.rx1) - t.ox ||
	    (1L << k) < (long)ceil(t.ry1) - t.oy)
		k++;
	t.s = 1L << k;
	t.vx0 = fmax(ceil(t.rx0), 0);
	t.vx1 = fmin(floor(t.rx1), d->w - 1);
	t.vy0 = fmax(ceil(t.ry0), 0);
	t.vy1 = fmin(floor(t.ry1), d->h - 1);
	r0[0] = r0[1] = r2[1] = r3[0] = 0;
	r1[0] = r1[1] = r2[0] = r3[1] = t.s;
	*forced = 0;
	do {
		add = 0;
		n = walk(&t, &split, r0, r1, r2, &add) +
		    walk(&t, &split, r1, r0, r3, &add);
		fx = close_splits(t.s, k, &split);
		*forced += fx;
	} while (add + fx > 0);
	free(split.k);
	return n;
}

static int
load(const char *path, struct dem *d)
{
	GDALDatasetH ds;
	GDALRasterBandH b;
	double nd, lat, lon;
	int has;
	size_t i;

	GDALAllRegister();
	if ((ds = GDALOpen(path, GA_ReadOnly)) == NULL)
		return -1;
	d->w = GDALGetRasterXSize(ds);
	d->h = GDALGetRasterYSize(ds);
	GDALGetGeoTransform(ds, d->gt);
	b = GDALGetRasterBand(ds, 1);
	nd = GDALGetRasterNoDataValue(b, &has);
	if ((d->z = malloc((size_t)d->w * d->h * sizeof(float))) == NULL ||
	    GDALRasterIO(b, GF_Read, 0, 0, d->w, d->h, d->z, d->w, d->h,
	    GDT_Float32, 0, 0) != CE_None)
		return -1;
	for (i = 0; i < (size_t)d->w * d->h; i++)
		if (has && d->z[i] == (float)nd)
			d->z[i] = NAN;
	if ((d->clat = malloc(3 * d->h * sizeof(double))) == NULL ||
	    (d->clon = malloc(2 * d->w * sizeof(double))) == NULL)
		return -1;
	d->slat = d->clat + d->h;
	d->nrad = d->slat + d->h;
	d->slon = d->clon + d->w;
	for (i = 0; i < (size_t)d->h; i++) {
		lat = (d->gt[3] + (i + 0.5) * d->gt[5]) * D2R;
		d->clat[i] = cos(lat);
		d->slat[i] = sin(lat);
		d->nrad[i] = WGS_A / sqrt(1 - WGS_E2 * d->slat[i] * d->slat[i]);
	}
	for (i = 0; i < (size_t)d->w; i++) {
		lon = (d->gt[0] + (i + 0.5) * d->gt[1]) * D2R;
		d->clon[i] = cos(lon);
		d->slon[i] = sin(lon);
	}
	GDALClose(ds);
	return 0;
}

static void
level(const struct dem *d, const char *dir, int z)
{
	char p[4096];
	DIR *dx, *dy;
	struct dirent *ex, *ey;
	long tiles = 0, tris = 0, forced = 0, f, tx, ty;

	snprintf(p, sizeof(p), "%s/%d", dir, z);
	if ((dx = opendir(p)) == NULL)
		return;
	while ((ex = readdir(dx)) != NULL) {
		if (ex->d_name[0] == '.')
			continue;
		tx = atol(ex->d_name);
		snprintf(p, sizeof(p), "%s/%d/%ld", dir, z, tx);
		if ((dy = opendir(p)) == NULL)
			continue;
		while ((ey = readdir(dy)) != NULL) {
			if (strstr(ey->d_name, ".terrain") == NULL)
				continue;
			ty = atol(ey->d_name);
			tris += tile_rtin(d, z, tx, ty, &f);
			forced += f;
			tiles++;
		}
		closedir(dy);
	}
	closedir(dx);
	printf("level %d tiles %ld triangles %ld forced %ld\n", z, tiles,
	    tris, forced);
	fflush(stdout);
}

int
main(int argc, char **argv)
{
	struct dem d;
	int z;

	if (argc < 3 || argc > 4 || (argc == 4 && (frac = atof(argv[3])) <= 0)) {
		fprintf(stderr, "usage: rtin DEM TERRAINDIR [fraction]\n");
		return 2;
	}
	if (load(argv[1], &d) == -1) {
		fprintf(stderr, "rtin: %s: cannot read\n", argv[1]);
		return 1;
	}
	for (z = 0; z < MAXLEV; z++)
		level(&d, argv[2], z);
	free(d.z);
	free(d.clat);
	free(d.clon);
	return 0;
}
