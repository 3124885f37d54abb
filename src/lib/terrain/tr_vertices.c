/* tr_vertices.c - a mesh under construction: vertices deduplicated by
 * place (an open-addressing hash of x, y), triangles appended, degenerate
 * ones dropped. A leaf: the selection (tr_mesh.c) and the clipper
 * (tr_clip.c) both add to it. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "terrain/tr_impl.h"

static unsigned
hkey(double x, double y)
{
	uint64_t a, b;

	memcpy(&a, &x, 8), memcpy(&b, &y, 8);
	a ^= b * 0x9E3779B97F4A7C15ull;
	a ^= a >> 29;
	return (unsigned)(a * 0xBF58476D1CE4E5B9ull >> 32);
}

static int
rehash(tr_mesh *m, tl_err *e)
{
	int cap = m->hcap ? 2 * m->hcap : 4096;
	int *h = calloc((size_t)cap, sizeof *h);

	if (h == NULL)
		return tl_fail(e, "mesh: out of memory");
	free(m->hash);
	m->hash = h, m->hcap = cap;
	for (int i = 0; i < m->nv; i++) {
		unsigned k = hkey(m->x[i], m->y[i]) & (unsigned)(cap - 1);
		while (h[k])
			k = (k + 1) & (unsigned)(cap - 1);
		h[k] = i + 1;
	}
	return 0;
}

int
tr_mesh_vertex(tr_mesh *m, double x, double y, double h, tl_err *e)
{
	unsigned k;

	if (2 * (m->nv + 1) > m->hcap && rehash(m, e) < 0)
		return -1;
	k = hkey(x, y) & (unsigned)(m->hcap - 1);
	for (; m->hash[k]; k = (k + 1) & (unsigned)(m->hcap - 1)) {
		int i = m->hash[k] - 1;
		if (m->x[i] == x && m->y[i] == y)
			return i;
	}
	if (m->nv == m->cv) {
		int c = m->cv ? 2 * m->cv : 1024;
		double *a = realloc(m->x, c * sizeof *a), *b, *d;
		if (a)
			m->x = a;
		b = a ? realloc(m->y, c * sizeof *b) : NULL;
		if (b)
			m->y = b;
		d = b ? realloc(m->h, c * sizeof *d) : NULL;
		if (d == NULL)
			return tl_fail(e, "mesh: out of memory");
		m->h = d, m->cv = c;
	}
	m->x[m->nv] = x, m->y[m->nv] = y, m->h[m->nv] = h;
	m->hash[k] = m->nv + 1;
	return m->nv++;
}

int
tr_mesh_tri(tr_mesh *m, int a, int b, int c, tl_err *e)
{
	if (a == b || b == c || a == c)
		return 0;
	if (m->nt == m->ct) {
		int n = m->ct ? 2 * m->ct : 2048;
		int *t = realloc(m->tri, (size_t)n * 3 * sizeof *t);
		if (t == NULL)
			return tl_fail(e, "mesh: out of memory");
		m->tri = t, m->ct = n;
	}
	m->tri[3 * m->nt] = a, m->tri[3 * m->nt + 1] = b;
	m->tri[3 * m->nt + 2] = c;
	m->nt++;
	return 0;
}

void
tr_mesh_free(tr_mesh *m)
{
	free(m->x), free(m->y), free(m->h), free(m->tri), free(m->hash);
	free(m->rim), free(m->src);
	memset(m, 0, sizeof *m);
}

double *
tr_area_normals(const tr_mesh *m, const double *pos)
{
	double *nr = calloc((size_t)m->nv * 3, sizeof *nr);

	for (int t = 0; nr && t < m->nt; t++) {
		const int *k = m->tri + 3 * t;
		const double *a = pos + 3 * k[0], *b = pos + 3 * k[1],
		    *c = pos + 3 * k[2];
		double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
		double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
		double x[3] = { u[1] * v[2] - u[2] * v[1],
			u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0] };
		for (int j = 0; j < 3; j++)
			for (int d = 0; d < 3; d++)
				nr[3 * k[j] + d] += x[d];
	}
	return nr;
}
