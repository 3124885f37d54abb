/* fqmeval - vertical error of a level's triangulated surface against every
 * valid sample of the original DEM: the grid's 4-8 triangles (diagonal by
 * the parity of cell column + row, as in the bintree), displaced by X/Y
 * offsets when the vertex map has them (3D: each sample is located in the
 * displaced triangle containing it). A benchmark and test tool.
 *
 * usage: fqmeval [-s dx[,dy]] [-e encoding] dem vertexmap
 * prints: n rms mean p99 max uncovered maxcol maxrow   (metres; uncovered
 * samples are those no triangle contains, which a fold-free level never
 * has; maxcol maxrow: the level-0 sample with the largest error) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dem/dem.h"
#include "qem/fqm.h"
#include "raster/raster.h"

/* error histogram: bins of 0.1 % relative width from 1 micrometre */
#define HBINS 30000
#define HMIN 1e-6
#define HRATIO 1.001

typedef struct {
	double n, sum, sum2, max;
	int maxi, maxj; /* where the max is */
	long long uncovered;
	long long *hist;
} stats;

static void
add(stats *s, double e, int i, int j)
{
	int b = 0;

	s->n++, s->sum += e, s->sum2 += e * e;
	if (e > s->max)
		s->max = e, s->maxi = i, s->maxj = j;
	if (e > HMIN)
		b = (int)(log(e / HMIN) / log(HRATIO)) + 1;
	s->hist[b < HBINS ? b : HBINS - 1]++;
}

static double
percentile(const stats *s, double p)
{
	double want = p * s->n, run = 0;

	for (int b = 0; b < HBINS; b++) {
		run += s->hist[b];
		if (run >= want)
			return b == 0 ? HMIN : HMIN * pow(HRATIO, b);
	}
	return s->max;
}

/* A ring of level rows: Z and level-0 index positions of each vertex. */
typedef struct {
	int w, h, level, cz, cx, cy;
	rs_reader *r;
	const geo_ground *m;
	float *buf;
	double *z[4], *px[4], *py[4];
	int tag[4], next;
} rows;

static int
load(rows *R, int j, tl_err *e)
{
	int s = j & 3, w = R->w;
	long J = (long)j << R->level, step = 1L << R->level;

	if (R->tag[s] == j)
		return 0;
	while (R->next <= j)
		if (rs_read_row(R->r, R->buf, e) < 0)
			return -1;
		else if (R->next++ == j)
			break;
	for (int i = 0; i < w; i++) {
		R->z[s][i] = R->buf[(size_t)R->cz * w + i];
		R->px[s][i] = (double)i * step;
		R->py[s][i] = (double)J;
		if (R->cx >= 0) {
			double di, dj;
			geo_offset_to_grid(R->m, (double)i * step, (double)J,
			    R->buf[(size_t)R->cx * w + i],
			    R->buf[(size_t)R->cy * w + i], &di, &dj);
			R->px[s][i] += di, R->py[s][i] += dj;
		}
	}
	R->tag[s] = j;
	return 0;
}

/* Height at (x, y) of triangle (a, b, c) if it contains the point. */
static int
in_tri(const double a[3], const double b[3], const double c[3], double x,
    double y, double *z)
{
	double d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
	double u, v, eps = 1e-9;

	if (d == 0)
		return 0;
	u = ((x - a[0]) * (c[1] - a[1]) - (y - a[1]) * (c[0] - a[0])) / d;
	v = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) / d;
	if (u < -eps || v < -eps || u + v > 1 + eps)
		return 0;
	*z = a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]);
	return 1;
}

/* Surface height of cell (ci, cj) at level-0 point (x, y), if inside. */
static int
cell_height(rows *R, int ci, int cj, double x, double y, double *z)
{
	double p[4][3];
	static const int di[4] = { 0, 1, 1, 0 }, dj[4] = { 0, 0, 1, 1 };

	if (ci < 0 || cj < 0 || ci + 1 >= R->w || cj + 1 >= R->h)
		return 0;
	for (int k = 0; k < 4; k++) {
		int s = (cj + dj[k]) & 3, i = ci + di[k];
		p[k][0] = R->px[s][i], p[k][1] = R->py[s][i];
		p[k][2] = R->z[s][i];
	}
	if (((ci + cj) & 1) == 0) /* diagonal 0-2 */
		return in_tri(p[0], p[1], p[2], x, y, z) ||
		    in_tri(p[0], p[2], p[3], x, y, z);
	return in_tri(p[0], p[1], p[3], x, y, z) ||
	    in_tri(p[1], p[2], p[3], x, y, z);
}

