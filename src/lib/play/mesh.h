/* mesh.h - the drawable geometry of a block: its vertices once (positions
 * in metres, normals, height and error), and per tolerance the triangles
 * of its bintree selection, with skirts.
 *
 * Cracks between blocks drawn at different levels or tolerances are
 * closed by skirts: under every border edge of the selection a vertical
 * quad hangs to the world's floor (world.base), so whatever the
 * neighbour draws, no gap between the two surfaces shows what is behind.
 * On displaced (QEM-3D) levels the border vertices are drawn on the
 * block's border line (their offset across it dropped, along it kept), so
 * neighbours also meet edge to edge in x and y, where a vertical skirt
 * could not close a gap. */
#ifndef TL_MESH_H
#define TL_MESH_H

#include <stdint.h>

#include "play/world.h"

#define MESH_SIDE (BT_SIZE)          /* border vertices per side */
#define MESH_NV (PYRAMID_N + 4 * MESH_SIDE) /* grid, then skirt floors */

typedef struct {
	double origin[3]; /* world position the floats are relative to */
	float *pos;       /* MESH_NV x 3, metres from origin */
	float *nrm;       /* MESH_NV x 3, unit */
	float *val;       /* MESH_NV x 2: height (m), E (m; FLT_MAX corners) */
} mesh_verts;

int mesh_verts_build(const world *w, const pyramid_block *b, mesh_verts *v,
    tl_err *e);
void mesh_verts_free(mesh_verts *v);

typedef struct {
	uint32_t *idx; /* 3 per triangle */
	size_t n, cap; /* indices */
	long tris;     /* terrain triangles */
	long skirts;   /* skirt triangles */
} mesh_tris;

/* The triangles of b's bintree refined where E > tau (tau < 0: every
 * vertex, the full grid), then with skirts two per border edge. */
int mesh_tris_build(const pyramid_block *b, double tau, int skirts, mesh_tris *t,
    tl_err *e);
void mesh_tris_free(mesh_tris *t);

#endif
