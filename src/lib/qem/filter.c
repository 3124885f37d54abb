/* filter.c - kernels and the separable, streaming quadric filter: one
 * level of the pyramid from the one below it.
 *
 * It implements the "filtering & sub-sampling" step of QEM-filtering
 * (F. Löffler and H. Schumann, "QEM-Filtering: A New Technique For
 * Feature-Sensitive Terrain Mesh Simplification", sections 3.3 and 3.4;
 * ../shared/papers/qem-filtering-loeffler-schumann.txt): the vertices'
 * Garland-Heckbert quadrics (quadric.h), not their heights, low-pass
 * filtered and sub-sampled by 2, a quadric moved into the frame of the
 * coarse vertex that receives it. The levels so made, each half the
 * last in both directions, coarse vertex k at fine vertex 2k, are those
 * of the VGIS quadtree (D. Koller, P. Lindstrom, W. Ribarsky et al.,
 * "Virtual GIS", IEEE Visualization 1995; P. Lindstrom et al., "Real-Time,
 * Continuous Level of Detail Rendering of Height Fields", SIGGRAPH 1996;
 * R. Pajarola's survey of quadtree terrain triangulation, section 4,
 * ../shared/papers/quadtree-terrain-triangulation-pajarola.txt). */
#include "qem/filter.h"

#include <assert.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "base/simd.h"

const filter_kernel filter_kernels[] = {
	{ "binomial", 1, { 2 / 4., 1 / 4. } },
	{ "none", 0, { 1 } },
	{ "box", 1, { 1 / 3., 1 / 3. } },
	{ "binomial5", 2, { 6 / 16., 4 / 16., 1 / 16. } },
	{ NULL, 0, { 0 } },
};

const filter_kernel *
filter_find(const char *name)
{
	for (const filter_kernel *k = filter_kernels; k->name != NULL; k++)
		if (strcmp(k->name, name) == 0)
			return k;
	return NULL;
}

double
filter_extend(const double *h, size_t stride, int n, int i)
{
	int r;

	if (i >= 0 && i < n)
		return h[(size_t)i * stride];
	if (i < 0) {
		r = -i < n ? -i : n - 1;
		return 2 * h[0] - h[(size_t)r * stride];
	}
	r = 2 * (n - 1) - i;
	if (r < 0)
		r = 0;
	return 2 * h[(size_t)(n - 1) * stride] - h[(size_t)r * stride];
}

/* A held row: FILTER_NF fields of stride doubles each (filter.h), in
 * fqm_vertex's order. */
enum { F_A = 0, F_B = 6, F_C = 9, F_Z = 10, F_S = 11, F_V = 12 };
_Static_assert(offsetof(fqm_vertex, q.a) == F_A * sizeof(double) &&
    offsetof(fqm_vertex, q.b) == F_B * sizeof(double) &&
    offsetof(fqm_vertex, q.c) == F_C * sizeof(double) &&
    offsetof(fqm_vertex, z) == F_Z * sizeof(double) &&
    offsetof(fqm_vertex, s) == F_S * sizeof(double) &&
    offsetof(fqm_vertex, v) == F_V * sizeof(double) &&
    sizeof(fqm_vertex) == FILTER_NF * sizeof(double),
    "fqm_vertex is the FILTER_NF fields, in order");

/* The stride of a field: the coarse width rounded up to whole vectors,
 * and one vector more, so that the vector loops may run past cw (into
 * zeros or stale values, never read back) and a tap one column right. */
static size_t
stride(const filter_state *f)
{
	return ((size_t)f->cw + VEC_N - 1) / VEC_N * VEC_N + VEC_N;
}

/* FQM field k's channel in a layout. */
static int
channel(const fqm_layout *L, int k)
{
	return k < F_Z ? L->q[k] : k == F_Z ? L->z : k == F_S ? L->s : L->v;
}

