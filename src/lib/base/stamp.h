/* stamp.h - what identifies input files, recorded once and checked
 * later: a plan's DEM (dem2vgis(1), PLANS), whose jobs must all read the
 * DEM that the plan was made from. Per file: its size, its modification
 * time to the nanosecond and its inode number. Not its device: one share
 * has other device numbers on other hosts, where a plan's jobs run. Not
 * a hash of its content: a job reads a window of the DEM, a hash all of
 * it, in every job. So a file replaced (another inode), rewritten in
 * place (mtime) or cut (size) is told apart; one rewritten in place with
 * its old mtime set back (touch -r) is not.
 *
 * The record, a text file: "tl-stamp 1", then a line a file,
 * "SIZE SEC NSEC INODE PATH", PATH absolute (one with a newline cannot
 * be recorded). */
#ifndef TL_STAMP_H
#define TL_STAMP_H

#include "base/util.h"

/* Records the n files (paths from the current directory; duplicates are
 * recorded once) into path, atomically. */
int stamp_write(const char *path, char **files, int n, tl_err *e);

/* Every file recorded in path as it was; fails naming the first that is
 * not, or is gone, and what changed. */
int stamp_check(const char *path, tl_err *e);

/* dem_stamp.c (GDAL): stamp_write of every file that reading the n DEMs
 * opens: each DEM, a list's entries (dem2fqm(1), MOSAICS), and each
 * raster's files as GDAL names them (GDALGetFileList: sidecars such as
 * .hdr, .prj or a world file; a VRT's sources, nested VRTs followed).
 * "-": a list on stdin, whose entries are recorded (not stdin). */
int dem_stamp(const char *path, char *const *dems, int n, tl_err *e);

#endif
