/* t_raster.c - both raster forms: bit-exact round trips, determinism,
 * pipes, damage and truncation reported, clean aborts, bounded memory. */
#include "raster/raster.h"
#include "tap.h"
#include "tmpdir.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <openexr.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[PATH_MAX / 2];

/* Entries of d but . and .. (tmpdir.h). */
static int
entries(const char *d)
{
	return tmpdir_entries(d, "");
}

static const char *
tmp(const char *name)
{
	static char buf[4][PATH_MAX];
	static int k;

	k = (k + 1) % 4;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

/* --- data ------------------------------------------------------------- */

static const uint32_t special[] = {
	0x00000000, 0x80000000, /* +-0 */
	0x00000001, 0x807fffff, 0x00400000, /* denormals */
	0x00800000, 0x7f7fffff, 0xff7fffff, /* FLT_MIN, +-FLT_MAX */
	0x7f800000, 0xff800000, /* +-inf */
	0x7fc00000, 0x7fc12345, 0xffc00001, 0x7f800001, /* NaNs, payloads */
	0x3f800000, 0x4b000001, 0xc61c4000,
};
#define NSPECIAL (sizeof special / sizeof special[0])

static uint32_t
mix(uint32_t a, uint32_t b, uint32_t c)
{
	uint32_t h = a * 0x9e3779b1u ^ b * 0x85ebca77u ^ c * 0xc2b2ae3du;

	h ^= h >> 15, h *= 0x2c1b3c6du, h ^= h >> 12, h *= 0x297a2d39u;
	return h ^ h >> 15;
}

/* Row y, channel c: channel 0 any bit pattern, channel 1 the specials,
 * the others smooth terrain-like values. Distinct per (seed, y, c, x). */
static void
fill(float *row, int w, int nch, int y, uint32_t seed, int smooth)
{
	for (int c = 0; c < nch; c++)
		for (int x = 0; x < w; x++) {
			uint32_t u;
			float f = 1000.0f + 0.25f * (float)x - 0.5f * (float)y +
			    (float)c + (float)seed;
			if (smooth || c > 1)
				memcpy(&u, &f, 4);
			else if (c == 0)
				u = mix(seed, (uint32_t)y, (uint32_t)x);
			else
				u = special[(unsigned)(x + 3 * y) % NSPECIAL];
			memcpy(&row[(size_t)c * w + x], &u, 4);
		}
}

static void
make_header(rs_header *h, int w, int ht, int nch)
{
	static const char *const names[] = { "Z", "V", "Q.a11", "S", "Q.c",
	    "X", "Y", "Q.b1", "Q.a12", "Q.a13", "Q.a22", "Q.a23", "Q.a33",
	    "Q.b2", "Q.b3", "E" };

	rs_header_init(h, w, ht);
	for (int i = 0; i < nch; i++)
		rs_add_channel(h, names[i], NULL);
	rs_set_int(h, "fqm:version", 1, NULL);
	rs_set_string(h, "fqm:kind", "fqm", NULL);
	rs_set_int(h, "fqm:level", INT_MIN, NULL);
	rs_set_v2i(h, "fqm:size0", 3601, -7, NULL);
	rs_set_string(h, "geo:crs", "+proj=utm +zone=33 +datum=WGS84 "
	    "+units=m +no_defs \"quoted\" \xc3\xa9", NULL);
	rs_set_string(h, "geo:vdatum", "", NULL);
	rs_set_v2d(h, "geo:origin", -0.0, 1e-310, NULL);
	rs_set_v2d(h, "geo:step", 0.000277777777777778, -1.0 / 3.0, NULL);
	rs_set_double(h, "geo:unit", 0.1 + 0.2, NULL);
	rs_set_double(h, "geo:nodata", -32768.0, NULL);
	rs_set_int(h, "an_attribute_name_longer_than_31_bytes", 42, NULL);
}

static int
same_attr(const rs_attr *a, const rs_attr *b)
{
	return strcmp(a->name, b->name) == 0 && rs_attr_same(a, b);
}

/* Same size, channels and attributes (in any order: EXR sorts them). */
static int
same_header(const rs_header *a, const rs_header *b)
{
	if (a->width != b->width || a->height != b->height ||
	    a->nch != b->nch || a->nattr != b->nattr)
		return 0;
	for (int i = 0; i < a->nch; i++)
		if (strcmp(a->ch[i], b->ch[i]) != 0)
			return 0;
	for (int i = 0; i < a->nattr; i++) {
		int found = 0;
		for (int j = 0; j < b->nattr; j++)
			found |= same_attr(&a->attr[i], &b->attr[j]);
		if (!found)
			return 0;
	}
	return 1;
}

/* --- writing and reading whole rasters -------------------------------- */

/* Runs f with stdout on fd; TAP output is flushed around it. */
static int
with_stdout(int fd, int (*f)(void *), void *arg)
{
	int save, r;

	fflush(stdout);
	save = dup(STDOUT_FILENO);
	dup2(fd, STDOUT_FILENO);
	r = f(arg);
	dup2(save, STDOUT_FILENO);
	close(save);
	return r;
}

struct job {
	const char *path;
	const rs_header *h;
	enum rs_compression c;
	uint32_t seed;
	int smooth;
	tl_err e;
};

static int
write_raster(void *arg)
{
	struct job *j = arg;
	const rs_header *h = j->h;
	float *row = malloc(sizeof *row * (size_t)h->nch * (size_t)h->width);
	rs_writer *w = rs_create(j->path, h, j->c, &j->e);
	int r = w == NULL ? -1 : 0;

	for (int y = 0; r == 0 && y < h->height; y++) {
		fill(row, h->width, h->nch, y, j->seed, j->smooth);
		r = rs_write_row(w, row, &j->e);
	}
	if (w != NULL)
		r = r == 0 ? rs_finish(w, &j->e) : (rs_abort(w), -1);
	free(row);
	return r;
}

static int
write_file(const char *path, const rs_header *h, enum rs_compression c,
    uint32_t seed, tl_err *e)
{
	struct job j = { path, h, c, seed, 0, { { 0 } } };
	int r = write_raster(&j);

	*e = j.e;
	return r;
}

/* The stream form, "-" with stdout sent to path. */
static int
write_stream(const char *path, const rs_header *h, uint32_t seed, tl_err *e)
{
	struct job j = { "-", h, RS_ZIP, seed, 0, { { 0 } } };
	int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	int r = with_stdout(fd, write_raster, &j);

	close(fd);
	*e = j.e;
	return r;
}

/* Reads every row; 0 only if all rows came back bit-exact and want (if
 * not NULL) equals the header. *bad_row gets the row of an error. */
static int
check_raster(rs_reader *r, const rs_header *want, uint32_t seed,
    int *bad_row, tl_err *e)
{
	const rs_header *h = rs_header_of(r);
	size_t n = (size_t)h->nch * (size_t)h->width;
	float *row = malloc(n * sizeof *row), *ref = malloc(n * sizeof *ref);
	int rv = 0;

	*bad_row = -1;
	if (want != NULL && !same_header(want, h))
		rv = tl_fail(e, "header differs");
	for (int y = 0; rv == 0 && y < h->height; y++) {
		if (rs_read_row(r, row, e) < 0) {
			*bad_row = y;
			rv = -1;
			break;
		}
		fill(ref, h->width, h->nch, y, seed, 0);
		if (memcmp(row, ref, n * sizeof *row) != 0)
			rv = tl_fail(e, "row %d differs", y);
	}
	free(row);
	free(ref);
	return rv;
}

static int
check_file(const char *path, const rs_header *want, uint32_t seed, tl_err *e)
{
	rs_reader *r = rs_open(path, e);
	int bad_row, rv;

	if (r == NULL)
		return -1;
	rv = check_raster(r, want, seed, &bad_row, e);
	rs_close(r);
	return rv;
}

/* Reads path through stdin, feeding it from a child over a pipe. */
static int
check_piped(const char *path, const rs_header *want, uint32_t seed,
    tl_err *e)
{
	int p[2], save, rv, st;
	pid_t pid;

	if (pipe(p) != 0)
		return tl_fail(e, "pipe");
	if ((pid = fork()) == 0) {
		char buf[65536];
		int fd = open(path, O_RDONLY);
		ssize_t n;
		close(p[0]);
		while ((n = read(fd, buf, sizeof buf)) > 0)
			if (write(p[1], buf, (size_t)n) != n)
				_exit(1);
		_exit(0);
	}
	close(p[1]);
	save = dup(STDIN_FILENO);
	dup2(p[0], STDIN_FILENO);
	close(p[0]);
	rv = check_file("-", want, seed, e);
	dup2(save, STDIN_FILENO);
	close(save);
	waitpid(pid, &st, 0);
	return rv;
}

/* A child writes the stream to a pipe that is our stdin. */
static int
check_stream_pipe(const rs_header *h, uint32_t seed, tl_err *e)
{
	int p[2], save, rv, st;
	pid_t pid;

	if (pipe(p) != 0)
		return tl_fail(e, "pipe");
	fflush(stdout);
	if ((pid = fork()) == 0) {
		struct job j = { "-", h, RS_ZIP, seed, 0, { { 0 } } };
		close(p[0]);
		dup2(p[1], STDOUT_FILENO);
		close(p[1]);
		_exit(write_raster(&j) == 0 ? 0 : 1);
	}
	close(p[1]);
	save = dup(STDIN_FILENO);
	dup2(p[0], STDIN_FILENO);
	close(p[0]);
	rv = check_file("-", h, seed, e);
	dup2(save, STDIN_FILENO);
	close(save);
	waitpid(pid, &st, 0);
	if (rv == 0 && (!WIFEXITED(st) || WEXITSTATUS(st) != 0))
		rv = tl_fail(e, "writer process failed");
	return rv;
}

static long
file_size(const char *path)
{
	struct stat st;

	return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

static int
same_file(const char *a, const char *b)
{
	FILE *f = fopen(a, "rb"), *g = fopen(b, "rb");
	int same = f != NULL && g != NULL, c = 0;

	while (same && c != EOF)
		same = (c = getc(f)) == getc(g);
	if (f)
		fclose(f);
	if (g)
		fclose(g);
	return same;
}

/* Copies the first n bytes of src to dst, xor-ing byte flip (if >= 0). */
static void
damage(const char *src, const char *dst, long n, long flip)
{
	FILE *f = fopen(src, "rb"), *g = fopen(dst, "wb");
	int c;

	for (long i = 0; i < n && (c = getc(f)) != EOF; i++)
		putc(i == flip ? c ^ 0x5a : c, g);
	fclose(f);
	fclose(g);
}

static void
append(const char *path, const char *text)
{
	FILE *f = fopen(path, "ab");

	fputs(text, f);
	fclose(f);
}

/* --- tests ------------------------------------------------------------ */

static void
test_header(void)
{
	rs_header h, c;
	tl_err e = { { 0 } };
	double d[2];
	int v[2], i;
	char name[16];

	rs_header_init(&h, 3, 2);
	ok(rs_add_channel(&h, "Z", &e) == 0 && rs_add_channel(&h, "Q.a11",
	    &e) == 0 && rs_add_channel(&h, "S", &e) == 0 &&
	    rs_add_channel(&h, "Q.b1", &e) == 0 && rs_add_channel(&h, "E",
	    &e) == 0, "channels added");
	ok(h.nch == 5 && strcmp(h.ch[0], "E") == 0 &&
	    strcmp(h.ch[1], "Q.a11") == 0 && strcmp(h.ch[2], "Q.b1") == 0 &&
	    strcmp(h.ch[3], "S") == 0 && strcmp(h.ch[4], "Z") == 0,
	    "channels kept in strcmp order");
	ok(rs_channel(&h, "S") == 3 && rs_channel(&h, "X") == -1,
	    "rs_channel finds by name");
	ok(rs_add_channel(&h, "S", &e) < 0 && strstr(e.msg, "S") != NULL,
	    "duplicate channel refused: %s", e.msg);
	ok(rs_add_channel(&h, "0123456789012345678901234567890123", &e) < 0,
	    "32-byte channel name refused");
	ok(rs_need_channel(&h, "V", "x.exr", &e) < 0 &&
	    strcmp(e.msg, "x.exr: no channel V") == 0,
	    "rs_need_channel: %s", e.msg);
	for (i = 0; h.nch < RS_MAXCH; i++) {
		snprintf(name, sizeof name, "c%d", i);
		rs_add_channel(&h, name, NULL);
	}
	ok(rs_add_channel(&h, "zz", &e) < 0, "17th channel refused: %s",
	    e.msg);
	rs_clear_channels(&h);
	ok(h.nch == 0, "channels cleared");

	rs_set_int(&h, "a", 1, NULL);
	rs_set_string(&h, "b", "one", NULL);
	rs_set_string(&h, "b", "two", NULL);
	rs_set_v2d(&h, "c", 1.5, 2.5, NULL);
	ok(h.nattr == 3 && strcmp(rs_get_string(&h, "b"), "two") == 0,
	    "setter replaces a same-named attribute");
	rs_set_double(&h, "a", 0.5, NULL);
	ok(rs_get_int(&h, "a", &i) < 0 && rs_get_double(&h, "a", d) == 0 &&
	    d[0] == 0.5, "a replacement may change the type");
	ok(rs_get_v2i(&h, "c", v) < 0 && rs_get_v2d(&h, "c", d) == 0 &&
	    d[1] == 2.5 && rs_get_string(&h, "c") == NULL,
	    "getters check the type");
	ok(rs_header_copy(&c, &h, &e) == 0 && c.attr[1].s != h.attr[1].s &&
	    strcmp(rs_get_string(&c, "b"), "two") == 0, "deep copy");
	rs_unset(&h, "b");
	ok(h.nattr == 2 && rs_get_string(&h, "b") == NULL &&
	    rs_get_v2d(&h, "c", d) == 0 && rs_get_string(&c, "b") != NULL,
	    "unset removes one attribute, the copy keeps it");
	ok(rs_set_int(&h, "0123456789012345678901234567890123456789"
	    "012345678901234567890123", 1, &e) < 0, "64-byte name refused");
	for (i = 0; h.nattr < RS_MAXATTR; i++) {
		snprintf(name, sizeof name, "n%d", i);
		rs_set_int(&h, name, i, NULL);
	}
	ok(rs_set_string(&h, "one-more", "x", &e) < 0 && h.nattr ==
	    RS_MAXATTR, "65th attribute refused: %s", e.msg);
	rs_header_free(&h);
	rs_header_free(&c);
}

static void
test_compression(void)
{
	enum rs_compression c;

	ok(rs_compression_parse("zip", &c) == 0 && c == RS_ZIP &&
	    rs_compression_parse("none", &c) == 0 && c == RS_NONE &&
	    rs_compression_parse("rle", &c) == 0 && c == RS_RLE &&
	    rs_compression_parse("zips", &c) == 0 && c == RS_ZIPS &&
	    rs_compression_parse("piz", &c) == 0 && c == RS_PIZ &&
	    rs_compression_parse("dwaa", &c) < 0, "compression names");
}

static void
test_exr(void)
{
	static const char *const cname[] = { "zip", "none", "rle", "zips",
	    "piz" };
	rs_header h;
	tl_err e = { { 0 } };

	make_header(&h, 37, 53, 5);
	for (int c = RS_ZIP; c <= RS_PIZ; c++) {
		int w = write_file(tmp("a.exr"), &h, c, 7, &e);
		ok(w == 0 && check_file(tmp("a.exr"), &h, 7, &e) == 0,
		    "EXR %s round trip bit-exact, header equal: %s", cname[c],
		    w == 0 ? e.msg : "write failed");
	}
	write_file(tmp("a.exr"), &h, RS_ZIP, 7, &e);
	write_file(tmp("b.exr"), &h, RS_ZIP, 7, &e);
	ok(same_file(tmp("a.exr"), tmp("b.exr")),
	    "two EXR writes are byte-identical");
	ok(check_piped(tmp("a.exr"), &h, 7, &e) == 0,
	    "EXR through a pipe (spooled) %s", e.msg);
	rs_header_free(&h);

	make_header(&h, 1, 1, 1);
	ok(write_file(tmp("c.exr"), &h, RS_PIZ, 3, &e) == 0 &&
	    check_file(tmp("c.exr"), &h, 3, &e) == 0, "1x1 EXR");
	rs_header_free(&h);
}

static void
test_stream(void)
{
	rs_header h;
	tl_err e = { { 0 } };
	int fd, save;

	make_header(&h, 37, 53, 16);
	ok(write_stream(tmp("a.fqm"), &h, 9, &e) == 0 &&
	    check_file(tmp("a.fqm"), &h, 9, &e) == 0,
	    "stream round trip bit-exact, header in order: %s", e.msg);
	write_stream(tmp("b.fqm"), &h, 9, &e);
	ok(same_file(tmp("a.fqm"), tmp("b.fqm")),
	    "two stream writes are byte-identical");
	ok(check_piped(tmp("a.fqm"), &h, 9, &e) == 0,
	    "stream through a pipe: %s", e.msg);
	ok(check_stream_pipe(&h, 11, &e) == 0,
	    "stream from a writer process through a pipe: %s", e.msg);
	rs_header_free(&h);
	make_header(&h, 9000, 5, 8); /* rows larger than the buffers */
	ok(check_stream_pipe(&h, 12, &e) == 0,
	    "288 kB rows through a pipe: %s", e.msg);
	ok(write_stream(tmp("w.fqm"), &h, 13, &e) == 0 &&
	    check_file(tmp("w.fqm"), &h, 13, &e) == 0 &&
	    write_file(tmp("w.exr"), &h, RS_ZIP, 13, &e) == 0 &&
	    check_file(tmp("w.exr"), &h, 13, &e) == 0,
	    "288 kB rows in files, both forms: %s", e.msg);
	unlink(tmp("w.fqm"));
	unlink(tmp("w.exr"));
	rs_header_free(&h);
	make_header(&h, 37, 53, 16);
	fd = open(tmp("a.fqm"), O_RDONLY);
	save = dup(STDIN_FILENO);
	dup2(fd, STDIN_FILENO);
	close(fd);
	ok(check_file("-", &h, 9, &e) == 0, "stream as stdin file: %s",
	    e.msg);
	fd = open(tmp("a.exr"), O_RDONLY);
	dup2(fd, STDIN_FILENO);
	close(fd);
	ok(check_file("-", NULL, 7, &e) == 0, "EXR as stdin file: %s", e.msg);
	dup2(save, STDIN_FILENO);
	close(save);
	rs_header_free(&h);
}

/* Columns x0 .. x0+n-1 of every row by rs_read_span: the rows' own values,
 * channel c at c n. */
static int
check_spans(const char *path, int x0, int n, uint32_t seed, tl_err *e)
{
	rs_reader *r = rs_open(path, e);
	const rs_header *h;
	float *sp = NULL, *ref = NULL;
	int rv = -1;

	if (r == NULL)
		return -1;
	h = rs_header_of(r);
	sp = malloc((size_t)n * h->nch * sizeof *sp);
	ref = malloc((size_t)h->width * h->nch * sizeof *ref);
	for (int y = 0; y < h->height; y++) {
		if (rs_read_span(r, x0, n, sp, e) < 0)
			goto out;
		fill(ref, h->width, h->nch, y, seed, 0);
		for (int c = 0; c < h->nch; c++)
			if (memcmp(sp + (size_t)c * n,
			    ref + (size_t)c * h->width + x0,
			    (size_t)n * sizeof *sp) != 0) {
				tl_fail(e, "row %d channel %d differs", y, c);
				goto out;
			}
	}
	rv = rs_read_span(r, x0, n, sp, e) < 0 ? 0 :
	    tl_fail(e, "a span past the last row read");
	if (rv == 0)
		e->msg[0] = '\0';
out:
	free(sp);
	free(ref);
	rs_close(r);
	return rv;
}

static void
test_spans(void)
{
	const char *src = tmp("s.fqm"), *cut = tmp("s-cut.fqm");
	rs_header h;
	tl_err e = { { 0 } };

	make_header(&h, 300, 41, 3);
	ok(write_stream(src, &h, 21, &e) == 0 &&
	    check_spans(src, 0, 300, 21, &e) == 0 &&
	    check_spans(src, 17, 5, 21, &e) == 0 &&
	    check_spans(src, 299, 1, 21, &e) == 0,
	    "stream file: spans of 300, 5 and 1 columns read alone %s", e.msg);
	ok(write_file(tmp("s.exr"), &h, RS_ZIP, 21, &e) == 0 &&
	    check_spans(tmp("s.exr"), 120, 64, 21, &e) == 0,
	    "EXR file: spans from whole rows %s", e.msg);
	ok(check_piped(src, &h, 21, &e) == 0, "stream on a pipe %s", e.msg);
	/* a stream file one byte short: no spans by pread, whole rows read,
	 * the truncation found where it is */
	/* a flipped byte in row 4's checksum: a span by pread checks the
	 * row it reads as whole rows do (fqm(5): damage reported by row) */
	damage(src, cut, file_size(src), file_size(src) - 16 -
	    36 * (3 * 300 * 4 + 4) - 2);
	ok(check_spans(cut, 17, 5, 21, &e) < 0 && strstr(e.msg, "row 4") !=
	    NULL && check_file(cut, &h, 21, &e) < 0 &&
	    strstr(e.msg, "row 4") != NULL, "spans of a stream file come by "
	    "pread: a bad row checksum is reported by row (%s)", e.msg);
	damage(src, cut, file_size(src) - 1, -1);
	ok(check_spans(cut, 17, 5, 21, &e) < 0 &&
	    strstr(e.msg, "trailer") != NULL, "a truncated stream file: "
	    "read by whole rows, the truncation reported: %s", e.msg);
	damage(src, cut, file_size(src), file_size(src) - 3);
	ok(check_spans(cut, 17, 5, 21, &e) < 0 &&
	    strstr(e.msg, "trailer") != NULL, "a damaged trailer: read by "
	    "whole rows, reported: %s", e.msg);
	damage(src, cut, file_size(src), -1);
	append(cut, "x");
	ok(check_spans(cut, 17, 5, 21, &e) < 0 &&
	    strstr(e.msg, "garbage") != NULL, "trailing garbage: read by "
	    "whole rows, reported: %s", e.msg);
	unlink(src), unlink(cut), unlink(tmp("s.exr"));
	rs_header_free(&h);
}

/* The first error reading path: from rs_open (*row = -2) or at a row. */
static const char *
first_error_seed(const char *path, uint32_t seed, int *row, tl_err *e)
{
	rs_reader *r = rs_open(path, e);

	*row = -2;
	if (r == NULL)
		return e->msg;
	if (check_raster(r, NULL, seed, row, e) == 0)
		snprintf(e->msg, sizeof e->msg, "no error");
	rs_close(r);
	return e->msg;
}

static const char *
first_error(const char *path, int *row, tl_err *e)
{
	return first_error_seed(path, 9, row, e);
}

static void
test_stream_damage(void)
{
	const char *src = tmp("a.fqm"), *dst = tmp("d.fqm");
	long size = file_size(src), rowb = 16 * 37 * 4 + 4;
	long end = size - 16; /* the trailer is 16 bytes */
	long hdr = end - 53 * rowb;
	const struct {
		long cut;
		const char *want;
		int row;
	} cuts[] = {
		{ 8, "truncated in the stream header", -2 },
		{ 30, "truncated in the stream header", -2 },
		{ hdr - 1, "truncated in the stream header", -2 },
		{ hdr, "truncated at row 0 of 53", 0 },
		{ hdr + 3 * rowb + 100, "truncated at row 3 of 53", 3 },
		{ hdr + 4 * rowb - 2, "truncated at row 3 of 53", 3 },
		{ end, "truncated after the last row", 52 },
		{ end + 7, "truncated in the end-of-stream trailer", 52 },
		{ size - 1, "truncated in the end-of-stream trailer", 52 },
	};
	tl_err e;
	int row;

	for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
		damage(src, dst, cuts[i].cut, -1);
		first_error(dst, &row, &e);
		ok(strstr(e.msg, cuts[i].want) != NULL && row == cuts[i].row,
		    "stream cut at %ld of %ld: %s", cuts[i].cut, size, e.msg);
	}
	damage(src, dst, size, hdr + 5 * rowb + 77);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "corrupt row 5 of 53") != NULL && row == 5,
	    "flipped byte in row data: %s", e.msg);
	damage(src, dst, size, hdr + 6 * rowb - 1);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "corrupt row 5 of 53") != NULL,
	    "flipped byte in a row checksum: %s", e.msg);
	damage(src, dst, size, 40);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "bad stream header") != NULL && row == -2,
	    "flipped byte in the header: %s", e.msg);
	damage(src, dst, size, 8);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "version") != NULL, "other version: %s", e.msg);
	damage(src, dst, size, 4);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "not an fqm stream or EXR file") != NULL,
	    "text-mode damage to the magic: %s", e.msg);
	damage(src, dst, size, size - 10);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "trailer") != NULL && row == 52,
	    "flipped byte in the trailer: %s", e.msg);
	damage(src, dst, size, -1);
	append(dst, "x");
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "garbage after the end") != NULL && row == 52,
	    "trailing garbage: %s", e.msg);
	damage(src, dst, 0, -1);
	append(dst, "not a raster\nat all\n");
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "not an fqm stream or EXR file") != NULL,
	    "garbage input: %s", e.msg);
	damage(src, dst, 0, -1);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "empty") != NULL, "empty input: %s", e.msg);
	first_error(tmp("nonexistent"), &row, &e);
	ok(strstr(e.msg, "No such file") != NULL, "missing file: %s", e.msg);
}

