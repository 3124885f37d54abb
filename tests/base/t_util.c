/* t_util - the shared plumbing (util.h): failure reports, checked
 * allocation, output files and directories that appear complete or not at
 * all (commit, abort, a fatal signal, a full registry), the sweep of what
 * killed runs left, trees of any depth, progress for a supervisor,
 * scratch files, pread/pwrite, the filters' operands and number
 * parsing. */
#include "base/progress.h"
#include "base/outfile.h"
#include "base/util.h"
#include "tap.h"
#include "tmpdir.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char dir[PATH_MAX / 2];

/* Under AddressSanitizer an impossible calloc returns NULL, as in libc,
 * instead of ending the test. */
const char *__asan_default_options(void);
const char *
__asan_default_options(void)
{
	return "allocator_may_return_null=1";
}

/* Entries of d but . and .. (tmpdir.h). */
static int
entries(const char *d)
{
	return tmpdir_entries(d, "");
}

static const char *
tmp(const char *name)
{
	return tmpdir_join(dir, name);
}

static int
file_is(const char *path, const char *text)
{
	char buf[256] = "";
	int fd = open(path, O_RDONLY);
	ssize_t n;

	if (fd < 0)
		return 0;
	n = read(fd, buf, sizeof buf - 1);
	close(fd);
	return n >= 0 && (size_t)n == strlen(text) && memcmp(buf, text, n) == 0;
}

static void
test_err(void)
{
	tl_err e = { "" };
	char big[3000];

	ok(tl_fail(&e, "%s: %d rows", "x.exr", 3) == -1 &&
	    strcmp(e.msg, "x.exr: 3 rows") == 0,
	    "tl_fail: returns -1, the message formatted");
	ok(tl_fail(NULL, "ignored %d", 1) == -1, "tl_fail: NULL e is fine");
	errno = ENOENT;
	ok(tl_failsys(&e, "%s: cannot open", "y") == -1 &&
	    strcmp(e.msg, "y: cannot open: No such file or directory") == 0 &&
	    errno == ENOENT, "tl_failsys: \": strerror(errno)\" appended, "
	    "errno kept (%s)", e.msg);
	memset(big, 'x', sizeof big - 1);
	big[sizeof big - 1] = '\0';
	tl_fail(&e, "%s", big);
	ok(strlen(e.msg) == sizeof e.msg - 1, "tl_fail: a long message is "
	    "cut to the buffer");
	ok(strcmp(tl_name("-", 0), "stdin") == 0 &&
	    strcmp(tl_name("-", 1), "stdout") == 0 &&
	    strcmp(tl_name("a.exr", 1), "a.exr") == 0,
	    "tl_name: \"-\" is stdin or stdout, a path itself");
}

static void
test_alloc(void)
{
	tl_err e = { "" };
	unsigned char *p;
	int zero = 1;

	ok(tl_alloc(SIZE_MAX / 2, 3, &e) == NULL &&
	    strstr(e.msg, "too large") != NULL,
	    "tl_alloc: n x size overflowing is refused (%s)", e.msg);
	e.msg[0] = '\0';
	ok(tl_alloc(SIZE_MAX / 4, 2, &e) == NULL && e.msg[0] != '\0',
	    "tl_alloc: an impossible size fails with a message (%s)", e.msg);
	p = tl_alloc(1000, 3, &e);
	for (int i = 0; p != NULL && i < 3000; i++)
		zero &= p[i] == 0;
	ok(p != NULL && zero, "tl_alloc: zeroed, like calloc");
	free(p);
	p = tl_alloc(0, 8, &e);
	ok(p != NULL, "tl_alloc: zero elements give a valid pointer");
	free(p);
}

