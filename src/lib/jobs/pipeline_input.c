/* pipeline_input.c - the DEM as the stages read it: a DEM on stdin
 * spooled, a mosaic's list of DEMs, and the reader's level count and size
 * (dem2fqm -I, after vgis-job guard). */
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "jobs/pipeline_impl.h"

/* A DEM on stdin is read twice (quadrics, then errors): a copy in
 * scratch, under the name -n gives, which GDAL may need (N44W072.hgt). */
int
pipeline_spool_stdin(const pipeline_opts *o, const scratch *s, char *path,
    size_t n, tl_err *e)
{
	char base[256], dir[PATHMAX];
	int fd;

	snprintf(base, sizeof base, "%s", o->name ? o->name : "stdin");
	snprintf(dir, sizeof dir, "%s/in", s->path);
	if (mkdir(dir, 0700) < 0)
		return tl_failsys(e, "%s", dir);
	if (snprintf(path, n, "%s/%s", dir, basename(base)) >= (int)n)
		return tl_fail(e, "%s: name too long", base);
	if ((fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC,
	    0600)) < 0)
		return tl_failsys(e, "%s", path);
	if (tl_copy_fd(0, "stdin", fd, 0, path, e) < 0) {
		close(fd);
		return -1;
	}
	return close(fd) < 0 ? tl_failsys(e, "%s", path) : 0;
}

/* A name the list could not give back as it is: entries lose the blanks
 * around them, and a line ends at a newline. */
static int
listable(const char *dem)
{
	size_t n = strlen(dem);

	return n > 0 && strchr(dem, '\n') == NULL &&
	    strchr(" \t\r\f\v", dem[n - 1]) == NULL;
}

/* Several DEMs: the list file the stages read as one mosaic, in dir
 * (scratch, or a plan), one absolute path a line (a relative entry would
 * be relative to the list's directory). Each is checked here first, so
 * that a missing one is named as the user gave it. */
int
pipeline_write_list(const pipeline_opts *o, const char *dir, char *path,
    size_t n, tl_err *e)
{
	char cwd[PATHMAX];
	FILE *f;
	int r = 0;

	if (getcwd(cwd, sizeof cwd) == NULL)
		return tl_failsys(e, "current directory");
	for (int k = 0; k < o->ndem; k++) {
		if (access(o->dems[k], F_OK) < 0)
			return tl_failsys(e, "%s", o->dems[k]);
		if (!listable(o->dems[k]))
			return tl_fail(e, "%s: a name holding a newline or "
			    "ending in a blank cannot go in a list of DEMs",
			    o->dems[k]);
	}
	if (snprintf(path, n, "%s/dems.txt", dir) >= (int)n)
		return tl_fail(e, "%s/dems.txt: name too long", dir);
	if ((f = fopen(path, "wx")) == NULL)
		return tl_failsys(e, "%s", path);
	for (int k = 0; k < o->ndem; k++) {
		const char *d = o->dems[k];
		fprintf(f, "%s%s%s\n", d[0] == '/' ? "" : cwd,
		    d[0] == '/' ? "" : "/", d);
	}
	if (ferror(f))
		r = tl_failsys(e, "%s", path);
	if (fclose(f) != 0 && r == 0)
		r = tl_failsys(e, "%s", path);
	return r;
}

/* The level count and the width from the reader itself ("dem2fqm -I");
 * its message is ours if it cannot read the DEM. */
int
pipeline_level_count(const pipeline_opts *o, const char *dem, int *levels,
    int *width, int *height, int *status, tl_err *e)
{
	char info[4096], *p;
	words a = { 0 };
	int in = -1, r;

	/* the reader keeps the outputs off the DEM's files (a list's
	 * entries, a VRT's sources), which it alone can tell */
	if (o->work != NULL && o->work->count != NULL &&
	    strcmp(o->dem, "-") != 0) {
		const char *outs[2] = { o->out, o->plan };
		if (o->work->count(o->work->ctx, dem, outs, o->plan ? 2 : 1,
		    levels, width, height, e) == 0)
			return 0;
		*status = 1;
		return -1;
	}
	say(&a, "vgis-job"), say(&a, "guard"), say(&a, "--"), say(&a, dem);
	say(&a, o->out);
	if (o->plan != NULL)
		say(&a, o->plan);
	if (pipeline_alone(o, &a, -1, 1, NULL, 0, status, e) < 0)
		return -1;
	a.n = 0;
	say(&a, "dem2fqm");
	say_demopts(&a, o);
	if (o->name != NULL && strcmp(o->dem, "-") != 0)
		say(&a, "-n"), say(&a, o->name);
	say(&a, "-I");
	if (strcmp(o->dem, "-") == 0 && o->name == NULL) {
		/* its messages say stdin, as the user gave it */
		say(&a, "-");
		if ((in = open(dem, O_RDONLY | O_CLOEXEC)) < 0)
			return tl_failsys(e, "%s: %s", o->prog, dem);
	} else
		say(&a, dem);
	r = pipeline_alone(o, &a, in, 1, info, sizeof info, status, e);
	if (in >= 0)
		close(in);
	if (r < 0)
		return -1;
	*levels = *width = *height = 0;
	for (p = info; p != NULL && *p; p = strchr(p, '\n'), p = p ? p + 1 : p)
		if (sscanf(p, "levels %d", levels) != 1)
			(void)sscanf(p, "size %d %d", width, height);
	if (*levels >= 1 && *levels <= MAXLEVELS && *width >= 1 &&
	    *height >= 1)
		return 0;
	*status = 1;
	return tl_fail(e, "%s: %s: dem2fqm -I gave no level count or size",
	    o->prog, dem);
}
