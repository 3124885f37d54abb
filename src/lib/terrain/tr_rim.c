/* tr_rim.c - a projected DEM's tile: its whole footprint (the selection
 * cut to the DEM, tr_cut.c), the rest of the tile the ellipsoid. Each
 * lattice cell takes the selection clipped to it (tr_clip.c); what the
 * DEM leaves of the cell is triangulated by GLU's tessellator at height 0
 * from the cell's sides (every vertex on them, so that neither this
 * cell's DEM part nor a neighbour's leaves a T-junction) and the DEM
 * part's boundary chords, no vertex added (a new one would be an
 * intersection: a bug, refused). Triangles past the footprint are marked
 * (m->rim): a sample under one is measured against its own height, not
 * against the selection's (tr_measure.c). */
#include <GL/glu.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/tr_impl.h"

/* Lattice line k of tile x (y) of level z, n cells: tr_lattice_lon and
 * tr_lattice_lat's arithmetic, so bit for bit the same lines. */
static double
llon(int z, int x, int n, int k)
{
	int l = 0;

	while ((1 << l) < n)
		l++;
	return -180 + ((double)x * n + k) * ldexp(180, -z - l);
}

static double
llat(int z, int y, int n, int k)
{
	int l = 0;

	while ((1 << l) < n)
		l++;
	return -90 + ((double)y * n + k) * ldexp(180, -z - l);
}

static double
area(const double *x, const double *y, int a, int b, int c)
{
	return (x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a]);
}

/* --- the cells: the DEM part, then the ellipsoid around it ---------- */

typedef struct {
	double at;  /* along its line */
	int line;   /* lattice line (vertical lists) */
	int v;
} lv;

typedef struct {
	int a, b;
} he;

typedef struct {
	tr_work *w;
	const tr_choice *ch;
	int x, y, n;
	double *lx, *ly;    /* lattice lines 0 .. n: longitudes, latitudes */
	int *st[2];         /* per row (j & 1): first triangle of cell i */
	int vr[3][2];       /* per row (j % 3): the vertices it made */
	lv *lst;            /* scratch: vertices on lattice lines */
	int nl, cl;
	he *ed;             /* scratch: edges */
	int ne, ce;
	int *loop;          /* scratch: a cell's sides, vertices */
	int nlp, clp;
	uint64_t *hs;       /* scratch: a cell's half-edges, hashed */
	int chs;
	double *co;         /* contour coordinates for GLU, 3 each */
	int cco;
	int tri[3], ntri;   /* GLU's current triangle */
	int failed;         /* GLU: an intersection, an error, no memory */
	tl_err *e;
} rim;

static int
grow(void **p, int *cap, int need, size_t sz)
{
	if (need <= *cap)
		return 0;
	int c = *cap ? *cap : 256;
	while (c < need)
		c *= 2;
	void *q = realloc(*p, (size_t)c * sz);
	if (q == NULL)
		return -1;
	*p = q, *cap = c;
	return 0;
}

/* m->src over triangles from .. m->nt set to s. */
static int
source(tr_mesh *m, int from, int s, tl_err *e)
{
	if (grow((void **)&m->src, &m->csrc, m->nt + 1, sizeof *m->src) < 0)
		return tl_fail(e, "mesh: out of memory");
	for (int t = from; t < m->nt; t++)
		m->src[t] = s;
	return 0;
}

/* m->rim over triangles from .. m->nt set to v (1: their m->src -1). */
static int
mark(tr_mesh *m, int from, int v, tl_err *e)
{
	if (grow((void **)&m->rim, &m->crim, m->nt + 1, 1) < 0 ||
	    (v && source(m, from, -1, e) < 0))
		return tl_fail(e, "mesh: out of memory");
	memset(m->rim + from, v, (size_t)(m->nt - from));
	return 0;
}

int
tr_rim_inherit(tr_mesh *m, int from, tl_err *e)
{
	if (m->rim == NULL)
		return 0;
	if (grow((void **)&m->rim, &m->crim, m->nt + 1, 1) < 0 ||
	    grow((void **)&m->src, &m->csrc, m->nt + 1, sizeof *m->src) < 0)
		return tl_fail(e, "mesh: out of memory");
	m->rim[m->nt - 1] = m->rim[from];
	m->src[m->nt - 1] = m->src[from];
	return 0;
}