static void
test_outfile(void)
{
	tl_outfile o;
	tl_err e = { "" };

	ok(tl_out_begin(&o, tmp("a.txt"), &e) == 0 && entries(dir) == 1 &&
	    access(tmp("a.txt"), F_OK) != 0 && strncmp(o.tmp, tmp(".a.txt."),
	    strlen(tmp(".a.txt."))) == 0, "tl_out_begin: a hidden temporary "
	    "beside the path, the path itself not there yet");
	ok(write(o.fd, "done\n", 5) == 5 && tl_out_commit(&o, &e) == 0 &&
	    file_is(tmp("a.txt"), "done\n") && entries(dir) == 1 &&
	    o.tmp == NULL, "tl_out_commit: renamed onto the path, no "
	    "temporary left");
	ok(tl_out_begin(&o, tmp("a.txt"), &e) == 0, "a second output over "
	    "the first");
	if (write(o.fd, "half", 4) != 4)
		ok(0, "write");
	tl_out_abort(&o);
	ok(file_is(tmp("a.txt"), "done\n") && entries(dir) == 1,
	    "tl_out_abort: the temporary removed, the old file untouched");
	tl_out_abort(&o); /* twice is harmless */
	ok(tl_out_begin(&o, tmp("new.txt"), &e) == 0, "an output to a new "
	    "name");
	tl_out_abort(&o);
	ok(access(tmp("new.txt"), F_OK) != 0 && entries(dir) == 1,
	    "tl_out_abort: nothing left at all");
	ok(tl_out_begin(&o, dir, &e) < 0 && strstr(e.msg, "is a directory"),
	    "tl_out_begin: a directory refused (%s)", e.msg);
	ok(tl_out_begin(&o, tmp("no/such/dir/x"), &e) < 0 &&
	    strstr(e.msg, "cannot create") != NULL, "tl_out_begin: an "
	    "impossible path fails with a message (%s)", e.msg);
	unlink(tmp("a.txt"));
}

/* A fatal signal removes the temporaries of every output in progress. */
static void
test_signal(void)
{
	int st;
	pid_t pid = fork();

	if (pid == 0) {
		tl_outfile a, b;
		if (tl_out_begin(&a, tmp("s1"), NULL) < 0 ||
		    tl_outdir_begin(&b, tmp("s2"), NULL) < 0)
			_exit(3);
		char p[PATH_MAX];
		if (write(a.fd, "x", 1) != 1)
			_exit(5);
		snprintf(p, sizeof p, "%s/f", b.tmp);
		close(open(p, O_CREAT | O_WRONLY, 0644));
		snprintf(p, sizeof p, "%s/d", b.tmp);
		mkdir(p, 0755);
		snprintf(p, sizeof p, "%s/d/g", b.tmp);
		close(open(p, O_CREAT | O_WRONLY, 0644));
		kill(getpid(), SIGTERM);
		_exit(4);
	}
	waitpid(pid, &st, 0);
	ok(WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM && entries(dir) == 0,
	    "SIGTERM: the process dies of it, its temporary file and "
	    "directory tree removed (%d left)", entries(dir));
}

/* More outputs at once than the registry holds: refused, not unguarded. */
static void
test_full(void)
{
	tl_outfile o[80];
	tl_err e = { "" };
	int n = 0;

	while (n < 80 && tl_out_begin(&o[n], tmp("many"), &e) == 0)
		n++;
	ok(n == 64 && strstr(e.msg, "more than 64 temporary outputs") &&
	    entries(dir) == 64, "the 65th output at once fails loudly (%s), "
	    "its temporary removed", e.msg);
	while (n > 0)
		tl_out_abort(&o[--n]);
	ok(entries(dir) == 0 && tl_out_begin(&o[0], tmp("many"), &e) == 0,
	    "aborted outputs free their slots");
	tl_out_abort(&o[0]);
}

