/* stage_pack.c - what tilepack and the plans' piece jobs (vgis-job piece,
 * part, gather) share (stage.h): a piece's name, the output's guard. */
#include <stdio.h>

#include "stage.h"
#include "base/paths.h"

int
stage_piece_parse(const char *s, int p[5])
{
	char end;
	int n = sscanf(s, "%d:%d:%d:%d:%d%c", &p[0], &p[1], &p[2], &p[3],
	    &p[4], &end);

	if (n == 3)
		p[3] = p[4] = 0;
	else if (n != 5 || p[3] < 0 || p[4] <= p[3])
		return -1;
	return p[0] < 0 || p[1] < 0 || p[2] <= p[1] ? -1 : 0;
}

int
stage_pack_guard(const pack_args *a, const char *gather, tl_err *e)
{
	tl_paths s = { 0 };
	int r = dem_paths(&s, a->dem_path, e);

	for (int l = 0; r == 0 && l < a->nlevels; l++)
		r = tl_paths_add_raster(&s, a->levels[l], "vertex map", e);
	if (r == 0 && gather != NULL)
		r = tl_paths_add(&s, gather, TL_PATH_TREE, e,
		    "the input work directory %s", gather);
	if (r == 0)
		r = tl_paths_check(&s, a->dir, e);
	tl_paths_free(&s);
	return r;
}
