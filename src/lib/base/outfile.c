/* outfile.c - outputs that appear complete or not at all, the registry
 * of temporaries a fatal signal removes, and the sweep of those that
 * killed runs left (outfile.h). */
#define _GNU_SOURCE
#include "base/outfile.h"
#include "base/sweep.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/xattr.h>
#include <time.h>
#include <unistd.h>


/* --- temporaries removed on a fatal signal ---------------------------- */

/* The registry the signal handler walks. Threads change it under a lock
 * with signals blocked; a slot's path is published last with an atomic
 * store and read with an atomic load, so the handler (which cannot lock)
 * sees each slot empty or complete, never half-written. */
#define MAXTMP 64
static struct {
	const char *path; /* owned by the tl_outfile; atomic */
	int dir;
	int lock;         /* a tree's lock file: closed first, for a
	                   * descriptor to remove the tree with */
} tmps[MAXTMP];
static pthread_mutex_t tmps_lock = PTHREAD_MUTEX_INITIALIZER;

/* Threads between making a temporary and registering it (fatal_block's
 * count), and whether a handler has begun: see fatal_block. */
static int making_n, dying;

/* The handler waits for the threads that are making a temporary (they
 * have the fatal signals blocked, so it never runs in one of them) to
 * register it, for at most 2 s: one may wait on a lock the interrupted
 * thread holds (malloc's), and then the handler goes on without it. */
static void
wait_made(void)
{
	struct timespec ms = { 0, 1000000 };

	__atomic_store_n(&dying, 1, __ATOMIC_SEQ_CST);
	for (int i = 0; i < 2000 &&
	    __atomic_load_n(&making_n, __ATOMIC_SEQ_CST) > 0; i++)
		nanosleep(&ms, NULL);
}

static void
on_signal(int sig)
{
	wait_made();
	for (int i = 0; i < MAXTMP; i++) {
		const char *p = __atomic_load_n(&tmps[i].path, __ATOMIC_ACQUIRE);
		int lk = __atomic_load_n(&tmps[i].lock, __ATOMIC_ACQUIRE);
		if (p == NULL)
			continue;
		if (tmps[i].dir && lk >= 0)
			close(lk); /* the owner dies: no lock needed */
		if (tmps[i].dir)
			tl_rmtree_at(AT_FDCWD, p);
		else
			unlink(p);
	}
	signal(sig, SIG_DFL);
	raise(sig);
}

void
tl_out_catch(void)
{
	struct sigaction sa;

	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigfillset(&sa.sa_mask);
	sigaction(SIGINT, &sa, NULL), sigaction(SIGTERM, &sa, NULL);
	sigaction(SIGHUP, &sa, NULL), sigaction(SIGPIPE, &sa, NULL);
}

/* Blocks the signals whose handler reads the registry, takes the lock. */
static void
tmps_enter(sigset_t *old)
{
	sigset_t all;

	sigfillset(&all);
	pthread_sigmask(SIG_BLOCK, &all, old);
	pthread_mutex_lock(&tmps_lock);
}

static void
tmps_leave(const sigset_t *old)
{
	pthread_mutex_unlock(&tmps_lock);
	pthread_sigmask(SIG_SETMASK, old, NULL);
}

/* -1 (e set) when the registry is full: an output that a signal could
 * leave behind is refused rather than silently unguarded. lock: a tree's
 * lock file, or -1. */
static int
tmp_register(const char *path, int dir, int lock, tl_err *e)
{
	sigset_t old;
	int i;

	tmps_enter(&old);
	tl_rmtree_reserve();
	for (i = 0; i < MAXTMP && tmps[i].path != NULL; i++)
		;
	if (i < MAXTMP) {
		tmps[i].dir = dir;
		__atomic_store_n(&tmps[i].lock, lock, __ATOMIC_RELEASE);
		__atomic_store_n(&tmps[i].path, path, __ATOMIC_RELEASE);
	}
	tmps_leave(&old);
	return i < MAXTMP ? 0 : tl_fail(e, "%s: more than %d temporary "
	    "outputs at once", path, MAXTMP);
}

static void
tmp_unregister(const char *path)
{
	sigset_t old;

	tmps_enter(&old);
	for (int i = 0; i < MAXTMP; i++)
		if (tmps[i].path == path)
			__atomic_store_n(&tmps[i].path, NULL, __ATOMIC_RELEASE);
	tmps_leave(&old);
}

