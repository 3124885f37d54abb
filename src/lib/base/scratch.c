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

int
scratch_begin(scratch *s, const char *prefix, tl_err *e)
{
	char lock[4200];

	s->lock = -1;
	scratch_sweep(prefix);
	if (snprintf(s->path, sizeof s->path, "%s/%s.XXXXXX", tl_tmpdir(),
	    prefix) >= (int)sizeof s->path)
		return tl_fail(e, "TMPDIR: path too long");
	if (mkdtemp(s->path) == NULL)
		return tl_failsys(e, "%s", s->path);
	snprintf(lock, sizeof lock, "%s/lock", s->path);
	if ((s->lock = open(lock, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC,
	    0600)) < 0 || flock(s->lock, LOCK_EX) < 0) {
		tl_failsys(e, "%s", lock);
		scratch_end(s);
		return -1;
	}
	return 0;
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
