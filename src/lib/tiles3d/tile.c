/* tile.c - one block as one glb: its selection at the level's tolerance,
 * positions through PROJ into the tile's east-north-up frame as float32,
 * normals, skirts, and the bound of its vertical error (t3_impl.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tiles3d/t3_impl.h"

#define NSKIRT (4 * BT_SIZE)            /* skirt vertices: per side */
#define NV (PYRAMID_N + NSKIRT)          /* grid, then skirt bottoms */
#define MAXI (3 * (2 * BT_CELLS * BT_CELLS + 2 * 4 * BT_CELLS))

int
t3_work_init(t3_work *w, const georef *g, const geo_ground *m, tl_err *e)
{
	memset(w, 0, sizeof *w);
	w->m = m;
	/* with X and Y: a tile's level decides whether they are read */
	if (pyramid_block_alloc(&w->blk, 1, e) < 0)
		return -1;
	w->px = tl_alloc(PYRAMID_N, sizeof *w->px, e);
	w->py = tl_alloc(PYRAMID_N, sizeof *w->py, e);
	w->lon = tl_alloc(PYRAMID_N, sizeof *w->lon, e);
	w->lat = tl_alloc(PYRAMID_N, sizeof *w->lat, e);
	w->h = tl_alloc(PYRAMID_N, sizeof *w->h, e);
	w->x = tl_alloc(3 * PYRAMID_N, sizeof *w->x, e);
	w->foot = tl_alloc(3 * PYRAMID_N, sizeof *w->foot, e);
	w->up = tl_alloc(3 * PYRAMID_N, sizeof *w->up, e);
	w->map = tl_alloc(NV, sizeof *w->map, e);
	w->pos = tl_alloc(3 * NV, sizeof *w->pos, e);
	w->nrm = tl_alloc(3 * NV, sizeof *w->nrm, e);
	w->idx = tl_alloc(MAXI, sizeof *w->idx, e);
	if (!w->px || !w->py || !w->lon || !w->lat || !w->h || !w->x ||
	    !w->foot || !w->up || !w->map || !w->pos || !w->nrm ||
	    !w->idx || geo_proj_open(&w->proj, g, e) < 0) {
		t3_work_free(w);
		return -1;
	}
	return 0;
}

void
t3_work_free(t3_work *w)
{
	pyramid_block_free(&w->blk);
	free(w->px), free(w->py), free(w->lon), free(w->lat), free(w->h), free(w->x), free(w->map);
	free(w->foot), free(w->up);
	free(w->pos), free(w->nrm), free(w->idx);
	free(w->tris.idx), free(w->tris.bound);
	if (w->proj.ctx)
		geo_proj_close(&w->proj);
	memset(w, 0, sizeof *w);
}

/* Every grid vertex: its level-0 grid place (QEM-3D: offset as the
 * checker has it), WGS 84 longitude, latitude, height, and ECEF. */
static int
place(t3_work *w, const georef *g, const t3_tile *t, tl_err *e)
{
	double s = ldexp(1, t->level);

	for (int r = 0; r < BT_SIZE; r++)
		for (int c = 0; c < BT_SIZE; c++) {
			int k = r * BT_SIZE + c;
			double di = 0, dj = 0;
			w->px[k] = (t->bi * BT_CELLS + c) * s;
			w->py[k] = (t->bj * BT_CELLS + r) * s;
			if (t->displaced && isfinite(w->blk.x[k]) &&
			    isfinite(w->blk.y[k]))
				geo_offset_to_grid(w->m, w->px[k], w->py[k],
				    w->blk.x[k], w->blk.y[k], &di, &dj);
			w->px[k] += di, w->py[k] += dj;
			geo_grid_crs(g, w->px[k], w->py[k], &w->lon[k],
			    &w->lat[k]);
			w->h[k] = w->blk.z[k];
		}
	if (geo_proj_lonlat(&w->proj, w->lon, w->lat, w->h, PYRAMID_N, e) < 0) {
		tl_err why = *e;
		return tl_fail(e, "block %d/%d_%d: %s", t->level, t->bj, t->bi,
		    why.msg);
	}
	for (int k = 0; k < PYRAMID_N; k++) {
		double *f = &w->foot[3 * k], *u = &w->up[3 * k];
		geo_ellipsoid(w->lon[k], w->lat[k], f, u);
		for (int a = 0; a < 3; a++)
			w->x[3 * k + a] = f[a] + w->h[k] * u[a];
	}
	return 0;
}

