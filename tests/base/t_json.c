/* t_json - base's JSON guards (json.h): a key given twice refused, a
 * syntax error worded (not taken for a failed allocation); numbers only
 * when numbers, integers only in range before they are narrowed; a write
 * that leaves the whole text and a newline, no temporary, and replaces
 * nothing when it fails. */
#include "base/json.h"
#include "tap.h"

#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/rmtree.h"

static char dir[256];

static void
test_parse(void)
{
	static const char dup[] = "{\"a\": 1, \"a\": 2}";
	static const char bad[] = "{\"a\": 1,}";
	static const char good[] = "{\"a\": [1.5, 3, 4294967296, \"x\"]}";
	json_error_t je;
	json_t *j, *a;
	double d;
	int oom = -1, v = 7;

	ok(tl_json_parse(dup, strlen(dup), &je, &oom) == NULL && !oom &&
	    json_error_code(&je) == json_error_duplicate_key,
	    "a key given twice is refused (%s)", je.text);
	ok(tl_json_parse(bad, strlen(bad), &je, &oom) == NULL && !oom &&
	    je.text[0] != '\0' && je.line == 1,
	    "a syntax error is worded, not an allocation (%s)", je.text);
	j = tl_json_parse(good, strlen(good), &je, &oom);
	a = json_object_get(j, "a");
	ok(j != NULL && oom == 0, "a valid text parses");
	ok(tl_json_num(json_array_get(a, 0), &d) == 0 && d == 1.5 &&
	    tl_json_num(json_array_get(a, 1), &d) == 0 && d == 3,
	    "numbers, integers included, read as numbers");
	d = -1;
	ok(tl_json_num(json_array_get(a, 3), &d) < 0 && d == -1 &&
	    tl_json_num(NULL, &d) < 0, "a string or nothing is no number");
	ok(tl_json_int(json_array_get(a, 1), 0, 3, &v) == 0 && v == 3,
	    "an integer at the top of its range");
	v = 7;
	ok(tl_json_int(json_array_get(a, 1), 0, 2, &v) < 0 && v == 7 &&
	    tl_json_int(json_array_get(a, 2), INT_MIN, INT_MAX, &v) < 0 &&
	    v == 7, "out of range (2^32 into an int): refused, not narrowed");
	ok(tl_json_int(json_array_get(a, 0), INT_MIN, INT_MAX, &v) < 0,
	    "1.5 is no integer");
	json_decref(j);
}

static int
entries(void)
{
	struct dirent *de;
	DIR *D = opendir(dir);
	int n = 0;

	while (D != NULL && (de = readdir(D)) != NULL)
		n += strcmp(de->d_name, ".") != 0 && strcmp(de->d_name, "..");
	if (D != NULL)
		closedir(D);
	return n;
}

static void
test_write(void)
{
	char path[512], text[256], bad[600];
	json_t *j = json_pack("{s:[f, i], s:s}", "v", 0.1, 42, "s", "x");
	tl_err e;
	FILE *f;
	size_t n = 0;

	snprintf(path, sizeof path, "%s/o.json", dir);
	ok(tl_json_write(j, JSON_INDENT(1) | JSON_SORT_KEYS |
	    JSON_REAL_PRECISION(17), path, &e) == 0, "written");
	if ((f = fopen(path, "r")) != NULL) {
		n = fread(text, 1, sizeof text - 1, f);
		fclose(f);
	}
	text[n] = '\0';
	ok(strcmp(text, "{\n \"s\": \"x\",\n \"v\": [\n  0.10000000000000001,\n"
	    "  42\n ]\n}\n") == 0, "the dump, flags kept, and a newline");
	ok(entries() == 1, "no temporary left beside it");
	snprintf(bad, sizeof bad, "%s/none/o.json", dir);
	ok(tl_json_write(j, 0, bad, &e) < 0 && strstr(e.msg, bad) != NULL,
	    "a directory missing: refused, the path named (%s)", e.msg);
	json_decref(j);
}

int
main(void)
{
	snprintf(dir, sizeof dir, "%s/t_json.XXXXXX",
	    getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(dir) == NULL)
		return 2;
	test_parse();
	test_write();
	tl_rmtree(dir);
	return tap_done();
}
