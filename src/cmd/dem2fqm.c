/* dem2fqm - a DEM in, its level-0 fundamental quadric map out: per vertex
 * the area-weighted plane quadrics of its triangles, in its own frame.
 * The work is stage_dem2fqm (stage.h). */
#include "cli.h"
#include "stage.h"

static const char usage[] =
    "[-I] [-D datum] [-e encoding] [-H datum] [-N nodata] [-n name]\n"
    "               [-s dx[,dy]] [-z compression] [--resample] "
    "[dem [out]]\n"
    "  -I              print the DEM's size, georeferencing, metric, datum "
    "and\n"
    "                  level count from its header; no output. -II also "
    "counts\n"
    "                  the voids, reading every sample\n"
    CLI_DEM_HELP
    "  -z compression  of an EXR output: zip (default), zips, rle, piz, none\n"
    "  dem             any raster GDAL reads, EXR, or a list of DEM files (a\n"
    "                  mosaic); - (stdin, default)\n"
    "  out             level-0 FQM: EXR file or - (stream, default)\n";

int
main(int argc, char **argv)
{
	stage_level0 o = { .in = "-", .out = "-" };
	cli c;
	tl_err e;
	int ch;

	cli_init(&c, argv, usage, CLI_COMPRESSION | CLI_DEM);
	while ((ch = cli_next(&c, argc, argv, "I", NULL)) != -1) {
		if (ch != 'I')
			return cli_usage_error(&c);
		o.info = o.info < 2 ? o.info + 1 : 2;
	}
	if (c.status >= 0)
		return c.status;
	argc -= optind, argv += optind;
	if (o.info) { /* one DEM in, no raster out */
		if (argc > 1)
			return cli_usage_error(&c);
		o.in = argc > 0 ? argv[0] : "-";
	} else if ((ch = cli_operands(&c, argc, argv, &o.in, &o.out)) != 0)
		return ch;
	return cli_exit(&c, stage_dem2fqm(&c, &o, &e), &e);
}
