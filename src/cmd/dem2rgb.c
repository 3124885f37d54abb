/* dem2rgb - a DEM as MapLibre / Mapbox raster-dem tiles (Terrarium or
 * Terrain-RGB, PNG or lossless WebP) on the Web Mercator quadtree, every
 * zoom's heights from the quadric chain: a z/x/y tree and tiles.json, or
 * one PMTiles archive (-o).
 * The work is rg_run (rgb/rgb.h). */
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "cli.h"
#include "rgb/rgb.h"

static const char usage[] =
    "[-cq] [-e terrarium|mapbox] [-f png|webp] [-m method] [-t 512|256]\n"
    "    [-Z minzoom] [-z maxzoom] [-j jobs] [-u url] [-H datum] "
    "[-D datum]\n    [-N nodata] DEM OUT\n"
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
    "  DEM           any raster GDAL opens, in any CRS\n"
    "  OUT           the tree to make (or replace): OUT/tiles.json,\n"
    "                OUT/{z}/{x}/{y}.png\n"
    "  -o archive    instead of a tree, one PMTiles v3 file (or replace\n"
    "                one) holding the tree's tiles, tiles.json's fields as\n"
    "                its metadata\n";

static const struct option longopts[] = {
	{ "dump", required_argument, NULL, 'U' },
	{ NULL, 0, NULL, 0 }
};

static int
method(const char *s, enum solve_mode *m)
{
	if (strcmp(s, "qem1d") == 0)
		*m = SOLVE_QEM1D;
	else if (strcmp(s, "average") == 0)
		*m = SOLVE_FILTERED;
	else if (strcmp(s, "subsample") == 0)
		*m = SOLVE_SUBSAMPLE;
	else
		return -1;
	return 0;
}

static void
report(const cli *c, const rg_report *r)
{
	for (int z = r->minzoom; z <= r->maxzoom; z++)
		fprintf(stderr, "%s: zoom %d: %lld tiles, %.1f KiB; error "
		    "max %.3f m, rms %.3f m over %lld samples\n", c->prog, z,
		    r->tiles[z], r->bytes[z] / 1024.0, r->max[z], r->rms[z],
		    r->n[z]);
}

static int
option(cli *c, rg_args *a, int ch, const char *arg, tl_err *e)
{
	switch (ch) {
	case 'e':
		if (strcmp(arg, "terrarium") && strcmp(arg, "mapbox"))
			return cli_bad(c, "-e %s: not terrarium or mapbox", arg);
		a->enc = strcmp(arg, "mapbox") == 0 ? RG_MAPBOX : RG_TERRARIUM;
		break;
	case 'f':
		if (strcmp(arg, "png") && strcmp(arg, "webp"))
			return cli_bad(c, "-f %s: not png or webp", arg);
		a->fmt = strcmp(arg, "webp") == 0 ? RG_WEBP : RG_PNG;
		break;
	case 'm':
		if (method(arg, &a->mode) < 0)
			return cli_bad(c, "-m %s: not qem1d, average or "
			    "subsample", arg);
		break;
	case 't':
		if (strcmp(arg, "512") && strcmp(arg, "256"))
			return cli_bad(c, "-t %s: not 512 or 256", arg);
		a->dim = atoi(arg);
		break;
	case 'Z':
		a->minzoom = (int)cli_number(c, "-Z", arg, 0, RG_MAXZOOM);
		break;
	case 'z':
		a->maxzoom = (int)cli_number(c, "-z", arg, 0, RG_MAXZOOM);
		break;
	case 'j':
		a->jobs = (int)cli_number(c, "-j", arg, 1, RG_MAXJOBS);
		break;
	case 'c':
		a->cubic = 1;
		break;
	case 'U':
		a->dump = arg;
		break;
	case 'u':
		a->url = arg;
		break;
	case 'o':
		a->out = arg, a->pmtiles = 1;
		break;
	case 'H': case 'D': case 'N':
		if (dem_option(&a->dopt, ch, arg, e) < 0)
			return cli_bad(c, "%s", e->msg);
		break;
	default:
		return cli_usage_error(c);
	}
	return c->status >= 0 ? c->status : 0;
}

int
main(int argc, char **argv)
{
	rg_args a = { .dim = 512, .maxzoom = -1 };
	rg_report rep;
	tl_err e;
	cli c;
	int ch, r, quiet = 0;

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
	while ((ch = cli_next(&c, argc, argv, "ce:f:m:t:Z:z:j:qu:o:H:D:N:",
	    longopts)) != -1) {
		if (ch == 'q')
			quiet = 1;
		else if ((r = option(&c, &a, ch, optarg, &e)) != 0)
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
	a.dem = argv[optind], a.prog = c.prog;
	if (!a.pmtiles)
		a.out = argv[optind + 1];
	r = rg_run(&a, &rep, &e);
	if (r == 0 && !quiet)
		report(&c, &rep);
	return cli_exit(&c, r, &e);
}