int
filter_init(filter_state *f, const filter_kernel *k, int level, int fw, int fh,
    int w0, int h0, const geo_ground *m, tl_err *e)
{
	size_t st;

	assert(k->radius >= 0 && k->radius <= FILTER_MAX_RADIUS);
	memset(f, 0, sizeof *f);
	f->w0 = w0, f->h0 = h0;
	f->k = k;
	f->level = level;
	f->fw = fw, f->fh = fh;
	f->cw = (fw - 1 + 1) / 2 + 1; /* ceil((fw-1)/2) + 1 */
	f->ch = (fh - 1 + 1) / 2 + 1;
	f->m = m;
	/* 2r+1 rows, and at least 2: a padded row's odd reflection
	 * (2h[n-1] - h[n-2]) needs the two last rows even without a kernel */
	f->nring = k->radius > 0 ? 2 * k->radius + 1 : 2;
	st = stride(f);
	f->ring = tl_alloc((size_t)f->nring * FILTER_NF * st, sizeof *f->ring,
	    e);
	f->tag = tl_alloc(f->nring, sizeof *f->tag, e);
	f->fine = tl_alloc(2 * FILTER_NF * st, sizeof *f->fine, e);
	f->coarse = tl_alloc(FILTER_NF * st, sizeof *f->coarse, e);
	f->tmp = tl_alloc((2 * FILTER_MAX_RADIUS + 3) * st, sizeof *f->tmp, e);
	if (f->ring == NULL || f->tag == NULL || f->fine == NULL ||
	    f->coarse == NULL || f->tmp == NULL) {
		filter_free(f);
		return -1;
	}
	for (int s = 0; s < f->nring; s++)
		f->tag[s] = -1;
	return 0;
}

void
filter_free(filter_state *f)
{
	free(f->ring), free(f->tag), free(f->fine), free(f->coarse);
	free(f->tmp);
	f->ring = f->fine = f->coarse = f->tmp = NULL;
	f->tag = NULL;
}

int
filter_ready(const filter_state *f)
{
	int need = 2 * f->out + f->k->radius;

	if (need > f->fh - 1)
		need = f->fh - 1;
	return f->out < f->ch && f->next > need;
}

/* The fine row is held split: even columns (fine[0 ..]), odd columns
 * (fine[FILTER_NF x stride ..]), so that the taps of consecutive coarse
 * columns are consecutive. Field k of fine column i: */
static double
fine_at(const filter_state *f, int k, int i)
{
	return f->fine[((size_t)(i & 1) * FILTER_NF + k) * stride(f) +
	    (size_t)(i >> 1)];
}

/* filter_extend on the split row. */
static double
fine_ext(const filter_state *f, int k, int i)
{
	int n = f->fw, r;

	if (i >= 0 && i < n)
		return fine_at(f, k, i);
	if (i < 0) {
		r = -i < n ? -i : n - 1;
		return 2 * fine_at(f, k, 0) - fine_at(f, k, r);
	}
	r = 2 * (n - 1) - i;
	if (r < 0)
		r = 0;
	return 2 * fine_at(f, k, n - 1) - fine_at(f, k, r);
}

/* Horizontal pass, one coarse column c (s: metres between fine columns
 * there), the general way: every tap through quadric_translate and
 * quadric_add. The columns whose taps reach past the row's ends. */
static void
push_column(filter_state *f, double *out, int c, double s)
{
	const filter_kernel *k = f->k;
	size_t st = stride(f);
	fqm_vertex o, t;
	double zh = 0, vw = 0, *tv = (double *)&t, *ov = (double *)&o;

	memset(&o, 0, sizeof o);
	for (int a = -k->radius; a <= k->radius; a++)
		zh += k->w[abs(a)] * fine_ext(f, F_Z, 2 * c + a);
	o.z = zh;
	o.s = fine_ext(f, F_S, 2 * c);
	for (int a = -k->radius; a <= k->radius; a++) {
		int i = 2 * c + a;
		double w = k->w[abs(a)], d[3];
		if (i >= f->fw) {
			/* past the edge: no planes there; a padded vertex no
			 * tap reaches (kernel none) takes its neighbour's,
			 * extrapolating its planes */
			if (k->radius > 0)
				continue;
			i = f->fw - 1, w = 1;
		}
		if (i < 0)
			continue;
		for (int q = 0; q < FILTER_NF; q++)
			tv[q] = fine_at(f, q, i);
		d[0] = -(i - 2 * c) * s, d[1] = 0, d[2] = zh - t.z;
		quadric_translate(&t.q, d);
		quadric_add(&o.q, &t.q, w);
		if (i == 2 * c + a)
			o.v += w * t.v, vw += w;
	}
	o.v = vw > 0 ? o.v / vw : 0;
	for (int q = 0; q < FILTER_NF; q++)
		out[(size_t)q * st + (size_t)c] = ov[q];
}