/* --- sizes a file cannot hold ------------------------------------------ */

static void
put32le(unsigned char *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (unsigned char)(v >> (8 * i));
}

/* A stream header alone, valid CRC: w x h, nch channels "a", "b", ...;
 * its length. */
static size_t
stream_header(unsigned char *b, uint32_t w, uint32_t h, int nch)
{
	static const unsigned char magic[8] = { 0x89, 'F', 'Q', 'M', '\r',
	    '\n', 0x1a, '\n' };
	size_t n = 8;

	memcpy(b, magic, 8);
	put32le(b + n, 1), n += 4;
	put32le(b + n, w), n += 4;
	put32le(b + n, h), n += 4;
	put32le(b + n, (uint32_t)nch), n += 4;
	put32le(b + n, 0), n += 4;
	for (int c = 0; c < nch; c++)
		b[n++] = 1, b[n++] = (unsigned char)('a' + c);
	put32le(b + n, (uint32_t)crc32(0, b, (uInt)n));
	return n + 4;
}

/* Opens path, or stdin fed with data by a pipe when path is NULL: the
 * message of a refusal, or "" when it opened. */
static const char *
open_error(const char *path, const unsigned char *data, size_t n, tl_err *e)
{
	rs_reader *r;
	int p[2], save = -1;

	e->msg[0] = '\0';
	if (path == NULL) {
		if (pipe(p) != 0 || write(p[1], data, n) != (ssize_t)n)
			return "pipe";
		close(p[1]);
		save = dup(STDIN_FILENO);
		dup2(p[0], STDIN_FILENO);
		close(p[0]);
	}
	r = rs_open(path != NULL ? path : "-", e);
	if (save >= 0) {
		dup2(save, STDIN_FILENO);
		close(save);
	}
	if (r != NULL) {
		rs_close(r);
		e->msg[0] = '\0';
	}
	return e->msg;
}