static void
test_outdir(void)
{
	tl_outfile o;
	tl_err e = { "" };
	char p[PATH_MAX];

	ok(tl_outdir_begin(&o, tmp("pyr"), &e) == 0 &&
	    access(tmp("pyr"), F_OK) != 0, "tl_outdir_begin: built under a "
	    "hidden name");
	snprintf(p, sizeof p, "%s/one", o.tmp);
	close(open(p, O_CREAT | O_WRONLY, 0644));
	ok(tl_outdir_commit(&o, &e) == 0 && access(tmp("pyr/one"), F_OK) == 0 &&
	    entries(dir) == 1, "tl_outdir_commit: renamed onto the path");
	tl_outdir_begin(&o, tmp("pyr"), &e);
	snprintf(p, sizeof p, "%s/two", o.tmp);
	close(open(p, O_CREAT | O_WRONLY, 0644));
	ok(tl_outdir_commit(&o, &e) == 0 && access(tmp("pyr/two"), F_OK) == 0 &&
	    access(tmp("pyr/one"), F_OK) != 0 && entries(dir) == 1,
	    "tl_outdir_commit: an existing tree replaced whole, the old one "
	    "removed");
	tl_outdir_begin(&o, tmp("pyr"), &e);
	snprintf(p, sizeof p, "%s/sub", o.tmp);
	mkdir(p, 0755);
	snprintf(p, sizeof p, "%s/sub/three", o.tmp);
	close(open(p, O_CREAT | O_WRONLY, 0644));
	tl_outdir_abort(&o);
	ok(access(tmp("pyr/two"), F_OK) == 0 && entries(dir) == 1,
	    "tl_outdir_abort: the tree removed recursively, the old one kept");
	close(open(tmp("plain"), O_CREAT | O_WRONLY, 0644));
	tl_outdir_begin(&o, tmp("plain"), &e);
	ok(tl_outdir_commit(&o, &e) < 0 && strstr(e.msg, "not a directory") &&
	    entries(dir) == 2, "tl_outdir_commit: a file in the way refused "
	    "(%s), the new tree removed", e.msg);
	unlink(tmp("plain"));
	unlink(tmp("pyr/two"));
	rmdir(tmp("pyr"));
}

/* A file inside a tree this process builds (tl_out_begin_tree): under
 * its final name from the start, mode 0666 less the umask, nothing made
 * beside it; kept by the commit, removed by the abort; a name that
 * exists refused. */
static void
test_tree(void)
{
	mode_t mask = umask(027);
	tl_outfile d, o;
	tl_err e = { "" };
	char p[PATH_MAX], q[PATH_MAX];
	struct stat st;

	if (tl_outdir_begin(&d, tmp("tree"), &e) < 0) {
		ok(0, "tl_outdir_begin (%s)", e.msg);
		umask(mask);
		return;
	}
	snprintf(p, sizeof p, "%s/f.exr", d.tmp);
	snprintf(q, sizeof q, "%s/g.exr", d.tmp);
	ok(tl_out_begin_tree(&o, p, &e) == 0 && o.tmp == NULL &&
	    lstat(p, &st) == 0 && S_ISREG(st.st_mode) &&
	    (st.st_mode & 07777) == 0640 && entries(d.tmp) == 2,
	    "tl_out_begin_tree: the file under its final name, mode 0666 "
	    "less the umask 027 (%04o), nothing else but the tree's lock",
	    (unsigned)(st.st_mode & 07777));
	ok(write(o.fd, "done\n", 5) == 5 && tl_out_commit(&o, &e) == 0 &&
	    o.path == NULL && file_is(p, "done\n") && entries(d.tmp) == 2,
	    "tl_out_commit: the file kept as written");
	ok(tl_out_begin_tree(&o, p, &e) < 0 && strstr(e.msg, "cannot create")
	    && file_is(p, "done\n"), "tl_out_begin_tree: a name that exists "
	    "refused, the file untouched (%s)", e.msg);
	ok(tl_out_begin_tree(&o, q, &e) == 0 && write(o.fd, "half", 4) == 4,
	    "a second file");
	tl_out_abort(&o);
	ok(access(q, F_OK) != 0 && entries(d.tmp) == 2,
	    "tl_out_abort: the half-written file removed");
	tl_out_abort(&o); /* twice is harmless */
	ok(tl_outdir_commit(&d, &e) == 0 &&
	    file_is(tmp("tree/f.exr"), "done\n") && entries(tmp("tree")) == 1,
	    "tl_outdir_commit: the tree publishes the file");
	unlink(tmp("tree/f.exr"));
	rmdir(tmp("tree"));
	umask(mask);
}

