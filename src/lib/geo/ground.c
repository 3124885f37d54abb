/* ground.c - ground metres per cell: the ground embedding of the level-0
 * grid (georef.h), per-row geodesic or constant scales, and the lattice
 * of a projected grid's scales measured once with PROJ and GeographicLib. */
#include "geo/georef.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <proj.h>

#include "geo/geodesy.h"

/* Largest lattice: 257 x 257 nodes, 4 doubles each (2 MB) whatever the
 * DEM's size; the finest spacing, 16 samples, keeps small DEMs cheap. */
#define LATTICE_NODES GEO_MAX_NODES
#define LATTICE_MIN_SPACING 16

/* --- per-row metrics --------------------------------------------------- */

/* A row's latitude; a pole missed by rounding (a geotransform's decimal
 * pixel size times 180 rows) is the pole: its cells are 0 m wide. */
static double
row_lat(const georef *g, int j)
{
	double lat = g->origin[1] + (j + (g->point ? 0 : 0.5)) * g->step[1];

	return fabs(lat) > 90 && fabs(lat) < 90 + GEO_POLE_EPS ?
	    copysign(90, lat) : lat;
}

static int
ground_geographic(geo_ground *m, const georef *g, tl_err *e)
{
	double sx = fabs(g->step[0]), lat, next, d;

	for (int j = 0; j < m->height; j++) {
		lat = row_lat(g, j);
		if (geodesy_inverse(lat, 0, lat, sx, &m->dx[j]) < 0)
			return tl_fail(e, "row %d: latitude %.9g outside "
			    "-90..90 (past the pole: a pixel-is-area cell's "
			    "centre, not its edge, must lie within) or pixel "
			    "size %g invalid", j, lat, sx);
		if (j + 1 == m->height)
			break;
		next = row_lat(g, j + 1);
		if (geodesy_inverse(lat, 0, next, 0, &d) < 0)
			return tl_fail(e, "row %d: latitude %.9g outside "
			    "-90..90 (past the pole: a pixel-is-area cell's "
			    "centre, not its edge, must lie within)", j + 1,
			    next);
		m->y[j + 1] = m->y[j] + d;
	}
	return 0;
}

static int
rows_alloc(geo_ground *m, int height, tl_err *e)
{
	memset(m, 0, sizeof *m);
	m->per_row = 1;
	m->height = height;
	m->dx = tl_alloc((size_t)height, sizeof *m->dx, e);
	m->y = tl_alloc((size_t)height, sizeof *m->y, e);
	if (m->dx == NULL || m->y == NULL) {
		geo_ground_free(m);
		return -1;
	}
	return 0;
}

int
geo_ground_const(geo_ground *m, int height, double dx, double dy, tl_err *e)
{
	if (height < 1 || !(dx > 0 && dy > 0 && isfinite(dx) && isfinite(dy)))
		return tl_fail(e, "metric: invalid cell size %g x %g or height "
		    "%d", dx, dy, height);
	if (rows_alloc(m, height, e) < 0)
		return -1;
	for (int j = 0; j < height; j++) {
		m->dx[j] = dx;
		m->y[j] = j * dy;
	}
	return 0;
}

/* --- the projected lattice -------------------------------------------- */

typedef struct {
	PJ_CONTEXT *ctx;
	PJ *crs, *geo, *op;
	geodesy *geod;
	char name[80]; /* the CRS for messages */
} proj_state;

static void
quiet(void *data, int level, const char *msg)
{
	(void)data, (void)level, (void)msg;
}

static void
proj_done(proj_state *p)
{
	proj_destroy(p->op);
	proj_destroy(p->geo);
	proj_destroy(p->crs);
	if (p->ctx != NULL)
		proj_context_destroy(p->ctx);
	geodesy_free(p->geod);
}

/* The CRS's name for messages, shortened. */
static void
label(proj_state *p, const char *s)
{
	size_t n = strlen(s);

	if (n >= sizeof p->name) {
		memcpy(p->name, s, sizeof p->name - 4);
		strcpy(p->name + sizeof p->name - 4, "...");
	} else
		memcpy(p->name, s, n + 1);
}

/* The CRS as PROJ takes it; a bare PROJ string names an operation unless
 * it says it is a CRS. */
