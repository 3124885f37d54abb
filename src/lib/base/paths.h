/* paths.h - whether writing an output could destroy an input: an output
 * file that is an input, an output directory that is, holds or lies
 * inside an input. Paths are compared as the kernel resolves them, not as
 * they are spelled: symbolic links and ".." resolved (realpath of what
 * exists; for what does not exist yet, realpath of its nearest existing
 * ancestor, then the rest, "." and ".." taken by name), and the device
 * and inode of every existing file and directory on the way compared, so
 * that a hard link or a bind mount is the same file. A program collects
 * its inputs in a tl_paths set (DEM files: dem.h's dem_paths) and checks
 * each output against it before any work. */
#ifndef TL_PATHS_H
#define TL_PATHS_H

#include "base/util.h"

enum tl_path_rel {
	TL_PATH_APART,   /* neither holds the other */
	TL_PATH_SAME,    /* one file or directory */
	TL_PATH_INSIDE,  /* out lies inside the directory in */
	TL_PATH_CONTAINS /* out is (or would be) a directory holding in */
};

/* Flags of an input. */
#define TL_PATH_TREE 1 /* a directory read whole (a pyramid): the files
                        * and directories its symbolic links reach, at
                        * any depth up to 8 (64 linked directories at
                        * most), are inside it too, and so is a hard
                        * link to one of its files */
#define TL_PATH_OUT 2  /* another output (plan and pyramid), compared
                        * even when neither exists yet; an input that
                        * does not exist is never at risk */

/* The relation of out to in: one of enum tl_path_rel, or -1 with e when
 * a path cannot be resolved (the current directory gone, too long). */
int tl_path_relation(const char *out, const char *in, int flags, tl_err *e);

/* The inputs to keep outputs off, each with its description. */
typedef struct tl_paths {
	struct tl_path_in *in;
	int n, cap;
} tl_paths;

/* Adds path ("-", stdin, is never at risk: not added), described by fmt
 * in messages, e.g. "the input DEM %s"; 0 or -1 (out of memory). */
int tl_paths_add(tl_paths *s, const char *path, int flags, tl_err *e,
    const char *fmt, ...) __attribute__((format(printf, 5, 6)));
/* Adds a raster input (an FQM or a vertex map, fqm(5)): the file, and a
 * band list's bands. */
int tl_paths_add_raster(tl_paths *s, const char *path, const char *what,
    tl_err *e);
/* 0 when out ("-", stdout: always 0) is apart from every input of s;
 * else -1 with e naming both, the first met: "OUT: is the input DEM X",
 * "OUT: contains ...", "OUT: is inside ...". */
int tl_paths_check(const tl_paths *s, const char *out, tl_err *e);
void tl_paths_free(tl_paths *s);

/* tl_paths_check against the one input in, "the input WHAT IN". */
int tl_path_check(const char *out, const char *in, const char *what,
    int flags, tl_err *e);

/* tl_paths_check against the raster in and a band list's bands (the
 * filters' fqmfilter in out, fqmsolve in out). */
int tl_path_check_raster(const char *out, const char *in, const char *what,
    tl_err *e);

#endif
