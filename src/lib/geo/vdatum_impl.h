/* vdatum_impl.h - private to vdatum.c (choosing the PROJ operation) and
 * vdatum_lattice.c (applying it to rows through a lattice of exact
 * shifts): the conversion object. Not for users of vdatum.h. */
#ifndef TL_VDATUM_IMPL_H
#define TL_VDATUM_IMPL_H

#include <proj.h>

#include "geo/vdatum.h"

/* One row of lattice nodes: the shift (metres) at each node, NaN until
 * computed, infinite where PROJ gives none. */
typedef struct {
	int m;     /* node row, -1 for none */
	double *d; /* nx values */
} vdatum_nodes;

struct vdatum_shift {
	PJ_CONTEXT *ctx;
	PJ *op;      /* source to target, normalised: x lon or easting, y
	              * lat or northing, z height; NULL: nothing to do */
	PJ *toll;    /* horizontal CRS to WGS 84 lon/lat, applied first when
	              * the source is EPSG:4979, which takes lon/lat */
	georef g;    /* where the samples are (geo_vertex_crs) */
	double fs, ft; /* metres per unit of the source / target heights */
	double *x, *y, *z; /* one row, for proj_trans_generic */
	int cap;
	int step;    /* lattice spacing S in samples, 1: exact everywhere */
	int nx, ny;  /* lattice nodes: columns min(k S, width - 1), rows */
	vdatum_nodes rows[2]; /* the two node rows around the last row */
	char name[192];   /* "EPSG:5773 to EPSG:4979", prefixes messages */
	char target[128]; /* vdatum_target_name */
	char opname[256]; /* vdatum_operation_name */
	char log[256];    /* PROJ's last message, for ours */
};

/* PROJ's last message, or a placeholder, for ours. */
static inline const char *
vdatum_why(const char *log)
{
	return log[0] != '\0' ? log : "PROJ gives no reason";
}

/* Sizes the lattice once the operation and v->toll are open: step 1
 * (every sample exact) for small grids, else the node rows allocated.
 * -1 with e set when out of memory. */
int vdatum_lattice_open(vdatum_shift *v, tl_err *e);

#endif