static void
cell(const rim *R, int i, int j, double c[4])
{
	c[0] = R->lx[i], c[1] = R->ly[j];
	c[2] = R->lx[i + 1], c[3] = R->ly[j + 1];
}

/* Row j of cells: the selection clipped to each cell, cell i's pieces
 * from st[j & 1][i]; the vertices made in vr[j % 3]. */
static int
dem_row(rim *R, int j)
{
	tr_work *w = R->w;
	tr_mesh *m = &w->m;
	int nrow = 0, *st = R->st[j & 1], t0 = m->nt;
	double c[4];

	R->vr[j % 3][0] = m->nv;
	cell(R, 0, j, c);
	for (int k = 0; k < w->nsel; k++)
		if (!(w->sel[k].hi[1] < c[1] || w->sel[k].lo[1] > c[3]))
			w->row[nrow++] = k;
	for (int i = 0; i < R->n; i++) {
		cell(R, i, j, c);
		st[i] = m->nt;
		for (int k = 0; k < nrow; k++) {
			const tr_tri *q = &w->sel[w->row[k]];
			if (q->hi[0] < c[0] || q->lo[0] > c[2])
				continue;
			int t1 = m->nt;
			if (tr_clip(m, q, c, R->e) < 0 ||
			    source(m, t1, w->row[k], R->e) < 0)
				return -1;
		}
	}
	st[R->n] = m->nt;
	R->vr[j % 3][1] = m->nv;
	return mark(m, t0, 0, R->e);
}

static int
cmp_lv(const void *a, const void *b)
{
	const lv *p = a, *q = b;

	if (p->line != q->line)
		return p->line < q->line ? -1 : 1;
	return (p->at > q->at) - (p->at < q->at);
}

/* Vertices made by row r (0 .. n-1) lying on a lattice line: vertical
 * (axis 0: line i, at the latitude) or horizontal at line l (axis 1:
 * line l, at the longitude), appended to R->lst. */
static int
on_lines(rim *R, int r, int axis, int l)
{
	const tr_mesh *m = &R->w->m;
	double o = axis ? 0 : R->lx[0];
	double s = axis ? 0 : R->lx[1] - o;
	double ly = axis ? R->ly[l] : 0;

	if (r < 0 || r >= R->n)
		return 0;
	for (int v = R->vr[r % 3][0]; v < R->vr[r % 3][1]; v++) {
		int line = l;
		if (axis == 0) {
			line = (int)rint((m->x[v] - o) / s);
			if (line < 0 || line > R->n || m->x[v] != R->lx[line])
				continue;
		} else if (m->y[v] != ly)
			continue;
		if (grow((void **)&R->lst, &R->cl, R->nl + 1, sizeof *R->lst) < 0)
			return tl_fail(R->e, "mesh: out of memory");
		R->lst[R->nl].line = axis ? -1 - l : line;
		R->lst[R->nl].at = axis ? m->x[v] : m->y[v];
		R->lst[R->nl++].v = v;
	}
	return 0;
}

/* The vertices on one side of cell c into R->loop, in order from corner
 * p to corner q (each once): those of the list on line `line` within the
 * side (along: x for a horizontal side, y for a vertical). */
static int
side(rim *R, int line, int hor, const double c[4], int p, int q, int rev)
{
	double lo = hor ? c[0] : c[1], hi = hor ? c[2] : c[3];
	int a = 0, b = R->nl, start = R->nlp;

	while (a < b) { /* first entry >= (line, lo) */
		int mid = (a + b) / 2;
		if (R->lst[mid].line < line || (R->lst[mid].line == line &&
		    R->lst[mid].at < lo))
			a = mid + 1;
		else
			b = mid;
	}
	if (grow((void **)&R->loop, &R->clp, R->nlp + 2, sizeof *R->loop) < 0)
		return tl_fail(R->e, "mesh: out of memory");
	R->loop[R->nlp++] = p;
	for (; a < R->nl && R->lst[a].line == line && R->lst[a].at <= hi; a++) {
		int v = R->lst[a].v;
		if (v == p || v == q || v == R->loop[R->nlp - 1])
			continue;
		if (grow((void **)&R->loop, &R->clp, R->nlp + 2,
		    sizeof *R->loop) < 0)
			return tl_fail(R->e, "mesh: out of memory");
		R->loop[R->nlp++] = v;
	}
	R->loop[R->nlp++] = q;
	if (rev)
		for (int i = start, k = R->nlp - 1; i < k; i++, k--) {
			int s = R->loop[i];
			R->loop[i] = R->loop[k], R->loop[k] = s;
		}
	return 0;
}

