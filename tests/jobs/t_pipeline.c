/* t_pipeline - the DEM-to-pyramid pipeline (pipeline.h) with this build's
 * programs as its stages: a real DEM to a pyramid whose index names every
 * level; an option a stage rejects is a usage error with that stage's own
 * message, before any work; a missing or unreadable DEM fails with one
 * clear message; nothing is left in TMPDIR. */
#include "jobs/pipeline.h"
#include "base/scratch.h"
#include "tap.h"

#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmp[256], bin[PATH_MAX];

static pipeline_opts
opts(const char *dem, const char *out)
{
	pipeline_opts o = { .prog = "t_pipeline", .bindir = bin, .dem = dem,
		.out = out, .mode = "qem1d", .kernel = "binomial", .quiet = 1 };
	return o;
}

static int
scratch_left(void)
{
	DIR *d = opendir(tmp);
	struct dirent *de;
	int n = 0;

	while ((de = readdir(d)) != NULL)
		n += strncmp(de->d_name, "t_pipeline.", 11) == 0;
	closedir(d);
	return n;
}

int
main(void)
{
	const char *data = getenv("DATA") ? getenv("DATA") : "../shared/data";
	char dem[PATH_MAX], out[PATH_MAX], idx[PATH_MAX + 16], bad[PATH_MAX];
	struct stat st;
	pipeline_opts o;
	tl_err e;
	int s;
	FILE *f;

	snprintf(tmp, sizeof tmp, "/tmp/t_pipeline_tmp.XXXXXX");
	if (mkdtemp(tmp) == NULL || realpath(getenv("TL_BUILD") ?
	    getenv("TL_BUILD") : "build", bin) == NULL)
		return 2;
	setenv("TMPDIR", tmp, 1);
	snprintf(dem, sizeof dem, "%s/N44W072.hgt", data);
	snprintf(out, sizeof out, "%s/pyr", tmp);
	if (access(dem, R_OK) != 0) {
		ok(1, "# SKIP %s missing", dem);
		return tap_done();
	}

	o = opts(dem, out);
	o.mode = "nope";
	ok(pipeline_run(&o, &s, &e) < 0 && s == 2 &&
	    strcmp(e.msg, "fqmsolve: -m nope: unknown mode") == 0,
	    "a mode fqmsolve rejects: status 2, its message (\"%s\")", e.msg);
	ok(stat(out, &st) < 0 && scratch_left() == 0, "and nothing made");

	o = opts(dem, out);
	o.kernel = "lanczos";
	ok(pipeline_run(&o, &s, &e) < 0 && s == 2 &&
	    strstr(e.msg, "fqmfilter: -k lanczos") == e.msg,
	    "a kernel fqmfilter rejects: status 2 (\"%s\")", e.msg);

	o = opts(dem, out);
	int r = pipeline_run(&o, &s, &e);
	ok(r == 0 && s == 0, "N44W072.hgt to a pyramid: %s", r ? e.msg : "done");
	snprintf(idx, sizeof idx, "%s/index.json", out);
	ok(stat(idx, &st) == 0 && st.st_size > 100, "its index.json is there");
	char top[PATH_MAX + 16];
	snprintf(top, sizeof top, "%s/4", out);
	ok(stat(top, &st) == 0 && S_ISDIR(st.st_mode), "up to level 4, the "
	    "first of one block (1201 -> 76)");
	ok(scratch_left() == 0, "no scratch left in TMPDIR");

	snprintf(bad, sizeof bad, "%s/none.hgt", tmp);
	o = opts(bad, out);
	ok(pipeline_run(&o, &s, &e) < 0 && s == 1 &&
	    strstr(e.msg, "t_pipeline: ") == e.msg && strstr(e.msg, "none.hgt"),
	    "a missing DEM: status 1, named (\"%s\")", e.msg);
	snprintf(bad, sizeof bad, "%s/text.tif", tmp);
	if ((f = fopen(bad, "w")) != NULL)
		fputs("not a raster\n", f), fclose(f);
	o = opts(bad, out);
	o.force = 1;
	ok(pipeline_run(&o, &s, &e) < 0 && s == 1 &&
	    strstr(e.msg, "dem2fqm: ") == e.msg,
	    "an unreadable DEM: status 1, dem2fqm's message (\"%s\")", e.msg);
	ok(stat(idx, &st) == 0, "the earlier pyramid untouched");
	ok(scratch_left() == 0, "no scratch left after the failures");
	tl_rmtree(tmp);
	return tap_done();
}
