/* rg_impl.h - inside the rgb layer: a zoom's grid, its band of tile rows
 * and its scratch of codes (rg_tiles.c), the quadric chain of
 * a segment of zooms (rg_chain.c), the error pass (rg_error.c). */
#ifndef TL_RG_IMPL_H
#define TL_RG_IMPL_H

#include <pthread.h>
#include <signal.h>
#include <stdint.h>

#include "rgb/rgb.h"
#include "rgb/pmtiles.h"
#include "dem/dem_warp.h"
#include "base/pool.h"
#include "base/scratch.h"
#include "qem/fqm.h"
#include "qem/filter.h"

/* A segment of the chain spans at most RG_SEG + 1 zooms: its level-0
 * origin is aligned to 2^RG_SEG pixels (with a margin of half of that),
 * so the padding it costs is under 1.5 2^RG_SEG pixels a side; the zooms
 * above restart from its top level's vertex heights on a grid aligned
 * anew. */
#define RG_SEG 5

#define RG_VALID 0x1000000u /* a pixel's code over valid samples */

typedef struct {
	dem_mgrid g;              /* the zoom's pixel grid */
	long long tx0;            /* first tile column of the band */
	int ntx;                  /* tile columns covering the grid */
	long long ty;             /* tile row in the band, -1: empty */
	int rlo, rhi;             /* band rows filled: rlo .. rhi - 1 */
	int fd;                   /* scratch: the grid's pixels, w x h, each
	                           * its 24-bit code | RG_VALID; the band's
	                           * tiles are cut from it, the error pass
	                           * decodes it */
	dem_mwriter *dz, *dv;     /* the dump's heights and validity */
	long long tiles, bytes;
	int on;                   /* the zoom is made */
} rg_zoom;

/* A plan's part of the split work (rg_split.c): segment 0 on a window
 * of the warped, filled grid (its level-0 columns x0 .. x1 - 1, a halo
 * of RG_HALO past those it owns). Part k owns the level-0 columns of
 * range k of the deepest zoom's tile columns (n ranges as even as
 * integers allow), and at level l the columns c whose c 2^l is one of
 * those (lo[l] .. hi[l] - 1 of the level's whole grid): it writes their
 * codes into pieces, the next segment's vertices of its columns, and
 * the tiles lying in its columns whole; the gather (k -1) the others. */
#define RG_HALO(t) ((long)(FILTER_MAX_RADIUS + 3) << (t))
typedef struct {
	int k, n, maxz, nl, dim;
	long long gx0, T0;        /* the grid's first column, its tile */
	int ntx, gw;              /* the deepest zoom's tile columns, the
	                           * grid's width */
	int x0, x1;               /* the window (level-0 columns) */
	int lo[RG_SEG + 1], hi[RG_SEG + 1];
	int fd[RG_SEG + 1], nfd;  /* the pieces (-1: none) */
	const char *filled;       /* the warped grid's filled file */
	double *h, *v;            /* a row of the window, owned only */
	float *f;
} rg_band;
/* rg_band.c: the part whose columns hold zoom maxz - l's tile column t
 * whole, or -1 (the gather's); b: part k of n (k -1: the gather, owning
 * no column) of segment 0 (nl levels) on grid g, its window. */
int rg_band_owner(const rg_band *b, int l, long long t);
void rg_band_of(rg_band *b, const dem_mgrid *g, int maxz, int nl, int k,
    int n);

typedef struct {
	const rg_args *a;
	rg_band *band;            /* a plan's part of the split work, or
	                           * NULL */
	const char *tree;         /* the tree being built (its temporary),
	                           * or NULL: the tiles go to the sink
	                           * only (-o, an archive) */
	const char *scratch;      /* the run's scratch directory */
	tl_pool *pool;
	int nt;
	unsigned char **rgb;      /* per thread: dim x dim x 3 */
	uint32_t **line;          /* per thread: a tile row's dim codes,
	                           * and dim more (the other end's) */
	unsigned char **img;      /* per tile of a band: the encoded file */
	size_t *imgn;
	int nimg;
	tl_err *terr;             /* per thread: a failure */
	int *tfail;
	int wrap;                 /* the grids run past the world's east
	                           * edge (a DEM across the antimeridian):
	                           * tile column x >= 2^z written as x - 2^z,
	                           * a zoom's two ends merged where they
	                           * share a tile (rg_tiles.c) */
	float *row;               /* a grid row of the widest zoom */
	uint32_t *code;           /* its codes */
	rg_zoom zoom[RG_MAXZOOM + 1];
} rg_job;

