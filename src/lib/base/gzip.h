/* gzip.h - whole gzip members in memory (RFC 1952), by zlib: what the
 * terrain tiles are written in on request (vgis2terrain -z) and what
 * their checker reads. base is zlib's only owner. */
#ifndef TL_GZIP_H
#define TL_GZIP_H

#include <stddef.h>

#include "base/util.h"

/* n bytes of src as one gzip member (level 9, deterministic for a given
 * zlib): 0 and *out malloc'd with *outlen bytes, or -1. */
int tl_gzip(const void *src, size_t n, unsigned char **out, size_t *outlen,
    tl_err *e);

/* The first gzip member of src inflated: 0 and *out malloc'd with
 * *outlen bytes, or -1 for a member that is damaged, cut short or
 * inflates past max bytes ("gzip stream ..."). */
int tl_gunzip(const void *src, size_t n, size_t max, unsigned char **out,
    size_t *outlen, tl_err *e);

#endif
