/* verify.h - the brute-force checker of a VGIS pyramid (tilecheck(1),
 * tileplay --verify), the one public header of these files:
 *
 *   verify.c         the pyramid as a whole, vf_check
 *   verify_tree.c    a block's bintree, built from the split rule
 *   verify_index.c   its own index.json reader
 *   verify_level.c   a level, one block row at a time
 *   verify_block.c   block files and their attributes   (index)
 *   verify_border.c  shared borders, padding       (border, padding)
 *   verify_sat.c     saturation                        (saturation)
 *   verify_match.c   selections at each tau           (matching, fold)
 *   verify_error.c   triangles against the DEM   (error, base, local)
 *   verify_dem.c     the DEM window                      (coverage)
 *   verify_report.c  the report, the programs' entry
 *   verify_impl.h    what they share
 *
 * It trusts neither the producer nor bintree.c and shares no code with
 * them (pyramid.h, level.h): the hierarchy is derived here from the split
 * rule of vgis(5) by building a block's bintree explicitly, and every
 * property is checked by exhaustion:
 *
 *   index       index.json against the block files: every block present,
 *               129x129, channels E Z (+ X Y), vgis:* geo:* fqm:*
 *               attributes, z range, base and largest finite E as listed;
 *               levels and sizes as vgis(5) says; no stray files
 *   border      vertices shared by neighbouring blocks identical
 *   padding     vertices past the level's size copy the nearest real edge
 *               vertex (same Z, X = Y = 0)
 *   saturation  E(apex) >= E(midpoint) for every split triangle; corners
 *               FLT_MAX, every other E finite and >= 0
 *   matching    per tau: parents of selected vertices selected, every
 *               selected vertex a corner of an emitted triangle, no
 *               selected vertex (here or in the neighbour block) strictly
 *               inside an emitted edge, areas summing to the block's
 *   fold        displaced levels: an emitted triangle flipped or flat
 * and with the DEM:
 *   error       per tau: |surface - DEM| <= max(tau, base error) + eps
 *               over every valid sample of every emitted triangle
 *   base        the finest triangles deviate at most the base error
 *   local       each split triangle deviates at most E of its midpoint
 *   coverage    at tau 0 every valid sample lies in some triangle
 *
 * eps = 1e-3 m + 1e-6 |z| (float32 storage). A sample is in a triangle
 * when its barycentric coordinates are >= -1e-9 (closed), positions
 * being level-0 grid columns and rows (QEM-3D offsets through
 * geo_offset_to_grid at the vertex's level-0 position); heights interpolate
 * linearly in that grid space.
 *
 * Memory: two block rows of a level, and the DEM rows one block row
 * covers (dem_read_row), whatever the pyramid's size. Nothing is
 * printed: violations are counted and the first few of each kind and
 * level kept in the report. */
#ifndef TL_VERIFY_H
#define TL_VERIFY_H

#include <stdio.h>

#include "pyramid/bintree.h"
#include "dem/dem.h"
#include "base/util.h"

/* --- the block's bintree, derived from the split rule --------------- */

typedef struct {
	unsigned char a[2], b[2], p[2]; /* hypotenuse ends, apex (col, row) */
	int m;      /* local index row * 129 + col of the hypotenuse midpoint,
	             * -1 for a leaf (legs of length 1) */
	int kid[2]; /* the two triangles of its split, -1 for a leaf */
} vf_node;

#define VF_NODES (4 * BT_CELLS * BT_CELLS - 2) /* 2 roots, 2^15 - 1 each */

typedef struct {
	vf_node *node;  /* VF_NODES */
	int root[2];    /* (0,0)-(128,128) apex (128,0), and apex (0,128) */
	int (*dia)[2];  /* per local vertex: the nodes whose hypotenuse
	                 * midpoint it is (-1: none); 2 inside, 1 on a block
	                 * border, 0 at corners */
} vf_tree;

int vf_tree_init(vf_tree *t, tl_err *e);
void vf_tree_free(vf_tree *t);

/* Relations of level vertex (gi, gj) in a level of bx x by blocks, from
 * the trees of every block holding it (a border vertex's second triangle
 * is the neighbour's): diamond triangles as (hypotenuse end, end, apex)
 * in level coordinates, parents (their apexes), children (midpoints of
 * the triangles their split creates). Nothing past the blocks. */
int vf_diamond(const vf_tree *t, int bx, int by, int gi, int gj,
    int tri[2][3][2]);
int vf_parents(const vf_tree *t, int bx, int by, int gi, int gj,
    int p[2][2]);
int vf_children(const vf_tree *t, int bx, int by, int gi, int gj,
    int c[4][2]);

