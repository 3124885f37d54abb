/* rmtree.c - the one removal of a directory tree (rmtree.h): system
 * calls only, so that the fatal-signal handler of outfile.c can use it. */
#define _GNU_SOURCE
#include "base/rmtree.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

/* A descriptor kept in reserve for removing a tree when the process has
 * none left: the failure being cleaned up may be that one (EMFILE). The
 * first removal that needs it gives it up; atomic, as the handler takes
 * it too. */
static int reserve = -1;

/* Directory entries with system calls only (readdir may allocate). */
struct dent {
	uint64_t ino;
	int64_t off;
	unsigned short reclen;
	unsigned char type;
	char name[];
};

#define DIRFLAGS (O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)

/* The directory name in fd, the reserve given up when no descriptor is
 * left. */
static int
open_dir(int fd, const char *name)
{
	int d = openat(fd, name, DIRFLAGS), r;

	if (d < 0 && errno == EMFILE &&
	    (r = __atomic_exchange_n(&reserve, -1, __ATOMIC_ACQ_REL)) >= 0) {
		close(r);
		d = openat(fd, name, DIRFLAGS);
	}
	return d;
}

/* Empties the directory fd as far as it can without descending: removes
 * every entry that is not a directory and every empty directory, in
 * passes from the start until one removes nothing (removal while reading
 * may hide entries). Returns 1 with the name of a non-empty
 * subdirectory in sub (256 bytes) as soon as it meets one, 0 when fd is
 * empty, -1 when an entry cannot be removed. *removed counts. */
static int
rmtree_clear(int fd, char *sub, int *removed)
{
	char buf[4096];
	long n;
	int stuck = 0, gone = 1;

	while (gone) {
		gone = stuck = 0;
		lseek(fd, 0, SEEK_SET);
		while ((n = syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0)
			for (long off = 0; off < n; off += ((struct dent *)
			    (void *)(buf + off))->reclen) {
				const char *name = ((struct dent *)(void *)
				    (buf + off))->name;
				if (strcmp(name, ".") == 0 ||
				    strcmp(name, "..") == 0)
					continue;
				/* a symbolic link goes like a file: its
				 * target is never touched */
				if (unlinkat(fd, name, 0) == 0 ||
				    (errno == EISDIR &&
				    unlinkat(fd, name, AT_REMOVEDIR) == 0)) {
					gone = 1, ++*removed;
				} else if (errno == ENOTEMPTY || errno == EEXIST) {
					size_t k = strlen(name);
					memcpy(sub, name, k + 1 < 256 ? k + 1 : 256);
					sub[255] = '\0';
					return 1;
				} else if (errno != ENOENT) {
					stuck = 1;
				}
			}
	}
	return stuck ? -1 : 0;
}

/* Removes name (relative to parent) and everything under it, at any
 * depth, never following a symbolic link nor entering a mount point, with
 * system calls only (async-signal-safe: the signal handler uses it), no
 * recursion and two descriptors at most. Each walk goes down from the top
 * to the first directory without non-empty subdirectories and empties it;
 * its parent removes it on the next walk. A walk that removes nothing
 * ends it (something there cannot be removed): the rest stays. */
void
tl_rmtree_at(int parent, const char *name)
{
	char sub[256];
	int late = 0;

	/* an empty directory goes without a descriptor */
	if (unlinkat(parent, name, 0) == 0 || errno != EISDIR ||
	    unlinkat(parent, name, AT_REMOVEDIR) == 0)
		return;
	for (;;) {
		int fd = open_dir(parent, name), depth = 0, removed = 0;
		int r = -1;

		if (fd < 0)
			return;
		while ((r = rmtree_clear(fd, sub, &removed)) == 1) {
			int c = open_dir(fd, sub);
			close(fd);
			if ((fd = c) < 0)
				break;
			depth++;
		}
		if (fd >= 0)
			close(fd);
		/* filled again meanwhile (a signal's removal while the
		 * owner's other threads still write): another walk */
		if (depth == 0 && (r != 0 || unlinkat(parent, name,
		    AT_REMOVEDIR) == 0 || (errno != ENOTEMPTY &&
		    errno != EEXIST) || ++late > 1000))
			return;
		if (depth > 0 && removed == 0)
			return;
	}
}

void
tl_rmtree_reserve(void)
{
	if (__atomic_load_n(&reserve, __ATOMIC_ACQUIRE) < 0)
		__atomic_store_n(&reserve, open("/dev/null", O_RDONLY |
		    O_CLOEXEC), __ATOMIC_RELEASE);
}

int
tl_rmtree(const char *path)
{
	struct stat st;

	tl_rmtree_at(AT_FDCWD, path);
	return lstat(path, &st) == 0 ? -1 : 0;
}
