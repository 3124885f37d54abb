/* tmpdir.h - a test program's scratch directory in $TMPDIR (or /tmp),
 * removed at the end when every test passed, kept for a look otherwise.
 * Include after tap.h. */
#ifndef T_TMPDIR_H
#define T_TMPDIR_H

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

/* dir: room for PATH_MAX - 64 bytes, "$TMPDIR/name.XXXXXX" made. */
static int
tmpdir_make(char *dir, size_t n, const char *name)
{
	snprintf(dir, n, "%s/%s.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", name);
	return mkdtemp(dir) != NULL ? 0 : -1;
}

/* dir/name, in one of 8 buffers used in turn: a call's result lives
 * through the next 7 calls. */
static inline const char *
tmpdir_join(const char *dir, const char *name)
{
	static char buf[8][PATH_MAX];
	static int k;

	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

static void
tmpdir_done(const char *dir)
{
	char cmd[PATH_MAX + 16];

	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (tap_failed != 0 || system(cmd) != 0)
		printf("# kept %s\n", dir);
}

#endif
