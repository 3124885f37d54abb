/* tr_mesh.c - a tile's mesh: the pyramid's selection at the level's
 * choice (pyramid level, tolerance, longest hypotenuse), cut by the
 * tile's lattice of n x n cells (lines of the global lattice, exact), the
 * part over the DEM clipped from the selection (tr_clip.c), the part past
 * it the ellipsoid (height 0): a frame of four trapezoids around the DEM
 * in a cell the DEM's edge crosses, fanned onto the DEM's edge vertices,
 * two triangles in a cell it misses. A projected DEM's selection is cut
 * to its grid (tr_cut.c) and its cells made by tr_rim.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/tr_impl.h"

void
tr_tile_rect(int z, int x, int y, double r[4])
{
	double w = ldexp(180, -z);

	r[0] = -180 + x * w, r[1] = -90 + y * w;
	r[2] = -180 + (x + 1) * w, r[3] = -90 + (y + 1) * w;
}

static int
lg2(int n)
{
	int k = 0;

	while ((1 << k) < n)
		k++;
	return k;
}

double
tr_lattice_lon(int z, int x, int n, int k)
{
	return -180 + ((double)x * n + k) * ldexp(180, -z - lg2(n));
}

double
tr_lattice_lat(int z, int y, int n, int k)
{
	return -90 + ((double)y * n + k) * ldexp(180, -z - lg2(n));
}

void
tr_tile_at(const tr_grid *g, int z, int nx, int ny, int i, int *x, int *y)
{
	double res = g->projected ? g->cell / 111320.0 : fabs(g->bx);
	double s = BT_CELLS * res / ldexp(180, -z);
	int sw = s < 1 ? 1 : s > nx ? nx : (int)s, k = i / (sw * ny);
	int r = i % (sw * ny), n = nx - k * sw < sw ? nx - k * sw : sw;

	/* odd strips bottom up: the blocks of the rows a strip ended on
	 * are still cached when the next begins */
	*x = k * sw + r % n, *y = k % 2 ? ny - 1 - r / n : r / n;
}

/* --- the selection over the tile ----------------------------------- */

typedef struct {
	tr_work *w;
	const pyramid_block *b;
	const double *lon, *lat; /* the block's vertices' */
	const tr_choice *c;
	double lmax2;      /* 2 lmax^2, level-p cells */
	double r[4];       /* the tile over the DEM, lon/lat */
	double dx, dy;     /* geographic: a level-p cell, degrees; else 0 */
	const double *bx;  /* projected: the block's boxes (tr_far), or NULL */
	int failed;
} sel;

/* As tiles3d's cut.c: twice the squared hypotenuse, in cells, of the
 * triangle that vertex (c, r) splits; it grows up the hierarchy, so
 * splitting every vertex past a length keeps the selection a matching. */
static double
hyp2(int c, int r)
{
	int k = 1;

	while (k < BT_CELLS && !((c | r) & k))
		k <<= 1;
	return (c & r & k) ? 16.0 * k * k : 8.0 * k * k;
}

static int
split(void *ctx, int gi, int gj)
{
	sel *s = ctx;
	int c = gi - s->b->bi * BT_CELLS, r = gj - s->b->bj * BT_CELLS;

	/* the padding past the level's last real vertex needs nothing:
	 * E bounds the real samples in a diamond against its triangles as
	 * they are, padding heights and all (vgis(5)) */
	/* a geographic grid: a triangle whose box (within half its
	 * hypotenuse of its midpoint) misses the tile is not split; emit
	 * drops it and all it holds alike, and those that meet the tile
	 * are cut as before, in the same order */
	if (s->dx > 0) {
		double h = sqrt(hyp2(c, r) / 8) + 1, x = s->lon[c];
		double y = s->lat[r], ex = h * s->dx + 1e-9;
		double ey = h * s->dy + 1e-9;
		if (x + ex < s->r[0] || x - ex > s->r[2] || y + ey < s->r[1] ||
		    y - ey > s->r[3])
			return 0;
	}
	if (!(s->b->e[r * BT_SIZE + c] > s->c->tau || hyp2(c, r) > s->lmax2))
		return 0;
	/* a projected grid: the same, by squares (tr_far.c) */
	return s->bx == NULL || !tr_far(s->w->g, s->bx, s->c->p, s->b->bi,
	    s->b->bj, c, r, s->c->z, s->r);
}

