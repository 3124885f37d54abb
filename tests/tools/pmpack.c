/* pmpack - a test tool: packs a z/x/y tree of tile files into one
 * PMTiles archive through the writer of rgb/pmtiles.h, in the order the
 * paths come on stdin ("Z/X/Y.ext" relative to TREE, one a line), so
 * that the tests can give the same tiles in different orders.
 *
 * usage: pmpack [-t png|jpg|webp] [-z min,max] [-b w,s,e,n]
 *               [-c lon,lat,zoom] [-m metadata.json] TREE OUT.pmtiles
 * Zooms default to those of the tiles, bounds to the Web Mercator world,
 * the centre to 0, 0 at the minimum zoom, the metadata to {}. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rgb/pmtiles.h"

static const char *prog = "pmpack";

/* The whole file: malloc'd, *n bytes, or NULL. */
static char *
slurp(const char *path, size_t *n)
{
	FILE *f = fopen(path, "rb");
	char *b = NULL;
	size_t cap = 0, k;

	*n = 0;
	if (f == NULL)
		return NULL;
	for (;;) {
		if (*n + 65536 + 1 > cap) {
			char *p = realloc(b, cap = 2 * cap + 65536 + 1);
			if (p == NULL)
				break;
			b = p;
		}
		if ((k = fread(b + *n, 1, cap - *n - 1, f)) == 0)
			break;
		*n += k;
	}
	if (ferror(f) || b == NULL) {
		free(b);
		b = NULL;
	} else
		b[*n] = '\0';
	fclose(f);
	return b;
}

static int
usage(void)
{
	fprintf(stderr, "usage: %s [-t png|jpg|webp] [-z min,max] "
	    "[-b w,s,e,n] [-c lon,lat,zoom] [-m metadata.json] TREE "
	    "OUT.pmtiles < paths\n", prog);
	return 2;
}

/* Every path of stdin added: 0, or 1 (reported). zooms: their range. */
static int
add_all(pm_writer *w, const char *tree, int zr[2])
{
	char *line = NULL, path[4096];
	size_t cap = 0, n;
	ssize_t len;
	tl_err e;
	int r = 0;

	zr[0] = 99, zr[1] = -1;
	while (r == 0 && (len = getline(&line, &cap, stdin)) > 0) {
		unsigned x, y;
		int z;
		char *b;

		if (line[len - 1] == '\n')
			line[len - 1] = '\0';
		if (sscanf(line, "%d/%u/%u.", &z, &x, &y) != 3) {
			fprintf(stderr, "%s: %s: not Z/X/Y.ext\n", prog, line);
			r = 1;
			break;
		}
		snprintf(path, sizeof path, "%s/%s", tree, line);
		if ((b = slurp(path, &n)) == NULL) {
			fprintf(stderr, "%s: %s: cannot read\n", prog, path);
			r = 1;
		} else if (pm_add(w, z, x, y, b, n, &e) < 0) {
			fprintf(stderr, "%s: %s\n", prog, e.msg);
			r = 1;
		}
		free(b);
		zr[0] = z < zr[0] ? z : zr[0], zr[1] = z > zr[1] ? z : zr[1];
	}
	free(line);
	return r;
}

int
main(int argc, char **argv)
{
	pm_meta m = { PM_PNG, -1, -1, { -180, -85.0511287798, 180,
	    85.0511287798 }, { 0, 0 }, -1, "{}" };
	const char *mfile = NULL;
	char *json = NULL;
	pm_writer *w;
	size_t n;
	tl_err e;
	int c, zr[2];

	while ((c = getopt(argc, argv, "t:z:b:c:m:")) != -1) {
		switch (c) {
		case 't':
			m.type = strcmp(optarg, "webp") == 0 ? PM_WEBP :
			    strcmp(optarg, "jpg") == 0 ? PM_JPEG : PM_PNG;
			break;
		case 'z':
			if (sscanf(optarg, "%d,%d", &m.minzoom, &m.maxzoom) != 2)
				return usage();
			break;
		case 'b':
			if (sscanf(optarg, "%lf,%lf,%lf,%lf", &m.bounds[0],
			    &m.bounds[1], &m.bounds[2], &m.bounds[3]) != 4)
				return usage();
			break;
		case 'c':
			if (sscanf(optarg, "%lf,%lf,%d", &m.center[0],
			    &m.center[1], &m.center_zoom) != 3)
				return usage();
			break;
		case 'm':
			mfile = optarg;
			break;
		default:
			return usage();
		}
	}
	if (argc - optind != 2)
		return usage();
	if (mfile != NULL && (m.json = json = slurp(mfile, &n)) == NULL) {
		fprintf(stderr, "%s: %s: cannot read\n", prog, mfile);
		return 1;
	}
	if ((w = pm_open(argv[optind + 1], &e)) == NULL) {
		fprintf(stderr, "%s: %s\n", prog, e.msg);
		return 1;
	}
	if (add_all(w, argv[optind], zr) != 0) {
		pm_abort(w);
		return 1;
	}
	if (zr[1] < 0) /* no tile: pm_close says so */
		zr[0] = zr[1] = 0;
	if (m.minzoom < 0)
		m.minzoom = zr[0], m.maxzoom = zr[1];
	if (m.center_zoom < 0)
		m.center_zoom = m.minzoom;
	if (pm_close(w, &m, &e) < 0) {
		fprintf(stderr, "%s: %s\n", prog, e.msg);
		return 1;
	}
	free(json);
	return 0;
}