/* Headers declaring more data than the input can hold are refused when
 * opened, before any row or chunk buffer exists. */
static void
test_sizes(void)
{
	unsigned char b[256];
	const char *f = tmp("forged.fqm");
	rs_header h;
	tl_err e;
	size_t n;
	int fd;
	struct stat st;
	long off;
	char *buf;
	FILE *F;

	/* a stream declaring 1000 rows of 1 GiB in a 70-byte file */
	n = stream_header(b, 1 << 24, 1000, 16);
	fd = open(f, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	ok(write(fd, b, n) == (ssize_t)n && close(fd) == 0 &&
	    strstr(open_error(f, NULL, 0, &e), "truncated: the header "
	    "declares 1000 rows of 1073741824 bytes") != NULL,
	    "stream file declaring 1000 rows of 1 GiB: refused at open (%s)",
	    e.msg);
	/* the same on a pipe: the width is what can be checked */
	ok(open_error(NULL, b, n, &e)[0] == '\0', "on a pipe, 2^24 columns "
	    "are still a stream that could be (%s)", e.msg);
	n = stream_header(b, (1 << 24) + 1, 2, 1);
	ok(strstr(open_error(NULL, b, n, &e), "rows of 16777217 columns, "
	    "more than 16777216: refused on a pipe") != NULL,
	    "stream on a pipe with 2^24 + 1 columns: refused (%s)", e.msg);
	n = stream_header(b, 100, 3, 2);
	fd = open(f, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	ok(write(fd, b, n) == (ssize_t)n && close(fd) == 0 &&
	    open_error(f, NULL, 0, &e)[0] == '\0', "a short stream file "
	    "declaring less than 1 MiB opens (its rows say where it ends)");

	/* An EXR declaring 14549001 x 9 pixels of 13 floats (6.8 GB, a 12 GB
	 * chunk buffer) in a few KB: tests/fuzz/regress/raster/exr-chunk-12g
	 * rebuilt from a valid 1 x 9 file with a forged data window. */
	make_header(&h, 1, 9, 13);
	f = tmp("forged.exr");
	ok(write_file(f, &h, RS_ZIP, 3, &e) == 0, "a valid 1x9 EXR");
	rs_header_free(&h);
	F = fopen(f, "r+b");
	buf = calloc(1, 1 << 16);
	n = F != NULL ? fread(buf, 1, 1 << 16, F) : 0;
	off = -1;
	for (size_t i = 0; i + 20 < n; i++)
		if (memcmp(buf + i, "dataWindow\0box2i\0", 17) == 0)
			off = (long)i + 17 + 4 + 8; /* size, then min */
	if (F != NULL && off > 0) {
		unsigned char mx[4];
		put32le(mx, 14549000);
		fseek(F, off, SEEK_SET);
		fwrite(mx, 1, 4, F);
	}
	if (F != NULL)
		fclose(F);
	free(buf);
	stat(f, &st);
	ok(off > 0 && strstr(open_error(f, NULL, 0, &e), "the header "
	    "declares 14549001x9 pixels of 52 bytes") != NULL &&
	    strstr(e.msg, "damaged or forged") != NULL, "EXR of %lld bytes "
	    "declaring 6.8 GB of pixels: refused at open (%s)",
	    (long long)st.st_size, e.msg);
	unlink(tmp("forged.fqm"));
	unlink(f);
}

static void
test_exr_damage(void)
{
	const char *src = tmp("a.exr"), *dst = tmp("d.exr");
	long size = file_size(src);
	tl_err e;
	int row;

	damage(src, dst, size / 2, -1);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "truncated") != NULL, "EXR cut in half: %s", e.msg);
	damage(src, dst, 200, -1);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "truncated") != NULL && row == -2,
	    "EXR cut in the header: %s", e.msg);
	damage(src, dst, size - 1, -1);
	first_error(dst, &row, &e);
	ok(strstr(e.msg, "truncated") != NULL && row == -2,
	    "EXR missing its last byte: %s", e.msg);
	damage(src, dst, size, size / 2);
	first_error_seed(dst, 7, &row, &e);
	ok(row >= 0 && strstr(e.msg, "corrupt data at row") != NULL,
	    "EXR with a flipped byte in chunk data: %s", e.msg);
	damage(src, dst, size, size - 100);
	first_error_seed(dst, 7, &row, &e);
	ok(row >= 0 && strstr(e.msg, "corrupt data at row") != NULL,
	    "EXR with a flipped byte in the last chunk: %s", e.msg);
}

