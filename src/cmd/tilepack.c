/* tilepack - the VGIS block pyramid: the vertex maps of levels 0..L and
 * the original DEM in, a directory of 129x129 blocks per level out, each
 * vertex with its height and its saturated error (see vgis(5)). */
#include <errno.h>
#include <getopt.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/dem.h"
#include "core/fqm.h"
#include "pyramid/pyramid.h"
#include "core/raster.h"
#include "pyramid/tiles.h"
#include "core/util.h"

static const char *prog = "tilepack";

static void
usage(FILE *f)
{
	fprintf(f, "usage: %s [-fq] [-D datum] [-e encoding] [-H datum] "
	    "[-j jobs] [-N nodata]\n"
	    "                [-n name] [-s dx[,dy]] dem dir level0 "
	    "[level1 ...]\n"
	    "  -f              replace dir even if it is not a pyramid\n"
	    "  -j jobs         levels done at once (default: the CPUs)\n"
	    "  -q              no report on stderr\n"
	    "  -D, -e, -H, -N, -n, -s  how to read the DEM, as for "
	    "dem2fqm(1)\n"
	    "  dem             the original DEM (errors are measured against "
	    "it)\n"
	    "  dir             the pyramid directory to make\n"
	    "  level0 ...      vertex maps (fqmsolve(1)) of levels 0, 1, ... "
	    "in order;\n"
	    "                  EXR or fqm stream files, FIFOs, - for one of "
	    "them\n", prog);
}

typedef struct {
	dem_opts dem;
	int force, quiet, jobs;
	const char *dem_path, *dir;
	char **levels;
	int nlevels;
} options;

/* The vertex map being read, for the row callback. */
typedef struct {
	rs_reader *r;
	const rs_header *h;
	int cz, cx, cy;
	float *row;
	const char *name;
} vmap;

static int
read_row(void *ctx, int r, float *z, float *x, float *y, tl_err *e)
{
	vmap *v = ctx;
	int w = v->h->width;

	(void)r;
	if (rs_read_row(v->r, v->row, e) < 0)
		return -1;
	memcpy(z, v->row + (size_t)v->cz * w, (size_t)w * sizeof *z);
	if (x != NULL) {
		memcpy(x, v->row + (size_t)v->cx * w, (size_t)w * sizeof *x);
		memcpy(y, v->row + (size_t)v->cy * w, (size_t)w * sizeof *y);
	}
	return 0;
}

/* Where finished blocks go, and what the index learns from them. */
typedef struct {
	const char *dir;
	const rs_header *attrs;
	pyramid_level *L;
} sink;

static int
write_block(void *ctx, const pyramid_block *b, tl_err *e)
{
	sink *k = ctx;
	char path[4096];
	size_t i = (size_t)b->bj * k->L->blocks[0] + b->bi;

	pyramid_block_path(path, sizeof path, k->dir, b->level, b->bi, b->bj);
	k->L->zmin[i] = b->zmin, k->L->zmax[i] = b->zmax;
	k->L->base[i] = b->base, k->L->emax[i] = b->emax;
	return pyramid_block_write(path, b, k->attrs, e);
}

/* Same DEM, same georeferencing, the right level. */
static int
check_level(const fqm_info *fi, int l, const georef *g, const char *name,
    tl_err *e)
{
	const char *what;

	if (fi->level != l)
		return tl_fail(e, "%s: is level %d, expected level %d (levels "
		    "go in order from 0)", name, fi->level, l);
	if (fi->size0[0] != g->width || fi->size0[1] != g->height)
		return tl_fail(e, "%s: made from a %dx%d DEM, the DEM is %dx%d",
		    name, fi->size0[0], fi->size0[1], g->width, g->height);
	if ((what = geo_differs(&fi->geo, g)) != NULL)
		return tl_fail(e, "%s: georeferencing (%s) differs from the "
		    "DEM's: made with other DEM options?", name, what);
	return 0;
}

/* One level: what every worker shares, read-only but for the next level
 * to take and the first failure. */
typedef struct {
	const options *o;
	dem *d;
	const char *tmp;
	pyramid_index *ix;
	const geo_metric *m;
	tiles_stats *st;
	pthread_mutex_t lock;
	int next, failed;
	tl_err err;
} work;

