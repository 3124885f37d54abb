/* tmpdir.h - a test program's scratch directory in $TMPDIR (or /tmp),
 * removed at the end when every test passed, kept for a look otherwise.
 * Include after tap.h. */
#ifndef T_TMPDIR_H
#define T_TMPDIR_H

#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* dir: room for PATH_MAX - 64 bytes, "$TMPDIR/name.XXXXXX" made. */
static inline int
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

/* Entries of directory d whose name starts with prefix (a temporary:
 * ".NAME."), or, prefix "", every one but . and ..; -1 when d cannot be
 * read. */
static inline int
tmpdir_entries(const char *d, const char *prefix)
{
	DIR *D = opendir(d);
	struct dirent *de;
	int n = 0;

	if (D == NULL)
		return -1;
	while ((de = readdir(D)) != NULL)
		n += prefix[0] != '\0' ? strncmp(de->d_name, prefix,
		    strlen(prefix)) == 0 : strcmp(de->d_name, ".") != 0 &&
		    strcmp(de->d_name, "..") != 0;
	closedir(D);
	return n;
}

static inline void
tmpdir_done(const char *dir)
{
	char cmd[PATH_MAX + 16];

	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (tap_failed != 0 || system(cmd) != 0)
		printf("# kept %s\n", dir);
}

#endif
