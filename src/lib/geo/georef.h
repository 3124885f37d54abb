/* georef.h - georeferencing carried from the DEM to every output, and the
 * ground embedding of the grid (cell sizes in metres, never degrees). */
#ifndef TL_GEOREF_H
#define TL_GEOREF_H

#include "base/util.h"

enum geo_model { GEO_NONE, GEO_PROJECTED, GEO_GEOGRAPHIC };

/* The model's name in headers and index.json ("none", "projected",
 * "geographic"), and back: 0, or -1 for an unknown name. */
const char *geo_model_name(enum geo_model m);
int geo_model_parse(const char *s, enum geo_model *m);

typedef struct {
	enum geo_model model;
	int epsg;        /* horizontal CRS EPSG code, 0 if none or unknown */
	char crs[4096];  /* "EPSG:32611" when the CRS is one EPSG code, else
	                  * its WKT2 (one line), "" for GEO_NONE */
	int point;       /* 1 PixelIsPoint, 0 PixelIsArea */
	double origin[2]; /* CRS coords of raster point (0,0): the corner of
	                   * pixel (0,0) (area) or its centre (point), exactly
	                   * as the file's tie point gives it */
	double step[2];  /* level-0 pixel size in CRS units, signed as in a
	                  * GDAL geotransform (y < 0 for north-up) */
	double unit;     /* metres per CRS unit; 1 for GEO_NONE (cells given
	                  * in metres), 0 for GEO_GEOGRAPHIC (degrees) */
	char vdatum[256]; /* vertical datum as declared ("EPSG:5773", a
	                   * citation, "EGM96 (SRTM)"), "" when not declared */
	double cell[2];  /* metres per column and per row step given by the
	                  * user (-s) on a georeferenced DEM, overriding the
	                  * CRS's metric; 0 0 = the metric comes from the CRS */
	int has_nodata;
	double nodata;   /* as declared by the file (may be NaN) */
	int width, height; /* level-0 size */
} georef;

/* The first field in which two georeferencings differ ("crs", "origin",
 * "vdatum", ...), NULL when they are the same (a NaN nodata equals a NaN
 * nodata): what "made from the same DEM, read the same way" means. */
const char *geo_differs(const georef *a, const georef *b);

/* CRS coordinates of the centre of vertex (i, j) of a level: level-0
 * position (i*2^level, j*2^level). */
void geo_vertex_crs(const georef *g, int level, double i, double j,
    double *x, double *y);

/* Degrees: a latitude this close past a pole is the pole (rounding). */
#define GEO_POLE_EPS 1e-9

/* --- the ground embedding of the level-0 grid --------------------------
 *
 * Ground metres for grid steps, never degrees or CRS units. Column I and
 * row J are level-0 grid positions (fractional allowed; past the grid the
 * scales of its edge continue). Vertex (I, J) seen from vertex (I0, J0)
 * sits, in the local frame of (I0, J0), at
 *     X = (I - I0) * geo_sx(m, I0, J),  Y = geo_y(m, I0, J) - geo_y(m, I0, J0)
 * (geo_local): x along the row, y along the column, both in metres, the
 * grid's axes taken as perpendicular on the ground.
 *
 * Per-row metrics (the column argument is ignored):
 * - GEO_GEOGRAPHIC: geodesics on WGS84 (GeographicLib): dx[J] along the
 *   parallel of row J for one column step, y[J] along the meridian. A
 *   row on a pole (within GEO_POLE_EPS) has dx 0: its vertices are one
 *   point, and offsets along it move nothing (geo_offset_to_grid); a
 *   row past a pole is refused.
 * - GEO_NONE: the pixel size times the unit, constant.
 * - a user cell size (georef.cell, any model): constant.
 * Between integer rows the per-row values interpolate linearly; before
 * row 0 and past the last row they continue the first / last spacing.
 *
 * GEO_PROJECTED (lattice): PROJ inverse-projects grid points to the CRS's
 * own geographic CRS and GeographicLib measures, on the CRS's ellipsoid,
 * the geodesic length of one grid step along x and along y (central
 * differences, +-half a step) at the nodes of a lattice every cs level-0
 * samples (cs >= 16, at most 257 x 257 nodes whatever the DEM's size).
 * Both scales interpolate bilinearly between nodes; geo_y integrates the
 * y scale along the column and geo_x the x scale along the row in closed
 * form (cumulative sums at the nodes), so every query is O(1) and PROJ is
 * only called at init. Conformal projections (UTM, Mercator, polar
 * stereographic, Lambert conformal) have perpendicular grid axes on the
 * ground; for other projections the angle between them is still taken as
 * 90 degrees (the lengths are right, the shear is ignored). Accuracy: the
 * lengths are exact at the nodes to the precision of the inverse
 * projection (about 1e-9 relative); between them the error is that of
 * linear interpolation of the scale, about (h/R)^2 relative for a node
 * spacing of h metres (R the Earth's radius; more near the poles of
 * Mercator): 2e-8 for 30 m cells. t_ground measures distances along rows
 * and columns within 1e-8 of WGS84 geodesics for Web Mercator, UTM and
 * polar stereographic grids. */
