/* scratch.c - per-run scratch directories and the sweep of dead runs'
 * (scratch.h). */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "base/rmtree.h"
#include "base/scratch.h"
#include "base/sweep.h"

/* PREFIX.XXXXXX exactly (mkdtemp's six characters): a run's directory,
 * taken when its run is dead (sweep.h). */
static int
scratch_rule(const char *name, void *arg)
{
	const char *prefix = arg;
	size_t n = strlen(prefix);

	if (strncmp(name, prefix, n) != 0 || name[n] != '.' ||
	    strlen(name + n + 1) != 6)
		return 0;
	return TL_SWEEP_DIR;
}

int
scratch_sweep(const char *prefix)
{
	return tl_sweep(open(tl_tmpdir(), O_RDONLY | O_DIRECTORY |
	    O_CLOEXEC), "lock", scratch_rule, (void *)prefix);
}

/* The lock file in the new directory s->path, locked (tl_sweep_hold:
 * a run starting beside us may sweep it between its creation and our
 * lock): 0, 1 when swept meanwhile, -1 with errno. */
static int
lock_new(scratch *s)
{
	char lock[4200];

	snprintf(lock, sizeof lock, "%s/lock", s->path);
	if ((s->lock = open(lock, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC,
	    0600)) < 0)
		return -1;
	return tl_sweep_hold(s->lock);
}

int
scratch_begin(scratch *s, const char *prefix, tl_err *e)
{
	int r;

	s->lock = -1;
	scratch_sweep(prefix);
	for (int tries = 0;; tries++) {
		if (snprintf(s->path, sizeof s->path, "%s/%s.XXXXXX",
		    tl_tmpdir(), prefix) >= (int)sizeof s->path - 8)
			return tl_fail(e, "TMPDIR: path too long");
		if (mkdtemp(s->path) == NULL)
			return tl_failsys(e, "%s", s->path);
		if ((r = lock_new(s)) == 0)
			return 0;
		if (r < 0 || tries == 8) {
			tl_failsys(e, "%s/lock", s->path);
			scratch_end(s);
			return -1;
		}
		close(s->lock); /* swept before we held it: a new one */
		s->lock = -1;
	}
}

void
scratch_end(scratch *s)
{
	/* the lock first: one more descriptor for the removal */
	if (s->lock >= 0)
		close(s->lock);
	s->lock = -1;
	if (s->path[0] != '\0')
		tl_rmtree(s->path);
	s->path[0] = '\0';
}