/* rg_scratch.c: the run's scratch directory (sc.path), made with
 * SIGINT, SIGTERM and SIGHUP blocked in the caller and the threads it
 * starts until rg_scratch_end (begun, it is always to be called): one
 * of them, read by a thread of its own, removes the directory and then
 * kills the run as it would have. */
typedef struct {
	scratch sc;
	char path[sizeof ((scratch *)0)->path]; /* the thread's copy */
	sigset_t old;
	pthread_t t;
	int sfd, quit[2], blocked, running;
} rg_scratch;
int rg_scratch_begin(rg_scratch *s, tl_err *e);
void rg_scratch_end(rg_scratch *s);

/* rg_tiles.c: zoom z made on grid g (its band, scratch, dump opened);
 * rg_zoom_cut: its tiles (those the plan's job owns) cut again from its
 * scratch, whole, tile row by tile row (the gather of a split plan). */
int rg_zoom_cut(rg_job *j, int z, tl_err *e);
int rg_zoom_open(rg_job *j, int z, const dem_mgrid *g, tl_err *e);
/* Row r of the zoom's grid: heights h (filled) and validity v (> 0). */
int rg_zoom_row(rg_job *j, int z, int r, const double *h, const double *v,
    tl_err *e);
void rg_zoom_close(rg_zoom *zz);

/* rg_chain.c: the chain on the DEM d (a segment's level 0, g its grid;
 * only its level-0 columns x0 .. x0 + n - 1, x0 a multiple of 2^(nl-1):
 * the levels' rows are those of the window, w their widths;
 * global level l0 of the chain, whose level 0 is the deepest zoom's pixel
 * centres): levels 0 .. nl - 1, each row handed to emit as it is solved
 * (centre 0: the level's vertices, row r), and each row of the zoom's
 * pixel centres between vertex rows r and r + 1 (centre 1: rg_centre.c;
 * at global level 0 the vertices themselves). */
typedef int (*rg_emit)(void *ctx, int level, int r, const double *h,
    const double *v, int w, int centre, tl_err *e);
int rg_chain(dem *d, int x0, int n, int nl, int l0, enum solve_mode mode,
    rg_emit emit, void *ctx, tl_err *e);

/* rg_centre.c: the row of zoom maxz - (l0 + l)'s pixel centres between
 * vertex rows j (a, sa: filtered and solved) and jb = j + 1 (b, sb; on
 * the last row jb = j, b = a), w of each; f = rg_centre_frac(l0 + l). */
typedef struct {
	const geo_ground *m;      /* the segment's level-0 metric */
	enum solve_mode mode;
	int l, j, jb, w;          /* l: the segment's level */
	double f;
	const fqm_vertex *a, *b;
	const solve_vertex *sa, *sb;
} rg_centre_in;
double rg_centre_frac(int l);
void rg_centre_row(const rg_centre_in *c, double *h, double *v);

/* rg_box.c: -m average, zooms z .. minz as 2 x 2 means of the zoom
 * below, from zoom g->z's rows (rg_box_row(b, g->z, ...)); opens them. */
typedef struct {
	rg_job *j;
	int minz;
	double *acc[RG_MAXZOOM + 1]; /* per zoom: 6 rows of its width */
} rg_box;
int rg_box_open(rg_box *b, rg_job *j, const dem_mgrid *g, int minz,
    tl_err *e);
int rg_box_row(rg_box *b, int z, int r, const double *h, const double *v,
    tl_err *e);
void rg_box_free(rg_box *b);

