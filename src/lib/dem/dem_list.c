/* dem_list.c - a list of DEM files as a DEM (dem2fqm(1), MOSAICS): one
 * path a line, blank lines and lines whose first non-blank character is
 * '#' skipped, blanks around a path dropped, a relative path relative to
 * the list's directory. The tiles are then one mosaic (dem_mosaic.c).
 *
 * A file that GDAL did not open is a list when it is a regular file of
 * at most LIST_MAX bytes, without a NUL byte, and one of its entries at
 * least names an existing file; every entry must then. So a text file
 * that is no list still says "not a raster", and a list with a bad line
 * says which. An entry that is not a regular file (a FIFO, on which GDAL
 * would wait for ever) is refused at once; /vsi paths are GDAL's. The
 * same entries, so checked, are dem2rgb(1)'s (dem_list_paths). */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dem/dem_impl.h"

#define LIST_MAX (16 << 20) /* bytes: names, not samples, held at once */

typedef struct {
	char *text;       /* the file, lines cut in place */
	char **paths;     /* the entries, resolved */
	int n, found;     /* entries, and those naming an existing file */
	int bad_line, bad_errno; /* the first that does not, or 0 */
	const char *bad_why;     /* its reason when not errno's */
	char *bad;
} entries;

/* The whole file, or NULL (no error: then it is no list) when it cannot
 * be one: not a regular file, too long, empty, binary. */
static char *
slurp(const char *path)
{
	struct stat st;
	char *t = NULL;
	ssize_t r = 0;
	size_t n = 0;
	int fd;

	if ((fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0)
		return NULL;
	if (fstat(fd, &st) < 0 || !S_ISREG(st.st_mode) || st.st_size < 1 ||
	    st.st_size > LIST_MAX || (t = malloc((size_t)st.st_size + 1)) ==
	    NULL) {
		close(fd);
		return NULL;
	}
	while (n < (size_t)st.st_size && ((r = read(fd, t + n,
	    (size_t)st.st_size - n)) > 0 || (r < 0 && errno == EINTR)))
		n += r > 0 ? (size_t)r : 0;
	close(fd);
	t[n] = '\0';
	if (r < 0 || n == 0 || memchr(t, '\0', n) != NULL) {
		free(t);
		return NULL;
	}
	return t;
}

/* One line: its entry resolved, and whether it names a file. */
static int
add(entries *l, const char *base, char *line, int lineno, tl_err *e)
{
	struct stat st;
	char *ent = tl_list_entry(line), *p, **np;
	int there;

	if (ent == NULL)
		return 0;
	if ((p = tl_list_path(base, ent, e)) == NULL)
		return -1;
	if ((np = realloc(l->paths, (size_t)(l->n + 1) * sizeof *np)) == NULL) {
		free(p);
		return tl_fail(e, "out of memory");
	}
	l->paths = np;
	l->paths[l->n++] = p;
	/* GDAL's virtual file systems (/vsizip/...): GDAL's to open */
	if (strncmp(p, "/vsi", 4) == 0)
		return 0;
	if ((there = stat(p, &st) == 0))
		l->found++;
	if (l->bad_line > 0)
		return 0;
	if (!there)
		l->bad_line = lineno, l->bad_errno = errno, l->bad = p;
	/* GDAL would wait on a FIFO for ever */
	else if (!S_ISREG(st.st_mode))
		l->bad_line = lineno, l->bad = p, l->bad_why =
		    S_ISDIR(st.st_mode) ? "a directory, not a DEM file" :
		    S_ISFIFO(st.st_mode) ? "a FIFO, not a regular file: list "
		    "DEM files only" : "a device or socket, not a regular file: "
		    "list DEM files only";
	return 0;
}

static int
parse(entries *l, const char *base, tl_err *e)
{
	char *line = l->text, *nl;
	int lineno = 1;

	/* a UTF-8 byte order mark (Windows editors write one) is no path */
	if (strncmp(line, "\xef\xbb\xbf", 3) == 0)
		line += 3;

	for (; line != NULL; line = nl, lineno++) {
		if ((nl = strchr(line, '\n')) != NULL)
			*nl++ = '\0';
		if (add(l, base, line, lineno, e) < 0)
			return -1;
	}
	return 0;
}

static void
entries_free(entries *l)
{
	for (int k = 0; k < l->n; k++)
		free(l->paths[k]);
	free(l->paths);
	free(l->text);
}

/* The list's directory: what its relative entries are relative to. */
static char *
list_dir(const char *path, tl_err *e)
{
	const char *slash = strrchr(path, '/');
	size_t n;
	char *d;

	if (slash == NULL)
		path = ".", n = 1;
	else
		n = slash == path ? 1 : (size_t)(slash - path);
	if ((d = tl_alloc(n + 1, 1, e)) != NULL)
		memcpy(d, path, n);
	return d;
}

/* The first entry that names no regular file, refused: what names the
 * list. */
static int
bad_entry(const entries *l, const char *what, tl_err *e)
{
	char name[DEM_NAME];

	dem_name(l->bad, name);
	errno = l->bad_errno;
	return l->bad_why != NULL ? tl_fail(e, "%s: line %d: %s: %s", what,
	    l->bad_line, name, l->bad_why) :
	    tl_failsys(e, "%s: line %d: %s", what, l->bad_line, name);
}

/* dem_adapter's read: path as a list of DEM files (dem2fqm(1) says what
 * is one), read as their mosaic; 1 when it is no list. */
static int
read_list(dem_load *L, georef *g, const char *path, const char *base,
    enum dem_input in, const dem_opts *o, tl_err *e)
{
	entries l = { 0 };
	char *dir = NULL;
	int r = -1;

	(void)in;
	if ((l.text = slurp(path)) == NULL)
		return 1;
	if (base == NULL && (base = dir = list_dir(path, e)) == NULL)
		goto out;
	if (parse(&l, base, e) < 0)
		goto out;
	if (l.found == 0) /* text, but no list */
		r = 1;
	else if (l.bad_line > 0)
		r = bad_entry(&l, L->what, e);
	else
		r = dem_read_mosaic(L, g, l.paths, l.n, o, e);
out:
	entries_free(&l);
	free(dir);
	return r;
}

/* The list's entries, resolved as read_list resolves them (strict: a
 * bad entry refused as read_list refuses it); 1 when it is no list. */
static int
entries_of(const char *path, char ***paths, int *n, int strict, tl_err *e)
{
	char what[DEM_NAME];
	entries l = { 0 };
	char *dir = NULL;
	int r = 1;

	if ((l.text = slurp(path)) == NULL)
		return 1;
	if ((dir = list_dir(path, e)) == NULL || parse(&l, dir, e) < 0)
		r = -1;
	else if (l.found > 0 && strict && l.bad_line > 0)
		r = bad_entry(&l, dem_name(path, what), e);
	else if (l.found > 0) {
		*paths = l.paths, *n = l.n, r = 0;
		l.paths = NULL, l.n = 0;
	}
	entries_free(&l);
	free(dir);
	return r;
}

/* dem_adapter's files: every entry, even one that names no file. */
static int
list_files(const char *path, char ***paths, int *n, tl_err *e)
{
	return entries_of(path, paths, n, 0, e);
}

int
dem_list_paths(const char *path, char ***paths, int *n, tl_err *e)
{
	return entries_of(path, paths, n, 1, e);
}

const dem_adapter dem_list_adapter = {
	"list of DEM files", 1u << DEM_IN_NONE, read_list, list_files,
};
