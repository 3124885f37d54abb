/* dem2rgb - a DEM as MapLibre / Mapbox raster-dem tiles (Terrarium or
 * Terrain-RGB, PNG or lossless WebP) on the Web Mercator quadtree, every
 * zoom's heights from the quadric chain: a z/x/y tree and tiles.json, or
 * one PMTiles archive (-o).
 * The work is rg_run (rgb/rgb.h); --plan writes it as a plan's jobs
 * instead (jobs/plan_rgb.h). */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "rgb_cli.h"
#include "jobs/plan_rgb.h"

static const char usage[] =
    "[-cq] [-e terrarium|mapbox] [-f png|webp] [-m method] [-t 512|256]\n"
    "    [-Z minzoom] [-z maxzoom] [-j jobs] [-u url] [-H datum] "
    "[-D datum]\n    [-N nodata] [--plan plandir [--part-tiles n | --parts n]] "
    "DEM OUT\n"
    "    or, with those options but -u: -o archive DEM\n"
    "  -e encoding   terrarium (default) or mapbox (Terrain-RGB)\n"
    "  -f format     png (default) or webp (lossless)\n"
    "  -m method     qem1d (default), average or subsample\n"
    "  -t size       tile size in pixels: 512 (default) or 256\n"
    "  -Z minzoom    the coarsest zoom (default 0)\n"
    "  -z maxzoom    the deepest zoom (default: the first whose pixel is\n"
    "                finer than the DEM's cell)\n"
    "  -c            the warp resamples cubic (default bilinear)\n"
    "  -j jobs       threads (default: the CPUs)\n"
    "  -q            no report on stderr\n"
    "  -u url        the tree's URL: tiles.json's tile URLs absolute\n"
    "                (TileJSON 3.0.0 asks for it; default relative)\n"
    "  -H datum      heights in this vertical datum (default: the DEM's;\n"
    "                ellipsoidal DEMs converted to EGM96, EPSG:5773)\n"
    "  -D datum      the DEM's vertical datum, when it declares none\n"
    "  -N nodata     the DEM's nodata value\n"
    "  --dump DIR    also the intended heights of each zoom, Z.tif and\n"
    "                Z.valid.tif (for tests)\n"
    "  --plan plandir  write the work as jobs for make, GNU parallel or\n"
    "                Slurm into plandir instead of doing it (dem2rgb(1),\n"
    "                PLANS); --part-tiles n: about n tiles of the deepest\n"
    "                zoom a job (default 256); --parts n: n jobs\n"
    "  DEM           any raster GDAL opens, in any CRS, or a list of DEM\n"
    "                files (dem2fqm(1), MOSAICS)\n"
    "  OUT           the tree to make (or replace): OUT/tiles.json,\n"
    "                OUT/{z}/{x}/{y}.png\n"
    "  -o archive    instead of a tree, one PMTiles v3 file (or replace\n"
    "                one) holding the tree's tiles, tiles.json's fields as\n"
    "                its metadata\n";

enum { OPT_DUMP = 'U', OPT_PLAN = 256, OPT_TILES, OPT_PARTS };
#define NWORDS 64

static const struct option longopts[] = {
	{ "dump", required_argument, NULL, OPT_DUMP },
	{ "plan", required_argument, NULL, OPT_PLAN },
	{ "part-tiles", required_argument, NULL, OPT_TILES },
	{ "parts", required_argument, NULL, OPT_PARTS },
	{ NULL, 0, NULL, 0 }
};

/* Option ch (and its value arg, or NULL: none) as the words every job
 * of a plan is given, appended to w (*n of them); 0, or the usage
 * error's status. */
static int
word(const cli *c, const char **w, int *n, int ch, const char *arg)
{
	static char opt[NWORDS][3];

	if (*n + 2 > NWORDS)
		return cli_bad(c, "over %d options", NWORDS / 2);
	snprintf(opt[*n], sizeof opt[0], "-%c", ch);
	w[*n] = opt[*n];
	*n += 1;
	if (arg != NULL)
		w[(*n)++] = arg;
	return 0;
}

