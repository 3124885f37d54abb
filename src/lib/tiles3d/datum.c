/* datum.c - may the pyramid go on a globe? Heights must be ellipsoidal
 * (WGS 84's, what ECEF needs); a pyramid of orthometric heights is
 * refused rather than converted here: shifting each vertex by the geoid
 * would leave the saturated errors, measured against the orthometric DEM,
 * bounding something else. */
#include <stdio.h>

#include "geo/vdatum.h"
#include "tiles3d/t3_impl.h"

int
t3_check_datum(const t3_args *a, const pyramid_index *ix, tl_err *e)
{
	const georef *g = &ix->geo;

	if (g->model == GEO_NONE)
		return tl_fail(e, "%s: the pyramid has no CRS: it cannot be "
		    "placed on the globe (rebuild it from a georeferenced DEM)",
		    a->dir);
	if (vdatum_is_ellipsoid(g->vdatum))
		return 0;
	if (g->vdatum[0] != '\0')
		return tl_fail(e, "%s: heights are in %s, not ellipsoidal: "
		    "rebuild the pyramid with dem2vgis -H ellipsoid DEM DIR",
		    a->dir, g->vdatum);
	if (a->prog != NULL && !a->quiet)
		fprintf(stderr, "%s: %s: vertical datum unknown: heights taken "
		    "as ellipsoidal (if they are not, rebuild with dem2vgis "
		    "-D datum -H ellipsoid)\n", a->prog, a->dir);
	return 0;
}