/* Top-down selection in one block: from the roots, a node is split when
 * sel[its midpoint] is non-zero. Writes the node indices of the emitted
 * triangles to out (room for 2 * 128 * 128) and returns their number. */
long vf_select(const vf_tree *t, const unsigned char *sel, int *out);

/* --- the check ------------------------------------------------------ */

enum vf_kind {
	VF_INDEX, VF_BORDER, VF_PADDING, VF_SATURATION, VF_MATCHING, VF_FOLD,
	VF_ERROR, VF_BASE, VF_LOCAL, VF_COVERAGE, VF_NKIND
};

const char *vf_kind_name(int kind); /* "index", "border", ... */

typedef struct {
	const double *tau; /* taus for every level (0 is added), or NULL */
	int ntau;
	int nsweep;     /* else per level: 0 and a geometric series from
	                 * emax / 1000 to emax, nsweep values in all (10) */
	int max_issues; /* kept per kind and level (20); all are counted */
	int local;      /* the local check, with a DEM (1) */
} vf_opts;

void vf_opts_init(vf_opts *o);

/* One violation. level -1: the pyramid as a whole; block, vertex -1 when
 * not about one (vertex: level coordinates gi, gj); tau NAN when none. */
typedef struct {
	int kind, level;
	int block[2];  /* column, row: the file DIR/level/row_col.exr */
	int vertex[2];
	double tau;
	char text[192];
} vf_issue;

typedef struct {
	double tau;
	long long triangles; /* emitted over the level's blocks */
	double maxerr;       /* largest |surface - DEM|; NAN without DEM */
} vf_taustat;

typedef struct {
	int level, size[2], blocks[2], displaced;
	long long blocks_read;
	long long count[VF_NKIND];
	int kept[VF_NKIND];
	int ntau;
	vf_taustat *tau;
	double emax;      /* largest finite E in the blocks */
	double base;      /* largest base error the index declares */
	double base_real; /* largest deviation of the finest triangles */
	double local_max; /* largest deviation of a split triangle */
	double tight;     /* largest real error / tau over the blocks and
	                   * the taus above their base error; NAN if none */
	double tight_tau;
	int tight_block[2];
	long long samples; /* valid DEM samples seen */
} vf_level;

typedef struct {
	int size0[2];
	int dem;     /* the DEM checks ran */
	int nlevels;
	vf_level *lev;
	long long count[VF_NKIND]; /* over everything */
	long long total;
	int kept[VF_NKIND];        /* pyramid-wide issues kept */
	vf_issue *issue;
	int nissue, capissue;
} vf_report;

/* Checks the pyramid in dir, against the DEM when dem_path is not NULL.
 * Returns -1 only when it cannot check (no index, DEM unreadable or of
 * another size, out of memory); violations go to r (r->total). */
int vf_check(const char *dir, const char *dem_path, const dem_opts *dopt,
    const vf_opts *o, vf_report *r, tl_err *e);
void vf_report_free(vf_report *r);

/* --- the programs' side: options, report, run (verify_report.c) ----- */

#define VF_MAXTAU 64

/* What tilecheck and tileplay --verify take. */
typedef struct {
	const char *dir;      /* the pyramid */
	const char *dem_path; /* --dem, or NULL */
	dem_opts dem;         /* -D -e -H -N -n -s */
	double tau[VF_MAXTAU]; /* --tau, ntau of them (0: the sweep) */
	int ntau;
} vf_args;

/* "t,...": up to VF_MAXTAU numbers >= 0 into a->tau; -1 when not. */
int vf_parse_taus(vf_args *a, const char *s);

/* The report as the programs print it: a block per level, the kept
 * violations, "result: pass" or "result: FAIL, n violations: ...". */
void vf_report_print(FILE *f, const vf_report *r, const char *dir,
    const char *dem_path, int max_issues);

/* Checks a->dir (against a->dem_path if set) and prints the report on
 * stdout. Returns 0 when every check passes, 1 on violations, -1 when
 * it cannot check (then "prog: what: why" on stderr, no report). */
int vf_run(const vf_args *a, const char *prog);

/* --- index.json as the checker reads it (verify_index.c) ------------
 * Its own reader, sharing no code with the producer's (pyramid.c). */

typedef struct {
	int level, size[2], blocks[2], displaced;
	char mode[64], kernel[64];
	double *zmin, *zmax, *base, *emax; /* per block, row-major */
} vf_ilevel;

typedef struct {
	int size0[2];
	georef geo;
	int nlevels;
	vf_ilevel *lev;
} vf_index;

/* Fails on a missing or unreadable file, text that is not JSON, and an
 * index it cannot check against (fields missing or of the wrong type,
 * block counts not those of the level's size). */
int vf_index_read(const char *dir, vf_index *ix, tl_err *e);
void vf_index_free(vf_index *ix);

#endif
