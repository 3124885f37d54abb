/* t_rs_list.c - band lists: a raster cut into column bands (stream, EXR or
 * both) reads as the whole, by rows and by spans, with bands skipped and
 * caught up; lists and bands that do not fit together are refused, named. */
#include "raster/raster.h"
#include "tap.h"
#include "tmpdir.h"
#include "urand.h"

#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define W 37
#define H 11
#define NCH 3

static char dir[PATH_MAX - 64];
static float whole[H][NCH][W]; /* the raster the bands are cut from */

static const char *
tmp(const char *name)
{
	return tmpdir_join(dir, name);
}

static void
fill_whole(void)
{
	unsigned s = 7;

	for (int y = 0; y < H; y++)
		for (int c = 0; c < NCH; c++)
			for (int x = 0; x < W; x++) {
				whole[y][c][x] = any_float(&s);
				if (c == 0 && x % 5 == 0) /* any bits: NaNs too */
					memcpy(&whole[y][c][x], &s, 4);
			}
}

/* The raster's header: w x ht, channels V X Z, attributes of each type,
 * fqm:x0 = x0 unless x0 < 0. */
static void
make_header(rs_header *h, int w, int ht, int x0)
{
	rs_header_init(h, w, ht);
	rs_add_channel(h, "Z", NULL);
	rs_add_channel(h, "V", NULL);
	rs_add_channel(h, "X", NULL);
	rs_set_int(h, "fqm:level", 3, NULL);
	rs_set_string(h, "fqm:kind", "vertices", NULL);
	rs_set_v2i(h, "fqm:size0", 289, 81, NULL);
	rs_set_v2d(h, "geo:step", 0.5, -0.25, NULL);
	rs_set_double(h, "geo:nodata", NAN, NULL);
	if (x0 >= 0)
		rs_set_int(h, RS_ATTR_X0, x0, NULL);
}

/* --- writing bands and lists -------------------------------------------- */

enum form { STREAM, EXR };

/* Columns c0 .. c0+h->width-1 of the raster's first h->height rows, as an
 * EXR file or a stream file (rs_create "-" with stdout on the file). */
static int
write_band(const char *path, enum form f, const rs_header *h, int c0)
{
	float row[NCH * W];
	rs_writer *w;
	tl_err e;
	int fd = -1, save = -1, rv = -1;

	if (f == STREAM) {
		fflush(stdout);
		fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
		save = dup(STDOUT_FILENO);
		dup2(fd, STDOUT_FILENO);
	}
	if ((w = rs_create(f == STREAM ? "-" : path, h, RS_ZIP, &e)) != NULL) {
		rv = 0;
		for (int y = 0; rv == 0 && y < h->height; y++) {
			for (int c = 0; c < h->nch; c++)
				memcpy(row + c * h->width,
				    &whole[y][c % NCH][c0],
				    (size_t)h->width * sizeof *row);
			rv = rs_write_row(w, row, &e);
		}
		rv = rv == 0 ? rs_finish(w, &e) : (rs_abort(w), -1);
	}
	if (f == STREAM) {
		dup2(save, STDOUT_FILENO);
		close(save);
		close(fd);
	}
	if (rv < 0)
		printf("# %s: %s\n", path, e.msg);
	return rv;
}

/* Bands cut at cut[0] = 0 < cut[1] < ... < cut[n] = W, named
 * prefix0.fqm (or .exr) ..., fqm:x0 = base + column (none on the first
 * band when base is 0 and noattr0). */
static int
write_bands(const char *prefix, const int *cut, int n, const enum form *f,
    int base, int noattr0)
{
	rs_header h;
	char name[64];
	int rv = 0;

	for (int k = 0; k < n; k++) {
		int x0 = k == 0 && noattr0 ? -1 : base + cut[k];
		snprintf(name, sizeof name, "%s%d.%s", prefix, k,
		    f[k] == EXR ? "exr" : "fqm");
		make_header(&h, cut[k + 1] - cut[k], H, x0);
		rv |= write_band(tmp(name), f[k], &h, cut[k]);
		rs_header_free(&h);
	}
	return rv;
}

/* A list file: the first line (NULL: the right one), then the lines. */
static const char *
write_list(const char *name, const char *first, ...)
{
	const char *path = tmp(name), *l;
	FILE *f = fopen(path, "w");
	va_list ap;

	fprintf(f, "%s\n", first != NULL ? first : "fqm-bands 1");
	va_start(ap, first);
	while ((l = va_arg(ap, const char *)) != NULL)
		fprintf(f, "%s\n", l);
	va_end(ap);
	fclose(f);
	return path;
}