/* An EXR from elsewhere: HALF and UINT channels, a data window away from
 * the origin, an attribute type we do not carry. */
static int
write_foreign(const char *path)
{
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	exr_attr_box2i_t dw = { { { { 5, -3 } } }, { { { 9, 0 } } } };
	exr_attr_v2f_t swc = { { { 0, 0 } } };
	exr_context_t c;
	exr_chunk_info_t ci;
	exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
	uint16_t half[5][4];
	uint32_t uint[5][4];
	float flt[5][4];
	int rv = 0;

	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 5; x++) {
			half[x][y] = 0x3c00 + (uint16_t)(x + 5 * y); /* ~1 */
			uint[x][y] = (uint32_t)(1000 * y + x);
			flt[x][y] = -0.5f * (float)(x + y);
		}
	rv |= exr_start_write(&c, path, EXR_WRITE_FILE_DIRECTLY, &init);
	rv |= exr_add_part(c, NULL, EXR_STORAGE_SCANLINE, NULL);
	rv |= exr_initialize_required_attr(c, 0, &dw, &dw, 1, &swc, 1,
	    EXR_LINEORDER_INCREASING_Y, EXR_COMPRESSION_ZIPS);
	rv |= exr_add_channel(c, 0, "U", EXR_PIXEL_UINT, 0, 1, 1);
	rv |= exr_add_channel(c, 0, "F", EXR_PIXEL_FLOAT, 0, 1, 1);
	rv |= exr_add_channel(c, 0, "H", EXR_PIXEL_HALF, 0, 1, 1);
	rv |= exr_attr_set_float(c, 0, "someFloat", 1.5f);
	rv |= exr_attr_set_int(c, 0, "kept", 5);
	rv |= exr_write_header(c);
	for (int y = -3; rv == 0 && y <= 0; y++) {
		rv |= exr_write_scanline_chunk_info(c, 0, y, &ci);
		rv |= y == -3 ? exr_encoding_initialize(c, 0, &ci, &enc) :
		    exr_encoding_update(c, 0, &ci, &enc);
		for (int k = 0; k < enc.channel_count; k++) {
			exr_coding_channel_info_t *ch = &enc.channels[k];
			const char *n = ch->channel_name;
			ch->encode_from_ptr = n[0] == 'U' ?
			    (uint8_t *)&uint[0][y + 3] : n[0] == 'F' ?
			    (uint8_t *)&flt[0][y + 3] :
			    (uint8_t *)&half[0][y + 3];
			ch->user_pixel_stride = n[0] == 'H' ? 4 * 2 : 4 * 4;
			ch->user_line_stride = n[0] == 'H' ? 2 : 4;
			ch->user_bytes_per_element = n[0] == 'H' ? 2 : 4;
			ch->user_data_type = ch->data_type;
		}
		if (y == -3)
			rv |= exr_encoding_choose_default_routines(c, 0, &enc);
		rv |= exr_encoding_run(c, 0, &enc);
	}
	exr_encoding_destroy(c, &enc);
	rv |= exr_finish(&c);
	return rv;
}