/* The taps of a run of columns that all take the same taps (the same
 * rows or column offsets, weights and plane offset kind): tap t is the
 * held row p[t] (its field 0 at the run's first column), weight w[t],
 * moved by d = (m[t] dd[t][c], 0, dz) (the horizontal pass, dd the
 * metres between fine columns, m the column offset) or (0, m[t]
 * dd[t][c], dz) (the vertical pass, dd the metres between rows, m 1), or
 * by (0, 0, dz) for tap zt, the coarse vertex's own column or row;
 * dz = zref[c] - the tap's reference height. */
#define NTAP (2 * FILTER_MAX_RADIUS + 1)
typedef struct {
	const double *p[NTAP], *dd[NTAP];
	double w[NTAP], m[NTAP];
	int with_v[NTAP]; /* the tap counts for V (not a stand-in row) */
	int nt, zt;       /* zt: the unmoved tap, or -1 */
	double vw;        /* the weights counted for V, summed in tap order */
} taps;

/* q += w * (the tap's quadric moved by d), for every field of q: the
 * operations of quadric_translate and quadric_add, in their order, save
 * the products with d's zero coordinate(s): x * 0 is +-0 for the finite x
 * of an FQM (checked on input; no sum here nears overflow, even for
 * float-max coefficients), and y +- 0 is y but for the sign of a zero y.
 * No such sign can reach an output: every output is a sum that starts
 * from +0 (q, zh, zc), a copy (s) or a quotient of such a sum (v), a sum
 * from +0 is never -0 (round to nearest: x + -x is +0), and a zero's sign
 * changes no other sum's or product's value. The A and V fields (plain
 * weighted sums) and the B and C fields (the moves) are separate loops:
 * fewer live vectors. Columns run in whole vectors up to n rounded up.
 * Inlined with constant nt, zt and vert, the tap loops unroll. */
static inline __attribute__((always_inline)) void
filter_taps(const taps *T, const double *zref, double *out, size_t st,
    size_t n, const int nt, const int zt, const int vert)
{
	/* the taps in locals: stores to out cannot change them */
	const double *p[NTAP], *dd[NTAP];
	vd w[NTAP], m[NTAP];
	int with_v[NTAP];
	double vw = T->vw;

	for (int t = 0; t < nt; t++) {
		p[t] = T->p[t], dd[t] = T->dd[t];
		w[t] = vd_splat(T->w[t]), m[t] = vd_splat(T->m[t]);
		with_v[t] = T->with_v[t];
	}
	for (int k = 0; k < 6; k++)
		for (size_t c = 0; c < n; c += VEC_N) {
			vd q = vd_splat(0);
#pragma GCC unroll 5
			for (int t = 0; t < nt; t++)
				q += w[t] * vd_load(p[t] + k * st + c);
			vd_store(out + k * st + c, q);
		}
	for (size_t c = 0; c < n; c += VEC_N) {
		vd v = vd_splat(0);
#pragma GCC unroll 5
		for (int t = 0; t < nt; t++)
			if (with_v[t])
				v += w[t] * vd_load(p[t] + F_V * st + c);
		vd_store(out + F_V * st + c, vw > 0 ? v / vw : vd_splat(0));
	}
	for (size_t c = 0; c < n; c += VEC_N) {
		vd z = vd_load(zref + c), q0 = vd_splat(0), q1 = q0, q2 = q0;
		vd qc = q0;
#pragma GCC unroll 5
		for (int t = 0; t < nt; t++) {
			const double *h = p[t] + c;
			vd dz = z - vd_load(h + F_Z * st);
			vd a13 = vd_load(h + 2 * st), a23 = vd_load(h + 4 * st);
			vd a33 = vd_load(h + 5 * st), b0 = vd_load(h + 6 * st);
			vd b1 = vd_load(h + 7 * st), b2 = vd_load(h + 8 * st);
			vd cc = vd_load(h + 9 * st), ad0, ad1, ad2;
			if (t == zt) { /* d = (0, 0, dz) */
				ad0 = a13 * dz;
				ad1 = a23 * dz;
				ad2 = a33 * dz;
				cc = cc + (2 * (b2 * dz) + ad2 * dz);
			} else if (!vert) { /* d = (dx, 0, dz) */
				vd dx = m[t] * vd_load(dd[t] + c);
				vd a11 = vd_load(h), a12 = vd_load(h + st);
				ad0 = a11 * dx + a13 * dz;
				ad1 = a12 * dx + a23 * dz;
				ad2 = a13 * dx + a33 * dz;
				cc = cc + ((2 * (b0 * dx + b2 * dz) + ad0 * dx) +
				    ad2 * dz);
			} else { /* d = (0, dy, dz) */
				vd dy = m[t] * vd_load(dd[t] + c);
				vd a12 = vd_load(h + st), a22 = vd_load(h + 3 * st);
				ad0 = a12 * dy + a13 * dz;
				ad1 = a22 * dy + a23 * dz;
				ad2 = a23 * dy + a33 * dz;
				cc = cc + ((2 * (b1 * dy + b2 * dz) + ad1 * dy) +
				    ad2 * dz);
			}
			q0 += w[t] * (b0 + ad0);
			q1 += w[t] * (b1 + ad1);
			q2 += w[t] * (b2 + ad2);
			qc += w[t] * cc;
		}
		vd_store(out + F_B * st + c, q0);
		vd_store(out + (F_B + 1) * st + c, q1);
		vd_store(out + (F_B + 2) * st + c, q2);
		vd_store(out + F_C * st + c, qc);
	}
}