/* The registry forgets a tree's lock file before its owner closes it. */
static void
tmp_unlock(const char *path)
{
	sigset_t old;

	tmps_enter(&old);
	for (int i = 0; i < MAXTMP; i++)
		if (tmps[i].path == path)
			__atomic_store_n(&tmps[i].lock, -1, __ATOMIC_RELEASE);
	tmps_leave(&old);
}

/* The umask, read once per process: from /proc where it can be read
 * without changing it (setting it, even back, would give a file another
 * thread creates meanwhile the wrong mode), else by umask(2) twice. */
static mode_t the_umask;
static pthread_once_t umask_once = PTHREAD_ONCE_INIT;

static void
read_umask(void)
{
	FILE *f = fopen("/proc/self/status", "re");
	char line[256];
	unsigned m;

	while (f != NULL && fgets(line, sizeof line, f) != NULL)
		if (sscanf(line, "Umask: %o", &m) == 1) {
			fclose(f);
			the_umask = (mode_t)m & 0777;
			return;
		}
	if (f != NULL)
		fclose(f);
	the_umask = umask(022);
	umask(the_umask);
}

static mode_t
current_umask(void)
{
	pthread_once(&umask_once, read_umask);
	return the_umask;
}

/* "dir/.base.XXXXXX" beside path. */
static char *
tmp_name(const char *path, tl_err *e)
{
	const char *slash = strrchr(path, '/');
	size_t dlen = slash ? (size_t)(slash - path + 1) : 0;
	size_t n = strlen(path) + 16;
	char *t = tl_alloc(n, 1, e);

	if (t == NULL)
		return NULL;
	snprintf(t, n, "%.*s.%s.XXXXXX", (int)dlen, path, path + dlen);
	return t;
}

/* --- the temporaries of killed runs --------------------------------------
 *
 * A process killed outright (SIGKILL, a crash, power) cannot remove its
 * temporaries, so each one says whether its owner lives: the owner holds
 * an flock(2) on it (a file) or on the lock file LOCKNAME inside it (a
 * directory) for as long as it works, and the kernel drops the lock when
 * the owner dies, however it dies. Whoever begins an output first sweeps
 * the temporaries in its directory whose lock it can take: those of the
 * same path, and those of any other name that carry MARK.
 *
 * The name and a free lock prove a temporary ours only for the path we
 * are about to replace anyway: other tools name theirs ".NAME.XXXXXX" too
 * (rsync), and hold no lock while they write. So the owner marks its
 * temporary with the extended attribute MARK once it holds the lock, and
 * removes the mark before the rename; another name's temporary is swept
 * only marked (where the file system has no user attributes, only by the
 * next output to its own path, as before).
 *
 * The owner creates the temporary, then waits for its lock (flock without
 * LOCK_NB): a sweeper may hold it for a moment, and if it has removed the
 * temporary meanwhile (no links left), the owner starts again under a new
 * name. The sweep itself is sweep.h's. */

#define LOCKNAME ".lock"
#define MARK TL_SWEEP_MARK
#define DIRFLAGS (O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)

/* 1 when name is ".BASE.XXXXXX". */
static int
is_tmp_of(const char *name, const char *base, size_t blen)
{
	return name[0] == '.' && strncmp(name + 1, base, blen) == 0 &&
	    strlen(name) == blen + 8 && tl_sweep_tail(name, blen + 8);
}

/* What a sweep before an output takes: path's own temporaries of its
 * kind (dir: directories, else files), and any other marked one. */
struct out_rule {
	const char *base;
	size_t blen;
	int dir;
};

static int
out_rule(const char *name, void *arg)
{
	const struct out_rule *r = arg;
	size_t n = strlen(name);

	/* ".N.XXXXXX" at least */
	if (name[0] != '.' || n < 9 || !tl_sweep_tail(name, n))
		return 0;
	if (!is_tmp_of(name, r->base, r->blen))
		return TL_SWEEP_MARKED;
	return TL_SWEEP_MARKED | (r->dir ? TL_SWEEP_DIR : TL_SWEEP_FILE);
}

/* Sweeps the hidden temporaries ".NAME.XXXXXX" that killed runs left in
 * path's directory (out_rule). */