/* ECEF x into the tile's frame, float32 and y-up (glTF): (e, u, -n). */
static void
to_local(const t3_frame *f, const double x[3], float *out)
{
	double d[3] = { x[0] - f->c[0], x[1] - f->c[1], x[2] - f->c[2] };
	double p[3];

	for (int a = 0; a < 3; a++)
		p[a] = f->r[3 * a] * d[0] + f->r[3 * a + 1] * d[1] +
		    f->r[3 * a + 2] * d[2];
	out[0] = (float)p[0], out[1] = (float)p[2], out[2] = (float)-p[1];
}

/* Back to ECEF from the stored floats: what a renderer draws. */
static void
from_local(const t3_frame *f, const float *v, double x[3])
{
	double p[3] = { v[0], -(double)v[2], v[1] };

	for (int a = 0; a < 3; a++)
		x[a] = f->c[a] + f->r[a] * p[0] + f->r[3 + a] * p[1] +
		    f->r[6 + a] * p[2];
}

/* Unit normal of grid vertex k, central differences of the full grid
 * (one-sided at the edges), facing up; in the frame, y-up. */
static void
normal(const t3_work *w, const t3_frame *f, int c, int r, float *out)
{
	int c0 = c > 0 ? c - 1 : c, c1 = c < BT_CELLS ? c + 1 : c;
	int r0 = r > 0 ? r - 1 : r, r1 = r < BT_CELLS ? r + 1 : r;
	const double *a = &w->x[3 * (r * BT_SIZE + c0)];
	const double *b = &w->x[3 * (r * BT_SIZE + c1)];
	const double *d = &w->x[3 * (r0 * BT_SIZE + c)];
	const double *u = &w->x[3 * (r1 * BT_SIZE + c)];
	double tx[3], ty[3], n[3], p[3], len;

	for (int q = 0; q < 3; q++)
		tx[q] = b[q] - a[q], ty[q] = d[q] - u[q];
	n[0] = tx[1] * ty[2] - tx[2] * ty[1];
	n[1] = tx[2] * ty[0] - tx[0] * ty[2];
	n[2] = tx[0] * ty[1] - tx[1] * ty[0];
	for (int a3 = 0; a3 < 3; a3++)
		p[a3] = f->r[3 * a3] * n[0] + f->r[3 * a3 + 1] * n[1] +
		    f->r[3 * a3 + 2] * n[2];
	len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
	if (!(len > 0))
		p[0] = p[1] = 0, p[2] = len = 1;
	if (p[2] < 0) /* grids flipped either way */
		len = -len;
	out[0] = (float)(p[0] / len), out[1] = (float)(p[2] / len);
	out[2] = (float)(-p[1] / len);
}

/* The border side (top, bottom, left, right) both ends of a grid edge
 * lie on, or -1; and the position along it. */
static int
side_of(int a, int b, int *ta, int *tb)
{
	int ca = a % BT_SIZE, ra = a / BT_SIZE, cb = b % BT_SIZE, rb = b / BT_SIZE;

	*ta = ca, *tb = cb;
	if (ra == 0 && rb == 0)
		return 0;
	if (ra == BT_CELLS && rb == BT_CELLS)
		return 1;
	*ta = ra, *tb = rb;
	if (ca == 0 && cb == 0)
		return 2;
	if (ca == BT_CELLS && cb == BT_CELLS)
		return 3;
	return -1;
}

/* Glb vertex of grid or skirt vertex v, numbered on first use. */
static int
use(t3_work *w, int v, int *nv)
{
	if (w->map[v] < 0)
		w->map[v] = (*nv)++;
	return w->map[v];
}

static int
skirt_vertex(int side, int t)
{
	return PYRAMID_N + side * BT_SIZE + t;
}

/* The grid vertex a skirt vertex hangs from. */
static int
skirt_top(int v)
{
	int side = (v - PYRAMID_N) / BT_SIZE, t = (v - PYRAMID_N) % BT_SIZE;

	return side < 2 ? (side ? BT_CELLS : 0) * BT_SIZE + t :
	    t * BT_SIZE + (side == 3 ? BT_CELLS : 0);
}

/* Indices: terrain triangles counter-clockwise seen from above (the
 * bintree's alternate), then two per border edge down to the skirt. */