/* filter_taps with the kernel's full tap set (every row or column inside,
 * the middle one unmoved) unrolled, or any other set. */
static void
run_taps(const taps *T, const double *zref, double *out, size_t st,
    size_t n, int vert)
{
	int full = T->zt == T->nt / 2;

	for (int t = 0; full && t < T->nt; t++)
		full = T->with_v[t];
	if (full && T->nt == 3 && !vert)
		filter_taps(T, zref, out, st, n, 3, 1, 0);
	else if (full && T->nt == 3)
		filter_taps(T, zref, out, st, n, 3, 1, 1);
	else if (full && T->nt == 5 && !vert)
		filter_taps(T, zref, out, st, n, 5, 2, 0);
	else if (full && T->nt == 5)
		filter_taps(T, zref, out, st, n, 5, 2, 1);
	else if (full && T->nt == 1)
		filter_taps(T, zref, out, st, n, 1, 0, vert);
	else
		filter_taps(T, zref, out, st, n, T->nt, T->zt, vert);
}

/* Horizontal pass over the coarse columns c0 .. c1-1, whose taps all lie
 * inside the fine row: filter_extend is the sample itself there and every
 * tap counts, so the columns differ only in their values. Vectors run
 * past c1: the caller does those columns again. */
static void
push_inner(filter_state *f, double *out, int c0, int c1, const double *s)
{
	const filter_kernel *k = f->k;
	size_t st = stride(f), n = (size_t)(c1 - c0);
	int r = k->radius;
	taps T = { .nt = 2 * r + 1, .zt = r };

	for (int a = -r; a <= r; a++) {
		int odd = a & 1;
		/* fine column 2c + a is column c + (a - odd) / 2 of its half:
		 * -1, 0 or 1 (c0 >= 1 when -1) */
		T.p[a + r] = f->fine + (size_t)odd * FILTER_NF * st +
		    (size_t)(c0 + (a - odd) / 2);
		T.dd[a + r] = s + c0;
		T.w[a + r] = k->w[abs(a)];
		T.m[a + r] = -a; /* dx = -(i - 2c) * s */
		T.with_v[a + r] = 1;
		T.vw += T.w[a + r];
	}
	out += c0;
	/* the reference height, the sub-sampled height */
	for (size_t c = 0; c < n; c += VEC_N) {
		vd zh = vd_splat(0);
		for (int t = 0; t < T.nt; t++)
			zh += T.w[t] * vd_load(T.p[t] + F_Z * st + c);
		vd_store(out + F_Z * st + c, zh);
		vd_store(out + F_S * st + c, vd_load(T.p[r] + F_S * st + c));
	}
	run_taps(&T, out + F_Z * st, out, st, n, 0);
}

