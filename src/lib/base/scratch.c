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

#include "base/outfile.h"
#include "base/scratch.h"

static const char *
tmpdir(void)
{
	const char *t = getenv("TMPDIR");

	return t != NULL && t[0] != '\0' ? t : "/tmp";
}

int
scratch_rmtree(const char *path)
{
	struct stat st;

	/* outfile.h's: no symlink followed, no depth limit, two descriptors
	 * at most and one in reserve (it runs after failures for want of
	 * them); nftw needs one a level */
	tl_rmtree(path);
	return lstat(path, &st) == 0 ? -1 : 0;
}

/* Whether the run that made dir is dead: its lock can be taken, or it has
 * no lock file and is older than a minute (killed while being made). */
static int
dead(const char *dir)
{
	char lock[4200];
	struct stat st;
	int fd, r;

	snprintf(lock, sizeof lock, "%s/lock", dir);
	if ((fd = open(lock, O_RDONLY | O_CLOEXEC | O_NOFOLLOW)) < 0)
		return errno == ENOENT && lstat(dir, &st) == 0 &&
		    S_ISDIR(st.st_mode) && time(NULL) - st.st_mtime > 60;
	r = flock(fd, LOCK_EX | LOCK_NB) == 0;
	close(fd); /* drops the lock taken, if any */
	return r;
}

int
scratch_sweep(const char *prefix)
{
	const char *t = tmpdir();
	size_t n = strlen(prefix);
	struct dirent *d;
	char path[4096];
	int swept = 0;
	DIR *dir;

	if ((dir = opendir(t)) == NULL)
		return 0;
	while ((d = readdir(dir)) != NULL) {
		/* PREFIX.XXXXXX exactly: mkdtemp's six characters */
		if (strncmp(d->d_name, prefix, n) != 0 ||
		    d->d_name[n] != '.' || strlen(d->d_name + n + 1) != 6)
			continue;
		snprintf(path, sizeof path, "%s/%s", t, d->d_name);
		if (dead(path) && scratch_rmtree(path) == 0)
			swept++;
	}
	closedir(dir);
	return swept;
}

int
scratch_begin(scratch *s, const char *prefix, tl_err *e)
{
	char lock[4200];

	s->lock = -1;
	scratch_sweep(prefix);
	if (snprintf(s->path, sizeof s->path, "%s/%s.XXXXXX", tmpdir(),
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
		scratch_rmtree(s->path);
	s->path[0] = '\0';
}
