/* fixture.h - what the play tests share: pyramids of the real DEMs made
 * by dem2vgis (the program of the build the test belongs
 * to) in a temporary directory, worlds opened on them, and a headless GL
 * context when the machine has one. Included by one test file each. */
#ifndef TL_PLAY_FIXTURE_H
#define TL_PLAY_FIXTURE_H

#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "play/gl_ctx.h"
#include "play/world.h"
#include "tap.h"

static char fx_tmp[256];

/* The build this test is in: argv[0] is BUILD/tests/play/t_x. */
static inline void
fx_build(const char *argv0, char *buf, size_t n)
{
	char path[PATH_MAX];
	char *s;

	if (realpath(argv0, path) == NULL)
		snprintf(path, sizeof path, "%s", argv0);
	for (int k = 0; k < 3 && (s = strrchr(path, '/')) != NULL; k++)
		*s = '\0';
	snprintf(buf, n, "%s", path);
}

/* The temporary directory; dem2vgis runs this build's programs
 * ($TL_BIN) and images are written with its plugin ($TL_OIIO_PLUGIN),
 * unless the environment says otherwise. */
static inline int
fx_init(const char *argv0, const char *name)
{
	char b[PATH_MAX], v[PATH_MAX + 16];

	fx_build(argv0, b, sizeof b);
	setenv("TL_BIN", b, 0);
	snprintf(v, sizeof v, "%s/tl_oiio.so", b);
	setenv("TL_OIIO_PLUGIN", v, 0);
	snprintf(fx_tmp, sizeof fx_tmp, "%s/%s.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", name);
	return mkdtemp(fx_tmp) != NULL ? 0 : -1;
}

static inline void
fx_done(void)
{
	char cmd[600];

	snprintf(cmd, sizeof cmd, "rm -rf '%s'", fx_tmp);
	if (system(cmd) != 0)
		printf("# could not remove %s\n", fx_tmp);
}

/* DEM file dem of $DATA (../shared/data) into a pyramid NAME in the
 * temporary directory, with dem2vgis options opts; 0 when made. */
static inline int
fx_make(const char *dem, const char *name, const char *opts)
{
	const char *data = getenv("DATA") ? getenv("DATA") : "../shared/data";
	char cmd[2048];

	snprintf(cmd, sizeof cmd, "sh -c '\"$0\" -q %s \"$1\" \"$2\"' "
	    "%s/dem2vgis %s/%s %s/%s", opts, getenv("TL_BIN"), data, dem,
	    fx_tmp, name);
	return system(cmd);
}

static inline void
fx_dir(const char *name, char *buf, size_t n)
{
	snprintf(buf, n, "%s/%s", fx_tmp, name);
}

/* The world of pyramid NAME; exits when it cannot be opened. */
static inline void
fx_world(world *w, const char *name)
{
	char dir[512];
	tl_err e;

	fx_dir(name, dir, sizeof dir);
	if (world_open(w, dir, &e) < 0) {
		printf("Bail out! %s\n", e.msg);
		exit(1);
	}
}

/* A headless context, or NULL after a TAP skip line saying why (no
 * EGL on this machine). */
static inline gl_ctx *
fx_headless(int w, int h)
{
	gl_ctx *g;
	tl_err e;

	if ((g = gl_ctx_headless(w, h, &e)) == NULL)
		ok(1, "# SKIP %s", e.msg);
	return g;
}

/* File descriptor fd (1, 2) into path until fx_restore; returns the
 * saved descriptor. */
static inline int
fx_redirect(int fd, const char *path)
{
	int saved, f;

	fflush(NULL);
	saved = dup(fd);
	if ((f = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644)) >= 0) {
		dup2(f, fd);
		close(f);
	}
	return saved;
}

static inline void
fx_restore(int fd, int saved)
{
	fflush(NULL);
	dup2(saved, fd);
	close(saved);
}

/* The first line of path starting with prefix, into buf; 0 when found. */
static inline int
fx_grep(const char *path, const char *prefix, char *buf, size_t n)
{
	FILE *f = fopen(path, "r");
	int found = -1;

	if (f == NULL)
		return -1;
	while (found < 0 && fgets(buf, (int)n, f) != NULL)
		if (strncmp(buf, prefix, strlen(prefix)) == 0)
			found = 0;
	fclose(f);
	return found;
}

#endif