static PJ *
create_crs(PJ_CONTEXT *ctx, const char *def)
{
	char buf[sizeof ((georef *)0)->crs + 16];
	PJ *crs = proj_create(ctx, def);

	if (crs != NULL && proj_is_crs(crs))
		return crs;
	proj_destroy(crs);
	if (def[0] != '+' || strstr(def, "+type=crs") != NULL)
		return NULL;
	snprintf(buf, sizeof buf, "%s +type=crs", def);
	crs = proj_create(ctx, buf);
	if (crs != NULL && proj_is_crs(crs))
		return crs;
	proj_destroy(crs);
	return NULL;
}

/* Opens the CRS, its geographic CRS (lon, lat order), the inverse
 * projection between them and geodesics on its ellipsoid. */
static int
proj_open(proj_state *p, const georef *g, tl_err *e)
{
	char def[32];
	const char *d = g->crs;
	double a, b, rf;
	int computed;
	PJ *ell, *op;

	memset(p, 0, sizeof *p);
	if (d[0] == '\0' && g->epsg > 0)
		snprintf(def, sizeof def, "EPSG:%d", g->epsg), d = def;
	if (d[0] == '\0')
		return tl_fail(e, "CRS unknown: cannot measure the grid in "
		    "metres (give the cell size)");
	label(p, d);
	if ((p->ctx = proj_context_create()) == NULL)
		return tl_fail(e, "CRS %s: cannot create a PROJ context",
		    p->name);
	proj_log_func(p->ctx, NULL, quiet);
	if ((p->crs = create_crs(p->ctx, d)) == NULL)
		return tl_fail(e, "CRS %s: cannot read it (PROJ)", p->name);
	if (strncmp(d, "EPSG:", 5) != 0 && proj_get_name(p->crs) != NULL)
		label(p, proj_get_name(p->crs));
	if ((p->geo = proj_crs_get_geodetic_crs(p->ctx, p->crs)) == NULL)
		return tl_fail(e, "CRS %s: cannot find its geographic CRS",
		    p->name);
	ell = proj_get_ellipsoid(p->ctx, p->geo);
	if (ell == NULL || !proj_ellipsoid_get_parameters(p->ctx, ell, &a, &b,
	    &computed, &rf)) {
		proj_destroy(ell);
		return tl_fail(e, "CRS %s: cannot find its ellipsoid", p->name);
	}
	proj_destroy(ell);
	if ((p->geod = geodesy_new(a, rf > 0 ? 1 / rf : (a - b) / a)) == NULL)
		return tl_fail(e, "CRS %s: cannot use its ellipsoid (a %g, "
		    "1/f %g)", p->name, a, rf);
	op = proj_create_crs_to_crs_from_pj(p->ctx, p->crs, p->geo, NULL, NULL);
	p->op = op != NULL ? proj_normalize_for_visualization(p->ctx, op) :
	    NULL;
	proj_destroy(op);
	if (p->op == NULL)
		return tl_fail(e, "CRS %s: cannot inverse-project to its "
		    "geographic CRS", p->name);
	return 0;
}

/* The 4 points a node's step lengths need, in CRS units: +-half a step
 * along x, then along y. */
static void
node_points(const georef *g, double I, double J, PJ_COORD *c)
{
	static const double d[4][2] = {
		{ -0.5, 0 }, { 0.5, 0 }, { 0, -0.5 }, { 0, 0.5 },
	};
	double off = g->point ? 0 : 0.5, x, y;

	for (int k = 0; k < 4; k++) {
		x = g->origin[0] + (I + d[k][0] + off) * g->step[0];
		y = g->origin[1] + (J + d[k][1] + off) * g->step[1];
		c[k] = proj_coord(x, y, 0, HUGE_VAL);
	}
}

/* PROJ marks a point it cannot convert with HUGE_VAL. */
static int
lonlat_ok(const PJ_COORD *c)
{
	return isfinite(c->lp.lam) && isfinite(c->lp.phi) &&
	    fabs(c->lp.phi) <= 90;
}

