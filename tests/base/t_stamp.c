/* t_stamp - input files recorded and checked (stamp.h): a record made
 * of two files (a duplicate recorded once) checks; a file written to,
 * cut, replaced by another with the same size and mtime, or removed
 * fails, naming it and what changed; a name with a newline cannot be
 * recorded; a file that is no record is refused. */
#include "base/stamp.h"
#include "tap.h"
#include "tmpdir.h"

#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static char dir[PATH_MAX - 64];

static int
put(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");

	if (f == NULL)
		return -1;
	fputs(text, f);
	return fclose(f);
}

/* The file's mtime set to t seconds (nanoseconds 0). */
static int
set_mtime(const char *path, time_t t)
{
	struct timespec ts[2] = { { t, 0 }, { t, 0 } };

	return utimensat(AT_FDCWD, path, ts, 0);
}

static int
fails_with(const char *stamp, const char *want)
{
	tl_err e;

	e.msg[0] = '\0';
	if (stamp_check(stamp, &e) == 0)
		return 0;
	if (strstr(e.msg, want) == NULL)
		printf("# %s\n", e.msg);
	return strstr(e.msg, want) != NULL;
}

int
main(void)
{
	char a[PATH_MAX], b[PATH_MAX], s[PATH_MAX], bad[PATH_MAX];
	char *files[3];
	tl_err e;

	if (tmpdir_make(dir, sizeof dir, "t_stamp") < 0)
		return 1;
	snprintf(a, sizeof a, "%s/a.tif", dir);
	snprintf(b, sizeof b, "%s/b c;#.tif", dir);
	snprintf(s, sizeof s, "%s/dem.stamp", dir);
	files[0] = b, files[1] = a, files[2] = a;
	/* mtimes in the past: a write now is another (the clock of file
	 * times may be coarser than a nanosecond) */
	ok(put(a, "aaaa") == 0 && put(b, "bbbb") == 0 && set_mtime(a, 2000000)
	    == 0 && set_mtime(b, 1000000) == 0 && stamp_write(s, files, 3, &e)
	    == 0, "two files recorded");
	ok(stamp_check(s, &e) == 0, "unchanged: the check passes");
	ok(put(a, "aaab") == 0 && fails_with(s, "a.tif: changed since") &&
	    fails_with(s, "written to (modification time)"),
	    "written to, same size: refused, naming it");
	ok(set_mtime(a, 2000000) == 0 && stamp_write(s, files, 3, &e) == 0 &&
	    put(a, "aa") == 0 &&
	    fails_with(s, "a.tif: changed since") && fails_with(s, "its size"),
	    "cut: refused (its size)");
	snprintf(bad, sizeof bad, "%s/new", dir);
	ok(stamp_write(s, files, 3, &e) == 0 && put(bad, "bbbc") == 0 &&
	    set_mtime(bad, 1000000) == 0 && rename(bad, b) == 0 &&
	    fails_with(s, "b c;#.tif: changed since") &&
	    fails_with(s, "replaced by another file (inode)"),
	    "replaced by another file of the same size and mtime: refused");
	ok(unlink(b) == 0 && fails_with(s, "b c;#.tif: No such file"),
	    "removed: refused, naming it");
	snprintf(bad, sizeof bad, "%s/x\ny", dir);
	files[0] = bad;
	ok(put(bad, "x") == 0 && stamp_write(s, files, 1, &e) < 0 &&
	    strstr(e.msg, "newline cannot be recorded") != NULL,
	    "a name with a newline: not recorded");
	ok(put(s, "tl-stamp 2\n") == 0 && fails_with(s, "not a stamp"),
	    "no record: refused");
	tmpdir_done(dir);
	return tap_done();
}
