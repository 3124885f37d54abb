/* attr_names.h - the names of the header attributes of FQMs and vertex maps
 * (fqm(5)), in one place for every reader and writer. */
#ifndef TL_ATTR_H
#define TL_ATTR_H

/* the level */
#define FQM_ATTR_KERNEL "fqm:kernel"
#define FQM_ATTR_KIND "fqm:kind"
#define FQM_ATTR_LEVEL "fqm:level"
#define FQM_ATTR_MODE "fqm:mode"
#define FQM_ATTR_SIZE0 "fqm:size0"
#define FQM_ATTR_VERSION "fqm:version"
/* a window (a band job's) has RS_ATTR_X0 (raster.h) */

/* georeferencing, also in vgis(5)'s blocks */
#define GEO_ATTR_CELL "geo:cell"
#define GEO_ATTR_CRS "geo:crs"
#define GEO_ATTR_EPSG "geo:epsg"
#define GEO_ATTR_MODEL "geo:model"
#define GEO_ATTR_NODATA "geo:nodata"
#define GEO_ATTR_ORIGIN "geo:origin"
#define GEO_ATTR_RASTER "geo:raster"
#define GEO_ATTR_STEP "geo:step"
#define GEO_ATTR_UNIT "geo:unit"
#define GEO_ATTR_VDATUM "geo:vdatum"

#endif