/* Horizontal pass over the split fine row into the next ring slot: into
 * the frame of fine column 2c, at the horizontally filtered reference
 * height. */
static void
push(filter_state *f)
{
	int j = f->next++, slot = j % f->nring, r = f->k->radius, c0, c1;
	size_t st = stride(f);
	double *out = f->ring + (size_t)slot * FILTER_NF * st;
	double *s = f->tmp, step = (double)(1L << f->level), sx[GEO_MAX_NODES];

	assert(j < f->fh); /* fine rows 0 .. fh-1, in order */
	f->tag[slot] = j;
	geo_row_sx(f->m, (double)((long)j << f->level), sx);
	/* metres between fine columns along this row, at the coarse vertex
	 * whose frame the taps move into (georef.h) */
	for (int c = 0; c < f->cw; c++)
		s[c] = step * geo_on_row(f->m, sx,
		    (double)((long)c << (f->level + 1)));
	/* the columns with taps 2c-r .. 2c+r in 0 .. fw-1 */
	c0 = (r + 1) / 2;
	c1 = f->fw - 1 - r >= 0 ? (f->fw - 1 - r) / 2 + 1 : 0;
	if (c1 < c0)
		c1 = c0;
	/* vectors run past c1: the columns there are done again below */
	push_inner(f, out, c0, c1, s);
	for (int c = 0; c < c0; c++)
		push_column(f, out, c, s[c]);
	for (int c = c1; c < f->cw; c++)
		push_column(f, out, c, s[c]);
}

void
filter_push(filter_state *f, const fqm_vertex *fine)
{
	size_t st = stride(f);

	for (int i = 0; i < f->fw; i++) {
		const double *v = (const double *)&fine[i];
		double *h = f->fine + (size_t)(i & 1) * FILTER_NF * st +
		    (size_t)(i >> 1);
		for (int k = 0; k < FILTER_NF; k++)
			h[(size_t)k * st] = v[k];
	}
	push(f);
}

void
filter_push_row(filter_state *f, const fqm_layout *L, const float *row)
{
	size_t st = stride(f), n = (size_t)f->fw;

	for (int k = 0; k < FILTER_NF; k++) {
		const float *p = row + (size_t)channel(L, k) * n;
		double *e = f->fine + (size_t)k * st;
		double *o = e + (size_t)FILTER_NF * st;
		size_t i = 0;
		/* 8 columns: 4 even, 4 odd */
		for (; i + 8 <= n; i += 8) {
			vf4 x = vf4_load(p + i), y = vf4_load(p + i + 4);
			vd4 de = __builtin_convertvector(
			    __builtin_shufflevector(x, y, 0, 2, 4, 6), vd4);
			vd4 od = __builtin_convertvector(
			    __builtin_shufflevector(x, y, 1, 3, 5, 7), vd4);
			memcpy(e + i / 2, &de, sizeof de);
			memcpy(o + i / 2, &od, sizeof od);
		}
		for (; i < n; i++)
			(i & 1 ? o : e)[i / 2] = p[i];
	}
	push(f);
}

/* The ring row holding fine row i (it is always there: see filter_ready). */
static const double *
held(const filter_state *f, int i)
{
	int slot = i % f->nring;

	assert(i >= 0 && i < f->fh && f->tag[slot] == i);
	return f->tag[slot] == i ? f->ring + (size_t)slot * FILTER_NF *
	    stride(f) : NULL;
}

/* Reference-height column c of the held rows (field F_Z or F_S),
 * odd-reflected past the first and last fine row. */
static double
ext_rows(const filter_state *f, int c, int i, int field)
{
	int n = f->fh, r;

	if (i >= 0 && i < n)
		return held(f, i)[(size_t)field * stride(f) + (size_t)c];
	if (i < 0) {
		r = -i < n ? -i : n - 1;
		return 2 * ext_rows(f, c, 0, field) - ext_rows(f, c, r, field);
	}
	r = 2 * (n - 1) - i;
	if (r < 0)
		r = 0;
	return 2 * ext_rows(f, c, n - 1, field) - ext_rows(f, c, r, field);
}

/* Vertical pass: coarse row m from fine rows 2m-r .. 2m+r, into
 * f->coarse. */