static void
test_foreign(void)
{
	tl_err e = { { 0 } };
	rs_reader *r;
	float row[15];
	int good = 1, v;

	if (!ok(write_foreign(tmp("f.exr")) == 0, "foreign EXR written"))
		return;
	r = rs_open(tmp("f.exr"), &e);
	if (!ok(r != NULL, "foreign EXR opens: %s", e.msg))
		return;
	const rs_header *h = rs_header_of(r);
	ok(h->width == 5 && h->height == 4 && h->nch == 3 &&
	    strcmp(h->ch[0], "F") == 0 && strcmp(h->ch[1], "H") == 0 &&
	    strcmp(h->ch[2], "U") == 0, "size from the data window, channels");
	ok(h->nattr == 1 && rs_get_int(h, "kept", &v) == 0 && v == 5,
	    "float attribute ignored, int kept");
	for (int y = 0; y < 4; y++) {
		if (rs_read_row(r, row, &e) < 0) {
			good = 0;
			break;
		}
		for (int x = 0; x < 5; x++)
			good &= row[x] == -0.5f * (float)(x + y) &&
			    row[5 + x] == 1.0f + (float)(x + 5 * y) / 1024 &&
			    row[10 + x] == (float)(1000 * y + x);
	}
	ok(good, "FLOAT, HALF and UINT read by name as float %s", e.msg);
	ok(rs_read_row(r, row, &e) < 0, "read past the end fails: %s",
	    e.msg);
	rs_close(r);
}