/* A child that begins an output (file or directory, with a file inside
 * the directory) and dies of SIGKILL, or, when live is not NULL, stays
 * alive until *live is closed (its write end): *pid. */
static pid_t
owner(const char *path, int isdir, int *live)
{
	int p[2], q[2];
	char c;
	pid_t pid;

	if (pipe(p) != 0 || pipe(q) != 0)
		return -1;
	if ((pid = fork()) == 0) {
		tl_outfile o;
		char f[PATH_MAX];
		close(p[1]), close(q[0]);
		if ((isdir ? tl_outdir_begin(&o, path, NULL) :
		    tl_out_begin(&o, path, NULL)) < 0)
			_exit(3);
		if (isdir) {
			snprintf(f, sizeof f, "%s/block", o.tmp);
			close(open(f, O_CREAT | O_WRONLY, 0644));
		}
		if (write(q[1], "r", 1) != 1)
			_exit(4);
		if (live == NULL)
			kill(getpid(), SIGKILL);
		if (read(p[0], &c, 1) < 0)
			_exit(5);
		_exit(0);
	}
	close(p[0]), close(q[1]);
	if (read(q[0], &c, 1) != 1)
		pid = -1;
	close(q[0]);
	if (live != NULL)
		*live = p[1];
	else
		close(p[1]);
	return pid;
}

/* Hidden temporaries ".NAME.XXXXXX" beside NAME in dir. */
static int
hidden(const char *name)
{
	DIR *D = opendir(dir);
	struct dirent *de;
	size_t n = strlen(name);
	int k = 0;

	if (D == NULL)
		return -1;
	while ((de = readdir(D)) != NULL)
		k += de->d_name[0] == '.' && strncmp(de->d_name + 1, name,
		    n) == 0 && de->d_name[n + 1] == '.';
	closedir(D);
	return k;
}

/* What killed runs left is removed by the next output to the same path;
 * what live ones are building is not. */