static int
indices(t3_work *w, const georef *g, int *nv)
{
	double s = (g->step[0] > 0) == (g->step[1] > 0) ? 1 : -1;
	int ni = 0;

	for (int v = 0; v < NV; v++)
		w->map[v] = -1;
	/* numbered in grid order: the same file whatever the selection order */
	for (int k = 0; k < 3 * w->tris.n; k++)
		w->map[w->tris.idx[k]] = 0;
	*nv = 0;
	for (int v = 0; v < PYRAMID_N; v++)
		if (w->map[v] == 0)
			w->map[v] = (*nv)++;
	for (int k = 0; k < w->tris.n; k++) {
		const uint16_t *q = &w->tris.idx[3 * k];
		int c[3], r[3];
		for (int a = 0; a < 3; a++)
			c[a] = q[a] % BT_SIZE, r[a] = q[a] / BT_SIZE;
		double x = s * ((c[1] - c[0]) * (r[2] - r[0]) -
		    (r[1] - r[0]) * (c[2] - c[0]));
		int o = x > 0 ? 1 : 2;
		w->idx[ni++] = (uint16_t)w->map[q[0]];
		w->idx[ni++] = (uint16_t)w->map[q[o]];
		w->idx[ni++] = (uint16_t)w->map[q[3 - o]];
	}
	for (int k = 0; k < w->tris.n; k++)
		for (int a = 0; a < 3; a++) {
			int p = w->tris.idx[3 * k + a];
			int q = w->tris.idx[3 * k + (a + 1) % 3], tp, tq;
			int side = side_of(p, q, &tp, &tq);
			if (side < 0)
				continue;
			int bp = use(w, skirt_vertex(side, tp), nv);
			int bq = use(w, skirt_vertex(side, tq), nv);
			w->idx[ni++] = (uint16_t)w->map[p];
			w->idx[ni++] = (uint16_t)w->map[q];
			w->idx[ni++] = (uint16_t)bq;
			w->idx[ni++] = (uint16_t)w->map[p];
			w->idx[ni++] = (uint16_t)bq;
			w->idx[ni++] = (uint16_t)bp;
		}
	return ni;
}

/* Glb vertices: floats in the frame, normals; skirt bottoms hang
 * t->skirt metres along the normal of the ellipsoid. */
static void
vertices(t3_work *w, const t3_tile *t)
{
	for (int v = 0; v < NV; v++) {
		int m = w->map[v], k = v < PYRAMID_N ? v : skirt_top(v);
		double x[3];
		if (m < 0)
			continue;
		if (v < PYRAMID_N)
			memcpy(x, &w->x[3 * k], sizeof x);
		else
			geo_ecef(w->lon[k], w->lat[k], w->h[k] - t->skirt, x);
		to_local(&t->f, x, &w->pos[3 * m]);
		normal(w, &t->f, k % BT_SIZE, k / BT_SIZE, &w->nrm[3 * m]);
	}
}

/* The tile's error: over its triangles, the pyramid's bound plus the
 * drawn triangle's distance from the grid-linear one (bound.c). */
static int
error_of(t3_work *w, const georef *g, t3_tile *t, tl_err *e)
{
	t->error = 0;
	for (int k = 0; k < w->tris.n; k++) {
		const uint16_t *q = &w->tris.idx[3 * k];
		double p[3][3], d;
		for (int a = 0; a < 3; a++)
			from_local(&t->f, &w->pos[3 * w->map[q[a]]], p[a]);
		if (t3_flat_bound(w, g, t, q, p, &d, e) < 0)
			return -1;
		w->curve = fmax(w->curve, d);
		t->error = fmax(t->error, w->tris.bound[k] + d);
	}
	return 0;
}

static int
write_glb(t3_work *w, const char *path, int nv, int ni, tl_err *e)
{
	FILE *f = fopen(path, "wb");
	long long bytes = 0;

	if (f == NULL)
		return tl_failsys(e, "%s", path);
	if (t3_glb_write(f, w->pos, w->nrm, nv, w->idx, ni, &bytes, e) < 0) {
		char why[sizeof e->msg];
		fclose(f);
		snprintf(why, sizeof why, "%s", e->msg);
		return tl_fail(e, "%s: %s", path, why);
	}
	if (ferror(f) | fclose(f))
		return tl_failsys(e, "%s", path);
	w->nbytes += bytes;
	return 0;
}

int
t3_tile_write(t3_work *w, const char *dir, const pyramid_index *ix,
    t3_tile *t, const char *path, tl_err *e)
{
	const georef *g = &ix->geo;
	int nv, ni;

	w->blk.level = t->level, w->blk.bi = t->bi, w->blk.bj = t->bj;
	w->blk.displaced = t->displaced;
	if (pyramid_block_load(dir, ix, &w->blk, e) < 0 ||
	    t3_cut(&w->blk, t->tau, t->lmax, t->cmax, t->rmax, &w->tris, e) < 0 ||
	    place(w, g, t, e) < 0)
		return -1;
	ni = indices(w, g, &nv);
	vertices(w, t);
	if (error_of(w, g, t, e) < 0 || write_glb(w, path, nv, ni, e) < 0)
		return -1;
	w->nverts += nv, w->ntris += ni / 3;
	return 0;
}
