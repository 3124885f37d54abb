/* t_paths - outputs kept off inputs (paths.h): the relation of two paths
 * however they are spelled (symbolic links, "..", hard links, paths not
 * made yet), a directory's tree and the messages (the files of a DEM:
 * tests/dem/t_dem_paths.c). */
#define _GNU_SOURCE
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tap.h"
#include "tmpdir.h"

#include "base/paths.h"

static char dir[PATH_MAX];

static const char *
at(const char *name)
{
	return tmpdir_join(dir, name);
}

static void
put(const char *name, const char *text)
{
	FILE *f = fopen(at(name), "w");

	if (f != NULL) {
		fputs(text, f);
		fclose(f);
	}
}

static int
rel(const char *out, const char *in, int flags)
{
	char o[PATH_MAX], i[PATH_MAX];
	tl_err e;

	snprintf(o, sizeof o, "%s", at(out));
	snprintf(i, sizeof i, "%s", at(in));
	return tl_path_relation(o, i, flags, &e);
}

static void
relations(void)
{
	mkdir(at("D"), 0777), mkdir(at("D/sub"), 0777), mkdir(at("E"), 0777);
	put("D/dem.tif", "x"), put("E/f", "y");
	symlink("D", at("L"));
	symlink("D/sub", at("S"));
	symlink("dem.tif", at("D/link.tif"));
	link(at("D/dem.tif"), at("hard.tif"));

	ok(rel("E/f", "D/dem.tif", 0) == TL_PATH_APART, "two files apart");
	ok(rel("E", "D/dem.tif", 0) == TL_PATH_APART, "a directory beside "
	    "the file: apart");
	ok(rel("D/dem.tif", "D/dem.tif", 0) == TL_PATH_SAME, "a file is "
	    "itself");
	ok(rel("L/dem.tif", "D/dem.tif", 0) == TL_PATH_SAME, "through a "
	    "symbolic link to its directory: the same");
	ok(rel("D/link.tif", "D/dem.tif", 0) == TL_PATH_SAME, "a symbolic "
	    "link to the file: the same");
	ok(rel("E/../D/dem.tif", "D/dem.tif", 0) == TL_PATH_SAME, "through "
	    "..: the same");
	ok(rel("S/../dem.tif", "D/dem.tif", 0) == TL_PATH_SAME, "a link "
	    "then ..: .. of the link's target, not of the link");
	ok(rel("hard.tif", "D/dem.tif", 0) == TL_PATH_SAME, "a hard link: "
	    "the same");
	ok(rel("D", "D/dem.tif", 0) == TL_PATH_CONTAINS, "a directory "
	    "contains its file");
	ok(rel(".", "D/dem.tif", 0) == TL_PATH_CONTAINS, "an ancestor "
	    "contains it");
	ok(rel("L", "D/dem.tif", 0) == TL_PATH_CONTAINS, "a link to the "
	    "directory contains it");
	ok(rel("D/sub", "D", 0) == TL_PATH_INSIDE, "a subdirectory is inside");
	ok(rel("D/new/x", "D", 0) == TL_PATH_INSIDE, "a path not made yet "
	    "inside the directory");
	ok(rel("nothere/../D", "D/dem.tif", 0) == TL_PATH_CONTAINS, ".. past "
	    "a missing directory: taken by name");
	ok(rel("D/dem.tif/x", "D/dem.tif", 0) == TL_PATH_INSIDE, "a path "
	    "under a file: inside it");
	ok(rel("new", "D/none", 0) == TL_PATH_APART, "an input that does "
	    "not exist is never at risk");
	ok(rel("P", "P/out", TL_PATH_OUT) == TL_PATH_CONTAINS &&
	    rel("P/out/x", "P/out", TL_PATH_OUT) == TL_PATH_INSIDE &&
	    rel("P/./q", "P/q/", TL_PATH_OUT) == TL_PATH_SAME &&
	    rel("P/a", "P/b", TL_PATH_OUT) == TL_PATH_APART,
	    "two outputs not made yet: by name under one directory");
	ok(rel("D/sub", "D", TL_PATH_OUT) == TL_PATH_INSIDE, "an output "
	    "inside another that exists");
}

/* A pyramid whose level is a symbolic link out of it, and a hard link of
 * one of its files. */
