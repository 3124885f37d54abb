/* verify_error.c - triangles against the DEM: the base error (the finest
 * triangles), the local errors (every triangle that splits against E of
 * its midpoint) and the error of an emitted triangle against max(tau,
 * base error) ("base", "local", "error" violations), by testing every
 * valid sample of the DEM window in the triangle's bounding box. */
#include "verify/verify_impl.h"

#include <math.h>
#include <string.h>

/* Largest deviation of triangle (x, y, z)[3] from the valid DEM samples
 * it holds (closed); marks them covered when cover is set. */
static void
tri_dev(const vf_checker *c, vf_dwin *w, const double x[3],
    const double y[3], const double z[3], int cover, vf_devmax *d)
{
	double det = (x[1] - x[0]) * (y[2] - y[0]) -
	    (y[1] - y[0]) * (x[2] - x[0]);
	double lo = fmin(y[0], fmin(y[1], y[2]));
	double hi = fmax(y[0], fmax(y[1], y[2]));
	double xl = fmin(x[0], fmin(x[1], x[2]));
	double xh = fmax(x[0], fmax(x[1], x[2]));
	long j0 = (long)ceil(lo - 1e-6), j1 = (long)floor(hi + 1e-6);
	long i0 = (long)ceil(xl - 1e-6), i1 = (long)floor(xh + 1e-6);

	if (det == 0 || !isfinite(det))
		return;
	j0 = j0 < w->j0 ? w->j0 : j0;
	j1 = j1 > w->j0 + w->n - 1 ? w->j0 + w->n - 1 : j1;
	i0 = i0 < 0 ? 0 : i0;
	i1 = i1 > c->W - 1 ? c->W - 1 : i1;
	for (long J = j0; J <= j1; J++) {
		size_t off = (size_t)(J - w->j0) * c->W;
		double ey = J - y[0];
		for (long I = i0; I <= i1; I++) {
			double ex = I - x[0];
			double u = (ex * (y[2] - y[0]) - ey * (x[2] - x[0])) /
			    det;
			double t = ((x[1] - x[0]) * ey - (y[1] - y[0]) * ex) /
			    det;
			double zs, zd, dev, adj;
			if (u < -VF_BARY_EPS || t < -VF_BARY_EPS ||
			    u + t > 1 + VF_BARY_EPS)
				continue;
			if (cover)
				w->f[off + I] |= 2;
			if (!(w->f[off + I] & 1))
				continue;
			zs = z[0] + u * (z[1] - z[0]) + t * (z[2] - z[0]);
			zd = w->z[off + I];
			dev = fabs(zs - zd);
			adj = dev - VF_REL_EPS * fmax(fabs(zs), fabs(zd));
			d->n++;
			if (dev > d->dev)
				d->dev = dev;
			if (adj > d->adj || d->n == 1) {
				d->adj = adj;
				d->I = (int)I, d->J = (int)J;
			}
		}
	}
}

void
vf_error_tri(const vf_blk *b, const vf_node *d, double x[3], double y[3],
    double z[3])
{
	int k[3] = { d->a[1] * BT_SIZE + d->a[0], d->b[1] * BT_SIZE + d->b[0],
		d->p[1] * BT_SIZE + d->p[0] };

	for (int q = 0; q < 3; q++)
		x[q] = b->px[k[q]], y[q] = b->py[k[q]], z[q] = b->z[k[q]];
}

/* The worst sample of node d's triangle in block b: the count inside. */
static int
node_dev(vf_lv *v, const vf_blk *b, const vf_node *d, int cover,
    vf_devmax *m)
{
	double x[3], y[3], z[3];

	memset(m, 0, sizeof *m);
	vf_error_tri(b, d, x, y, z);
	tri_dev(v->c, &v->w, x, y, z, cover, m);
	return m->n;
}

/* Base error (the leaves) and local errors (split triangles). */
void
vf_error_base_local(vf_lv *v, int bi, int bj)
{
	const vf_blk *b = &v->row[1][bi];
	const vf_tree *t = &v->c->tree;
	double base = v->L->base[(size_t)bj * v->bx + bi];
	vf_devmax m, worst = { 0 };

	for (int n = 0; n < VF_NODES; n++) {
		const vf_node *d = &t->node[n];
		if (d->m >= 0 && !v->c->o.local)
			continue;
		if (node_dev(v, b, d, 0, &m) == 0)
			continue;
		if (d->m < 0) {
			v->R->base_real = fmax(v->R->base_real, m.dev);
			if (worst.n == 0 || m.adj > worst.adj)
				worst = m;
			continue;
		}
		v->R->local_max = fmax(v->R->local_max, m.dev);
		if (m.adj > b->e[d->m] + VF_ABS_EPS)
			VNOTE(v, VF_LOCAL, bi, bj, d->m, NAN, "E %.9g, its "
			    "triangle with apex (%d,%d) is %.6g m off DEM "
			    "sample (%d,%d)", b->e[d->m],
			    bi * BT_CELLS + d->p[0], bj * BT_CELLS + d->p[1],
			    m.dev, m.I, m.J);
	}
	if (worst.n > 0 && worst.adj > base + VF_ABS_EPS)
		BNOTE(v, VF_BASE, bi, bj, "base error %.9g, the finest "
		    "triangles are %.6g m off DEM sample (%d,%d)", base,
		    worst.dev, worst.I, worst.J);
}

void
vf_error_check(vf_lv *v, const vf_blk *b, const vf_node *d, int bi,
    int bj, int t, double *worst)
{
	double tau = v->tau[t];
	double base = v->L->base[(size_t)bj * v->bx + bi];
	double bound = fmax(tau, base);
	vf_devmax m;

	if (node_dev(v, b, d, t == 0, &m) == 0)
		return;
	*worst = fmax(*worst, m.dev);
	if (m.adj > bound + VF_ABS_EPS)
		VNOTE(v, VF_ERROR, bi, bj, d->p[1] * BT_SIZE + d->p[0], tau,
		    "triangle (%d,%d)-(%d,%d) apex here is %.6g m off DEM "
		    "sample (%d,%d), bound %.6g", bi * BT_CELLS + d->a[0],
		    bj * BT_CELLS + d->a[1], bi * BT_CELLS + d->b[0],
		    bj * BT_CELLS + d->b[1], m.dev, m.I, m.J, bound);
}