static int
pack_level(work *w, int l, tl_err *e)
{
	const options *o = w->o;
	const char *name = tl_name(o->levels[l], 0);
	char label[64], path[4096];
	vmap v = { 0 };
	fqm_info fi;
	tiles_level L = { 0 };
	pyramid_level *pl = &w->ix->lev[l];
	sink k;
	const char *s;
	int r = -1;

	v.name = name;
	if ((v.r = rs_open(o->levels[l], e)) == NULL)
		return -1;
	v.h = rs_header_of(v.r);
	if (fqm_info_of(v.h, "vertices", &fi, name, e) < 0 ||
	    check_level(&fi, l, dem_georef(w->d), name, e) < 0 ||
	    (v.cz = rs_need_channel(v.h, "Z", name, e)) < 0)
		goto done;
	v.cx = rs_channel(v.h, "X"), v.cy = rs_channel(v.h, "Y");
	if ((v.cx < 0) != (v.cy < 0)) {
		tl_fail(e, "%s: has only one of channels X and Y", name);
		goto done;
	}
	if ((v.row = tl_alloc((size_t)v.h->width * v.h->nch, sizeof(float),
	    e)) == NULL || pyramid_level_init(pl, l, v.h->width, v.h->height, e) < 0)
		goto done;
	pl->displaced = v.cx >= 0;
	snprintf(pl->mode, sizeof pl->mode, "%s",
	    (s = rs_get_string(v.h, FQM_ATTR_MODE)) ? s : "");
	snprintf(pl->kernel, sizeof pl->kernel, "%s",
	    (s = rs_get_string(v.h, FQM_ATTR_KERNEL)) ? s : "");
	snprintf(path, sizeof path, "%s/%d", w->tmp, l);
	if (mkdir(path, 0777) != 0) {
		tl_failsys(e, "%s", path);
		goto done;
	}
	k.dir = w->tmp, k.attrs = v.h, k.L = pl;
	snprintf(label, sizeof label, "%s: level %d", prog, l);
	L.level = l;
	L.size[0] = v.h->width, L.size[1] = v.h->height;
	L.displaced = pl->displaced;
	L.m = w->m;
	L.row = read_row, L.row_ctx = &v;
	L.block = write_block, L.block_ctx = &k;
	/* one progress line at a time: only when working alone */
	L.label = o->jobs == 1 ? label : NULL;
	r = tiles_run(&L, w->d, &w->st[l], e);
done:
	rs_close(v.r);
	free(v.row);
	return r;
}

/* A worker takes levels in order (level 0, the largest, first) until
 * none is left or one failed. */
static void *
worker(void *arg)
{
	work *w = arg;
	tl_err e;

	for (;;) {
		int l;
		pthread_mutex_lock(&w->lock);
		l = w->failed ? w->o->nlevels : w->next++;
		pthread_mutex_unlock(&w->lock);
		if (l >= w->o->nlevels)
			return NULL;
		if (pack_level(w, l, &e) < 0) {
			pthread_mutex_lock(&w->lock);
			if (!w->failed)
				w->err = e;
			w->failed = 1;
			pthread_mutex_unlock(&w->lock);
			return NULL;
		}
	}
}

static int
run_levels(work *w, tl_err *e)
{
	int n = w->o->jobs < w->o->nlevels ? w->o->jobs : w->o->nlevels;
	pthread_t t[64];
	int started = 0;

	if (n > 64)
		n = 64;
	pthread_mutex_init(&w->lock, NULL);
	for (int k = 1; k < n; k++)
		if (pthread_create(&t[started], NULL, worker, w) == 0)
			started++;
	worker(w); /* this thread works too */
	for (int k = 0; k < started; k++)
		pthread_join(t[k], NULL);
	pthread_mutex_destroy(&w->lock);
	if (w->failed) {
		*e = w->err;
		return -1;
	}
	return 0;
}

