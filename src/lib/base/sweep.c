/* sweep.c - the sweep of dead owners' temporaries (sweep.h). */
#define _GNU_SOURCE
#include "base/sweep.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <time.h>
#include <unistd.h>

#include "base/rmtree.h"

#define DIRFLAGS (O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)
#define STALE 60 /* seconds: a directory without a lock file (a killed run
                  * of an older version, or one killed between mkdtemp and
                  * its lock) is taken as abandoned after this long */

int
tl_sweep_tail(const char *x, size_t n)
{
	if (n < 7 || x[n - 7] != '.')
		return 0;
	for (size_t i = n - 6; i < n; i++)
		if (!((x[i] >= 'a' && x[i] <= 'z') || (x[i] >= 'A' &&
		    x[i] <= 'Z') || (x[i] >= '0' && x[i] <= '9')))
			return 0;
	return 1;
}

int
tl_sweep_hold(int fd)
{
	struct stat st;

	while (flock(fd, LOCK_EX) != 0)
		if (errno != EINTR)
			return -1;
	return fstat(fd, &st) == 0 && st.st_nlink == 0;
}

/* 1 when fd carries the mark. */
static int
marked(int fd)
{
	char v[8];

	return fgetxattr(fd, TL_SWEEP_MARK, v, sizeof v) >= 0;
}

/* A temporary file whose lock can be taken: its owner is dead. 1 when
 * removed. */
static int
sweep_file(int pfd, const char *name, int take)
{
	int fd = openat(pfd, name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK |
	    O_CLOEXEC), r = 0;
	struct stat a, b;

	if (fd < 0)
		return 0;
	if (((take & TL_SWEEP_FILE) || ((take & TL_SWEEP_MARKED) &&
	    marked(fd))) && flock(fd, LOCK_EX | LOCK_NB) == 0 &&
	    fstat(fd, &a) == 0 && S_ISREG(a.st_mode) && fstatat(pfd, name,
	    &b, AT_SYMLINK_NOFOLLOW) == 0 && a.st_dev == b.st_dev &&
	    a.st_ino == b.st_ino)
		r = unlinkat(pfd, name, 0) == 0;
	close(fd); /* the lock goes with it */
	return r;
}

/* A temporary directory whose lock file's lock can be taken, or, taken
 * unmarked, one that has no lock file and is older than STALE seconds.
 * 1 when removed. */
static int
sweep_dir(int pfd, const char *name, const struct stat *st, int take,
    const char *lockname)
{
	int d = openat(pfd, name, DIRFLAGS), lk, gone = 0;
	struct stat after;

	if (d < 0)
		return 0;
	if (!(take & TL_SWEEP_DIR) && !((take & TL_SWEEP_MARKED) &&
	    marked(d))) {
		close(d);
		return 0;
	}
	lk = openat(d, lockname, O_RDONLY | O_NOFOLLOW | O_NONBLOCK |
	    O_CLOEXEC);
	if (lk >= 0) {
		if (flock(lk, LOCK_EX | LOCK_NB) == 0)
			tl_rmtree_at(pfd, name), gone = 1;
		close(lk);
	} else if ((take & TL_SWEEP_DIR) && errno == ENOENT &&
	    time(NULL) - st->st_mtime > STALE) {
		tl_rmtree_at(pfd, name), gone = 1;
	}
	close(d);
	return gone && fstatat(pfd, name, &after, AT_SYMLINK_NOFOLLOW) != 0;
}

int
tl_sweep(int pfd, const char *lockname, tl_sweep_rule *rule, void *arg)
{
	struct dirent *de;
	struct stat st;
	int take, n = 0;
	DIR *D;

	if (pfd < 0)
		return 0;
	if ((D = fdopendir(pfd)) == NULL) {
		close(pfd);
		return 0;
	}
	while ((de = readdir(D)) != NULL) {
		if ((take = rule(de->d_name, arg)) == 0 ||
		    fstatat(pfd, de->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0)
			continue;
		if (S_ISDIR(st.st_mode))
			n += sweep_dir(pfd, de->d_name, &st, take, lockname);
		else if (S_ISREG(st.st_mode))
			n += sweep_file(pfd, de->d_name, take);
	}
	closedir(D);
	return n;
}