/* The list of the bands write_bands made, with a comment and a blank. */
static const char *
list_of(const char *name, const char *prefix, int n, const enum form *f)
{
	const char *path = tmp(name);
	FILE *fp = fopen(path, "w");

	fprintf(fp, "fqm-bands 1\n# bands left to right\n\n");
	for (int k = 0; k < n; k++)
		fprintf(fp, "%s%d.%s\n", prefix, k, f[k] == EXR ? "exr" : "fqm");
	fclose(fp);
	return path;
}

/* --- reading ------------------------------------------------------------ */

/* Bit for bit. */
static int
same_attr(const rs_attr *a, const rs_attr *b)
{
	return strcmp(a->name, b->name) == 0 && rs_attr_same(a, b);
}

/* The list's header is the raster's: W wide, fqm:x0 = x0 or absent. */
static int
header_ok(const rs_header *h, int x0, tl_err *e)
{
	rs_header want;
	int v, ok = 1;

	make_header(&want, W, H, x0 > 0 ? x0 : -1);
	ok = h->width == W && h->height == H && h->nch == NCH &&
	    h->nattr == want.nattr;
	for (int i = 0; ok && i < NCH; i++)
		ok = strcmp(h->ch[i], want.ch[i]) == 0;
	for (int i = 0; ok && i < want.nattr; i++) {
		const rs_attr *a = &want.attr[i];
		int found = 0;
		for (int j = 0; j < h->nattr; j++)
			found |= same_attr(a, &h->attr[j]);
		ok = found;
	}
	rs_header_free(&want);
	if (ok && x0 == 0 && rs_get_int(h, RS_ATTR_X0, &v) == 0)
		ok = 0;
	return ok ? 0 : tl_fail(e, "header differs");
}

/* Every row by rs_read_row equals the raster's; then a read past the end
 * fails. */
static int
rows_match(const char *list, int x0, tl_err *e)
{
	rs_reader *r = rs_open(list, e);
	float row[NCH * W];
	int rv = 0;

	if (r == NULL)
		return -1;
	if (header_ok(rs_header_of(r), x0, e) < 0)
		rv = -1;
	for (int y = 0; rv == 0 && y < H; y++) {
		if (rs_read_row(r, row, e) < 0)
			rv = -1;
		else if (memcmp(row, whole[y], sizeof row) != 0)
			rv = tl_fail(e, "row %d differs", y);
	}
	if (rv == 0 && rs_read_row(r, row, e) == 0)
		rv = tl_fail(e, "a row past the last one read");
	rs_close(r);
	if (rv == 0)
		e->msg[0] = '\0';
	return rv;
}

/* Row y's span is span[y][0], n = span[y][1]: the raster's columns. */
static int
spans_match(const char *list, const int (*span)[2], tl_err *e)
{
	rs_reader *r = rs_open(list, e);
	float sp[NCH * W];
	int rv = 0;

	if (r == NULL)
		return -1;
	for (int y = 0; rv == 0 && y < H; y++) {
		int x0 = span[y][0], n = span[y][1];
		if (rs_read_span(r, x0, n, sp, e) < 0) {
			rv = -1;
			break;
		}
		for (int c = 0; rv == 0 && c < NCH; c++)
			if (memcmp(sp + c * n, &whole[y][c][x0],
			    (size_t)n * sizeof *sp) != 0)
				rv = tl_fail(e, "row %d channel %d differs", y,
				    c);
	}
	if (rv == 0 && rs_read_span(r, 0, 1, sp, e) == 0)
		rv = tl_fail(e, "a span past the last row read");
	rs_close(r);
	if (rv == 0)
		e->msg[0] = '\0';
	return rv;
}

/* The same span on every row. */
static int
span_match(const char *list, int x0, int n, tl_err *e)
{
	int span[H][2];

	for (int y = 0; y < H; y++)
		span[y][0] = x0, span[y][1] = n;
	return spans_match(list, (const int (*)[2])span, e);
}

/* Spans that move: bands left alone for rows, then caught up. */
static int
moving_spans(const char *list, tl_err *e)
{
	static const int span[H][2] = {
		{ 0, 3 }, { 1, 4 }, { 2, 2 },     /* first band only */
		{ 33, 4 }, { 35, 2 },             /* last band only */
		{ 0, W }, { 0, 1 },               /* all, then the first */
		{ 5, 25 }, { 36, 1 }, { 19, 2 }, { 0, W },
	};

	return spans_match(list, span, e);
}