static void
sweep(const char *path, int dir)
{
	const char *slash = strrchr(path, '/');
	struct out_rule r;
	char parent[PATH_MAX];

	r.base = slash != NULL ? slash + 1 : path;
	r.blen = strlen(r.base);
	r.dir = dir;
	if (slash == NULL)
		snprintf(parent, sizeof parent, ".");
	else if ((size_t)snprintf(parent, sizeof parent, "%.*s",
	    slash == path ? 1 : (int)(slash - path), path) >= sizeof parent)
		return;
	if (r.blen > 0)
		tl_sweep(open(parent, DIRFLAGS), LOCKNAME, out_rule, &r);
}

static int
out_begin(tl_outfile *o, const char *path, tl_err *e)
{
	struct stat st;
	int held = -1;

	memset(o, 0, sizeof *o);
	o->fd = -1;
	if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
		return tl_fail(e, "%s: is a directory", path);
	for (int tries = 0;; tries++) {
		if ((o->path = strdup(path)) == NULL ||
		    (o->tmp = tmp_name(path, e)) == NULL) {
			free(o->path);
			o->path = NULL;
			return tl_fail(e, "%s: out of memory", path);
		}
		o->fd = mkostemp(o->tmp, O_CLOEXEC);
		if (o->fd < 0) {
			tl_failsys(e, "%s: cannot create", path);
			free(o->path), free(o->tmp);
			o->path = o->tmp = NULL;
			return -1;
		}
		if ((held = tl_sweep_hold(o->fd)) != 1 || tries == 8)
			break;
		close(o->fd); /* swept before we held it */
		free(o->path), free(o->tmp);
	}
	fchmod(o->fd, 0666 & ~current_umask());
	if (held == 0) /* ours, and its owner alive while it holds the lock */
		fsetxattr(o->fd, MARK, "1", 1, 0);
	if (tmp_register(o->tmp, 0, -1, e) < 0) {
		close(o->fd);
		unlink(o->tmp);
		free(o->path), free(o->tmp);
		o->path = o->tmp = NULL;
		o->fd = -1;
		return -1;
	}
	return 0;
}

/* The fatal signals wait while a temporary is created, locked and
 * registered (not while the directory is swept): one arriving between
 * the creation and the registration would leave a temporary neither the
 * handler nor a sweep of another name removes. The mask is this
 * thread's; a signal sent to the process runs the handler in another
 * thread, which waits for the count to fall to 0 (wait_made). A thread
 * that comes here once a handler has begun makes nothing: the process
 * is about to end (a handler that returns, at most 2 s later, would
 * not end it: then it goes on). */
static void
making_begin(sigset_t *old)
{
	struct timespec ms = { 0, 1000000 };
	sigset_t s;

	sigemptyset(&s);
	sigaddset(&s, SIGINT), sigaddset(&s, SIGTERM);
	sigaddset(&s, SIGHUP), sigaddset(&s, SIGPIPE);
	pthread_sigmask(SIG_BLOCK, &s, old);
	__atomic_add_fetch(&making_n, 1, __ATOMIC_SEQ_CST);
	for (int i = 0; i < 4000 && __atomic_load_n(&dying, __ATOMIC_SEQ_CST);
	    i++) {
		__atomic_sub_fetch(&making_n, 1, __ATOMIC_SEQ_CST);
		nanosleep(&ms, NULL);
		__atomic_add_fetch(&making_n, 1, __ATOMIC_SEQ_CST);
	}
}

/* making_begin, the handler installed (as it may not be yet) */
static void
fatal_block(sigset_t *old)
{
	making_begin(old);
	tl_out_catch();
}

static void
fatal_unblock(const sigset_t *old)
{
	__atomic_sub_fetch(&making_n, 1, __ATOMIC_SEQ_CST);
	pthread_sigmask(SIG_SETMASK, old, NULL);
}

int
tl_out_begin(tl_outfile *o, const char *path, tl_err *e)
{
	sigset_t old;
	int r;

	sweep(path, 0);
	fatal_block(&old);
	r = out_begin(o, path, e);
	fatal_unblock(&old);
	return r;
}

