/* indextext.h - index.json as text for the tests of its two readers
 * (pyramid_index.c, verify_index.c): a good two-level index of a 200x150
 * DEM (itext_good), and that index with one edit (itext_edit). */
#ifndef T_INDEXTEXT_H
#define T_INDEXTEXT_H

#include <limits.h>
#include <stdio.h>
#include <string.h>

/* DIR/index.json with text. */
static int
itext_write(const char *dir, const char *text)
{
	char p[PATH_MAX];
	FILE *f;

	snprintf(p, sizeof p, "%s/index.json", dir);
	if ((f = fopen(p, "w")) == NULL)
		return -1;
	fputs(text, f);
	return fclose(f);
}

static const char itext_good[] =
    "{\"format\": \"terrain-lod vgis\", \"version\": 1, \"block\": 129, "
    "\"size0\": [200, 150], \"georef\": {\"model\": \"none\", "
    "\"epsg\": 0, \"crs\": \"\", \"raster\": \"point\", "
    "\"origin\": [0, 0], \"step\": [1, -1], \"unit\": 1}, "
    "\"levels\": [LEVEL0, LEVEL1]}";
static const char itext_level0[] =
    "{\"level\": 0, \"size\": [200, 150], \"blocks\": [2, 2], "
    "\"displaced\": false, \"mode\": \"qem1d\", \"kernel\": \"none\", "
    "\"zmin\": [0, 0, 0, 0], \"zmax\": [1, 1, 1, 1], "
    "\"base_error\": [0, 0, 0, 0], \"max_error\": [1, 1, 1, 1]}";
static const char itext_level1[] =
    "{\"level\": 1, \"size\": [101, 76], \"blocks\": [1, 1], "
    "\"displaced\": false, \"mode\": \"qem1d\", \"kernel\": \"binomial\", "
    "\"zmin\": [0], \"zmax\": [1], \"base_error\": [0], "
    "\"max_error\": [1]}";

/* The good index with `what` replaced by `with` once (LEVEL0, LEVEL1
 * expanded first); unedited when what is NULL or absent. */
static void
itext_edit(char *buf, size_t n, const char *what, const char *with)
{
	char a[4096], b[4096];
	const char *p;

	snprintf(a, sizeof a, "%s", itext_good);
	p = strstr(a, "LEVEL0");
	snprintf(b, sizeof b, "%.*s%s%s", (int)(p - a), a, itext_level0,
	    p + 6);
	p = strstr(b, "LEVEL1");
	snprintf(a, sizeof a, "%.*s%s%s", (int)(p - b), b, itext_level1,
	    p + 6);
	p = what != NULL ? strstr(a, what) : NULL;
	if (p == NULL)
		snprintf(buf, n, "%s", a);
	else
		snprintf(buf, n, "%.*s%s%s", (int)(p - a), a, with,
		    p + strlen(what));
}

#endif
