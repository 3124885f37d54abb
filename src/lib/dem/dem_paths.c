/* dem_paths.c - the files a DEM is read from, for the outputs to keep off
 * them (dem.h, paths.h): the DEM, a list's entries, and what GDAL says
 * the DEM reads (the GDAL adapter's files: a VRT's sources, a world
 * file), VRTs within VRTs and VRT entries of a list followed. */
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dem/dem_impl.h"
#include "base/paths.h"

#define VRT_DEPTH 8 /* VRTs of VRTs followed this deep */

/* 1 when path is a regular file whose text opens as a VRT: GDAL lists a
 * VRT's sources, not theirs. */
static int
is_vrt(const char *path)
{
	char b[64];
	struct stat st;
	ssize_t n = -1;
	int fd;

	if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) ||
	    (fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0)
		return 0;
	n = pread(fd, b, sizeof b - 1, 0);
	close(fd);
	if (n <= 0)
		return 0;
	b[n] = '\0';
	return strstr(b, "<VRTDataset") != NULL;
}

/* Frees the n files of an adapter's files method. */
static void
files_free(char **v, int n)
{
	for (int k = 0; k < n; k++)
		free(v[k]);
	free(v);
}

/* The files GDAL reads for path (a regular file: nothing else is opened,
 * a FIFO would block), as parts of the DEM top. */
static int
gdal_files(tl_paths *s, const char *path, const char *top, int depth,
    tl_err *e)
{
	struct stat st;
	char **list = NULL;
	int n = 0, r;

	if (depth > VRT_DEPTH || stat(path, &st) != 0 || !S_ISREG(st.st_mode))
		return 0;
	if ((r = dem_gdal_adapter.files(path, &list, &n, e)) != 0)
		return r;
	for (int k = 0; r == 0 && k < n; k++) {
		/* "/vsizip/..." and the like: within a file listed already */
		if (strncmp(list[k], "/vsi", 4) == 0 ||
		    strcmp(list[k], path) == 0)
			continue;
		r = tl_paths_add(s, list[k], 0, e, "%s, a file of the input "
		    "DEM %s", list[k], top);
		if (r == 0 && is_vrt(list[k]))
			r = gdal_files(s, list[k], top, depth + 1, e) < 0 ? -1 : 0;
	}
	files_free(list, n);
	return r;
}

int
dem_paths(tl_paths *s, const char *path, tl_err *e)
{
	char **ent = NULL;
	int n = 0, r;

	if (strcmp(path, "-") == 0)
		return 0;
	if (tl_paths_add(s, path, 0, e, "the input DEM %s", path) < 0 ||
	    (r = gdal_files(s, path, path, 0, e)) < 0)
		return -1;
	if (r == 0 || (r = dem_list_adapter.files(path, &ent, &n, e)) != 0)
		return r < 0 ? -1 : 0;
	for (int k = 0; k < n; k++) {
		if (r == 0)
			r = tl_paths_add(s, ent[k], 0, e, "%s, an entry of the "
			    "input DEM list %s", ent[k], path);
		/* a VRT's sources; other tiles' sidecars are not worth
		 * opening every tile again (the reader does already) */
		if (r == 0 && is_vrt(ent[k]))
			r = gdal_files(s, ent[k], path, 1, e) < 0 ? -1 : 0;
		free(ent[k]);
	}
	free(ent);
	return r;
}