static void
trees(void)
{
	mkdir(at("pyr"), 0777), mkdir(at("elsewhere"), 0777);
	mkdir(at("elsewhere/0"), 0777);
	put("pyr/index.json", "{}"), put("elsewhere/0/0_0.exr", "b");
	symlink("../elsewhere/0", at("pyr/0"));
	link(at("pyr/index.json"), at("ix.json"));

	ok(rel("elsewhere/0/0_0.exr", "pyr", 0) == TL_PATH_APART &&
	    rel("elsewhere/0/0_0.exr", "pyr", TL_PATH_TREE) == TL_PATH_INSIDE,
	    "a file reached through the tree's link: inside it as a tree");
	ok(rel("elsewhere/0/new.png", "pyr", TL_PATH_TREE) == TL_PATH_INSIDE,
	    "a new file in a directory the tree's link reaches: inside");
	ok(rel("elsewhere", "pyr", TL_PATH_TREE) == TL_PATH_CONTAINS,
	    "a directory holding what the tree's link reaches: contains it");
	ok(rel("ix.json", "pyr", 0) == TL_PATH_APART &&
	    rel("ix.json", "pyr", TL_PATH_TREE) == TL_PATH_INSIDE,
	    "a hard link of a file of the tree: inside it");
	ok(rel("other.png", "pyr", TL_PATH_TREE) == TL_PATH_APART,
	    "a file beside the tree: apart");
	symlink(".", at("pyr/self")), symlink("self", at("pyr/self2"));
	symlink("../../pyr", at("elsewhere/0/back"));
	ok(rel("other.png", "elsewhere", TL_PATH_TREE) == TL_PATH_APART &&
	    rel("pyr/x.png", "elsewhere", TL_PATH_TREE) == TL_PATH_INSIDE,
	    "links in loops: each directory walked once, what they reach "
	    "still found");
}

static void
messages(void)
{
	char o[PATH_MAX], in[PATH_MAX];
	tl_paths s = { 0 };
	tl_err e;

	snprintf(in, sizeof in, "%s", at("D/dem.tif"));
	snprintf(o, sizeof o, "%s", at("D"));
	ok(tl_path_check(o, in, "DEM", 0, &e) < 0 && strstr(e.msg, o) ==
	    e.msg && strstr(e.msg, ": contains the input DEM ") &&
	    strstr(e.msg, in), "the message names both: %s", e.msg);
	ok(tl_path_check(in, in, "DEM", 0, &e) < 0 &&
	    strstr(e.msg, ": is the input DEM "), "is: %s", e.msg);
	snprintf(o, sizeof o, "%s", at("D/sub/x.png"));
	ok(tl_path_check(o, at("D"), "pyramid", 0, &e) < 0 &&
	    strstr(e.msg, ": is inside the input pyramid "), "is inside: %s",
	    e.msg);
	ok(tl_paths_add(&s, "-", 0, &e, "stdin") == 0 && s.n == 0 &&
	    tl_paths_check(&s, "-", &e) == 0, "stdin and stdout: never "
	    "compared");
	tl_paths_add(&s, in, 0, &e, "the input DEM %s", in);
	ok(tl_paths_check(&s, "-", &e) == 0 && tl_paths_check(&s, at("E"),
	    &e) == 0 && tl_paths_check(&s, at("D"), &e) < 0, "a set: apart, "
	    "then contains");
	tl_paths_free(&s);

	mkdir(at("B"), 0777);
	put("B/b0.fqm", "x"), put("B/b1.fqm", "x");
	put("B/bands.txt", "fqm-bands 1\nb0.fqm\n# a comment\n  b1.fqm  \n");
	snprintf(in, sizeof in, "%s", at("B/bands.txt"));
	snprintf(o, sizeof o, "%s", at("B/b1.fqm"));
	ok(tl_path_check_raster(o, in, "FQM", &e) < 0 &&
	    strstr(e.msg, "a band of the input FQM"), "a band list's band: %s",
	    e.msg);
	snprintf(o, sizeof o, "%s", at("B/new.fqm"));
	ok(tl_path_check_raster(o, in, "FQM", &e) == 0, "beside the bands: "
	    "apart");
}

/* A bind mount is the same directory under another path (root only, in
 * a mount namespace of our own: skipped where that is refused). */
static void
bind_mount(void)
{
	char a[PATH_MAX], b[PATH_MAX];

	mkdir(at("real"), 0777), mkdir(at("bound"), 0777);
	put("real/dem.tif", "x");
	snprintf(a, sizeof a, "%s", at("real"));
	snprintf(b, sizeof b, "%s", at("bound"));
	if (unshare(CLONE_NEWNS) != 0 || mount("none", "/", "none", MS_REC |
	    MS_PRIVATE, NULL) != 0 || mount(a, b, "none", MS_BIND, NULL) != 0) {
		ok(1, "# SKIP bind mounts: not allowed here");
		return;
	}
	ok(rel("bound", "real/dem.tif", 0) == TL_PATH_CONTAINS &&
	    rel("bound/dem.tif", "real/dem.tif", 0) == TL_PATH_SAME,
	    "a bind mount of the directory: the same directory");
	umount(b);
}

int
main(void)
{
	if (tmpdir_make(dir, sizeof dir, "t_paths") < 0)
		return 1;
	relations();
	trees();
	messages();
	bind_mount();
	tmpdir_done(dir);
	return tap_done();
}