typedef struct {
	int per_row;      /* 1: dx, y per row; 0: the projected lattice */
	int width, height; /* level-0 grid */
	double *dx, *y;   /* per row: height values each */
	int cs, nx, ny;   /* lattice: node spacing (level-0 samples), nodes */
	double inv;       /* 1 / cs */
	double *sx, *sy;  /* nx x ny nodes, row-major: metres per step */
	double *cx, *cy;  /* metres from column 0 along the node's row, from
	                   * row 0 along its column */
	double x0;        /* column offset: the metric of a window whose
	                   * column 0 is level-0 column x0 of the grid (a
	                   * band job, fqm(5) fqm:x0); every column argument
	                   * I below is then the window's. 0 after init */
} geo_ground;

/* Fails with "CRS ...: cannot ..." when PROJ cannot use a projected CRS. */
int geo_ground_init(geo_ground *m, const georef *g, tl_err *e);
/* A constant per-row metric (tests, hand-built grids): dx metres per
 * column, dy per row, height rows. */
int geo_ground_const(geo_ground *m, int height, double dx, double dy,
    tl_err *e);
void geo_ground_free(geo_ground *m);

/* Metres per level-0 column step along row J near column I. */
double geo_sx(const geo_ground *m, double I, double J);
/* Metres from row 0 to row J along column I (the integral of the row
 * step's length along that column); negative before row 0. */
double geo_y(const geo_ground *m, double I, double J);
/* Metres along row J from column I0 to column I (signed; the integral of
 * geo_sx along the row; per-row metrics: (I - I0) * geo_sx). */
double geo_x(const geo_ground *m, double I0, double I, double J);
/* Vertex (I, J) in the local frame of vertex (I0, J0) (see above). */
void geo_local(const geo_ground *m, double I0, double J0, double I, double J,
    double p[2]);
/* Metres per level-0 column and per row step at vertex (I, J): what a
 * QEM-3D offset (X, Y) metres is divided by. Per-row metrics: dx[J] and
 * the row spacing centred on J (one-sided at row 0). */
void geo_scale(const geo_ground *m, double I, double J, double *sx,
    double *sy);
/* A vertex at (I, J) displaced by (X, Y) metres (a QEM-3D vertex map)
 * sits di, dj level-0 columns and rows off its grid position. */
void geo_offset_to_grid(const geo_ground *m, double I, double J, double X,
    double Y, double *di, double *dj);

/* For loops over the vertices of a row: geo_sx, geo_y and the y scale of
 * geo_scale along row J at the lattice's node columns (geo_row_nodes
 * values, at most GEO_MAX_NODES; 1 for a per-row metric), from which
 * geo_on_row gives the value at any column I without the metric's
 * interpolation between rows. geo_sx and geo_scale come out bit for bit;
 * geo_y to rounding (it is linear in I between node columns). */
#define GEO_MAX_NODES 257
int geo_row_nodes(const geo_ground *m);
void geo_row_sx(const geo_ground *m, double J, double *v);
void geo_row_sy(const geo_ground *m, double J, double *v);
void geo_row_y(const geo_ground *m, double J, double *v);

static inline double
geo_on_row(const geo_ground *m, const double *v, double I)
{
	double t = (I + m->x0) * m->inv, u;
	int k;

	if (m->per_row || !(t > 0)) /* per-row metrics: inv is 0 */
		return v[0];
	if (t >= m->nx - 1)
		k = m->nx - 2, u = 1;
	else
		k = (int)t, u = t - k;
	return v[k] + u * (v[k + 1] - v[k]);
}

/* For dem.c and programs that build a georef by hand. */

/* GEO_NONE: origin (0,0), step (cx, -cy) in metres, unit 1, point 1. */
void geo_init_none(georef *g, double cx, double cy);

#endif