/* Every fixed span of the tests: inside bands, across, all, the edges. */
static int
all_spans(const char *list, const int *cut, int nb, tl_err *e)
{
	int x[][2] = { { 0, W }, { 0, 1 }, { W - 1, 1 }, { 3, 5 },
	    { W - 6, 6 }, { 0, 0 }, { 0, 0 }, { 0, 0 } };
	int n = 5;

	if (nb > 1) { /* straddling the first cut, both sides, and its edge */
		x[n][0] = cut[1] - 2, x[n++][1] = 4;
		x[n][0] = cut[1], x[n++][1] = 1;
		x[n][0] = cut[1] - 1, x[n++][1] = 1;
	}
	for (int i = 0; i < n; i++)
		if (span_match(list, x[i][0], x[i][1], e) < 0) {
			char m[sizeof e->msg];
			memcpy(m, e->msg, sizeof m);
			return tl_fail(e, "span %d+%d: %s", x[i][0], x[i][1],
			    m);
		}
	return 0;
}

static int
open_fds(void)
{
	DIR *d = opendir("/proc/self/fd");
	int n = 0;

	if (d == NULL)
		return -1;
	while (readdir(d) != NULL)
		n++;
	closedir(d);
	return n;
}

/* The message of rs_open's refusal, or "" when it opened. */
static const char *
open_error(const char *path, tl_err *e)
{
	rs_reader *r = rs_open(path, e);

	if (r != NULL) {
		rs_close(r);
		e->msg[0] = '\0';
	}
	return e->msg;
}

static int
has(const char *msg, const char *a, const char *b)
{
	return strstr(msg, a) != NULL && (b == NULL || strstr(msg, b) != NULL);
}

/* --- tests -------------------------------------------------------------- */

static const enum form stream4[4] = { STREAM, STREAM, STREAM, STREAM };
static const enum form exr4[4] = { EXR, EXR, EXR, EXR };
static const enum form mix4[4] = { EXR, STREAM, STREAM, EXR };

static void
test_whole(void)
{
	static const int cut1[] = { 0, W }, cut2[] = { 0, 20, W },
	    cut4[] = { 0, 9, 10, 25, W };
	static const struct {
		const char *name;
		const int *cut;
		int n;
		const enum form *f;
		int base, noattr0;
	} set[] = {
		{ "one", cut1, 1, stream4, 0, 0 },
		{ "two", cut2, 2, stream4, 0, 1 },
		{ "four", cut4, 4, stream4, 0, 0 },
		{ "exr", cut4, 4, exr4, 0, 1 },
		{ "mix", cut4, 4, mix4, 0, 0 },
		{ "at100", cut2, 2, mix4 + 1, 100, 0 },
	};
	tl_err e = { { 0 } };
	char list[64], prefix[32];

	for (size_t i = 0; i < sizeof set / sizeof set[0]; i++) {
		const char *l;
		snprintf(prefix, sizeof prefix, "%s-", set[i].name);
		snprintf(list, sizeof list, "%s.bands", set[i].name);
		if (!ok(write_bands(prefix, set[i].cut, set[i].n, set[i].f,
		    set[i].base, set[i].noattr0) == 0, "%s: %d bands written",
		    set[i].name, set[i].n))
			continue;
		l = list_of(list, prefix, set[i].n, set[i].f);
		ok(rows_match(l, set[i].base, &e) == 0, "%s: %d bands read by "
		    "rows equal the whole raster, header too %s", set[i].name,
		    set[i].n, e.msg);
		ok(all_spans(l, set[i].cut, set[i].n, &e) == 0, "%s: spans "
		    "inside a band, across bands, all, at the edges %s",
		    set[i].name, e.msg);
		ok(moving_spans(l, &e) == 0, "%s: spans moving between bands "
		    "(bands left behind catch up) %s", set[i].name, e.msg);
	}
}

/* The list holds one descriptor per band, none of its own. */
static void
test_fds(void)
{
	tl_err e = { { 0 } };
	int before = open_fds();
	rs_reader *r = rs_open(tmp("mix.bands"), &e);

	ok(r != NULL && open_fds() - before == 4, "4 bands open: %d file "
	    "descriptors more %s", open_fds() - before, e.msg);
	rs_close(r);
	ok(open_fds() == before, "all closed by rs_close");
}