/* Step lengths at the nodes of lattice row ky. */
static int
lattice_row(geo_ground *m, const georef *g, proj_state *p, int ky,
    PJ_COORD *c, tl_err *e)
{
	double J = (double)ky * m->cs;

	for (int kx = 0; kx < m->nx; kx++)
		node_points(g, (double)kx * m->cs, J, c + 4 * kx);
	proj_errno_reset(p->op);
	proj_trans_array(p->op, PJ_FWD, (size_t)4 * m->nx, c);
	for (int kx = 0; kx < m->nx; kx++) {
		const PJ_COORD *q = c + 4 * kx;
		size_t n = (size_t)ky * m->nx + kx;
		if (!lonlat_ok(&q[0]) || !lonlat_ok(&q[1]) ||
		    !lonlat_ok(&q[2]) || !lonlat_ok(&q[3]))
			return tl_fail(e, "CRS %s: cannot inverse-project grid "
			    "point (%d, %g) to longitude and latitude", p->name,
			    kx * m->cs, J);
		if (geodesy_distance(p->geod, q[0].lp.phi, q[0].lp.lam,
		    q[1].lp.phi, q[1].lp.lam, &m->sx[n]) < 0 ||
		    geodesy_distance(p->geod, q[2].lp.phi, q[2].lp.lam,
		    q[3].lp.phi, q[3].lp.lam, &m->sy[n]) < 0 ||
		    !(m->sx[n] > 0 && m->sy[n] > 0))
			return tl_fail(e, "CRS %s: cannot measure the grid "
			    "step at grid point (%d, %g)", p->name, kx * m->cs,
			    J);
	}
	return 0;
}

/* Node spacing: at least 16 samples, at most 257 nodes a side. */
static int
lattice_spacing(int w, int h)
{
	int n = (w > h ? w : h) - 1;
	int cs = (n + LATTICE_NODES - 2) / (LATTICE_NODES - 1);

	return cs > LATTICE_MIN_SPACING ? cs : LATTICE_MIN_SPACING;
}

/* Integrals of the bilinear scales along node rows (cx) and node columns
 * (cy): the trapezoid rule is exact on linear pieces. */
static void
lattice_sums(geo_ground *m)
{
	int nx = m->nx;

	for (int ky = 0; ky < m->ny; ky++)
		for (int kx = 0; kx < nx; kx++) {
			size_t n = (size_t)ky * nx + kx;
			m->cx[n] = kx == 0 ? 0 : m->cx[n - 1] + 0.5 * m->cs *
			    (m->sx[n - 1] + m->sx[n]);
			m->cy[n] = ky == 0 ? 0 : m->cy[n - nx] + 0.5 * m->cs *
			    (m->sy[n - nx] + m->sy[n]);
		}
}

static int
ground_projected(geo_ground *m, const georef *g, tl_err *e)
{
	proj_state p;
	PJ_COORD *c;
	size_t n;
	int r;

	m->per_row = 0;
	m->cs = lattice_spacing(g->width > 0 ? g->width : 1, g->height);
	m->inv = 1.0 / m->cs;
	m->nx = (g->width > 1 ? g->width - 2 : 0) / m->cs + 2;
	m->ny = (g->height - 2 >= 0 ? g->height - 2 : 0) / m->cs + 2;
	n = (size_t)m->nx * m->ny;
	m->sx = tl_alloc(n, sizeof *m->sx, e);
	m->sy = tl_alloc(n, sizeof *m->sy, e);
	m->cx = tl_alloc(n, sizeof *m->cx, e);
	m->cy = tl_alloc(n, sizeof *m->cy, e);
	c = tl_alloc((size_t)4 * m->nx, sizeof *c, e);
	if (!m->sx || !m->sy || !m->cx || !m->cy || !c) {
		free(c);
		return -1;
	}
	r = proj_open(&p, g, e);
	for (int ky = 0; r == 0 && ky < m->ny; ky++)
		r = lattice_row(m, g, &p, ky, c, e);
	proj_done(&p);
	free(c);
	if (r == 0)
		lattice_sums(m);
	return r;
}

/* --- init ---------------------------------------------------------------- */

