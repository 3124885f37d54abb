/* dem_opts.c - the DEM options every program reading a DEM takes (dem.h:
 * -e -N -n -s -H -D --resample): their values. Their names, usage lines
 * and the argv words a stage is given are cli.c's table, which calls
 * dem_option. Apart from the DEM reader on purpose: cli.c calls
 * dem_option for every program, so this file must not reference GDAL,
 * PROJ or the reader, or every program would link them. */
#include <stdio.h>
#include <string.h>

#include "dem/dem.h"

static int
parse_cell(const char *s, double cell[2])
{
	char buf[64], *comma;

	if (strlen(s) >= sizeof buf)
		return -1;
	strcpy(buf, s);
	if ((comma = strchr(buf, ',')) != NULL)
		*comma++ = '\0';
	if (tl_parse_double(buf, &cell[0]) < 0 || cell[0] <= 0)
		return -1;
	cell[1] = cell[0];
	if (comma != NULL && (tl_parse_double(comma, &cell[1]) < 0 ||
	    cell[1] <= 0))
		return -1;
	return 0;
}

static int
encoding_option(dem_opts *o, const char *arg, tl_err *e)
{
	static const struct {
		const char *name;
		enum dem_encoding enc;
	} encs[] = {
		{ "auto", DEM_ENC_AUTO }, { "grey", DEM_ENC_GREY },
		{ "gray", DEM_ENC_GREY }, { "terrainrgb", DEM_ENC_TERRAINRGB },
		{ "terrarium", DEM_ENC_TERRARIUM },
	};

	for (size_t k = 0; k < sizeof encs / sizeof encs[0]; k++)
		if (strcmp(arg, encs[k].name) == 0) {
			o->encoding = encs[k].enc;
			return 1;
		}
	return tl_fail(e, "-e %s: unknown encoding (auto, grey, terrainrgb, "
	    "terrarium)", arg);
}

int
dem_option(dem_opts *o, int c, const char *arg, tl_err *e)
{
	switch (c) {
	case 'e':
		return encoding_option(o, arg, e);
	case 'N':
		if (tl_parse_double(arg, &o->nodata) < 0)
			return tl_fail(e, "-N %s: not a number", arg);
		o->has_nodata = 1;
		return 1;
	case 'n':
		o->hgt_name = arg;
		return 1;
	case 's':
		if (parse_cell(arg, o->cell) < 0)
			return tl_fail(e, "-s %s: expected dx or dx,dy in "
			    "metres, > 0", arg);
		return 1;
	case 'H':
		if (*arg == '\0')
			return tl_fail(e, "-H: empty datum");
		o->heights = arg;
		return 1;
	case 'D':
		if (*arg == '\0')
			return tl_fail(e, "-D: empty datum");
		o->vdatum = arg;
		return 1;
	case DEM_RESAMPLE:
		o->resample = 1;
		return 1;
	}
	return 0;
}
