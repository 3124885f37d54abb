/* vgis.h - the names vgis(5) fixes: the index's format and version, where
 * a block lives, the vgis:* attributes of a block. Shared by the producer
 * (pyramid.c) and the checker (verify*.c), which share no code. */
#ifndef TL_VGIS_H
#define TL_VGIS_H

#define VGIS_FORMAT "terrain-lod vgis" /* index.json "format" */
#define VGIS_VERSION 1                 /* "version", vgis:version */
#define VGIS_INDEX "index.json"

/* DIR/<level>/<row>_<col>.exr: dir, level, bj, bi */
#define VGIS_BLOCK_PATH "%s/%d/%d_%d.exr"

#define VGIS_ATTR_BASE_ERROR "vgis:base_error"
#define VGIS_ATTR_BLOCK "vgis:block"
#define VGIS_ATTR_LEVEL "vgis:level"
#define VGIS_ATTR_ORIGIN "vgis:origin"
#define VGIS_ATTR_VERSION "vgis:version"
#define VGIS_ATTR_ZRANGE "vgis:zrange"

#endif
