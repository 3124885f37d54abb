/* tilecheck - the brute-force checker of a VGIS pyramid (pyramid/verify.h):
 * its options into a vf_args, then vf_run, which prints the report. No GL.
 * Exit 0 pass, 1 violations, 2 usage, 3 cannot check (as cmp(1) has it). */
#include "cli.h"
#include "verify/qm.h"
#include "verify/t3c.h"

#include <stdio.h>
#include <unistd.h>
#include "verify/verify.h"

enum { CANNOT_CHECK = 3 };

static const char usage[] =
    "[--dem dem] [--tau t,...] [-D datum] [-e encoding] [-H datum]\n"
    "                 [-N nodata] [-n name] [-s dx[,dy]] dir\n"
    "       tilecheck --terrain [--dump] [--dem dem] [DEM options] outdir\n"
    "  dir             the pyramid: index, blocks, borders, saturation, "
    "triangulations\n"
    "                  at a sweep of tolerances\n"
    "  --dem dem       the DEM it was made from (a VRT or a list of DEM files\n"
    "                  for a mosaic): check its errors too\n"
    "  --tau t,...     tolerances in metres instead of each level's sweep\n"
    CLI_DEM_HELP
    "  --terrain       outdir is terrain: quantized-mesh (layer.json) or the\n"
    "                  3D Tiles terrain profile (tileset.json)\n"
    "  --dump          per tile: vertices, triangles, checksum\n"
    "exit status: 0 pass, 1 violations, 2 usage, 3 cannot check\n";

enum { OPT_DEM = 256, OPT_TAU, OPT_TERRAIN, OPT_DUMP };

int
main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "dem", required_argument, NULL, OPT_DEM },
		{ "tau", required_argument, NULL, OPT_TAU },
		{ "terrain", no_argument, NULL, OPT_TERRAIN },
		{ "dump", no_argument, NULL, OPT_DUMP },
		{ NULL, 0, NULL, 0 },
	};
	vf_args a = { 0 };
	qm_args q = { 0 };
	cli c;
	int ch, r;

	cli_init(&c, argv, usage, CLI_DEM);
	while ((ch = cli_next(&c, argc, argv, "", longopts)) != -1) {
		switch (ch) {
		case OPT_DEM:
			a.dem_path = optarg;
			break;
		case OPT_TAU:
			if (vf_parse_taus(&a, optarg) < 0)
				return cli_bad(&c, "--tau %s: expected up to "
				    "%d numbers >= 0, comma-separated", optarg,
				    VF_MAXTAU);
			break;
		case OPT_TERRAIN:
		case OPT_DUMP:
			q.dump |= ch == OPT_DUMP, q.dir = "";
			break;
		default:
			return cli_usage_error(&c);
		}
	}
	if (c.status >= 0)
		return c.status;
	if (optind != argc - 1)
		return cli_usage_error(&c);
	if (q.dir != NULL) { /* --terrain (tilecheck(1) TERRAIN) */
		char tj[4096];

		q.dir = argv[optind], q.dem_path = a.dem_path, q.dem = c.dem;
		/* the format is what outdir holds: layer.json, else
		 * tileset.json (the 3D Tiles profile) */
		snprintf(tj, sizeof tj, "%s/layer.json", q.dir);
		if (access(tj, F_OK) == 0 ||
		    (snprintf(tj, sizeof tj, "%s/tileset.json", q.dir),
		    access(tj, F_OK) < 0))
			r = qm_run(&q, c.prog);
		else
			r = t3c_run(&q, c.prog);
		return r < 0 ? CANNOT_CHECK : r;
	}
	a.dir = argv[optind];
	a.dem = c.dem;
	/* vf_run has said why it cannot check */
	r = vf_run(&a, c.prog);
	return r < 0 ? CANNOT_CHECK : r;
}
