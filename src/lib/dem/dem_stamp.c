/* dem_stamp.c - every file a DEM reads, recorded (stamp.h): the part
 * that needs GDAL (through its adapter's files), apart from stamp.c so
 * that checking a stamp does not link it. */
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dem/dem_impl.h"
#include "base/stamp.h"

#define DEPTH 8              /* VRTs of VRTs followed; GDAL refuses loops */
#define LIST_MAX (16 << 20)  /* as dem_list.c: a list's bytes at most */

typedef struct {
	char **v;
	int n, cap;
} names;

static int
add(names *l, const char *p, tl_err *e)
{
	if (l->n == l->cap) {
		int cap = l->cap ? 2 * l->cap : 16;
		char **v = realloc(l->v, (size_t)cap * sizeof *v);
		if (v == NULL)
			return tl_fail(e, "out of memory");
		l->v = v, l->cap = cap;
	}
	if ((l->v[l->n] = strdup(p)) == NULL)
		return tl_fail(e, "out of memory");
	l->n++;
	return 0;
}

static int files(names *l, const char *path, int depth, tl_err *e);

/* GDAL's files of the raster path: 0, or 1 when GDAL cannot open it. A
 * name that is no file here (/vsizip/...: the archive is path) is left
 * out; a VRT among them is followed. */
static int
gdal_files(names *l, const char *path, int depth, tl_err *e)
{
	char **f = NULL;
	int n = 0, r;

	if ((r = dem_gdal_adapter.files(path, &f, &n, e)) != 0)
		return r;
	for (int k = 0; k < n && r == 0; k++) {
		struct stat st;
		if (strcmp(f[k], path) == 0 || stat(f[k], &st) != 0 ||
		    !S_ISREG(st.st_mode))
			continue;
		if (depth < DEPTH && dem_gdal_is_vrt(f[k]))
			r = files(l, f[k], depth + 1, e);
		else
			r = add(l, f[k], e);
	}
	for (int k = 0; k < n; k++)
		free(f[k]);
	free(f);
	return r;
}

/* The text of a list of DEM files (dem_list.c), at most LIST_MAX bytes
 * and no NUL, or NULL (then it is no list). */
static char *
slurp(int fd)
{
	struct stat st;
	char *t = NULL;
	size_t n = 0;
	ssize_t r = 1;

	if (fstat(fd, &st) != 0 || (S_ISREG(st.st_mode) && (st.st_size < 1 ||
	    st.st_size > LIST_MAX)) || (t = malloc(LIST_MAX + 1)) == NULL)
		return NULL;
	while (n < LIST_MAX && (r = read(fd, t + n, LIST_MAX - n)) > 0)
		n += (size_t)r;
	t[n] = '\0';
	if (r < 0 || n == 0 || memchr(t, '\0', n) != NULL) {
		free(t);
		return NULL;
	}
	return t;
}

/* A list's entries' files, those that name a file (the reader has
 * refused the list otherwise), relative ones from dir. */
static int
entries(names *l, char *text, const char *dir, int depth, tl_err *e)
{
	char *line = strncmp(text, "\xef\xbb\xbf", 3) == 0 ? text + 3 : text;
	char *nl;
	int r = 0;

	for (; line != NULL && r == 0; line = nl) {
		struct stat st;
		char *ent, *p;
		if ((nl = strchr(line, '\n')) != NULL)
			*nl++ = '\0';
		if ((ent = tl_list_entry(line)) == NULL ||
		    (p = tl_list_path(dir, ent, e)) == NULL)
			continue;
		if (stat(p, &st) == 0 && S_ISREG(st.st_mode))
			r = files(l, p, depth + 1, e);
		free(p);
	}
	return r;
}

/* The file path as a list (no list: nothing). */
static int
list_files(names *l, const char *path, int depth, tl_err *e)
{
	char *text, *dir, *slash;
	int fd, r = 0;

	if ((fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK)) < 0)
		return 0;
	text = slurp(fd);
	close(fd);
	if (text == NULL || (dir = strdup(path)) == NULL) {
		free(text);
		return 0;
	}
	if ((slash = strrchr(dir, '/')) != NULL)
		slash[slash == dir] = '\0';
	r = entries(l, text, slash != NULL ? dir : ".", depth, e);
	free(dir);
	free(text);
	return r;
}

static int
files(names *l, const char *path, int depth, tl_err *e)
{
	int r;

	if (add(l, path, e) < 0)
		return -1;
	if ((r = gdal_files(l, path, depth, e)) <= 0 || depth >= DEPTH)
		return r < 0 ? -1 : 0;
	return list_files(l, path, depth, e);
}

int
dem_stamp(const char *path, char *const *dems, int n, tl_err *e)
{
	names l = { 0 };
	int r = 0;

	for (int k = 0; k < n && r == 0; k++) {
		char *text;
		if (strcmp(dems[k], "-") != 0)
			r = files(&l, dems[k], 0, e);
		else if ((text = slurp(0)) != NULL) { /* a list on stdin */
			r = entries(&l, text, ".", 0, e);
			free(text);
		}
	}
	if (r == 0)
		r = stamp_write(path, l.v, l.n, e);
	for (int k = 0; k < l.n; k++)
		free(l.v[k]);
	free(l.v);
	return r;
}