static void
test_sweep(void)
{
	tl_outfile o;
	tl_err e = { "" };
	char p[PATH_MAX + 8], old[PATH_MAX];
	struct timespec ts[2] = { { 0, 0 }, { 0, 0 } };
	int live, st;
	pid_t pid;

	waitpid(owner(tmp("pyr"), 1, NULL), &st, 0);
	ok(hidden("pyr") == 1, "a SIGKILLed tl_outdir_begin leaves its "
	    "temporary tree (%d)", hidden("pyr"));
	pid = owner(tmp("pyr"), 1, &live);
	ok(hidden("pyr") == 1, "a live run's tl_outdir_begin sweeps it "
	    "(%d)", hidden("pyr"));
	waitpid(owner(tmp("pyr"), 1, NULL), &st, 0);
	ok(hidden("pyr") == 2, "and a run killed meanwhile does not sweep "
	    "the live one's (%d)", hidden("pyr"));
	ok(tl_outdir_begin(&o, tmp("pyr"), &e) == 0 && hidden("pyr") == 2,
	    "tl_outdir_begin: the dead run's tree swept, the live run's "
	    "and its own kept (%d)", hidden("pyr"));
	snprintf(p, sizeof p, "%s/.lock", o.tmp);
	ok(access(p, F_OK) == 0, "the tree being built holds its lock file");
	snprintf(p, sizeof p, "%s/one", o.tmp);
	close(open(p, O_CREAT | O_WRONLY, 0644));
	ok(tl_outdir_commit(&o, &e) == 0 && entries(tmp("pyr")) == 1,
	    "tl_outdir_commit: the tree holds what was put there, no lock "
	    "file (%d entries)", entries(tmp("pyr")));
	close(live);
	waitpid(pid, &st, 0);
	ok(tl_outdir_begin(&o, tmp("pyr"), &e) == 0 && hidden("pyr") == 1,
	    "the live run ended, its tree is swept by the next");
	tl_outdir_abort(&o);
	/* a tree without a lock file: an older run's, or one killed before
	 * its lock; taken as abandoned after a minute */
	snprintf(old, sizeof old, "%s/.pyr.abc123", dir);
	mkdir(old, 0755);
	snprintf(p, sizeof p, "%s/x", old);
	mkdir(p, 0755);
	ok(tl_outdir_begin(&o, tmp("pyr"), &e) == 0 && access(old, F_OK) == 0,
	    "a fresh tree without a lock file is left alone");
	tl_outdir_abort(&o);
	ts[0].tv_sec = ts[1].tv_sec = time(NULL) - 120;
	utimensat(AT_FDCWD, old, ts, 0);
	ok(tl_outdir_begin(&o, tmp("pyr"), &e) == 0 && access(old, F_OK) != 0,
	    "one without a lock file, two minutes old, is swept");
	tl_outdir_abort(&o);
	snprintf(old, sizeof old, "%s/.pyrx.abc123", dir);
	mkdir(old, 0755);
	utimensat(AT_FDCWD, old, ts, 0);
	ok(tl_outdir_begin(&o, tmp("pyr"), &e) == 0 && access(old, F_OK) == 0,
	    "another name's temporaries are not touched");
	tl_outdir_abort(&o);
	rmdir(old);
	/* files: the lock on the temporary itself */
	waitpid(owner(tmp("f.exr"), 0, NULL), &st, 0);
	pid = owner(tmp("f.exr"), 0, &live);
	waitpid(owner(tmp("f.exr"), 0, NULL), &st, 0);
	ok(hidden("f.exr") == 2, "killed, live, killed tl_out_begin: "
	    "the first swept by the second, two temporary files (%d)",
	    hidden("f.exr"));
	ok(tl_out_begin(&o, tmp("f.exr"), &e) == 0 && hidden("f.exr") == 2,
	    "tl_out_begin: the dead run's file swept, the live one's kept "
	    "(%d)", hidden("f.exr"));
	ok(tl_out_commit(&o, &e) == 0 && hidden("f.exr") == 1,
	    "tl_out_commit");
	close(live);
	waitpid(pid, &st, 0);
	tl_out_begin(&o, tmp("f.exr"), &e);
	tl_out_abort(&o);
	ok(hidden("f.exr") == 0 && entries(dir) == 2, "all gone once the "
	    "live run has ended");
	unlink(tmp("f.exr"));
	unlink(tmp("pyr/one"));
	rmdir(tmp("pyr"));
}

/* Trees of any depth go whole; a symbolic link inside is removed, never
 * followed. */
static void
test_deep(void)
{
	tl_outfile o;
	tl_err e = { "" };
	char p[PATH_MAX], *end;
	int ok1;

	mkdir(tmp("keep"), 0755);
	close(open(tmp("keep/file"), O_CREAT | O_WRONLY, 0644));
	tl_outdir_begin(&o, tmp("deep"), &e);
	snprintf(p, sizeof p, "%s", o.tmp);
	end = p + strlen(p);
	for (int d = 0; d < 200; d++) { /* 200 levels, files on the way */
		snprintf(end, sizeof p - (end - p), "/d");
		end += 2;
		mkdir(p, 0755);
		snprintf(end, sizeof p - (end - p), "/f");
		close(open(p, O_CREAT | O_WRONLY, 0644));
		if (d % 50 == 0) {
			snprintf(end, sizeof p - (end - p), "/l");
			ok1 = symlink(tmp("keep"), p);
			(void)ok1;
		}
		*end = '\0';
	}
	ok(tl_outdir_commit(&o, &e) == 0, "a tree 200 deep committed");
	tl_outdir_begin(&o, tmp("deep"), &e);
	ok(tl_outdir_commit(&o, &e) == 0 && entries(tmp("deep")) == 0 &&
	    entries(dir) == 2, "replaced: the old tree 200 deep removed whole "
	    "(%d entries left)", entries(dir));
	ok(access(tmp("keep/file"), F_OK) == 0, "symbolic links in it "
	    "removed, their targets untouched");
	rmdir(tmp("deep"));
	unlink(tmp("keep/file"));
	rmdir(tmp("keep"));
}