static void
emit(void *ctx, const int t[3][2])
{
	sel *s = ctx;
	tr_work *w = s->w;
	tr_tri q;
	double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };

	if (w->g->projected) { /* cut to the DEM's grid (tr_cut.c) */
		if (!s->failed && tr_rim_sel(w, s->c, s->b, s->lon, s->lat, t,
		    s->r) < 0)
			s->failed = 1;
		return;
	}
	for (int k = 0; k < 3; k++) {
		int c = t[k][0] - s->b->bi * BT_CELLS;
		int r = t[k][1] - s->b->bj * BT_CELLS;
		q.x[k] = s->lon[c], q.y[k] = s->lat[r]; /* geographic */
		q.h[k] = s->b->z[r * BT_SIZE + c];
		lo[0] = fmin(lo[0], q.x[k]), hi[0] = fmax(hi[0], q.x[k]);
		lo[1] = fmin(lo[1], q.y[k]), hi[1] = fmax(hi[1], q.y[k]);
	}
	if (hi[0] < s->r[0] || lo[0] > s->r[2] || hi[1] < s->r[1] ||
	    lo[1] > s->r[3] || s->failed)
		return;
	q.lo[0] = lo[0], q.lo[1] = lo[1], q.hi[0] = hi[0], q.hi[1] = hi[1];
	if (w->nsel == w->csel) {
		int n = w->csel ? 2 * w->csel : 1024;
		tr_tri *a = realloc(w->sel, (size_t)n * sizeof *a);
		int *o = a ? realloc(w->row, (size_t)n * sizeof *o) : NULL;
		if (a)
			w->sel = a;
		if (o == NULL) {
			s->failed = 1;
			return;
		}
		w->row = o, w->csel = n;
	}
	w->sel[w->nsel++] = q;
}

/* The selection over tile t (west, south, east, north) within the
 * terrain's rectangle: every block of level p whose box meets it. */
static int
select_tile(tr_work *w, const tr_choice *c, const double t[4], tl_err *e)
{
	const pyramid_level *L = &w->ix->lev[c->p];
	const double *box = w->g->box[c->p];
	sel s = { .w = w, .c = c };
	/* the longest hypotenuse: a chord sagging E_L / 8 at most */
	double lmax = sqrt(6335439.0 * c->el / 2) / w->g->cell / (1 << c->p);

	s.lmax2 = 2 * fmax(lmax, 1) * fmax(lmax, 1);
	if (!w->g->projected)
		s.dx = ldexp(fabs(w->g->bx), c->p), s.dy = ldexp(fabs(w->g->by),
		    c->p);
	s.r[0] = fmax(t[0], w->g->r[0]), s.r[2] = fmin(t[2], w->g->r[2]);
	s.r[1] = fmax(t[1], w->g->r[1]), s.r[3] = fmin(t[3], w->g->r[3]);
	w->nsel = 0;
	if (!(s.r[0] < s.r[2] && s.r[1] < s.r[3]))
		return 0;
	for (int k = 0; k < L->blocks[0] * L->blocks[1]; k++) {
		const double *o = box + 4 * k;
		int bi = k % L->blocks[0], bj = k / L->blocks[0];
		if (o[2] < s.r[0] || o[0] > s.r[2] || o[3] < s.r[1] ||
		    o[1] > s.r[3])
			continue;
		if ((s.b = tr_block(w, c->p, bi, bj, &s.lon, &s.lat, e)) == NULL)
			return -1;
		if (w->g->projected)
			s.bx = tr_far_boxes(w, s.b, s.lon, s.lat);
		bt_select(bi * BT_CELLS, bj * BT_CELLS, split, &s, emit, &s);
		if (s.failed)
			return tl_fail(e, "mesh: out of memory");
	}
	return 0;
}

/* --- the lattice cells ---------------------------------------------- */

static int
cmp_key(const void *a, const void *b)
{
	double x = ((const double *)a)[0], y = ((const double *)b)[0];

	return (x > y) - (x < y);
}

/* Fan from corner o0 over the mesh's vertices on the segment p q (axis:
 * the coordinate that varies along it) to corner o1. */
static int
trapezoid(tr_mesh *m, const double o0[2], const double o1[2],
    const double p[2], const double q[2], int axis, tl_err *e)
{
	double (*v)[2] = NULL;
	int n = 0, a, b, r = -1;

	if ((p[0] == o0[0] && p[1] == o0[1]) && (q[0] == o1[0] &&
	    q[1] == o1[1]))
		return 0; /* the DEM reaches the cell's side */
	if ((v = malloc(((size_t)m->nv + 1) * sizeof *v)) == NULL)
		return tl_fail(e, "mesh: out of memory");
	for (int i = 0; i < m->nv; i++) {
		double s = axis ? m->y[i] : m->x[i], f = axis ? m->x[i] : m->y[i];
		if (f == (axis ? p[0] : p[1]) && s >= (axis ? p[1] : p[0]) &&
		    s <= (axis ? q[1] : q[0]))
			v[n][0] = s, v[n][1] = i, n++;
	}
	qsort(v, (size_t)n, sizeof *v, cmp_key);
	if ((a = tr_mesh_vertex(m, o0[0], o0[1], 0, e)) < 0 ||
	    (b = tr_mesh_vertex(m, o1[0], o1[1], 0, e)) < 0)
		goto done;
	for (int i = 0; i + 1 < n; i++)
		if (tr_mesh_tri(m, a, (int)v[i][1], (int)v[i + 1][1], e) < 0)
			goto done;
	if (n > 0 && tr_mesh_tri(m, a, (int)v[n - 1][1], b, e) < 0)
		goto done;
	r = 0;
done:
	free(v);
	return r;
}