static void
test_abort(void)
{
	rs_header h;
	tl_err e = { { 0 } };
	float row[16 * 37] = { 0 };
	rs_writer *w;
	char sub[PATH_MAX];
	int n;

	snprintf(sub, sizeof sub, "%s/sub", dir);
	mkdir(sub, 0755);
	make_header(&h, 37, 53, 16);
	w = rs_create(tmp("sub/x.exr"), &h, RS_ZIP, &e);
	for (int y = 0; w != NULL && y < 20; y++)
		rs_write_row(w, row, &e);
	ok(w != NULL && entries(sub) == 1, "a temporary while writing");
	rs_abort(w);
	ok(entries(sub) == 0, "rs_abort leaves nothing behind");
	w = rs_create(tmp("sub/x.exr"), &h, RS_ZIP, &e);
	for (int y = 0; w != NULL && y < 52; y++)
		rs_write_row(w, row, &e);
	ok(w != NULL && rs_finish(w, &e) < 0 && strstr(e.msg, "52 of 53") &&
	    entries(sub) == 0, "finish with a row missing fails, no file: %s",
	    e.msg);
	w = rs_create(tmp("sub/x.exr"), &h, RS_ZIP, &e);
	for (int y = 0; w != NULL && y < 53; y++)
		rs_write_row(w, row, &e);
	n = w != NULL ? rs_write_row(w, row, &e) : 0;
	ok(n < 0 && rs_finish(w, &e) == 0 && entries(sub) == 1,
	    "a 54th row is refused, the file still completes");
	unlink(tmp("sub/x.exr"));
	w = rs_create(tmp("nodir/x.exr"), &h, RS_ZIP, &e);
	ok(w == NULL && strstr(e.msg, "nodir/x.exr") != NULL,
	    "missing directory: %s", e.msg);
	if (geteuid() != 0) {
		chmod(sub, 0555);
		w = rs_create(tmp("sub/x.exr"), &h, RS_ZIP, &e);
		ok(w == NULL && entries(sub) == 0,
		    "read-only directory fails cleanly: %s", e.msg);
		chmod(sub, 0755);
	} else {
		/* root writes anywhere: an existing directory as the target
		 * is the unwritable case left. */
		w = rs_create(sub, &h, RS_ZIP, &e);
		ok(w == NULL && entries(sub) == 0,
		    "a directory as target fails cleanly: %s", e.msg);
	}
	rmdir(sub);
	rs_header_free(&h);
}