/* Progress lines for a supervisor on TL_PROGRESS_FD. */
static void
test_progress(void)
{
	tl_progress pr;
	char buf[8192] = "", fdname[16];
	int p[2], lines = 0, whole = 1, last = -1;
	ssize_t n;

	if (pipe(p) != 0)
		return;
	snprintf(fdname, sizeof fdname, "%d", p[1]);
	setenv("TL_PROGRESS_FD", fdname, 1);
	tl_progress_start(&pr, "dem2fqm", 1201);
	for (int y = 1; y <= 1201; y++)
		tl_progress_step(&pr, y);
	tl_progress_end(&pr);
	n = read(p[0], buf, sizeof buf - 1);
	buf[n > 0 ? n : 0] = '\0';
	for (char *l = buf, *nl; (nl = strchr(l, '\n')) != NULL; l = nl + 1) {
		long long d, t;
		char lab[64];
		*nl = '\0';
		if (sscanf(l, "%63[^\t]\t%lld\t%lld", lab, &d, &t) != 3 ||
		    strcmp(lab, "dem2fqm") != 0 || t != 1201 || d < last)
			whole = 0;
		last = (int)d;
		lines++;
	}
	ok(lines == 101 && whole && last == 1201, "TL_PROGRESS_FD: a line "
	    "\"LABEL\\tDONE\\tTOTAL\" per percentage and one at the end (%d "
	    "lines, last %d)", lines, last);
	tl_progress_start(&pr, "a\tb\nc", 10);
	tl_progress_end(&pr);
	n = read(p[0], buf, sizeof buf - 1);
	buf[n > 0 ? n : 0] = '\0';
	ok(strcmp(buf, "a b c\t10\t10\n") == 0, "a label's tabs and "
	    "newlines become spaces");
	tl_progress_start(&pr, "quiet", 10);
	pr.on = 0;
	tl_progress_step(&pr, 5);
	tl_progress_end(&pr);
	close(p[1]);
	ok(read(p[0], buf, sizeof buf) == 0, "a progress turned off reports "
	    "nothing");
	close(p[0]);
	setenv("TL_PROGRESS_FD", "999", 1); /* closed */
	tl_progress_start(&pr, "x", 10);
	ok(pr.fd < 0, "TL_PROGRESS_FD naming a closed fd is ignored");
	setenv("TL_PROGRESS_FD", "3x", 1);
	tl_progress_start(&pr, "x", 10);
	ok(pr.fd < 0, "TL_PROGRESS_FD not a number is ignored");
	unsetenv("TL_PROGRESS_FD");
}

static void
test_io(void)
{
	tl_err e = { "" };
	char buf[16] = "";
	int fd = tl_scratch(&e);
	struct stat st;

	ok(fd >= 0 && fstat(fd, &st) == 0 && st.st_nlink == 0,
	    "tl_scratch: an open file with no name");
	ok(tl_pwrite(fd, "abcdef", 6, 10, "scratch", &e) == 0 &&
	    tl_pread(fd, buf, 6, 10, "scratch", &e) == 0 &&
	    memcmp(buf, "abcdef", 6) == 0, "tl_pwrite / tl_pread at an "
	    "offset");
	ok(tl_pread(fd, buf, 8, 12, "scratch", &e) < 0 &&
	    strcmp(e.msg, "scratch: unexpected end of file") == 0,
	    "tl_pread: a short file is an error (%s)", e.msg);
	close(fd);
	ok(tl_pread(fd, buf, 1, 0, "closed", &e) < 0 &&
	    strncmp(e.msg, "closed: read: ", 14) == 0,
	    "tl_pread: a read error names the file (%s)", e.msg);
}

