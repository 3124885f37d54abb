/* t_scratch - per-run scratch directories (scratch.h): made in TMPDIR
 * with a held lock; the next run removes those of dead runs (their lock
 * free, or no lock and older than a minute) and keeps a live run's and a
 * young one's; the removal goes any depth and follows no symlink. Runs
 * that start together (each sweeping the others' directories while it
 * makes its own) never remove a live run's directory. */
#include "base/scratch.h"
#include "tap.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char dir[256];

static int
exists(const char *p)
{
	struct stat st;

	return lstat(p, &st) == 0;
}

static void
mk(const char *name, int lock, int age)
{
	char p[512];
	int fd;

	snprintf(p, sizeof p, "%s/%s", dir, name);
	mkdir(p, 0700);
	if (lock) {
		snprintf(p, sizeof p, "%s/%s/lock", dir, name);
		fd = open(p, O_CREAT | O_WRONLY, 0600);
		close(fd);
	}
	if (age) {
		struct timespec t[2] = { { time(NULL) - age, 0 },
			{ time(NULL) - age, 0 } };
		snprintf(p, sizeof p, "%s/%s", dir, name);
		utimensat(AT_FDCWD, p, t, 0);
	}
}

static int
present(const char *name)
{
	char p[512];

	snprintf(p, sizeof p, "%s/%s", dir, name);
	return exists(p);
}

static void
test_sweep(void)
{
	int held[2];
	pid_t pid;
	scratch s;
	tl_err e;
	char c;

	mk("tlx.dead01", 1, 0);		/* lock free: dead */
	mk("tlx.young1", 0, 0);		/* no lock, young: being made */
	mk("tlx.stale1", 0, 120);	/* no lock, two minutes old: dead */
	mk("tlx.live01", 1, 0);		/* lock held by a live process */
	mk("tlx.toolong", 1, 0);	/* not PREFIX.XXXXXX */
	mk("other.dead02", 1, 0);	/* another prefix */
	pipe(held);
	if ((pid = fork()) == 0) {
		char p[512];
		snprintf(p, sizeof p, "%s/tlx.live01/lock", dir);
		int fd = open(p, O_RDWR);
		flock(fd, LOCK_EX);
		write(held[1], "x", 1);
		pause();
		_exit(0);
	}
	read(held[0], &c, 1);
	ok(scratch_begin(&s, "tlx", &e) == 0, "scratch_begin: %s", s.path);
	ok(!present("tlx.dead01"), "a dead run's directory (lock free) is removed");
	ok(!present("tlx.stale1"), "an old one without a lock is removed");
	ok(present("tlx.young1"), "a young one without a lock is kept");
	ok(present("tlx.live01"), "a live run's directory (lock held) is kept");
	ok(present("tlx.toolong") && present("other.dead02"),
	    "names not PREFIX.XXXXXX are not touched");
	char lock[4200];
	snprintf(lock, sizeof lock, "%s/lock", s.path);
	int fd = open(lock, O_RDONLY);
	ok(fd >= 0 && flock(fd, LOCK_EX | LOCK_NB) < 0,
	    "ours is locked while we run");
	close(fd);
	ok(scratch_sweep("tlx") == 0 && exists(s.path),
	    "another sweep leaves ours alone");
	char mine[4096];
	snprintf(mine, sizeof mine, "%s", s.path);
	scratch_end(&s);
	ok(!exists(mine), "scratch_end removes it");
	kill(pid, SIGKILL);
	waitpid(pid, NULL, 0);
	ok(scratch_sweep("tlx") == 1 && !present("tlx.live01"),
	    "once its owner is killed, the live one goes too");
}

/* ROUNDS of make, use, end in each of PROCS processes at once: each
 * scratch_begin sweeps while the others make theirs. A directory taken
 * between its lock file's creation and its flock was the CI failure of
 * dem2rgb's plans ("z3.code: No such file or directory"). */
#define PROCS 4
#define ROUNDS 300

static int
race_child(void)
{
	char p[4200];
	scratch s;
	tl_err e;
	int bad = 0;

	for (int r = 0; r < ROUNDS; r++) {
		if (scratch_begin(&s, "tlr", &e) < 0)
			return 1;
		snprintf(p, sizeof p, "%s/work", s.path);
		int fd = open(p, O_CREAT | O_WRONLY | O_CLOEXEC, 0600);
		if (fd < 0)
			bad++;
		else
			close(fd);
		if (!exists(p))
			bad++;
		scratch_end(&s);
	}
	return bad != 0;
}

static void
test_race(void)
{
	pid_t pid[PROCS];
	int lost = 0, st;

	for (int i = 0; i < PROCS; i++)
		if ((pid[i] = fork()) == 0)
			_exit(race_child());
	for (int i = 0; i < PROCS; i++)
		if (pid[i] < 0 || waitpid(pid[i], &st, 0) < 0 ||
		    !WIFEXITED(st) || WEXITSTATUS(st) != 0)
			lost++;
	ok(lost == 0, "%d runs starting together, %d rounds each: no live "
	    "run's directory swept (%d runs lost one)", PROCS, ROUNDS, lost);
}

static void
test_rmtree(void)
{
	char p[4096], outside[512];
	size_t n;
	int fd;

	snprintf(outside, sizeof outside, "%s/keep", dir);
	fd = open(outside, O_CREAT | O_WRONLY, 0600);
	close(fd);
	n = (size_t)snprintf(p, sizeof p, "%s/deep", dir);
	mkdir(p, 0700);
	for (int d = 0; d < 40; d++) {	/* 40 levels: no depth limit */
		n += (size_t)snprintf(p + n, sizeof p - n, "/d");
		mkdir(p, 0700);
	}
	snprintf(p + n, sizeof p - n, "/link");
	symlink(dir, p);	/* to the parent: must not be followed */
	snprintf(p, sizeof p, "%s/deep", dir);
	ok(tl_rmtree(p) == 0 && !exists(p), "a tree 40 deep is removed");
	ok(exists(outside), "a symlink in it is removed, not followed");
}

int
main(void)
{
	snprintf(dir, sizeof dir, "%s/t_scratch.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(dir) == NULL)
		return 2;
	setenv("TMPDIR", dir, 1);
	test_sweep();
	test_race();
	test_rmtree();
	tl_rmtree(dir);
	return tap_done();
}