static int
write_to_closed_pipe(void *arg)
{
	struct job *j = arg;

	return write_raster(j);
}

static void
test_epipe(void)
{
	struct job j = { "-", NULL, RS_ZIP, 1, 0, { { 0 } } };
	struct sigaction ign = { .sa_handler = SIG_IGN }, old;
	rs_header h;
	int p[2];

	make_header(&h, 1000, 100, 4);
	j.h = &h;
	if (pipe(p) != 0)
		return;
	close(p[0]);
	sigaction(SIGPIPE, &ign, &old);
	ok(with_stdout(p[1], write_to_closed_pipe, &j) < 0 &&
	    strstr(j.e.msg, "stdout: write") != NULL,
	    "a closed pipe is a clean error: %s", j.e.msg);
	sigaction(SIGPIPE, &old, NULL);
	close(p[1]);
	rs_header_free(&h);
}

/* A full disk, as a file size limit: the error comes back from the EXR
 * encoder thread or the stream writer, and no file is left. */
static void
test_full(void)
{
	struct sigaction ign = { .sa_handler = SIG_IGN }, old;
	struct rlimit rl, lim;
	struct job j = { NULL, NULL, RS_NONE, 1, 0, { { 0 } } };
	rs_header h;
	char sub[PATH_MAX];
	int fd;

	snprintf(sub, sizeof sub, "%s/full", dir);
	mkdir(sub, 0755);
	make_header(&h, 1000, 100, 4);
	j.h = &h;
	getrlimit(RLIMIT_FSIZE, &rl);
	lim = rl;
	lim.rlim_cur = 100000;
	sigaction(SIGXFSZ, &ign, &old);
	setrlimit(RLIMIT_FSIZE, &lim);
	j.path = tmp("full/x.exr");
	ok(write_raster(&j) < 0 && strstr(j.e.msg, "File too large") &&
	    entries(sub) == 0, "EXR on a full disk: %s", j.e.msg);
	j.path = "-";
	fd = open(tmp("full/x.fqm"), O_WRONLY | O_CREAT | O_TRUNC, 0644);
	ok(with_stdout(fd, write_raster, &j) < 0 &&
	    strstr(j.e.msg, "stdout: write: File too large"),
	    "stream on a full disk: %s", j.e.msg);
	close(fd);
	setrlimit(RLIMIT_FSIZE, &rl);
	sigaction(SIGXFSZ, &old, NULL);
	unlink(tmp("full/x.fqm"));
	rmdir(sub);
	rs_header_free(&h);
}

static long
peak_kb(void)
{
	struct rusage ru;

	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss;
}

/* 2000x1500x13 is 156 MB of floats: a delta far below that shows that
 * neither form holds the raster. */