/* Refuse to replace a directory that is not a pyramid, unless -f. */
static int
check_dir(const options *o, tl_err *e)
{
	char path[4096];
	struct stat st;

	if (stat(o->dir, &st) != 0)
		return errno == ENOENT ? 0 : tl_failsys(e, "%s", o->dir);
	if (!S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: exists and is not a directory", o->dir);
	snprintf(path, sizeof path, "%s/index.json", o->dir);
	if (!o->force && access(path, F_OK) != 0 && rmdir(o->dir) != 0)
		return tl_fail(e, "%s: exists and is not a pyramid (no "
		    "index.json); use -f to replace it", o->dir);
	return 0;
}

/* Levels 0 .. the first that fits one block, no fewer, no more: the
 * rule viewers and the checker hold a pyramid to. */
static int
levels_complete(const pyramid_index *ix, tl_err *e)
{
	int want = fqm_levels(ix->size0[0], ix->size0[1]);

	if (ix->nlevels == want)
		return 0;
	return tl_fail(e, "%d levels given, a %dx%d DEM's pyramid has %d "
	    "(0 .. the first that fits one %dx%d block)", ix->nlevels,
	    ix->size0[0], ix->size0[1], want, FQM_BLOCK, FQM_BLOCK);
}

static int
pack(const options *o, tl_err *e)
{
	pyramid_index ix = { 0 };
	geo_metric m = { 0 };
	tl_outfile out = { 0 };
	work w = { 0 };
	dem *d;
	int r = -1;

	if (check_dir(o, e) < 0 || (d = dem_open(o->dem_path, &o->dem, e)) == NULL)
		return -1;
	ix.version = PYRAMID_VERSION;
	ix.geo = *dem_georef(d);
	ix.size0[0] = ix.geo.width, ix.size0[1] = ix.geo.height;
	ix.nlevels = o->nlevels;
	w.o = o, w.d = d, w.ix = &ix, w.m = &m;
	if ((ix.lev = tl_alloc(o->nlevels, sizeof *ix.lev, e)) == NULL ||
	    (w.st = tl_alloc(o->nlevels, sizeof *w.st, e)) == NULL ||
	    geo_metric_init(&m, &ix.geo, e) < 0 ||
	    tl_outdir_begin(&out, o->dir, e) < 0)
		goto done;
	w.tmp = out.tmp;
	/* the count after the levels, whose own faults say more */
	if (run_levels(&w, e) < 0 || levels_complete(&ix, e) < 0 ||
	    pyramid_index_write(out.tmp, &ix, e) < 0)
		goto done;
	r = tl_outdir_commit(&out, e);
	for (int l = 0; r == 0 && !o->quiet && l < o->nlevels; l++) {
		pyramid_level *pl = &ix.lev[l];
		fprintf(stderr, "%s: level %d: %dx%d vertices, %dx%d blocks, "
		    "%s, max E %.3f m, max base error %.3f m\n", prog, l,
		    pl->size[0], pl->size[1], pl->blocks[0], pl->blocks[1],
		    pl->displaced ? "3D" : "1D", w.st[l].max_e,
		    w.st[l].max_base);
	}
done:
	if (r < 0)
		tl_outdir_abort(&out);
	dem_close(d);
	geo_metric_free(&m);
	pyramid_index_free(&ix);
	free(w.st);
	return r;
}

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	options o = { 0 };
	tl_err e;
	int c, stdin_uses = 0;
	long ncpu = sysconf(_SC_NPROCESSORS_ONLN);

	o.jobs = ncpu > 0 ? (int)ncpu : 1;
	while ((c = getopt_long(argc, argv, DEM_OPTS "fhj:qV", longopts,
	    NULL)) != -1) {
		switch (c) {
		case 'j':
			if (tl_parse_int(optarg, &o.jobs) < 0 || o.jobs < 1) {
				tl_warn(prog, "-j %s: expected a number >= 1",
				    optarg);
				return 2;
			}
			break;
		case 'f':
			o.force = 1;
			break;
		case 'h':
			usage(stdout);
			return 0;
		case 'q':
			o.quiet = 1;
			break;
		case 'V':
			printf("%s %s\n", prog, TL_VERSION);
			return 0;
		default:
			switch (dem_option(&o.dem, c, optarg, &e)) {
			case 1:
				continue;
			case -1:
				tl_warn(prog, "%s", e.msg);
				return 2;
			}
			usage(stderr);
			return 2;
		}
	}
	argc -= optind, argv += optind;
	if (argc < 3) {
		usage(stderr);
		return 2;
	}
	o.dem_path = argv[0], o.dir = argv[1];
	o.levels = argv + 2, o.nlevels = argc - 2;
	for (int k = 0; k < argc; k++)
		stdin_uses += k != 1 && strcmp(argv[k], "-") == 0;
	if (stdin_uses > 1) {
		tl_warn(prog, "stdin can feed only one input");
		return 2;
	}
	if (pack(&o, &e) < 0) {
		tl_warn(prog, "%s", e.msg);
		return 1;
	}
	return 0;
}