static void
pull(filter_state *f)
{
	const filter_kernel *k = f->k;
	int m = f->out, j0 = 2 * m, r = k->radius, cw = f->cw;
	size_t st = stride(f);
	double *co = f->coarse, *zc = co + F_Z * st;
	double y0[GEO_MAX_NODES], y[NTAP][GEO_MAX_NODES];
	taps T = { .nt = 0, .zt = -1 };

	/* every fine row the taps reach is in the ring */
	assert(filter_ready(f));
	f->out++;
	/* geo_y of the coarse row and of each tap's fine row (rows are
	 * measured along the coarse vertex's column) */
	geo_row_y(f->m, (double)((long)j0 << f->level), y0);
	for (int b = -r; b <= r; b++) {
		int i = j0 + b < f->fh ? j0 + b : f->fh - 1;
		if (i >= 0)
			geo_row_y(f->m, (double)((long)i << f->level),
			    y[b + r]);
	}
	/* the reference height: every tap row, odd-reflected past the ends */
	if (j0 - r >= 0 && j0 + r <= f->fh - 1) {
		const double *hz[2 * FILTER_MAX_RADIUS + 1];
		for (int b = -r; b <= r; b++)
			hz[b + r] = held(f, j0 + b) + F_Z * st;
		for (int c = 0; c < cw; c += VEC_N) {
			vd z = vd_splat(0);
			for (int b = -r; b <= r; b++)
				z += k->w[abs(b)] * vd_load(hz[b + r] + c);
			vd_store(zc + c, z);
		}
	} else {
		for (int c = 0; c < cw; c++) {
			zc[c] = 0;
			for (int b = -r; b <= r; b++)
				zc[c] += k->w[abs(b)] *
				    ext_rows(f, c, j0 + b, F_Z);
		}
	}
	/* the taps that count */
	for (int b = -r; b <= r; b++) {
		int i = j0 + b, yi = j0 + b < f->fh ? j0 + b : f->fh - 1;
		double w = k->w[abs(b)], *dy = f->tmp + (size_t)(1 + T.nt) * st;
		if (i >= f->fh) { /* as in filter_push */
			if (r > 0)
				continue;
			i = f->fh - 1, w = 1;
		}
		if (i < 0)
			continue;
		for (int c = 0; c < cw; c++) {
			double I = (double)((long)c << (f->level + 1));
			dy[c] = geo_on_row(f->m, y0, I) -
			    geo_on_row(f->m, y[b + r], I);
		}
		T.p[T.nt] = held(f, i), T.dd[T.nt] = dy, T.w[T.nt] = w;
		T.m[T.nt] = 1; /* 1 * dy is dy */
		/* the row of the coarse vertex itself: dy = y - y = +0 */
		if (yi == j0)
			T.zt = T.nt;
		T.with_v[T.nt] = i == j0 + b;
		if (T.with_v[T.nt])
			T.vw += w;
		T.nt++;
	}
	run_taps(&T, co + F_Z * st, co, st, (size_t)cw, 1);
	if (j0 < f->fh)
		memcpy(co + F_S * st, held(f, j0) + F_S * st, cw * sizeof *co);
	else
		for (int c = 0; c < cw; c++)
			co[F_S * st + (size_t)c] = ext_rows(f, c, j0, F_S);
	/* past the DEM's last sample: padding, marked invalid */
	assert(f->x0 % 2 == 0);
	for (int c = 0; c < cw; c++)
		if ((long)(c + f->x0 / 2) << (f->level + 1) > f->w0 - 1 ||
		    (long)m << (f->level + 1) > f->h0 - 1)
			co[F_V * st + (size_t)c] = 0;
}

void
filter_pull(filter_state *f, fqm_vertex *coarse)
{
	size_t st = stride(f);

	pull(f);
	for (int c = 0; c < f->cw; c++) {
		double *v = (double *)&coarse[c];
		for (int k = 0; k < FILTER_NF; k++)
			v[k] = f->coarse[(size_t)k * st + (size_t)c];
	}
}

void
filter_pull_row(filter_state *f, const fqm_layout *L, float *row)
{
	size_t st = stride(f), n = (size_t)f->cw;

	pull(f);
	for (int k = 0; k < FILTER_NF; k++)
		vec_narrow(f->coarse + (size_t)k * st,
		    row + (size_t)channel(L, k) * n, n);
}
