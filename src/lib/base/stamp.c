/* stamp.c - input files recorded and checked (stamp.h). */
#include "base/stamp.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"

static int
cmp(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

/* One file's line, or -1 (it cannot be recorded). */
static int
record(FILE *f, const char *cwd, const char *file, tl_err *e)
{
	struct stat st;

	if (strchr(file, '\n') != NULL)
		return tl_fail(e, "%s: a name with a newline cannot be "
		    "recorded", file);
	if (stat(file, &st) != 0)
		return tl_failsys(e, "%s", file);
	while (file[0] == '.' && file[1] == '/') /* ./-x: a name as given */
		file += 2;
	fprintf(f, "%lld %lld %ld %llu %s%s%s\n", (long long)st.st_size,
	    (long long)st.st_mtim.tv_sec, (long)st.st_mtim.tv_nsec,
	    (unsigned long long)st.st_ino, file[0] == '/' ? "" : cwd,
	    file[0] == '/' ? "" : "/", file);
	return 0;
}

int
stamp_write(const char *path, char **files, int n, tl_err *e)
{
	char cwd[4096];
	tl_outfile o;
	FILE *f;
	int r = 0;

	if (getcwd(cwd, sizeof cwd) == NULL)
		return tl_failsys(e, "current directory");
	qsort(files, (size_t)n, sizeof *files, cmp);
	if (tl_out_begin(&o, path, e) < 0)
		return -1;
	if ((f = fdopen(dup(o.fd), "w")) == NULL) {
		tl_out_abort(&o);
		return tl_failsys(e, "%s", path);
	}
	fputs("tl-stamp 1\n", f);
	for (int k = 0; k < n && r == 0; k++)
		if (k == 0 || strcmp(files[k], files[k - 1]) != 0)
			r = record(f, cwd, files[k], e);
	if (fclose(f) != 0 && r == 0)
		r = tl_failsys(e, "%s", path);
	if (r < 0) {
		tl_out_abort(&o);
		return -1;
	}
	return tl_out_commit(&o, e);
}

/* A line "SIZE SEC NSEC INODE PATH" against the file now. */
static int
check_line(const char *stamp, char *line, int lineno, tl_err *e)
{
	long long size, sec;
	long nsec;
	unsigned long long ino;
	struct stat st;
	int at = 0;
	const char *what;

	line[strcspn(line, "\n")] = '\0';
	if (sscanf(line, "%lld %lld %ld %llu %n", &size, &sec, &nsec, &ino,
	    &at) != 4 || at == 0 || line[at] != '/')
		return tl_fail(e, "%s: line %d: not a stamp line", stamp,
		    lineno);
	if (stat(line + at, &st) != 0)
		return tl_failsys(e, "%s", line + at);
	if (st.st_ino != ino)
		what = "replaced by another file (inode)";
	else if (st.st_size != size)
		what = "its size";
	else if (st.st_mtim.tv_sec != sec || st.st_mtim.tv_nsec != nsec)
		what = "written to (modification time)";
	else
		return 0;
	return tl_fail(e, "%s: changed since %s recorded it: %s", line + at,
	    stamp, what);
}

int
stamp_check(const char *path, tl_err *e)
{
	char line[8192], *full;
	int lineno = 1, r = 0;
	FILE *f;

	if ((f = tl_fopen_regular(path, e)) == NULL)
		return -1;
	/* messages name the record by its absolute path */
	if ((full = realpath(path, NULL)) != NULL)
		path = full;
	if (fgets(line, sizeof line, f) == NULL ||
	    strcmp(line, "tl-stamp 1\n") != 0)
		r = tl_fail(e, "%s: not a stamp (tl-stamp 1)", path);
	while (r == 0 && fgets(line, sizeof line, f) != NULL)
		r = check_line(path, line, ++lineno, e);
	if (r == 0 && ferror(f))
		r = tl_failsys(e, "%s", path);
	fclose(f);
	free(full);
	return r;
}