static int
cmp_he(const void *a, const void *b)
{
	const he *p = a, *q = b;

	if (p->a != q->a)
		return p->a < q->a ? -1 : 1;
	return (p->b > q->b) - (p->b < q->b);
}

static int
edge(rim *R, int a, int b)
{
	if (grow((void **)&R->ed, &R->ce, R->ne + 1, sizeof *R->ed) < 0)
		return tl_fail(R->e, "mesh: out of memory");
	R->ed[R->ne].a = a, R->ed[R->ne++].b = b;
	return 0;
}

/* The side of cell c that edge a b lies along (0 south, 1 east, 2
 * north, 3 west), or -1. */
static int
sideof(const tr_mesh *m, const double c[4], int a, int b)
{
	if (a == b)
		return -1;
	if (m->y[a] == c[1] && m->y[b] == c[1])
		return 0;
	if (m->x[a] == c[2] && m->x[b] == c[2])
		return 1;
	if (m->y[a] == c[3] && m->y[b] == c[3])
		return 2;
	if (m->x[a] == c[0] && m->x[b] == c[0])
		return 3;
	return -1;
}

static uint64_t
hekey(int a, int b)
{
	return (uint64_t)(uint32_t)a << 32 | (uint32_t)b;
}

/* The slot of half-edge key k in R->hs (2^(64 - sh) slots, UINT64_MAX
 * empty): where it is, or the empty one where it would go. */
static unsigned
heslot(const rim *R, uint64_t k, int sh)
{
	unsigned mask = (unsigned)(UINT64_MAX >> sh);
	unsigned h = (unsigned)((k * 0x9e3779b97f4a7c15u) >> sh);

	while (R->hs[h] != UINT64_MAX && R->hs[h] != k)
		h = (h + 1) & mask;
	return h;
}

/* The boundary half-edges of the cell's pieces t0 .. t1 (turned
 * counter-clockwise), those whose reverse no piece has, into R->ed after
 * the pieces' own; returns how many are chords (not on the cell's
 * sides), or -1. Paired through a hash of the half-edges, not a sort:
 * most cells are covered, and the order of the boundary is the
 * tessellator's sort's (tessellate). */
static int
pieces(rim *R, int t0, int t1, const double c[4], he **bd, int *nbd)
{
	const tr_mesh *m = &R->w->m;
	int n0, chords = 0, sz = 16, sh = 60;

	/* the boundary no more than the half-edges */
	if (grow((void **)&R->ed, &R->ce, 6 * (t1 - t0), sizeof *R->ed) < 0)
		return tl_fail(R->e, "mesh: out of memory");
	R->ne = 0;
	for (int t = t0; t < t1; t++) {
		const int *k = m->tri + 3 * t;
		double s = area(m->x, m->y, k[0], k[1], k[2]);
		if (s == 0)
			continue;
		for (int i = 0; i < 3; i++) {
			he *d = R->ed + R->ne++;
			d->a = k[s > 0 ? i : (3 - i) % 3];
			d->b = k[s > 0 ? (i + 1) % 3 : (5 - i) % 3];
		}
	}
	n0 = R->ne;
	while (sz < 2 * n0)
		sz *= 2, sh--;
	if (grow((void **)&R->hs, &R->chs, sz, sizeof *R->hs) < 0)
		return tl_fail(R->e, "mesh: out of memory");
	memset(R->hs, 0xff, (size_t)sz * sizeof *R->hs);
	for (int i = 0; i < n0; i++) {
		uint64_t k = hekey(R->ed[i].a, R->ed[i].b);
		R->hs[heslot(R, k, sh)] = k;
	}
	for (int i = 0; i < n0; i++) {
		int a = R->ed[i].a, b = R->ed[i].b;
		uint64_t k = hekey(b, a);
		if (R->hs[heslot(R, k, sh)] == k)
			continue;
		R->ed[R->ne].a = a, R->ed[R->ne++].b = b;
		chords += sideof(m, c, a, b) < 0;
	}
	*bd = R->ed + n0, *nbd = R->ne - n0;
	return chords;
}