/* The work of a written as a plan into dir: parts of about `tiles`
 * tiles of the deepest zoom (or `parts` of them, when not 0), every job
 * given the options' words w (n of them; jobs: -j, when given). */
static int
write_plan(const cli *c, const rg_args *a, const char *dir,
    long long tiles, int parts, const char *const *w, int n, int jobs,
    tl_err *e)
{
	plan_rgb_opts o = { .prog = c->prog, .dem = a->dem, .out = a->out,
		.archive = a->pmtiles, .opt = w, .nopt = n, .jobs = jobs };
	char self[PATH_MAX];

	if (rg_plan_parts(a, tiles, &o.nparts, e) < 0)
		return -1;
	if (parts > 0)
		o.nparts = parts;
	o.bindir = cli_bindir(self, sizeof self);
	return plan_rgb_write(&o, dir, e);
}

int
main(int argc, char **argv)
{
	rg_args a = { .dim = 512, .maxzoom = -1 };
	rg_report rep;
	const char *plan = NULL, *w[NWORDS];
	long long tiles = 256;
	tl_err e;
	cli c;
	int ch, r, quiet = 0, nw = 0, jobs = 0, parts = 0;

	cli_init(&c, argv, usage, 0);
#ifdef __GLIBC__
	/* blocks of 128 KiB and more (libwebp's, the warper's, a tile's
	 * image) mapped and unmapped each time, not kept resident by the
	 * threads' arenas at their high-water mark: dem2rgb(1) MEMORY */
	mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
	a.jobs = cli_jobs();
	if (a.jobs > RG_MAXJOBS)
		a.jobs = RG_MAXJOBS;
	while ((ch = cli_next(&c, argc, argv, RG_CLI_OPTS "qo:",
	    longopts)) != -1) {
		if (ch == 'q') {
			if (!quiet && (r = word(&c, w, &nw, ch, NULL)) != 0)
				return r;
			quiet = 1;
		} else if (ch == OPT_DUMP)
			a.dump = optarg;
		else if (ch == OPT_PLAN)
			plan = optarg;
		else if (ch == OPT_TILES)
			tiles = cli_number(&c, "--part-tiles", optarg, 1,
			    LLONG_MAX);
		else if (ch == OPT_PARTS)
			parts = (int)cli_number(&c, "--parts", optarg, 1,
			    RG_MAXPARTS);
		else if ((r = rg_cli_option(&c, &a, ch, optarg, &e)) != 0)
			return r;
		else if (ch == 'j')
			jobs = a.jobs;
		else if (ch != 'o' && (r = word(&c, w, &nw, ch,
		    ch == 'c' ? NULL : optarg)) != 0)
			return r;
	}
	if (c.status >= 0)
		return c.status;
	if (argc - optind != (a.pmtiles ? 1 : 2))
		return cli_usage_error(&c);
	if (a.pmtiles && a.url != NULL)
		return cli_bad(&c, "-u: no tile URLs in an archive (-o)");
	if (a.maxzoom >= 0 && a.minzoom > a.maxzoom)
		return cli_bad(&c, "-Z %d: above -z %d", a.minzoom, a.maxzoom);
	if (plan != NULL && a.dump != NULL)
		return cli_bad(&c, "--dump: not with --plan");
	a.dem = argv[optind], a.prog = c.prog;
	if (!a.pmtiles && cli_outdir(&c, argv[optind + 1]) != 0)
		return CLI_USAGE;
	if (!a.pmtiles)
		a.out = argv[optind + 1];
	if (plan != NULL)
		return cli_exit(&c, write_plan(&c, &a, plan, tiles, parts, w,
		    nw, jobs, &e), &e);
	r = rg_run(&a, &rep, &e);
	if (r == 0 && !quiet)
		rg_cli_report(&c, &rep);
	return cli_exit(&c, r, &e);
}
