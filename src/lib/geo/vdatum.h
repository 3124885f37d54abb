/* vdatum.h - DEM heights converted from the DEM's vertical datum to the
 * one the user asks for, with PROJ, before anything is computed from them.
 *
 * Heights are metres on both sides: the DEM reader scales a DEM in feet
 * to metres first (vdatum_unit_of), vdatum_apply converts metres to metres, and
 * the operation's own units are compensated inside. One vdatum_shift owns its
 * PROJ context: use it from one thread at a time (one per thread if
 * several threads convert rows). */
#ifndef TL_VDATUM_H
#define TL_VDATUM_H

#include "geo/georef.h"
#include "base/util.h"

typedef struct vdatum_shift vdatum_shift;

/* Prepares the conversion of heights on the grid g (its horizontal CRS,
 * origin, step and point give each sample's position) from the vertical
 * CRS `from` to `to`. Each is "ellipsoid" (WGS 84 ellipsoidal heights,
 * EPSG:4979's height; "EPSG:4979" is taken as the same) or a vertical CRS
 * PROJ knows ("EPSG:5773" EGM96, "EPSG:3855" EGM2008, "EPSG:5703"
 * NAVD88, a WKT); `from` may be in feet, `to` must be in metres (the
 * pyramid stores metres). from NULL or "" (the DEM declares no datum)
 * fails with a hint to name it with -D.
 *
 * Refuses, rather than shift by zero: an operation that needs a grid PROJ
 * cannot find (the message names the grid and where it goes), or that is
 * only a "ballpark" one (heights left as they are), or none covering the
 * whole DEM. Same datum on both sides (units aside): a valid object whose
 * vdatum_apply does nothing. Returns NULL with e set on failure. */
vdatum_shift *vdatum_open(const georef *g, const char *from, const char *to,
    tl_err *e);

/* Converts the heights z[0..n-1], metres, of level-0 row j from column i0
 * on, in place; rows and pieces of rows in any order. NaN samples stay
 * NaN. The shift is exact (PROJ) at a lattice of nodes at most 250 m
 * apart (x plus y) and bilinear in between: within 1.4 cm for EGM96
 * (vdatum_lattice.c derives the bound), about 12 ns a sample for a geographic
 * DEM instead of PROJ's 150. Fails (-1, e set), leaving z as it was,
 * when PROJ gives no finite height for a sample (outside a grid). */
int vdatum_apply(vdatum_shift *v, int j, int i0, int n, float *z, tl_err *e);

/* The stored heights' datum, for the index: "EPSG:4979" for ellipsoidal
 * heights, else the target's "AUTH:code" ("EPSG:5773"), or its name when
 * it has no code. */
const char *vdatum_target_name(const vdatum_shift *v);

/* Whether a datum name means WGS 84 ellipsoidal heights: "ellipsoid"
 * or "EPSG:4979", any case (what -H takes and the index records). */
int vdatum_is_ellipsoid(const char *name);

/* The PROJ operation chosen ("Inverse of WGS 84 to EGM96 height (1)"),
 * "identity" when there is nothing to do: for verbose output and tests. */
const char *vdatum_operation_name(const vdatum_shift *v);

void vdatum_close(vdatum_shift *v);

/* Metres per unit of a vertical CRS's height axis ("EPSG:6360", NAVD88 in
 * US survey feet: 1200/3937; "EPSG:5773": 1; "ellipsoid": 1), so that
 * the reader can scale heights to metres even when no datum conversion is
 * asked for. Returns -1 with e set when vcrs is not a vertical CRS. */
double vdatum_unit_of(const char *vcrs, tl_err *e);

#endif