static void
test_memory(void)
{
	int W = 2000, H = 1500;
	rs_header h;
	tl_err e = { { 0 } };
	struct job j = { "-", &h, RS_ZIP, 0, 1, { { 0 } } };
	long before = peak_kb(), fd, rv;
	rs_reader *r;
	float *row;

	if (getenv("T_RASTER_SMALL") != NULL)
		W = 400, H = 300; /* under valgrind */
	make_header(&h, W, H, 13);
	row = malloc(sizeof *row * 13 * (size_t)W);
	j.path = tmp("m.exr");
	rv = write_raster(&j);
	r = rv == 0 ? rs_open(tmp("m.exr"), &e) : NULL;
	for (int y = 0; r != NULL && y < H && rv == 0; y++)
		rv = rs_read_row(r, row, &e);
	rs_close(r);
	ok(rv == 0 && r != NULL, "big EXR written and read: %s", j.e.msg);
	unlink(tmp("m.exr"));
	j.path = "-";
	fd = open(tmp("m.fqm"), O_WRONLY | O_CREAT | O_TRUNC, 0644);
	rv = with_stdout((int)fd, write_raster, &j);
	close((int)fd);
	r = rv == 0 ? rs_open(tmp("m.fqm"), &e) : NULL;
	for (int y = 0; r != NULL && y < H && rv == 0; y++)
		rv = rs_read_row(r, row, &e);
	rs_close(r);
	ok(rv == 0 && r != NULL, "big stream written and read: %s", e.msg);
	unlink(tmp("m.fqm"));
	if (TAP_SANITIZED)
		ok(1, "# SKIP peak RSS under ASan");
	else
		ok(peak_kb() - before < 40 * 1024, "peak RSS grew by %ld kB "
		    "for %d MB of raster", peak_kb() - before,
		    (int)((size_t)W * H * 13 * 4 >> 20));
	free(row);
	rs_header_free(&h);
}

static void
cleanup(void)
{
	static const char *const names[] = { "a.exr", "b.exr", "c.exr",
	    "d.exr", "f.exr", "a.fqm", "b.fqm", "d.fqm" };

	for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
		unlink(tmp(names[i]));
	ok(entries(dir) == 0 && rmdir(dir) == 0, "temporary directory clean");
}

/* EXR's ZIP: bytes split into even and odd halves, delta-coded, deflated;
 * the size OpenEXR's zip would produce for a chunk of n bytes. */
static size_t
zip_size(const unsigned char *in, size_t n, int level)
{
	unsigned char *t = malloc(n), *out;
	uLongf len = compressBound(n);
	size_t half = (n + 1) / 2;

	for (size_t i = 0; i < n; i++)
		t[i % 2 ? half + i / 2 : i / 2] = in[i];
	for (size_t i = n - 1; i > 0; i--)
		t[i] = (unsigned char)(t[i] - t[i - 1] + 128 + 256);
	out = malloc(len);
	compress2(out, &len, t, n, level);
	free(t), free(out);
	return len;
}

/* OpenEXRCore 3.1.5 writes a ZIP chunk whose deflated size is exactly
 * its raw size as the deflated bytes; readers take a chunk of raw size
 * for raw and return garbage (seen on a real block's lone last row).
 * exr.c stores such chunks raw: find a row that hits the tie and check
 * it round-trips, in ZIP and ZIPS. */
static void
test_zip_tie(void)
{
	enum { W = 129 };
	unsigned char row[2 * W * 4];
	int level, found = -1;

	exr_get_default_zip_compression_level(&level);
	if (level < 0)
		level = Z_DEFAULT_COMPRESSION;
	/* random bytes in the first k, zeros after: the size climbs past
	 * the raw size as k grows, hitting it exactly for some k */
	for (int k = 0; k <= (int)sizeof row && found < 0; k++) {
		unsigned s = 99;
		memset(row, 0, sizeof row);
		for (int i = 0; i < k; i++) {
			s ^= s << 13, s ^= s >> 17, s ^= s << 5;
			row[i] = (unsigned char)(s >> 8);
		}
		for (int i = 3; i < (int)sizeof row; i += 4) /* finite */
			if ((row[i] & 0x7f) == 0x7f && (row[i - 1] & 0x80))
				row[i] ^= 0x40;
		if (zip_size(row, sizeof row, level) == sizeof row)
			found = k;
	}
	ok(found >= 0, "a row whose ZIP size ties its raw size exists "
	    "(k = %d)", found);
	for (int c = 0; c < 2 && found >= 0; c++) {
		rs_header h;
		rs_writer *w;
		rs_reader *r = NULL;
		tl_err e;
		float back[2 * W];
		int same = 0;

		rs_header_init(&h, W, 1);
		rs_add_channel(&h, "E", &e);
		rs_add_channel(&h, "Z", &e);
		if ((w = rs_create(tmp("tie.exr"), &h, c ? RS_ZIPS : RS_ZIP,
		    &e)) != NULL && rs_write_row(w, (float *)row, &e) == 0 &&
		    rs_finish(w, &e) == 0 && (r = rs_open(tmp("tie.exr"), &e)) &&
		    rs_read_row(r, back, &e) == 0)
			same = memcmp(back, row, sizeof row) == 0;
		ok(same, "%s: the tying row round-trips bit-exact",
		    c ? "zips" : "zip");
		rs_close(r);
		rs_header_free(&h);
		unlink(tmp("tie.exr"));
	}
}

int
main(void)
{
	const char *t = getenv("TMPDIR");

	snprintf(dir, sizeof dir, "%s/t_raster.XXXXXX", t && *t ? t : "/tmp");
	if (mkdtemp(dir) == NULL) {
		perror(dir);
		return 1;
	}
	test_memory(); /* first: the peak RSS is the whole run's */
	test_header();
	test_compression();
	test_zip_tie();
	test_exr();
	test_stream();
	test_stream_damage();
	test_spans();
	test_exr_damage();
	test_sizes();
	test_foreign();
	test_abort();
	test_epipe();
	test_full();
	cleanup();
	return tap_done();
}
