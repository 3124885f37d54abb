/* rg_centre.c - the heights of a zoom's pixel centres from the chain's
 * level of vertices (rg_impl.h). Level l's vertex i stands at the deepest
 * zoom's pixel centre i 2^l; zoom maxz - l's pixel centre k lies between
 * level-l vertices k and k + 1 at the fraction f = 1/2 - 2^-(l+1) (both
 * axes), never on one. QEM-1D: the four surrounding filtered quadrics,
 * moved into the centre's frame and blended bilinearly (1 - f, f), give
 * the height minimising the blend at the centre (quadric_min_z); the
 * other modes (and a centre with no plane at all, a void, as solve.c
 * falls back): the vertices' heights blended the same way. */
#include <math.h>
#include <string.h>

#include "rgb/rg_impl.h"
#include "qem/quadric.h"

double
rg_centre_frac(int l)
{
	return 0.5 - ldexp(1, -(l + 1));
}

/* Centre i of the row between vertex rows a (row j) and b (row j + 1,
 * or row j again on the last row, jb then j). */
static void
centre(const rg_centre_in *c, int i, double *h, double *v)
{
	int i1 = i + 1 < c->w ? i + 1 : i;
	double f = c->f, s = ldexp(1, c->l);
	double I[2] = { i * s, i1 * s }, J[2] = { c->j * s, c->jb * s };
	double Ic = (i + f) * s, Jc = (c->j + f) * s;
	double wx[2] = { 1 - f, f }, zref = c->a[i].z, hb = 0, vb = 0, z;
	const fqm_vertex *fv[2][2] = { { &c->a[i], &c->a[i1] },
	    { &c->b[i], &c->b[i1] } };
	const solve_vertex *sv[2][2] = { { &c->sa[i], &c->sa[i1] },
	    { &c->sb[i], &c->sb[i1] } };
	quadric Q, q;

	quadric_zero(&Q);
	for (int y = 0; y < 2; y++)
		for (int x = 0; x < 2; x++) {
			double w = wx[x] * wx[y], p[2], d[3];
			hb += w * sv[y][x]->z, vb += w * fv[y][x]->v;
			if (c->mode != SOLVE_QEM1D)
				continue;
			/* the centre, in the vertex's frame */
			geo_local(c->m, I[x], J[y], Ic, Jc, p);
			d[0] = p[0], d[1] = p[1], d[2] = zref - fv[y][x]->z;
			q = fv[y][x]->q;
			quadric_translate(&q, d);
			quadric_add(&Q, &q, w);
		}
	*v = vb;
	if (c->mode == SOLVE_QEM1D && quadric_min_z(&Q, 0, 0, &z) == 0 &&
	    isfinite(z))
		*h = zref + z;
	else
		*h = hb;
}

void
rg_centre_row(const rg_centre_in *c, double *h, double *v)
{
	for (int i = 0; i < c->w; i++)
		centre(c, i, &h[i], &v[i]);
}
