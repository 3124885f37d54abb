/* verify_impl.h - what the checker's files share (verify.h is its public
 * side): tolerances, the state of a check and of a level, one function
 * per check. Nothing here comes from the producer: the format's names
 * are vgis.h's, the hierarchy the explicit tree of verify_tree.c. */
#ifndef TL_VERIFY_IMPL_H
#define TL_VERIFY_IMPL_H

#include <math.h>

#include "geo/georef.h"
#include "verify/verify.h"
#include "pyramid/vgis.h"

#define VF_NV (BT_SIZE * BT_SIZE)           /* vertices of a block */
#define VF_LEAVES (2 * BT_CELLS * BT_CELLS) /* triangles of a full block */
#define VF_BARY_EPS 1e-9                    /* closed triangles */
#define VF_ABS_EPS 1e-3                     /* metres, float32 heights */
#define VF_REL_EPS 1e-6                     /* of |z| */

/* One check of a pyramid. */
typedef struct {
	const char *dir;
	vf_opts o;
	vf_report *r;
	vf_index ix;
	vf_tree tree;
	dem *dem;          /* or NULL: no DEM checks */
	int W, H;          /* level-0 size */
	geo_ground metric; /* for QEM-3D offsets */
	tl_err *e;
} vf_checker;

/* A block as read. */
typedef struct {
	int ok;               /* read and usable */
	float *z, *e, *x, *y; /* VF_NV each; x, y NULL unless displaced */
	double *px, *py;      /* level-0 grid position of each vertex */
} vf_blk;

/* DEM rows j0 .. j0+n-1, full width; f: bit 0 valid, bit 1 covered */
typedef struct {
	int j0, n, cap;
	float *z;
	unsigned char *f;
} vf_dwin;

/* One level being checked. */
typedef struct {
	vf_checker *c;
	const vf_ilevel *L;
	vf_level *R;
	int l, s, bx, by, disp; /* level, 2^level, blocks, displaced */
	double *tau;
	int ntau;
	vf_blk *row[2];         /* the block row above, this one */
	unsigned char *inside;  /* bx x VF_NV: strictly inside an emitted
	                         * edge */
	unsigned char *bot[2];  /* ntau x bx x 129: bottom rows of inside */
	unsigned char *sel, *used;
	int *emit;
	int *w0, *w1;           /* DEM rows of each block row */
	vf_dwin w;
} vf_lv;

/* The worst DEM sample of a triangle. */
typedef struct {
	double dev, adj; /* largest |surface - DEM|, and less VF_REL_EPS |z| */
	int I, J, n;     /* worst sample; samples inside */
} vf_devmax;

/* verify_note.c: one violation, counted; the first o.max_issues of each kind
 * and level kept. level -1: the pyramid; bi, gi -1: no block, vertex. */
void vf_note(vf_checker *c, int kind, int level, int bi, int bj, int gi,
    int gj, double tau, const char *fmt, ...)
    __attribute__((format(printf, 9, 10)));

/* A note about vertex k of block (bi, bj) of the level. */
#define VNOTE(v, kind, bi, bj, k, tau, ...)                                \
	vf_note((v)->c, kind, (v)->l, bi, bj,                              \
	    (bi) * BT_CELLS + (k) % BT_SIZE, (bj) * BT_CELLS + (k) / BT_SIZE, \
	    tau, __VA_ARGS__)
/* A note about block (bi, bj) of the level. */
#define BNOTE(v, kind, bi, bj, ...)                                        \
	vf_note((v)->c, kind, (v)->l, bi, bj, -1, -1, NAN, __VA_ARGS__)

static inline int
vf_corner(int k)
{
	return k == 0 || k == BT_CELLS || k == BT_CELLS * BT_SIZE ||
	    k == VF_NV - 1;
}

/* Vertex k is selected at tau: corners always. */
static inline int
vf_selected(const vf_blk *b, int k, double tau)
{
	return vf_corner(k) || b->e[k] > tau;
}

/* verify_level.c */
int vf_level_check(vf_checker *c, int l);

/* verify_block.c: reads block (bi, bj) into b (b->ok), noting what is
 * wrong with the file unless quiet (the DEM pre-pass); its content
 * against the index. */
void vf_block_load(vf_lv *v, vf_blk *b, int bi, int bj, int quiet);
void vf_block_content(vf_lv *v, const vf_blk *b, int bi, int bj);

/* verify_border.c: padding of block (bi, bj); its borders with the
 * blocks left of it and above it. */
void vf_border_padding(vf_lv *v, const vf_blk *b, int bi, int bj);
void vf_border_check(vf_lv *v, int bi, int bj);

/* verify_sat.c */
void vf_sat_check(vf_lv *v, const vf_blk *b, int bi, int bj);

/* verify_match.c: the selection of block (bi, bj) of this block row at
 * tau number t; then T-vertices across the row's borders. */
void vf_match_block(vf_lv *v, int bi, int bj, int t);
void vf_match_borders(vf_lv *v, int bj, int t);

/* verify_error.c */
void vf_error_tri(const vf_blk *b, const vf_node *d, double x[3],
    double y[3], double z[3]);
void vf_error_base_local(vf_lv *v, int bi, int bj);
void vf_error_check(vf_lv *v, const vf_blk *b, const vf_node *d, int bi,
    int bj, int t, double *worst);

/* verify_dem.c: the rows of each block row (v->w0, v->w1) and the
 * window; the window moved to rows a..b; rows before upto final. */
int vf_dem_plan(vf_lv *v);
int vf_dem_slide(vf_lv *v, int a, int b);
void vf_dem_finish(vf_lv *v, int upto);

#endif