int
geo_ground_init(geo_ground *m, const georef *g, tl_err *e)
{
	double u = g->model == GEO_GEOGRAPHIC ? 0 : g->unit;
	int r;

	memset(m, 0, sizeof *m);
	if (g->height < 1)
		return tl_fail(e, "georeferencing: no grid height");
	if (!isfinite(g->step[0]) || !isfinite(g->step[1]) ||
	    g->step[0] == 0 || g->step[1] == 0)
		return tl_fail(e, "georeferencing: invalid pixel size %g x %g",
		    g->step[0], g->step[1]);
	if (g->model != GEO_GEOGRAPHIC && !(u > 0 && isfinite(u)))
		return tl_fail(e, "georeferencing: invalid unit %g", u);
	if (g->cell[0] > 0) /* the user's cell size beats any CRS */
		r = geo_ground_const(m, g->height, g->cell[0], g->cell[1], e);
	else if (g->model == GEO_PROJECTED)
		r = ground_projected(m, g, e);
	else if ((r = rows_alloc(m, g->height, e)) == 0 &&
	    g->model == GEO_GEOGRAPHIC)
		r = ground_geographic(m, g, e);
	else if (r == 0) /* GEO_NONE: the pixel size in metres */
		for (int j = 0; j < m->height; j++) {
			m->dx[j] = fabs(g->step[0]) * u;
			m->y[j] = j * fabs(g->step[1]) * u;
		}
	if (r < 0) {
		geo_ground_free(m);
		return -1;
	}
	m->width = g->width, m->height = g->height;
	return 0;
}

void
geo_ground_free(geo_ground *m)
{
	free(m->dx), free(m->y);
	free(m->sx), free(m->sy), free(m->cx), free(m->cy);
	memset(m, 0, sizeof *m);
}

/* --- queries: per-row ---------------------------------------------------- */

static double
row_dx(const geo_ground *m, long J)
{
	return m->dx[J < 0 ? 0 : J < m->height ? J : m->height - 1];
}

/* y of an integer row; rows past the last continue its spacing (the
 * padding of coarse levels), rows before 0 the first one. */
static double
row_y(const geo_ground *m, long J)
{
	long last = m->height - 1;
	double step;

	if (J < 0)
		return (double)J * (row_y(m, 1) - row_y(m, 0));
	if (J <= last)
		return m->y[J];
	step = last > 0 ? m->y[last] - m->y[last - 1] : m->dx[0];
	return m->y[last] + (double)(J - last) * step;
}

/* A per-row quantity at a fractional row: linear between rows; exactly
 * the row's value on a row. */
static double
rows_at(const geo_ground *m, double J, double (*f)(const geo_ground *, long))
{
	long j0 = (long)floor(J);
	double t = J - (double)j0;

	if (t == 0)
		return f(m, j0);
	return (1 - t) * f(m, j0) + t * f(m, j0 + 1);
}

/* --- queries: the lattice -------------------------------------------- */

/* Node k (0 .. n-2) and fraction u (0 .. 1) of grid coordinate t; past
 * the lattice the edge node's values hold. */
static inline void
node_of(const geo_ground *m, double t, int n, int *k, double *u)
{
	double s = t * m->inv;

	if (!(s > 0))
		*k = 0, *u = 0;
	else if (s >= n - 1)
		*k = n - 2, *u = 1;
	else
		*k = (int)s, *u = s - *k;
	assert(*k >= 0 && *k <= n - 2);
}

/* v (a node array) on node row ky, linear in the column between kx and
 * kx + 1. */
static inline double
along_row(const geo_ground *m, const double *v, int kx, double u, int ky)
{
	const double *r = v + (size_t)ky * m->nx + kx;

	assert(ky >= 0 && ky < m->ny && kx >= 0 && kx + 1 < m->nx);
	return r[0] + u * (r[1] - r[0]);
}

/* ... on node column kx, linear in the row between ky and ky + 1. */
static inline double
along_col(const geo_ground *m, const double *v, int ky, double u, int kx)
{
	const double *r = v + (size_t)ky * m->nx + kx;

	assert(ky >= 0 && ky + 1 < m->ny && kx >= 0 && kx < m->nx);
	return r[0] + u * (r[m->nx] - r[0]);
}

/* Bilinear: along the node columns first, then along the row, as
 * geo_row_scales and geo_scale_on_row do it. */
static double
lattice_bilinear(const geo_ground *m, const double *v, double I, double J)
{
	int kx, ky;
	double u, w, a, b;

	node_of(m, I, m->nx, &kx, &u);
	node_of(m, J, m->ny, &ky, &w);
	a = along_col(m, v, ky, w, kx);
	b = along_col(m, v, ky, w, kx + 1);
	return a + u * (b - a);
}

/* The integral from 0 to t of a scale linear between nodes, s0 and s1 at
 * the ends of piece k, cum the integral up to node k; linear beyond the
 * last node and before the first. */