/* tl_out_sweep_dir's: every file ".X.XXXXXX" (all ours there). */
static int
dir_rule(const char *name, void *arg)
{
	return name[0] == '.' && tl_sweep_tail(name, strlen(name)) ?
	    TL_SWEEP_FILE : 0;
}

void
tl_out_sweep_dir(const char *dir)
{
	tl_sweep(open(dir, DIRFLAGS), LOCKNAME, dir_rule, NULL);
}

int
tl_out_begin_fresh(tl_outfile *o, const char *path, tl_err *e)
{
	sigset_t old;
	int r;

	fatal_block(&old);
	r = out_begin(o, path, e);
	fatal_unblock(&old);
	return r;
}

/* Under its final name: see tl_out_begin_tree. O_EXCL: the file is
 * new, ours alone, and neither a link nor a directory followed; the
 * kernel applies the umask to 0666 as to any new file. */
static int
out_open(tl_outfile *o, const char *path, tl_err *e)
{
	memset(o, 0, sizeof *o);
	if ((o->path = strdup(path)) == NULL) {
		o->fd = -1;
		return tl_fail(e, "%s: out of memory", path);
	}
	o->fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
	if (o->fd < 0) {
		tl_failsys(e, "%s: cannot create", path);
		free(o->path);
		o->path = NULL;
		return -1;
	}
	return 0;
}

/* Only the count of files being made (making_begin): a signal's handler
 * then waits for the file to exist before it removes the tree, which a
 * file created after it listed the directory would keep from going.
 * The handler was installed with the tree. */
int
tl_out_begin_tree(tl_outfile *o, const char *path, tl_err *e)
{
	sigset_t old;
	int r;

	making_begin(&old);
	r = out_open(o, path, e);
	fatal_unblock(&old);
	return r;
}

/* tl_out_commit of a file under its final name: only close's verdict. */
static int
commit_in_place(tl_outfile *o, tl_err *e)
{
	int r = 0;

	if (o->fd >= 0 && close(o->fd) != 0) {
		r = tl_failsys(e, "%s: write", o->path);
		unlink(o->path);
	}
	o->fd = -1;
	free(o->path);
	o->path = NULL;
	return r;
}

int
tl_out_commit(tl_outfile *o, tl_err *e)
{
	/* the lock, on a second descriptor, lasts until the rename is done:
	 * a sweeper finds the locked temporary or the committed file */
	int lk, r = 0;

	if (o->tmp == NULL)
		return commit_in_place(o, e);
	lk = o->fd >= 0 ? fcntl(o->fd, F_DUPFD_CLOEXEC, 0) : -1;
	if (o->fd >= 0)
		fremovexattr(o->fd, MARK); /* the result is no temporary */
	if (o->fd >= 0 && close(o->fd) != 0)
		r = tl_failsys(e, "%s: write", o->path);
	o->fd = -1;
	if (r == 0 && rename(o->tmp, o->path) != 0)
		r = tl_failsys(e, "%s: rename", o->path);
	if (r != 0)
		unlink(o->tmp);
	if (lk >= 0)
		close(lk);
	tmp_unregister(o->tmp);
	free(o->tmp), free(o->path);
	o->tmp = o->path = NULL;
	return r;
}

void
tl_out_abort(tl_outfile *o)
{
	if (o->path == NULL)
		return;
	unlink(o->tmp != NULL ? o->tmp : o->path);
	if (o->fd >= 0)
		close(o->fd);
	if (o->tmp != NULL)
		tmp_unregister(o->tmp);
	free(o->tmp), free(o->path);
	o->tmp = o->path = NULL;
	o->fd = -1;
}

/* The lock file inside the new directory t, locked: its descriptor, 1 in
 * *again when a sweeper removed the directory meanwhile, or -1. */
static int
dir_lock(const char *t, int *again, tl_err *e)
{
	char p[PATH_MAX];
	int fd;

	*again = 0;
	if ((size_t)snprintf(p, sizeof p, "%s/%s", t, LOCKNAME) >= sizeof p) {
		errno = ENAMETOOLONG;
		return -1;
	}
	fd = open(p, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
	    0600);
	if (fd < 0)
		return -1;
	switch (tl_sweep_hold(fd)) {
	case 1:
		*again = 1;
		close(fd);
		return -1;
	case 0: /* see out_begin */
		lsetxattr(t, MARK, "1", 1, 0);
		break;
	}
	return fd;
}