/* --- GLU ------------------------------------------------------------ */

static void
cb_vertex(void *v, void *ctx)
{
	rim *R = ctx;

	R->tri[R->ntri++] = (int)(intptr_t)v - 1;
	if (R->ntri == 3) {
		R->ntri = 0;
		if (!R->failed && tr_mesh_tri(&R->w->m, R->tri[0], R->tri[1],
		    R->tri[2], R->e) < 0)
			R->failed = 1;
	}
}

static void
cb_begin(GLenum type, void *ctx)
{
	(void)type;
	((rim *)ctx)->ntri = 0;
}

static void
cb_edge(GLboolean f, void *ctx)
{
	(void)f, (void)ctx; /* given, so that only triangles come */
}

/* Two contour vertices at one place are one mesh vertex: that is all a
 * combination may be; a new place is an intersection, a bug. */
static void
cb_combine(GLdouble co[3], void *d[4], GLfloat wt[4], void **out, void *ctx)
{
	rim *R = ctx;
	tr_mesh *m = &R->w->m;
	int nv = m->nv, v = tr_mesh_vertex(m, co[0], co[1], 0, R->e);

	(void)d, (void)wt;
	if (v < 0)
		R->failed = 1, v = 0;
	else if (m->nv != nv && !R->failed) {
		R->failed = 1;
		tl_fail(R->e, "mesh: the ellipsoid's outline crosses itself at "
		    "%.12g, %.12g (a bug)", co[0], co[1]);
	}
	*out = (void *)(intptr_t)(v + 1);
}

static void
cb_error(GLenum err, void *ctx)
{
	rim *R = ctx;

	if (!R->failed)
		tl_fail(R->e, "mesh: GLU tessellator: %s", (const char *)
		    gluErrorString(err));
	R->failed = 1;
}

/* The contours of R->ed (closed chains of directed edges) to tess, as
 * one polygon, odd winding. */
static int
tessellate(rim *R, GLUtesselator *tess)
{
	const tr_mesh *m = &R->w->m;
	int n = R->ne, nl = 0;
	char *used;

	if (n > 1)
		qsort(R->ed, (size_t)n, sizeof *R->ed, cmp_he);
	if ((used = calloc((size_t)n + 1, 1)) == NULL ||
	    grow((void **)&R->co, &R->cco, 3 * (n + 1), sizeof *R->co) < 0) {
		free(used);
		return tl_fail(R->e, "mesh: out of memory");
	}
	for (int i = 0; i < n; i++)
		R->co[3 * i + 2] = 0;
	gluTessBeginPolygon(tess, R);
	for (int s = 0; s < n; s++) {
		if (used[s])
			continue;
		gluTessBeginContour(tess);
		for (int k = s; k >= 0;) {
			int v = R->ed[k].a, to = R->ed[k].b, a = 0, b = n;
			used[k] = 1;
			R->co[3 * nl] = m->x[v], R->co[3 * nl + 1] = m->y[v];
			gluTessVertex(tess, R->co + 3 * nl, (void *)(intptr_t)(v + 1));
			nl++;
			while (a < b) { /* the first edge from `to` */
				int mid = (a + b) / 2;
				if (R->ed[mid].a < to)
					a = mid + 1;
				else
					b = mid;
			}
			for (k = -1; a < n && R->ed[a].a == to; a++)
				if (!used[a]) {
					k = a;
					break;
				}
		}
		gluTessEndContour(tess);
	}
	gluTessEndPolygon(tess);
	free(used);
	return R->failed ? -1 : 0;
}

/* A sliver among triangles t0 .. nt (say three vertices of the DEM
 * part's outline where it turns in: its obtuse vertex within a quantum
 * or two, qd degrees, of the side across) would turn over in
 * quantisation; with the triangle across its long side it is flipped
 * into two that meet at that vertex. */