static double
integral(const geo_ground *m, double t, int n, int k, double cum, double s0,
    double s1)
{
	double d;

	if (t < 0)
		return t * s0;
	d = t - (double)k * m->cs;
	if (k == n - 2 && d >= m->cs) /* past the last node */
		return cum + 0.5 * m->cs * (s0 + s1) + (d - m->cs) * s1;
	return cum + d * (s0 + 0.5 * d * m->inv * (s1 - s0));
}

static double
lattice_y(const geo_ground *m, double I, double J)
{
	int kx, ky;
	double u, w;

	node_of(m, I, m->nx, &kx, &u);
	node_of(m, J, m->ny, &ky, &w);
	return integral(m, J, m->ny, ky, along_row(m, m->cy, kx, u, ky),
	    along_row(m, m->sy, kx, u, ky), along_row(m, m->sy, kx, u, ky + 1));
}

/* Metres along row J from column 0 to column I. */
static double
lattice_x(const geo_ground *m, double I, double J)
{
	int kx, ky;
	double u, w;

	node_of(m, I, m->nx, &kx, &u);
	node_of(m, J, m->ny, &ky, &w);
	return integral(m, I, m->nx, kx, along_col(m, m->cx, ky, w, kx),
	    along_col(m, m->sx, ky, w, kx), along_col(m, m->sx, ky, w, kx + 1));
}

/* --- queries ------------------------------------------------------------- */

double
geo_sx(const geo_ground *m, double I, double J)
{
	if (m->per_row)
		return J < 0 ? m->dx[0] : rows_at(m, J, row_dx);
	return lattice_bilinear(m, m->sx, I + m->x0, J);
}

double
geo_y(const geo_ground *m, double I, double J)
{
	if (m->per_row)
		return J < 0 ? J * (row_y(m, 1) - row_y(m, 0)) :
		    rows_at(m, J, row_y);
	return lattice_y(m, I + m->x0, J);
}

double
geo_x(const geo_ground *m, double I0, double I, double J)
{
	if (m->per_row)
		return (I - I0) * geo_sx(m, I0, J);
	return lattice_x(m, I + m->x0, J) - lattice_x(m, I0 + m->x0, J);
}

void
geo_local(const geo_ground *m, double I0, double J0, double I, double J,
    double p[2])
{
	p[0] = (I - I0) * geo_sx(m, I0, J);
	p[1] = geo_y(m, I0, J) - geo_y(m, I0, J0);
}

void
geo_scale(const geo_ground *m, double I, double J, double *sx, double *sy)
{
	if (!m->per_row) {
		*sx = lattice_bilinear(m, m->sx, I + m->x0, J);
		*sy = lattice_bilinear(m, m->sy, I + m->x0, J);
		return;
	}
	*sx = geo_sx(m, I, J);
	*sy = J > 0 ? (geo_y(m, I, J + 1) - geo_y(m, I, J - 1)) / 2 :
	    geo_y(m, I, 1) - geo_y(m, I, 0);
}

int
geo_row_nodes(const geo_ground *m)
{
	return m->per_row ? 1 : m->nx;
}

void
geo_row_sx(const geo_ground *m, double J, double *v)
{
	int ky;
	double w;

	if (m->per_row) {
		v[0] = geo_sx(m, 0, J);
		return;
	}
	node_of(m, J, m->ny, &ky, &w);
	for (int kx = 0; kx < m->nx; kx++)
		v[kx] = along_col(m, m->sx, ky, w, kx);
}

void
geo_row_sy(const geo_ground *m, double J, double *v)
{
	int ky;
	double w, sx;

	if (m->per_row) {
		geo_scale(m, 0, J, &sx, &v[0]);
		return;
	}
	node_of(m, J, m->ny, &ky, &w);
	for (int kx = 0; kx < m->nx; kx++)
		v[kx] = along_col(m, m->sy, ky, w, kx);
}

void
geo_row_y(const geo_ground *m, double J, double *v)
{
	if (m->per_row) {
		v[0] = geo_y(m, 0, J);
		return;
	}
	for (int kx = 0; kx < m->nx; kx++)
		v[kx] = lattice_y(m, (double)kx * m->cs, J);
}

void
geo_offset_to_grid(const geo_ground *m, double I, double J, double X,
    double Y, double *di, double *dj)
{
	double sx, sy;

	geo_scale(m, I, J, &sx, &sy);
	/* a row on a pole is one point: no offset along it moves a vertex */
	*di = sx > 0 ? X / sx : 0;
	*dj = sy > 0 ? Y / sy : 0;
}