static int
outdir_begin(tl_outfile *o, const char *path, tl_err *e)
{
	int again = 0;

	memset(o, 0, sizeof *o);
	o->fd = -1;
	for (int tries = 0;; tries++) {
		if ((o->path = strdup(path)) == NULL ||
		    (o->tmp = tmp_name(path, e)) == NULL) {
			free(o->path);
			o->path = NULL;
			return tl_fail(e, "%s: out of memory", path);
		}
		if (mkdtemp(o->tmp) == NULL) {
			tl_failsys(e, "%s: cannot create", path);
			free(o->path), free(o->tmp);
			o->path = o->tmp = NULL;
			return -1;
		}
		if ((o->fd = dir_lock(o->tmp, &again, e)) >= 0)
			break;
		if (!again || tries == 8) {
			tl_failsys(e, "%s: cannot create", path);
			tl_rmtree_at(AT_FDCWD, o->tmp);
			free(o->path), free(o->tmp);
			o->path = o->tmp = NULL;
			return -1;
		}
		free(o->path), free(o->tmp); /* swept before we held it */
	}
	chmod(o->tmp, 0777 & ~current_umask());
	if (tmp_register(o->tmp, 1, o->fd, e) < 0) {
		tl_rmtree_at(AT_FDCWD, o->tmp);
		close(o->fd);
		free(o->path), free(o->tmp);
		o->path = o->tmp = NULL;
		o->fd = -1;
		return -1;
	}
	return 0;
}

int
tl_outdir_begin(tl_outfile *o, const char *path, tl_err *e)
{
	sigset_t old;
	int r;

	sweep(path, 1);
	fatal_block(&old);
	r = outdir_begin(o, path, e);
	fatal_unblock(&old);
	return r;
}

/* The lock released and the tree's descriptor state cleared. */
static void
outdir_end(tl_outfile *o)
{
	tmp_unregister(o->tmp);
	if (o->fd >= 0)
		close(o->fd);
	free(o->tmp), free(o->path);
	o->tmp = o->path = NULL;
	o->fd = -1;
}

int
tl_dir_install(const char *tmp, const char *path, tl_err *e)
{
	struct stat st;

	/* Replace an earlier directory by swapping the two atomically
	 * (renameat2 RENAME_EXCHANGE), then remove the old one: readers
	 * see the old tree or the new one, never a mix or nothing. */
	if (lstat(path, &st) == 0) {
		if (!S_ISDIR(st.st_mode))
			return tl_fail(e, "%s: exists and is not a directory",
			    path);
		if (syscall(SYS_renameat2, AT_FDCWD, tmp, AT_FDCWD, path,
		    2 /* RENAME_EXCHANGE */) != 0)
			return tl_failsys(e, "%s: replace", path);
		tl_rmtree_at(AT_FDCWD, tmp); /* now the old tree */
		return 0;
	}
	return rename(tmp, path) != 0 ? tl_failsys(e, "%s: rename", path) : 0;
}

int
tl_outdir_commit(tl_outfile *o, tl_err *e)
{
	char lock[PATH_MAX];
	int r = 0;

	/* The lock file leaves the tree before it is committed (the
	 * lock itself holds on its descriptor until the rename is done):
	 * the result holds exactly what the caller put there. */
	if ((size_t)snprintf(lock, sizeof lock, "%s/%s", o->tmp, LOCKNAME) <
	    sizeof lock && unlink(lock) != 0 && errno != ENOENT)
		r = tl_failsys(e, "%s: remove", lock);
	lremovexattr(o->tmp, MARK); /* the result is no temporary */
	if (r == 0)
		r = tl_dir_install(o->tmp, o->path, e);
	if (r != 0)
		tl_rmtree_at(AT_FDCWD, o->tmp);
	outdir_end(o);
	return r;
}

void
tl_outdir_abort(tl_outfile *o)
{
	if (o->tmp == NULL)
		return;
	/* the lock first: a descriptor for the removal, which may follow
	 * a failure for want of one */
	if (o->fd >= 0) {
		tmp_unlock(o->tmp);
		close(o->fd);
		o->fd = -1;
	}
	tl_rmtree_at(AT_FDCWD, o->tmp);
	outdir_end(o);
}