/* tl_operands prints, so its messages go to a file. */
static void
test_operands(void)
{
	const char *in, *out;
	char *three[] = { "a", "b", "c" };
	char *same[] = { (char *)tmp("in.exr"), (char *)tmp("in.exr") };
	char *two[] = { (char *)tmp("in.exr"), (char *)tmp("out.exr") };
	int err = dup(STDERR_FILENO), devnull = open("/dev/null", O_WRONLY), r;

	close(open(tmp("in.exr"), O_CREAT | O_WRONLY, 0644));
	dup2(devnull, STDERR_FILENO);
	ok(tl_operands("t", 3, three, &in, &out) == 2, "tl_operands: three "
	    "operands are a usage error (2)");
	ok(tl_operands("t", 2, same, &in, &out) == 1, "tl_operands: the "
	    "same file in and out refused (1)");
	dup2(err, STDERR_FILENO);
	ok(tl_operands("t", 2, two, &in, &out) == 0 && in == two[0] &&
	    out == two[1], "tl_operands: in and out as given");
	dup2(devnull, STDERR_FILENO);
	r = tl_operands("t", 1, two, &in, &out);
	dup2(err, STDERR_FILENO);
	ok(isatty(STDOUT_FILENO) ? r == 1 : r == 0 && in == two[0] &&
	    strcmp(out, "-") == 0, "tl_operands: the output defaults to "
	    "\"-\" (stdout, refused when a terminal)");
	close(err), close(devnull);
	unlink(tmp("in.exr"));
}

static void
test_parse(void)
{
	double d = 7;
	int i = 7, bad = 0;
	static const char *const nums[] = { "", " ", "1x", "x1", "1e999",
		"nan", "inf", "-inf", "0x", "1.5.2", "1 " };
	static const char *const ints[] = { "", "1.5", "2147483648",
		"-2147483649", "12a", "a", "99999999999999999999", "1e3" };

	ok(tl_parse_double("-12.5e-1", &d) == 0 && d == -1.25 &&
	    tl_parse_double("0x10", &d) == 0 && d == 16,
	    "tl_parse_double: decimal, exponent, hex");
	for (size_t k = 0; k < sizeof nums / sizeof nums[0]; k++)
		bad += tl_parse_double(nums[k], &d) == 0;
	ok(bad == 0, "tl_parse_double: empty, trailing garbage, overflow, "
	    "NaN and infinities refused");
	ok(tl_parse_int("-2147483648", &i) == 0 && i == INT_MIN &&
	    tl_parse_int("2147483647", &i) == 0 && i == INT_MAX &&
	    tl_parse_int("+42", &i) == 0 && i == 42,
	    "tl_parse_int: the whole int range");
	bad = 0;
	for (size_t k = 0; k < sizeof ints / sizeof ints[0]; k++)
		bad += tl_parse_int(ints[k], &i) == 0;
	ok(bad == 0 && i == 42, "tl_parse_int: out of range, fractions, "
	    "garbage refused, the value untouched");
}

int
main(void)
{
	const char *t = getenv("TMPDIR");

	snprintf(dir, sizeof dir, "%s/t_util.XXXXXX", t && *t ? t : "/tmp");
	if (mkdtemp(dir) == NULL) {
		perror(dir);
		return 1;
	}
	test_err();
	test_alloc();
	test_outfile();
	test_signal();
	test_full();
	test_outdir();
	test_tree();
	test_sweep();
	test_deep();
	test_progress();
	test_io();
	test_operands();
	test_parse();
	rmdir(dir);
	return tap_done();
}