/* The ellipsoid around the DEM's part r of cell c (both level-0 grid
 * rectangles x0 y0 x1 y1): four trapezoids, those of zero width left. */
static int
frame(tr_mesh *m, const double c[4], const double r[4], tl_err *e)
{
	double c00[2] = { c[0], c[1] }, c10[2] = { c[2], c[1] };
	double c01[2] = { c[0], c[3] }, c11[2] = { c[2], c[3] };
	double r00[2] = { r[0], r[1] }, r10[2] = { r[2], r[1] };
	double r01[2] = { r[0], r[3] }, r11[2] = { r[2], r[3] };

	if ((r[0] > c[0] && trapezoid(m, c00, c01, r00, r01, 1, e) < 0) ||
	    (r[2] < c[2] && trapezoid(m, c10, c11, r10, r11, 1, e) < 0) ||
	    (r[1] > c[1] && trapezoid(m, c00, c10, r00, r10, 0, e) < 0) ||
	    (r[3] < c[3] && trapezoid(m, c01, c11, r01, r11, 0, e) < 0))
		return -1;
	return 0;
}

/* 1 when a vertex of m other than c's corners lies in r, the DEM's part
 * of cell c where it has no area (a side or corner the DEM touches): a
 * vertex there is the DEM's edge in the next cell, and c must fan onto
 * it (frame) or leave a T-junction. */
static int
touched(const tr_mesh *m, const double c[4], const double r[4])
{
	if (!(r[0] <= r[2] && r[1] <= r[3]))
		return 0;
	for (int i = 0; i < m->nv; i++)
		if (m->x[i] >= r[0] && m->x[i] <= r[2] && m->y[i] >= r[1] &&
		    m->y[i] <= r[3] && !((m->x[i] == c[0] || m->x[i] == c[2]) &&
		    (m->y[i] == c[1] || m->y[i] == c[3])))
			return 1;
	return 0;
}

/* Cell (i, j) of the tile's lattice: its rectangle c and its part r in
 * the terrain's rectangle (lon/lat); 1 when r has an area. */
static int
cell_rects(const tr_work *w, const tr_choice *ch, int x, int y, int i,
    int j, double c[4], double r[4])
{
	c[0] = tr_lattice_lon(ch->z, x, ch->n, i);
	c[1] = tr_lattice_lat(ch->z, y, ch->n, j);
	c[2] = tr_lattice_lon(ch->z, x, ch->n, i + 1);
	c[3] = tr_lattice_lat(ch->z, y, ch->n, j + 1);
	r[0] = fmax(c[0], w->g->r[0]), r[2] = fmin(c[2], w->g->r[2]);
	r[1] = fmax(c[1], w->g->r[1]), r[3] = fmin(c[3], w->g->r[3]);
	return r[0] < r[2] && r[1] < r[3];
}

int
tr_mesh_tile(tr_work *w, const tr_choice *ch, int x, int y, tl_err *e)
{
	tr_mesh *m = &w->m;
	double t[4], c[4], r[4];
	int n = ch->n;

	m->nv = m->nt = 0;
	w->ngsel = 0;
	if (m->hash)
		memset(m->hash, 0, (size_t)m->hcap * sizeof *m->hash);
	tr_tile_rect(ch->z, x, y, t);
	if (select_tile(w, ch, t, e) < 0)
		return -1;
	if (w->g->projected)
		return tr_rim_tile(w, ch, x, y, e);
	/* the DEM first, so that a cell corner on its edge takes its height;
	 * per row of cells the triangles meeting it, in their order */
	for (int j = 0; j < n; j++) {
		int nrow = 0, built = 0;
		for (int i = 0; i < n; i++) {
			if (!cell_rects(w, ch, x, y, i, j, c, r))
				continue;
			/* r[1], r[3]: the same along the row */
			for (int k = 0; !built && k < w->nsel; k++)
				if (!(w->sel[k].hi[1] < r[1] || w->sel[k].lo[1] > r[3]))
					w->row[nrow++] = k;
			built = 1;
			for (int k = 0; k < nrow; k++) {
				const tr_tri *q = &w->sel[w->row[k]];
				if (q->hi[0] < r[0] || q->lo[0] > r[2])
					continue;
				if (tr_clip(m, q, r, e) < 0)
					return -1;
			}
		}
	}
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			int a, b, d, f;
			if (cell_rects(w, ch, x, y, i, j, c, r) ||
			    touched(m, c, r)) {
				if (frame(m, c, r, e) < 0)
					return -1;
				continue;
			}
			if ((a = tr_mesh_vertex(m, c[0], c[1], 0, e)) < 0 ||
			    (b = tr_mesh_vertex(m, c[2], c[1], 0, e)) < 0 ||
			    (d = tr_mesh_vertex(m, c[2], c[3], 0, e)) < 0 ||
			    (f = tr_mesh_vertex(m, c[0], c[3], 0, e)) < 0 ||
			    tr_mesh_tri(m, a, b, d, e) < 0 ||
			    tr_mesh_tri(m, a, d, f, e) < 0)
				return -1;
		}
	return 0;
}
