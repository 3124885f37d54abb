/* vgis2terrain - a VGIS pyramid as quantized-mesh-1.0 terrain for
 * CesiumJS, cesium-native and the other terrain readers: layer.json and
 * {z}/{x}/{y}.terrain on the global geographic quadtree. The work is
 * tr_run (terrain/terrain.h). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "terrain/terrain.h"

static const char usage[] =
    "[-qz] [-f qm|3dtiles] [-j jobs] [--parent-url URL] [--attribution "
    "TEXT] dir outdir\n"
    "  -f format           qm: quantized-mesh (default); 3dtiles: the 3D "
    "Tiles terrain profile\n"
    "  -j jobs             threads (default: the CPUs)\n"
    "  -q                  no warnings, no report on stderr\n"
    "  -z                  gzip the tiles (serve them with "
    "Content-Encoding: gzip)\n"
    "  --parent-url URL    layer.json's parentUrl: the terrain past the "
    "DEM\n"
    "  --attribution TEXT  layer.json's attribution\n"
    "  dir                 the pyramid (dem2vgis(1)), heights ellipsoidal\n"
    "  outdir              the terrain directory to make (or replace)\n";

static const struct option longopts[] = {
	{ "parent-url", required_argument, NULL, 'P' },
	{ "attribution", required_argument, NULL, 'A' },
	{ NULL, 0, NULL, 0 }
};

static void
report(const cli *c, const tr_report *r)
{
	for (int z = 0; z <= r->maxzoom; z++)
		fprintf(stderr, "%s: level %d: %lld tiles, %lld triangles, "
		    "%.1f KiB; pyramid level %d, tolerance %.3f m (try %d); "
		    "measured %.3f m; bound %.3f m = %.3f E_L\n", c->prog, z,
		    r->tiles[z], r->tris[z], r->bytes[z] / 1024.0, r->plevel[z],
		    r->tau[z], r->tries[z], r->direct[z], r->err[z],
		    r->err[z] / (TR_E0 / (1 << z)));
}

int
main(int argc, char **argv)
{
	tr_args a = { 0 };
	tr_report rep;
	tl_err e;
	cli c;
	int ch, r;

	cli_init(&c, argv, usage, 0);
	a.jobs = cli_jobs();
	while ((ch = cli_next(&c, argc, argv, "f:j:qz", longopts)) != -1) {
		switch (ch) {
		case 'j':
			a.jobs = (int)cli_number(&c, "-j", optarg, 1,
			    TR_MAXJOBS);
			break;
		case 'f':
			if (strcmp(optarg, "qm") && strcmp(optarg, "3dtiles"))
				return cli_usage_error(&c);
			a.format = strcmp(optarg, "3dtiles") == 0;
			break;
		case 'q':
			a.quiet = 1;
			break;
		case 'z':
			a.gzip = 1;
			break;
		case 'P':
			a.parent = optarg;
			break;
		case 'A':
			a.attrib = optarg;
			break;
		default:
			return cli_usage_error(&c);
		}
	}
	if (c.status >= 0)
		return c.status;
	if (argc - optind != 2 || (a.format && a.gzip))
		return cli_usage_error(&c); /* glbs are not gzipped */
	a.dir = argv[optind], a.out = argv[optind + 1], a.prog = c.prog;
	r = tr_run(&a, &rep, &e);
	if (r == 0 && !a.quiet)
		report(&c, &rep);
	return cli_exit(&c, r, &e);
}
