/* t_rowpipe - the filters' drive (rowpipe.h): a raster made row by row by
 * a callback, as an EXR file or the stream on stdout, rows asked for once
 * each and in order; a failing callback or a bad header leaves no output
 * (and an existing file untouched). */
#include "raster/rowpipe.h"
#include "tap.h"
#include "tmpdir.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[PATH_MAX / 2];

static const char *
tmp(const char *name)
{
	return tmpdir_join(dir, name);
}

/* Entries of dir but . and .. */
static int
entries(void)
{
	return tmpdir_entries(dir, "");
}

typedef struct {
	int w, nch;
	int calls, order_bad;
	int fail_at; /* -1: never */
} gen;

static float
value(int y, int c, int x)
{
	return (float)(y * 1000 + c * 100 + x) + 0.25f;
}

static int
make_row(void *ctx, int y, float *row, tl_err *e)
{
	gen *g = ctx;

	g->order_bad += y != g->calls++;
	if (y == g->fail_at)
		return tl_fail(e, "row %d: the input ended", y);
	for (int c = 0; c < g->nch; c++)
		for (int x = 0; x < g->w; x++)
			row[c * g->w + x] = value(y, c, x);
	return 0;
}

static void
header(rs_header *h, int w, int hh)
{
	rs_header_init(h, w, hh);
	rs_add_channel(h, "Z", NULL);
	rs_add_channel(h, "V", NULL);
	rs_set_string(h, "fqm:kind", "test", NULL);
}

/* Every row of path as make_row made it, and the header's attribute. */
static int
readback(const char *path, const rs_header *h)
{
	tl_err e;
	rs_reader *r = rs_open(path, &e);
	float *row = malloc(sizeof *row * h->width * h->nch);
	int good = r != NULL && rs_header_of(r)->width == h->width &&
	    rs_header_of(r)->height == h->height &&
	    rs_get_string(rs_header_of(r), "fqm:kind") != NULL;

	for (int y = 0; good && y < h->height; y++) {
		good = rs_read_row(r, row, &e) == 0;
		for (int c = 0; good && c < h->nch; c++)
			for (int x = 0; good && x < h->width; x++)
				good = row[c * h->width + x] == value(y, c, x);
	}
	rs_close(r);
	free(row);
	return good;
}

static void
test_write(void)
{
	rs_header h;
	gen g = { 37, 2, 0, 0, -1 };
	tl_err e = { "" };
	struct stat st;
	int r;

	header(&h, 37, 29);
	r = rowpipe_run("test", tmp("a.exr"), &h, RS_ZIP, make_row, &g, &e);
	ok(r == 0 && g.calls == 29 && g.order_bad == 0, "rowpipe_run: every "
	    "row asked for once, in order (%d calls)", g.calls);
	ok(readback(tmp("a.exr"), &h) && entries() == 1, "the EXR holds "
	    "every row and the header's attributes, no temporary left");
	g.calls = 0;
	r = rowpipe_run("test", tmp("b.exr"), &h, RS_NONE, make_row, &g, &e);
	if (stat(tmp("b.exr"), &st) != 0)
		st.st_size = 0;
	ok(r == 0 && readback(tmp("b.exr"), &h) &&
	    st.st_size > 37 * 29 * 2 * 4, "compression none: the same rows, "
	    "uncompressed (%lld bytes)", (long long)st.st_size);
	unlink(tmp("b.exr"));
	rs_header_free(&h);
}

/* "-": the stream on stdout (here a file). */
static void
test_stream(void)
{
	rs_header h;
	gen g = { 5, 2, 0, 0, -1 };
	tl_err e = { "" };
	int out = dup(STDOUT_FILENO), f, r;

	header(&h, 5, 4);
	fflush(stdout);
	f = open(tmp("s.fqm"), O_CREAT | O_TRUNC | O_WRONLY, 0644);
	dup2(f, STDOUT_FILENO);
	close(f);
	r = rowpipe_run("test", "-", &h, RS_ZIP, make_row, &g, &e);
	dup2(out, STDOUT_FILENO);
	close(out);
	ok(r == 0 && readback(tmp("s.fqm"), &h), "rowpipe_run to \"-\": the "
	    "stream on stdout, every row");
	unlink(tmp("s.fqm"));
	rs_header_free(&h);
}

static void
test_failure(void)
{
	rs_header h;
	gen g = { 37, 2, 0, 0, 17 };
	tl_err e = { "" };

	header(&h, 37, 29);
	ok(rowpipe_run("test", tmp("c.exr"), &h, RS_ZIP, make_row, &g, &e) <
	    0 && strcmp(e.msg, "row 17: the input ended") == 0 &&
	    g.calls == 18, "a failing callback: -1 with its message, no row "
	    "asked for after it");
	ok(access(tmp("c.exr"), F_OK) != 0 && entries() == 1, "a failing "
	    "callback leaves no output file and no temporary");
	g.calls = 0, g.fail_at = 0;
	ok(rowpipe_run("test", tmp("a.exr"), &h, RS_ZIP, make_row, &g, &e) <
	    0 && readback(tmp("a.exr"), &h) && entries() == 1,
	    "a failure on the first row leaves an existing output as it was");
	rs_header_free(&h);
	rs_header_init(&h, 37, 29); /* no channel */
	g.calls = 0;
	ok(rowpipe_run("test", tmp("d.exr"), &h, RS_ZIP, make_row, &g, &e) <
	    0 && g.calls == 0 && access(tmp("d.exr"), F_OK) != 0,
	    "a header no raster can hold: refused before any row (%s)", e.msg);
	unlink(tmp("a.exr"));
}

int
main(void)
{
	if (tmpdir_make(dir, sizeof dir, "t_rowpipe") < 0) {
		perror(dir);
		return 1;
	}
	test_write();
	test_stream();
	test_failure();
	tmpdir_done(dir);
	return tap_done();
}