/* A row by spans and by rows is refused, whichever came first. */
static void
test_modes(void)
{
	tl_err e = { { 0 } };
	rs_reader *r = rs_open(tmp("four.bands"), &e);
	float row[NCH * W];

	ok(r != NULL && rs_read_span(r, 0, 3, row, &e) == 0 &&
	    rs_read_row(r, row, &e) < 0 && has(e.msg, "four.bands",
	    "by rows and by spans"), "spans then rows refused: %s", e.msg);
	rs_close(r);
	r = rs_open(tmp("four.bands"), &e);
	ok(r != NULL && rs_read_row(r, row, &e) == 0 &&
	    rs_read_span(r, 0, 3, row, &e) < 0 && has(e.msg, "four.bands",
	    "by rows and by spans"), "rows then spans refused: %s", e.msg);
	rs_close(r);
}

static long
file_size(const char *path)
{
	struct stat st;

	return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/* Copies src to dst, cut to n bytes (n < 0: whole), byte flip xor-ed. */
static void
damage(const char *src, const char *dst, long n, long flip)
{
	FILE *f = fopen(src, "rb"), *g = fopen(dst, "wb");
	int c;

	for (long i = 0; (n < 0 || i < n) && (c = getc(f)) != EOF; i++)
		putc(i == flip ? c ^ 0x5a : c, g);
	fclose(f);
	fclose(g);
}

/* Read system calls so far (pread included), or -1. */
static long
syscr(void)
{
	FILE *f = fopen("/proc/self/io", "r");
	char line[128];
	long n = -1;

	while (f != NULL && fgets(line, sizeof line, f) != NULL)
		if (sscanf(line, "syscr: %ld", &n) == 1)
			break;
	if (f != NULL)
		fclose(f);
	return n;
}

/* Band 2 of list, a complete stream file, left alone for rows 0 .. 5:
 * the span of row 6 costs a pread per channel of each band, one of band
 * 2's trailer and syscr's own read, not the 6 rows skipped (26). */
static void
skip_cost(const char *list)
{
	tl_err e = { { 0 } };
	rs_reader *r = rs_open(list, &e);
	float sp[NCH * W];
	long before, reads;
	int rv = r == NULL ? -1 : 0;

	for (int y = 0; rv == 0 && y < 6; y++)
		rv = rs_read_span(r, 0, 5, sp, &e);
	before = syscr();
	if (rv == 0)
		rv = rs_read_span(r, 18, 10, sp, &e);
	reads = syscr() - before;
	rs_close(r);
	if (before < 0)
		ok(1, "# SKIP no /proc/self/io");
	else
		ok(rv == 0 && reads <= 2 * NCH + 2, "band 2 skipped 6 rows "
		    "by position: %ld reads for the next span %s", reads,
		    e.msg);
}

/* A damaged band is found by its own reader, at the row that reaches it,
 * named; spans by pread check their rows' checksums, never other bands'. */
static void
test_damage(void)
{
	const char *b1 = tmp("two-1.fqm"), *d1 = tmp("dmg-1.fqm");
	long size = file_size(b1), rec = NCH * (W - 20) * 4 + 4;
	long row3 = size - 16 - (H - 3) * rec; /* row 3's record */
	tl_err e = { { 0 } };
	const char *l = write_list("dmg.bands", NULL, "two-0.fqm",
	    "dmg-1.fqm", NULL);
	int skip[H][2];

	damage(b1, d1, -1, row3 + 7);
	ok(rows_match(l, 0, &e) < 0 && has(e.msg, "dmg.bands: ",
	    "dmg-1.fqm: corrupt row 3 of 11"), "a corrupt row of band 2, "
	    "read by rows: %s", e.msg);
	ok(span_match(l, 0, 20, &e) == 0, "spans of band 1 alone do not read "
	    "band 2 %s", e.msg);
	damage(b1, d1, -1, row3 + rec - 2); /* row 3's checksum */
	ok(rows_match(l, 0, &e) < 0 && has(e.msg, "dmg.bands: ",
	    "corrupt row 3"), "a bad row checksum in band 2, by rows: %s",
	    e.msg);
	ok(span_match(l, 10, 20, &e) < 0 && has(e.msg, "dmg.bands: ",
	    "corrupt row 3"), "spans by pread check the checksums of the "
	    "rows they read: %s", e.msg);
	for (int y = 0; y < H; y++) /* band 2 left alone on rows 0 .. 5 */
		skip[y][0] = y < 6 ? 0 : 18, skip[y][1] = y < 6 ? 5 : 10;
	ok(spans_match(l, (const int (*)[2])skip, &e) == 0, "band 2 left "
	    "behind skips its rows by position %s", e.msg);
	skip_cost(l);
	damage(b1, d1, size - 16, -1);
	ok(rows_match(l, 0, &e) < 0 && has(e.msg, "dmg.bands: ",
	    "dmg-1.fqm: truncated after the last row"), "band 2 without "
	    "its trailer, by rows: %s", e.msg);
	ok(span_match(l, 0, 20, &e) == 0, "spans of band 1 alone never read "
	    "band 2 %s", e.msg);
	ok(spans_match(l, (const int (*)[2])skip, &e) < 0 &&
	    has(e.msg, "dmg.bands: ", "dmg-1.fqm: truncated after the last "
	    "row"), "... by spans, its skipped rows read and its end "
	    "checked: %s", e.msg);
	unlink(d1);
}

/* Lists and bands that do not make one raster are refused, named. */
static void
test_refused(void)
{
	rs_header h;
	tl_err e = { { 0 } };
	const char *l;
	int fd, save;

	make_header(&h, 17, H, 21); /* the second band, starting at 21 */
	write_band(tmp("x0.fqm"), STREAM, &h, 20);
	l = write_list("x0.bands", NULL, "two-0.fqm", "x0.fqm", NULL);
	ok(has(open_error(l, &e), "x0.bands: ", "x0.fqm: columns start at "
	    "21, expected 20"), "a band at the wrong column: %s", e.msg);
	l = write_list("order.bands", NULL, "two-1.fqm", "two-0.fqm", NULL);
	ok(has(open_error(l, &e), "order.bands: ", "two-0.fqm: columns "
	    "start at 0, expected 37"), "bands out of order: %s", e.msg);
	rs_header_free(&h);

	make_header(&h, 17, H - 1, 20);
	write_band(tmp("ht.fqm"), STREAM, &h, 20);
	l = write_list("ht.bands", NULL, "two-0.fqm", "ht.fqm", NULL);
	ok(has(open_error(l, &e), "ht.bands: ", "ht.fqm: height 10, the "
	    "first band's 11"), "a band of another height: %s", e.msg);
	rs_header_free(&h);

	make_header(&h, 17, H, 20);
	rs_add_channel(&h, "Y", NULL);
	write_band(tmp("ch.exr"), EXR, &h, 20);
	l = write_list("ch.bands", NULL, "two-0.fqm", "ch.exr", NULL);
	ok(has(open_error(l, &e), "ch.bands: ", "ch.exr: channels V,X,Y,Z, "
	    "the first band's V,X,Z"), "a band of other channels: %s", e.msg);
	rs_header_free(&h);

	make_header(&h, 17, H, 20);
	rs_set_v2d(&h, "geo:step", 0.5, 0.25, NULL);
	write_band(tmp("at.fqm"), STREAM, &h, 20);
	l = write_list("at.bands", NULL, "two-0.fqm", "at.fqm", NULL);
	ok(has(open_error(l, &e), "at.bands: ", "at.fqm: attribute "
	    "geo:step differs"), "a band with another attribute value: %s",
	    e.msg);
	rs_set_v2d(&h, "geo:step", 0.5, -0.25, NULL);
	rs_set_string(&h, "geo:vdatum", "EPSG:5773", NULL);
	write_band(tmp("at.fqm"), STREAM, &h, 20);
	ok(has(open_error(l, &e), "at.bands: ", "at.fqm: attribute "
	    "geo:vdatum, which the first band lacks"), "a band with an "
	    "attribute more: %s", e.msg);
	rs_unset(&h, "geo:vdatum");
	rs_unset(&h, "fqm:level");
	write_band(tmp("at.fqm"), STREAM, &h, 20);
	ok(has(open_error(l, &e), "at.bands: ", "at.fqm: no attribute "
	    "fqm:level"), "a band with an attribute less: %s", e.msg);
	rs_set_int(&h, "fqm:level", 3, NULL);
	rs_set_string(&h, RS_ATTR_X0, "20", NULL);
	write_band(tmp("at.fqm"), STREAM, &h, 20);
	ok(has(open_error(l, &e), "at.bands: ", "at.fqm: fqm:x0 is not an "
	    "int"), "fqm:x0 a string: %s", e.msg);
	rs_header_free(&h);

	l = write_list("miss.bands", NULL, "two-0.fqm", "nothere.fqm", NULL);
	ok(has(open_error(l, &e), "miss.bands: ", "nothere.fqm: cannot "
	    "open: No such file"), "a missing band: %s", e.msg);
	l = write_list("empty.bands", NULL, "", "# none", NULL);
	ok(has(open_error(l, &e), "empty.bands: no bands", NULL),
	    "no bands: %s", e.msg);
	l = write_list("v2.bands", "fqm-bands 2", "two-0.fqm", NULL);
	ok(has(open_error(l, &e), "v2.bands: first line is not \"fqm-bands "
	    "1\"", NULL), "another version: %s", e.msg);
	l = write_list("sp.bands", "fqm-bands 1 ", "two-0.fqm", NULL);
	ok(has(open_error(l, &e), "sp.bands: first line", NULL),
	    "a first line with a space more: %s", e.msg);
	l = write_list("nest.bands", NULL, "two.bands", NULL);
	ok(has(open_error(l, &e), "nest.bands: ", "two.bands: a band list "
	    "cannot be a band"), "a list in a list: %s", e.msg);
	l = write_list("self.bands", NULL, "self.bands", NULL);
	ok(has(open_error(l, &e), "self.bands: ", "self.bands: a band list "
	    "cannot be a band"), "a list naming itself: %s", e.msg);
	l = write_list("dir.bands", NULL, ".", NULL);
	ok(has(open_error(l, &e), "dir.bands: ", "not a regular file"),
	    "a directory as a band: %s", e.msg);
	l = write_list("junk.bands", NULL, "junk.txt", NULL);
	write_list("junk.txt", "a text file", NULL);
	ok(has(open_error(l, &e), "junk.bands: ", "junk.txt: not an fqm "
	    "stream or EXR file"), "a band of text: %s", e.msg);

	fd = open(tmp("two.bands"), O_RDONLY);
	save = dup(STDIN_FILENO);
	dup2(fd, STDIN_FILENO);
	close(fd);
	ok(has(open_error("-", &e), "stdin: a band list is read from a file",
	    NULL), "a list on stdin: %s", e.msg);
	dup2(save, STDIN_FILENO);
	close(save);
}

/* Paths relative to the list's directory, whatever the working one. */
static void
test_paths(void)
{
	static const int cut[] = { 0, 12, W };
	static const enum form f[] = { STREAM, EXR };
	char abs1[PATH_MAX + 32];
	tl_err e = { { 0 } };
	int cwd = open(".", O_RDONLY | O_DIRECTORY);

	mkdir(tmp("sub"), 0755);
	mkdir(tmp("other"), 0755);
	ok(write_bands("sub/r-", cut, 2, f, 0, 0) == 0, "bands in sub/");
	write_list("sub/r.bands", NULL, "r-0.fqm", "r-1.exr", NULL);
	ok(rows_match(tmp("sub/r.bands"), 0, &e) == 0, "absolute list path, "
	    "bands beside it %s", e.msg);
	ok(chdir(dir) == 0 && rows_match("sub/r.bands", 0, &e) == 0,
	    "relative list path from its parent %s", e.msg);
	ok(chdir("other") == 0 && rows_match("../sub/r.bands", 0, &e) == 0,
	    "from a sibling directory %s", e.msg);
	ok(chdir("../sub") == 0 && rows_match("r.bands", 0, &e) == 0,
	    "from its own directory %s", e.msg);
	snprintf(abs1, sizeof abs1, "%s/sub/r-1.exr", dir);
	write_list("other/r.bands", NULL, "../sub/r-0.fqm", abs1, NULL);
	ok(chdir("/") == 0 && rows_match(tmp("other/r.bands"), 0, &e) == 0,
	    "a ../ path and an absolute one, from / %s", e.msg);
	/* a DEM list's rules: blanks around a path, an indented comment */
	write_list("sub/b.bands", NULL, "  r-0.fqm\t", "   # second", " r-1.exr ",
	    NULL);
	ok(rows_match(tmp("sub/b.bands"), 0, &e) == 0, "blanks around paths "
	    "dropped, an indented # a comment %s", e.msg);
	if (fchdir(cwd) != 0)
		perror("fchdir");
	close(cwd);
}

int
main(void)
{
	if (tmpdir_make(dir, sizeof dir, "t_rs_list") < 0) {
		perror(dir);
		return 1;
	}
	fill_whole();
	test_whole();
	test_fds();
	test_modes();
	test_damage();
	test_refused();
	test_paths();
	tmpdir_done(dir);
	return tap_done();
}
