/* json.c - strict parsing, checked numbers and atomic writing of JSON
 * (json.h). */
#include "base/json.h"

#include <assert.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/outfile.h"

json_t *
tl_json_parse(const char *text, size_t n, json_error_t *je, int *oom)
{
	json_t *root;

	errno = 0;
	root = json_loadb(text, n, JSON_REJECT_DUPLICATES, je);
	/* an empty reason: an allocation failed inside jansson (its error
	 * code is not always set then) */
	*oom = root == NULL && (json_error_code(je) ==
	    json_error_out_of_memory || je->text[0] == '\0' ||
	    errno == ENOMEM);
	return root;
}

int
tl_json_num(const json_t *x, double *v)
{
	if (!json_is_number(x) || !isfinite(json_number_value(x)))
		return -1;
	*v = json_number_value(x);
	return 0;
}

int
tl_json_int(const json_t *x, long long lo, long long hi, int *v)
{
	assert(lo >= INT_MIN && hi <= INT_MAX);
	if (!json_is_integer(x) || json_integer_value(x) < lo ||
	    json_integer_value(x) > hi)
		return -1;
	*v = (int)json_integer_value(x);
	return 0;
}

int
tl_json_write(const json_t *j, size_t flags, const char *path, tl_err *e)
{
	char *text = json_dumps(j, flags);
	tl_outfile o;
	size_t n;
	int r;

	if (text == NULL)
		return tl_fail(e, "%s: out of memory", path);
	n = strlen(text);
	r = tl_out_begin(&o, path, e);
	if (r == 0 && (r = tl_pwrite(o.fd, text, n, 0, path, e)) == 0)
		r = tl_pwrite(o.fd, "\n", 1, (long long)n, path, e);
	free(text);
	if (r != 0) {
		tl_out_abort(&o);
		return -1;
	}
	return tl_out_commit(&o, e);
}