static int
eval(dem *d, rows *R, stats *s, tl_err *e)
{
	const georef *g = dem_georef(d);
	float *z = malloc(g->width * sizeof *z);
	unsigned char *valid = malloc(g->width);
	int reach = R->cx >= 0 ? 1 : 0; /* 3D: neighbouring cells too */

	for (int J = 0; J < g->height; J++) {
		int cj = J >> R->level;
		if (cj >= R->h - 1)
			cj = R->h - 2;
		for (int j = cj - reach; j <= cj + 1 + reach; j++)
			if (j >= 0 && j < R->h && load(R, j, e) < 0)
				return -1;
		if (dem_read_row(d, J, z, valid, e) < 0)
			return -1;
		for (int I = 0; I < g->width; I++) {
			int ci = I >> R->level, found = 0;
			double h = 0;
			if (!valid[I])
				continue;
			if (ci >= R->w - 1)
				ci = R->w - 2;
			for (int dj = 0; !found && dj <= 2 * reach; dj++)
				for (int di = 0; !found && di <= 2 * reach; di++) {
					/* own cell first, then its neighbours */
					int oj = dj == 0 ? 0 : (dj == 1 ? -1 : 1);
					int oi = di == 0 ? 0 : (di == 1 ? -1 : 1);
					found = cell_height(R, ci + oi, cj + oj,
					    I, J, &h);
				}
			if (!found) {
				s->uncovered++;
				continue;
			}
			add(s, fabs(h - z[I]), I, J);
		}
	}
	free(z), free(valid);
	return 0;
}

/* A test tool exits right after its work: its own leaks are not what
 * make check-asan looks for (the programs' and the library's are). */
const char *__asan_default_options(void);
const char *
__asan_default_options(void)
{
	return "detect_leaks=0";
}

int
main(int argc, char **argv)
{
	dem_opts o = { 0 };
	tl_err e;
	dem *d = NULL;
	rows R = { 0 };
	stats s = { 0 };
	fqm_info fi;
	geo_ground m = { 0 };
	int c, r = 1;

	while ((c = getopt(argc, argv, "e:s:")) != -1) {
		switch (c) {
		case 'e':
			o.encoding = strcmp(optarg, "terrainrgb") == 0 ?
			    DEM_ENC_TERRAINRGB : DEM_ENC_GREY;
			break;
		case 's':
			o.cell[0] = o.cell[1] = atof(optarg);
			break;
		default:
			fprintf(stderr, "usage: fqmeval [-s cell] [-e enc] "
			    "dem vertexmap\n");
			return 2;
		}
	}
	if (argc - optind != 2) {
		fprintf(stderr, "usage: fqmeval [-s cell] [-e enc] dem vertexmap\n");
		return 2;
	}
	if ((d = dem_open(argv[optind], &o, &e)) == NULL ||
	    (R.r = rs_open(argv[optind + 1], &e)) == NULL)
		goto fail;
	const rs_header *h = rs_header_of(R.r);
	if (fqm_info_of(h, "vertices", &fi, argv[optind + 1], &e) < 0 ||
	    (R.cz = rs_need_channel(h, "Z", argv[optind + 1], &e)) < 0 ||
	    geo_ground_init(&m, &fi.geo, &e) < 0)
		goto fail;
	R.w = h->width, R.h = h->height, R.level = fi.level, R.m = &m;
	R.cx = rs_channel(h, "X"), R.cy = rs_channel(h, "Y");
	R.buf = malloc((size_t)h->nch * R.w * sizeof *R.buf);
	for (int k = 0; k < 4; k++) {
		R.z[k] = malloc(R.w * sizeof(double));
		R.px[k] = malloc(R.w * sizeof(double));
		R.py[k] = malloc(R.w * sizeof(double));
		R.tag[k] = -1;
	}
	s.hist = calloc(HBINS, sizeof *s.hist);
	if (R.h < 2 || R.w < 2) {
		tl_fail(&e, "level too small");
		goto fail;
	}
	if (eval(d, &R, &s, &e) < 0)
		goto fail;
	printf("%.0f %.6f %.6f %.6f %.6f %lld %d %d\n", s.n, sqrt(s.sum2 / s.n),
	    s.sum / s.n, percentile(&s, 0.99), s.max, s.uncovered, s.maxi,
	    s.maxj);
	r = 0;
	goto done;
fail:
	fprintf(stderr, "fqmeval: %s\n", e.msg);
done: /* everything freed: make check-asan counts leaks */
	rs_close(R.r);
	dem_close(d);
	geo_ground_free(&m);
	free(R.buf), free(s.hist);
	for (int k = 0; k < 4; k++)
		free(R.z[k]), free(R.px[k]), free(R.py[k]);
	return r;
}