static void
unsliver(tr_mesh *m, int t0, double qd)
{
	for (int t = t0; t < m->nt; t++) {
		int *k = m->tri + 3 * t, o = -1;
		double s = area(m->x, m->y, k[0], k[1], k[2]), l = 0;
		for (int i = 0; i < 3; i++) {
			int a = k[(i + 1) % 3], b = k[(i + 2) % 3];
			double d = hypot(m->x[b] - m->x[a], m->y[b] - m->y[a]);
			if (d > l)
				l = d, o = i;
		}
		if (!(fabs(s) < 2 * qd * l))
			continue; /* as high as two quanta of u, v */
		int mv = k[o], a = k[(o + 1) % 3], b = k[(o + 2) % 3];
		for (int u = t0; u < m->nt; u++) {
			int *q = m->tri + 3 * u, x = -1;
			if (u == t)
				continue;
			for (int i = 0; i < 3; i++)
				if ((q[i] == b && q[(i + 1) % 3] == a) ||
				    (q[i] == a && q[(i + 1) % 3] == b))
					x = q[(i + 2) % 3];
			if (x < 0)
				continue;
			double s1 = area(m->x, m->y, a, mv, x);
			double s2 = area(m->x, m->y, mv, b, x);
			double s0 = area(m->x, m->y, a, b, x);
			if (!(s1 * s0 > 0 && s2 * s0 > 0))
				break;
			k[0] = a, k[1] = mv, k[2] = x;
			q[0] = mv, q[1] = b, q[2] = x;
			break;
		}
	}
}

/* Cell (i, j) of the current rim row: nothing when its pieces cover it,
 * else the ellipsoid over the rest. */
static int
rim_cell(rim *R, GLUtesselator *tess, int i, int j, const int *st)
{
	tr_mesh *m = &R->w->m;
	double c[4];
	int k[4], t0 = m->nt, nbd = 0, chords = 0;
	he *bd = NULL;

	cell(R, i, j, c);
	if (st[i] < st[i + 1] && (chords = pieces(R, st[i], st[i + 1], c, &bd,
	    &nbd)) <= 0)
		return chords; /* covered (0) or failed */
	for (int q = 0; q < 4; q++)
		if ((k[q] = tr_mesh_vertex(m, c[q == 1 || q == 2 ? 2 : 0],
		    c[q >= 2 ? 3 : 1], 0, R->e)) < 0)
			return -1;
	/* the sides, counter-clockwise: south, east, north, west */
	R->nlp = 0;
	if (side(R, -1 - j, 1, c, k[0], k[1], 0) < 0 ||
	    side(R, i + 1, 0, c, k[1], k[2], 0) < 0 ||
	    side(R, -1 - (j + 1), 1, c, k[3], k[2], 1) < 0 ||
	    side(R, i, 0, c, k[0], k[3], 1) < 0)
		return -1;
	if (nbd == 0 && R->nlp == 8) { /* corners alone: two triangles */
		if (tr_mesh_tri(m, k[0], k[1], k[2], R->e) < 0 ||
		    tr_mesh_tri(m, k[0], k[2], k[3], R->e) < 0)
			return -1;
		return mark(m, t0, 1, R->e);
	}
	/* the edges: the sides' pieces not along the DEM's, the DEM's
	 * chords reversed (the ellipsoid's outline, counter-clockwise) */
	he *b = malloc(((size_t)nbd + 1) * sizeof *b);
	if (b == NULL)
		return tl_fail(R->e, "mesh: out of memory");
	if (nbd > 0)
		memcpy(b, bd, (size_t)nbd * sizeof *b);
	R->ne = 0;
	for (int q = 0; q + 1 < R->nlp; q++) {
		int a = R->loop[q], z = R->loop[q + 1], sd = sideof(m, c, a, z);
		int along = 0;
		if (sd < 0)
			continue; /* a corner to itself, between two sides */
		for (int s = 0; s < nbd && !along; s++) {
			int p = b[s].a, r = b[s].b, h = sd == 0 || sd == 2;
			if (sideof(m, c, p, r) != sd)
				continue;
			/* a z within p r, the same way */
			double u0 = h ? m->x[p] : m->y[p], u1 = h ? m->x[r] : m->y[r];
			double ua = h ? m->x[a] : m->y[a], uz = h ? m->x[z] : m->y[z];
			along = (u1 - u0) * (uz - ua) > 0 &&
			    fmin(ua, uz) >= fmin(u0, u1) &&
			    fmax(ua, uz) <= fmax(u0, u1);
		}
		if (!along && edge(R, a, z) < 0) {
			free(b);
			return -1;
		}
	}
	for (int s = 0; s < nbd; s++)
		if (sideof(m, c, b[s].a, b[s].b) < 0 &&
		    edge(R, b[s].b, b[s].a) < 0) {
			free(b);
			return -1;
		}
	free(b);
	if (tessellate(R, tess) < 0)
		return -1;
	for (int pass = 0; pass < 2; pass++)
		unsliver(m, t0, ldexp(180, -R->ch->z) / QM_MAX);
	return mark(m, t0, 1, R->e);
}