/* rg_error.c: per zoom, the largest and RMS vertical distance between
 * the surface MapLibre draws from its decoded heights (bilinear between
 * pixel centres, clamped at the grid's edges) and every valid sample of
 * src (the DEM, opened as the warp read it, heights as the tiles'). */
int rg_error(rg_job *j, dem *src, rg_report *rep, tl_err *e);

/* rg_grid.c: g covering the WGS84 bounds ll at zoom z, its origin
 * aligned down to a multiple of 2^s (pad: the columns, rows added); the
 * next segment's grid, level s of g aligned anew to 2^s2. */
void rg_grid_of(dem_mgrid *g, int z, int dim, const double ll[4], int s,
    long long pad[2]);
void rg_grid_next(dem_mgrid *n, const dem_mgrid *g, int s, int s2,
    long long pad[2]);
/* Global pixel-corner coordinates (pixel k's centre at k + 0.5, res
 * metres a pixel) of longitude, latitude (degrees). */
double rg_merc_x(double lon, double res);
double rg_merc_y(double lat, double res);

/* rg_json.c: OUT/tiles.json; the archive w closed with the same
 * fields (but tilejson and tiles) as its metadata, the same zooms,
 * bounds and centre in its header (pm_close: w freed either way). */
int rg_tilejson(const rg_job *j, const rg_report *rep, const double ll[4],
    tl_err *e);
int rg_pmtiles_close(pm_writer *w, const rg_job *j, const rg_report *rep,
    const double ll[4], tl_err *e);

/* rg_band.c: whether tile column t of zoom zz's band (row zz->ty) is
 * the part's (always, outside a plan's job); rg_run.c: OUT checked. */
int rg_part_owns(const rg_job *j, const rg_zoom *zz, int t);
/* rg_tiles.c: the tiles a band of zoom zz writes (its tile columns, at
 * most the world's 2^z when j->wrap), and the column tile t of the band
 * is written as. */
int rg_zoom_ntiles(const rg_job *j, const rg_zoom *zz);
long long rg_zoom_column(const rg_job *j, const rg_zoom *zz, int t);
int rg_check_out(const rg_args *a, tl_err *e);

/* rg_run.c, shared with a plan's jobs (rg_split.c): the zooms and the
 * deepest zoom's grid g around the DEM's bounds ll; the options the
 * warped grid is opened with (vd holds its datum); the job's threads and
 * buffers; its rows for grids up to w wide; segment k of the chain on
 * grid g from the DEM file path; after segment 0 (r its result, ng the
 * next grid): the later segments, the error pass and tiles.json. */
int rg_grid0(const rg_args *a, rg_report *rep, double ll[4], dem_mgrid *g,
    tl_err *e);
int rg_warp_opts(const rg_args *a, dem_opts *o, char *vd, size_t n,
    tl_err *e);
int rg_job_init(rg_job *j, const rg_args *a, tl_err *e);
void rg_job_free(rg_job *j);
int rg_rows_alloc(rg_job *j, int w, tl_err *e);
int rg_segment(rg_job *j, int k, const dem_mgrid *g, const char *path,
    const dem_opts *o, dem_mgrid *ng, rg_report *rep, tl_err *e);
int rg_finish(rg_job *j, int r, const dem_mgrid *ng, const dem_opts *o,
    const double ll[4], rg_report *rep, tl_err *e);
/* rg_tiles.c: a part's row of zoom z (level l of segment 0): its owned
 * columns into the zoom's tiles and its piece; row r of the next
 * segment's vertices (level nl - 1), its owned columns into its piece. */
int rg_band_row(rg_job *j, int l, int z, int r, const double *h,
    const double *v, tl_err *e);
int rg_band_next(rg_job *j, int r, const double *h, const double *v,
    tl_err *e);
/* A part's work (win: its window of the grid's w columns, x0 x1 w), and
 * the gather's: what one process holds after segment 0, then the later
 * segments and the error (n parts; rep's counts of segment 0 kept). */
int rg_split_part(const rg_args *a, const char *work, int k, int n,
    rg_report *rep, int win[3], tl_err *e);
int rg_split_gather(const rg_args *a, const char *work, int n,
    rg_report *rep, tl_err *e);

#endif
