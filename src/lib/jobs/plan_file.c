/* plan_file.c - what every plan writer (plan.c, plan_terrain.c,
 * plan_rgb.c) does with its files: one written whole by a function, a
 * path made absolute for the scripts (a leaf). */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "jobs/plan_impl.h"

int
plan_put(const char *dir, const char *name, int exec,
    void (*fn)(FILE *, const void *), const void *arg, tl_err *e)
{
	char path[4400];
	FILE *f;

	snprintf(path, sizeof path, "%s/%s", dir, name);
	if ((f = fopen(path, "w")) == NULL)
		return tl_failsys(e, "%s", path);
	fn(f, arg);
	if (fclose(f) != 0)
		return tl_failsys(e, "%s", path);
	if (exec && chmod(path, 0755) != 0)
		return tl_failsys(e, "%s", path);
	return 0;
}

int
plan_absolute(const char *what, const char *p, char *full, size_t n,
    tl_err *e)
{
	char cwd[4096];

	if (strchr(p, '\n') != NULL)
		return tl_fail(e, "%s: a newline cannot go into a plan (make "
		    "reads its jobs' commands a line at a time): rename it",
		    what);
	if (p[0] != '/' && getcwd(cwd, sizeof cwd) == NULL)
		return tl_failsys(e, "current directory");
	if ((size_t)snprintf(full, n, "%s%s%s", p[0] == '/' ? "" : cwd,
	    p[0] == '/' ? "" : "/", p) >= n)
		return tl_fail(e, "%s: name too long", p);
	return 0;
}