/* Row j's ellipsoid: the lists of vertices on its lattice lines (made by
 * rows j-1 .. j+1, all clipped by now), then each cell. */
static int
rim_row(rim *R, GLUtesselator *tess, int j)
{
	R->nl = 0;
	if (on_lines(R, j, 0, 0) < 0 || on_lines(R, j - 1, 1, j) < 0 ||
	    on_lines(R, j, 1, j) < 0 || on_lines(R, j, 1, j + 1) < 0 ||
	    on_lines(R, j + 1, 1, j + 1) < 0)
		return -1;
	if (R->nl > 1) /* lst is NULL while nothing was listed */
		qsort(R->lst, (size_t)R->nl, sizeof *R->lst, cmp_lv);
	for (int i = 0; i < R->n; i++)
		if (rim_cell(R, tess, i, j, R->st[j & 1]) < 0)
			return -1;
	return 0;
}

int
tr_rim_tile(tr_work *w, const tr_choice *ch, int x, int y, tl_err *e)
{
	rim R = { .w = w, .ch = ch, .x = x, .y = y, .n = ch->n, .e = e };
	GLUtesselator *tess = gluNewTess();
	int r = -1;

	R.st[0] = malloc(((size_t)R.n + 1) * sizeof *R.st[0]);
	R.st[1] = malloc(((size_t)R.n + 1) * sizeof *R.st[1]);
	R.lx = malloc(2 * ((size_t)R.n + 1) * sizeof *R.lx);
	if (tess == NULL || !R.st[0] || !R.st[1] || !R.lx) {
		tl_fail(e, "mesh: out of memory");
		goto done;
	}
	R.ly = R.lx + R.n + 1;
	for (int k = 0; k <= R.n; k++)
		R.lx[k] = llon(ch->z, x, R.n, k), R.ly[k] = llat(ch->z, y, R.n, k);
	gluTessProperty(tess, GLU_TESS_WINDING_RULE, GLU_TESS_WINDING_ODD);
	gluTessNormal(tess, 0, 0, 1);
	gluTessCallback(tess, GLU_TESS_BEGIN_DATA, (_GLUfuncptr)cb_begin);
	gluTessCallback(tess, GLU_TESS_VERTEX_DATA, (_GLUfuncptr)cb_vertex);
	gluTessCallback(tess, GLU_TESS_EDGE_FLAG_DATA, (_GLUfuncptr)cb_edge);
	gluTessCallback(tess, GLU_TESS_COMBINE_DATA, (_GLUfuncptr)cb_combine);
	gluTessCallback(tess, GLU_TESS_ERROR_DATA, (_GLUfuncptr)cb_error);
	/* the DEM first, so that a cell corner on its edge takes its
	 * height: row j's ellipsoid once rows j-1 .. j+1 are clipped */
	for (int j = 0; j <= R.n; j++) {
		if (j < R.n && dem_row(&R, j) < 0)
			goto done;
		if (j > 0 && rim_row(&R, tess, j - 1) < 0)
			goto done;
	}
	r = 0;
done:
	if (tess)
		gluDeleteTess(tess);
	free(R.st[0]), free(R.st[1]), free(R.lst), free(R.ed), free(R.loop);
	free(R.co), free(R.hs), free(R.lx);
	return r;
}
