/* json.h - JSON for every layer that reads or writes it (vgis(5)'s
 * index.json, 3D Tiles): jansson, included here only, and the guards
 * each reader of untrusted text needs.
 *
 * A text is parsed strictly: a key given twice is refused, not resolved
 * by the last one. Numbers read are finite and integers range-checked
 * before they are narrowed. A file is written as outfile.h's: complete
 * or not at all. The wording of a refusal stays with each reader (the
 * checker's reader shares nothing of the other's but these guards). */
#ifndef TL_JSON_H
#define TL_JSON_H

#include <jansson.h>
#include <stddef.h>

#include "base/util.h"

/* n bytes of text, duplicate keys refused: the root, or NULL with je
 * filled and *oom 1 when the failure was an allocation (jansson words
 * every syntax error: a failure without words, or ENOMEM, is one). */
json_t *tl_json_parse(const char *text, size_t n, json_error_t *je,
    int *oom);
/* A finite number into *v: 0, or -1 (x not a number, or not finite). */
int tl_json_num(const json_t *x, double *v);
/* An integer in lo .. hi into *v, checked before it is narrowed: 0, or
 * -1. */
int tl_json_int(const json_t *x, long long lo, long long hi, int *v);
/* Writes j, as json_dumps(j, flags) and a newline, to path through
 * outfile.h (atomically; "path: out of memory" or outfile.h's failure). */
int tl_json_write(const json_t *j, size_t flags, const char *path,
    tl_err *e);

#endif
