/* rs_list.c - a band list: a text file naming rasters that are column
 * bands of one raster, read as that one (fqm(5) BAND LISTS). Each band
 * keeps its own reader, so its own file descriptor and its own checks; a
 * row is the bands' rows side by side, a span the spans of the bands it
 * overlaps. Memory: the bands' readers and one band's row.
 *
 * The one call loop allowed between object files (tests/cmd/t_loops.sh):
 * a band list is a raster made of rasters, so the front door raster.c
 * opens a list here and the list opens its bands there
 * (rs_open_listed, which refuses a list inside a list), reading them
 * through rs_read_row and rs_read_span like any reader. */
#include "raster/rs_impl.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const unsigned char rs_list_magic[8] = { 'f', 'q', 'm', '-', 'b', 'a',
    'n', 'd' };

#define BD_FIRST "fqm-bands 1"
#define BD_MAXLIST (1 << 24) /* bytes: a list is paths, not data */

struct band {
	rs_reader *r;
	int x0; /* its column 0 among the list's columns */
};

struct bands {
	int n;      /* bands open */
	int by;     /* read by: 0 not yet, 1 rows, 2 spans */
	float *tmp; /* one band's row, every channel */
	struct band b[];
};

/* e's message prefixed with the list's name. */
static int
in_list(const rs_reader *r, tl_err *e)
{
	char m[sizeof e->msg];

	memcpy(m, e->msg, sizeof m);
	return tl_fail(e, "%s: %s", r->name, m);
}

__attribute__((format(printf, 4, 5))) static int
band_fail(const rs_reader *r, const rs_reader *b, tl_err *e,
    const char *fmt, ...)
{
	char m[sizeof e->msg];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(m, sizeof m, fmt, ap);
	va_end(ap);
	return tl_fail(e, "%s: %s: %s", r->name, b->name, m);
}

/* --- the list file ------------------------------------------------------ */

/* The whole list, NUL-terminated: r->pre, then the rest of r->fd. */
static char *
slurp(rs_reader *r, size_t *len, tl_err *e)
{
	size_t cap = 4096, n = (size_t)r->npre;
	char *s = tl_alloc(cap, 1, e), *t;
	ssize_t k;

	if (s == NULL)
		return NULL;
	memcpy(s, r->pre, n);
	for (;;) {
		if (n + 1 == cap) {
			if (cap >= BD_MAXLIST) {
				tl_fail(e, "%s: band list longer than %d bytes",
				    r->name, BD_MAXLIST);
				goto fail;
			}
			if ((t = realloc(s, cap * 2)) == NULL) {
				tl_fail(e, "%s: out of memory", r->name);
				goto fail;
			}
			s = t, cap *= 2;
		}
		k = read(r->fd, s + n, cap - 1 - n);
		if (k < 0 && errno == EINTR)
			continue;
		if (k < 0) {
			tl_failsys(e, "%s: read", r->name);
			goto fail;
		}
		if (k == 0)
			break;
		n += (size_t)k;
	}
	s[n] = '\0';
	if (strlen(s) != n) {
		tl_fail(e, "%s: NUL byte in a band list", r->name);
		goto fail;
	}
	*len = n;
	return s;
fail:
	free(s);
	return NULL;
}

/* Ends the lines in place and points ent[] at the bands' entries
 * (tl_list_entry: DEM lists' rules); their number, or -1. */
static int
split(const rs_reader *r, char *s, size_t len, char ***ent, tl_err *e)
{
	char *next;
	int n = 0, lines = 1;

	for (size_t i = 0; i < len; i++)
		if (s[i] == '\n')
			s[i] = '\0', lines++;
	if (strcmp(s, BD_FIRST) != 0)
		return tl_fail(e, "%s: first line is not \"%s\"", r->name,
		    BD_FIRST);
	if ((*ent = tl_alloc((size_t)lines, sizeof **ent, e)) == NULL)
		return -1;
	for (char *p = s + strlen(s) + 1; p < s + len; p = next) {
		next = p + strlen(p) + 1; /* before the entry is cut */
		if (((*ent)[n] = tl_list_entry(p)) != NULL)
			n++;
	}
	if (n == 0)
		return tl_fail(e, "%s: no bands", r->name);
	return n;
}

/* p relative to the list's directory; "-" stays a file. */
static char *
band_path(const rs_reader *r, const char *p, tl_err *e)
{
	const char *slash = strrchr(r->name, '/');
	char dir[4096];

	if (strcmp(p, "-") == 0)
		p = "./-";
	if (slash == NULL)
		return tl_list_path(NULL, p, e);
	if (slash - r->name >= (long)sizeof dir) {
		tl_fail(e, "%s: name too long", r->name);
		return NULL;
	}
	/* "" for a list in /: the entry becomes "/entry" */
	snprintf(dir, sizeof dir, "%.*s", (int)(slash - r->name), r->name);
	return tl_list_path(dir, p, e);
}

/* Bands are files: a FIFO or a device could block the open, or feed
 * anything; a missing file is left to rs_open_listed to report. */
static rs_reader *
open_band(const rs_reader *r, const char *p, tl_err *e)
{
	char *path = band_path(r, p, e);
	rs_reader *b = NULL;
	struct stat st;

	if (path == NULL)
		return NULL;
	if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
		tl_fail(e, "%s: %s: not a regular file", r->name, path);
	else if ((b = rs_open_listed(path, e)) == NULL)
		in_list(r, e);
	free(path);
	return b;
}

/* --- checks ------------------------------------------------------------- */

/* The band's RS_ATTR_X0, 0 when absent; -1 when not an int >= 0. */
static int
x0_of(const rs_header *h, int *x0)
{
	const rs_attr *a = rs_find_attr(h, RS_ATTR_X0);

	*x0 = 0;
	if (a == NULL)
		return 0;
	if (a->type != RS_INT || a->v.i < 0)
		return -1;
	*x0 = a->v.i;
	return 0;
}

static void
channel_names(const rs_header *h, char *s, size_t n)
{
	s[0] = '\0';
	for (int i = 0; i < h->nch; i++)
		snprintf(s + strlen(s), n - strlen(s), "%s%s", i ? "," : "",
		    h->ch[i]);
}

static int
same_channels(const rs_reader *r, const rs_reader *b, const rs_header *h0,
    tl_err *e)
{
	char want[RS_MAXCH * 33], got[RS_MAXCH * 33];
	int same = b->h.nch == h0->nch;

	for (int i = 0; same && i < h0->nch; i++)
		same = strcmp(b->h.ch[i], h0->ch[i]) == 0;
	if (same)
		return 0;
	channel_names(h0, want, sizeof want);
	channel_names(&b->h, got, sizeof got);
	return band_fail(r, b, e, "channels %s, the first band's %s", got,
	    want);
}

/* The same attributes, in any order (EXR sorts them), RS_ATTR_X0 apart. */
static int
same_attrs(const rs_reader *r, const rs_reader *b, const rs_header *h0,
    tl_err *e)
{
	for (int i = 0; i < h0->nattr; i++) {
		const rs_attr *a = &h0->attr[i];
		const rs_attr *o = rs_find_attr(&b->h, a->name);
		if (strcmp(a->name, RS_ATTR_X0) == 0)
			continue;
		if (o == NULL)
			return band_fail(r, b, e, "no attribute %s, which the "
			    "first band has", a->name);
		if (!rs_attr_same(a, o))
			return band_fail(r, b, e, "attribute %s differs from "
			    "the first band's", a->name);
	}
	for (int i = 0; i < b->h.nattr; i++) {
		const char *name = b->h.attr[i].name;
		if (strcmp(name, RS_ATTR_X0) != 0 &&
		    rs_find_attr(h0, name) == NULL)
			return band_fail(r, b, e, "attribute %s, which the "
			    "first band lacks", name);
	}
	return 0;
}

/* Every band against the first, each starting where the last ended; the
 * list's header: the first band's, as wide as all. */
static int
join(rs_reader *r, tl_err *e)
{
	struct bands *bd = r->impl;
	const rs_header *h0 = &bd->b[0].r->h;
	long long first = 0, x = 0;
	int x0, wmax = 0;

	for (int k = 0; k < bd->n; k++) {
		const rs_reader *b = bd->b[k].r;
		if (x0_of(&b->h, &x0) < 0)
			return band_fail(r, b, e, "%s is not an int >= 0",
			    RS_ATTR_X0);
		if (k == 0)
			first = x = x0;
		if (b->h.height != h0->height)
			return band_fail(r, b, e, "height %d, the first "
			    "band's %d", b->h.height, h0->height);
		if (same_channels(r, b, h0, e) < 0 ||
		    same_attrs(r, b, h0, e) < 0)
			return -1;
		if (x0 != x)
			return band_fail(r, b, e, "columns start at %d, "
			    "expected %lld", x0, x);
		bd->b[k].x0 = (int)(x - first);
		x += b->h.width;
		wmax = b->h.width > wmax ? b->h.width : wmax;
		if (x - first > RS_MAXDIM)
			return tl_fail(e, "%s: bands wider than %d columns "
			    "together", r->name, RS_MAXDIM);
	}
	if (rs_header_copy(&r->h, h0, e) < 0)
		return -1;
	r->h.width = (int)(x - first);
	if (first == 0)
		rs_unset(&r->h, RS_ATTR_X0);
	if (rs_check_size(&r->h, r->name, e) < 0)
		return -1;
	bd->tmp = tl_alloc((size_t)wmax * (size_t)h0->nch, sizeof *bd->tmp, e);
	return bd->tmp == NULL ? -1 : 0;
}

/* --- reading ------------------------------------------------------------ */

/* Read by rows, the bands keep in step; by spans, some may fall behind:
 * the two do not mix. */
static int
read_by(rs_reader *r, int how, tl_err *e)
{
	struct bands *bd = r->impl;

	if (bd->by != 0 && bd->by != how)
		return tl_fail(e, "%s: read by rows and by spans", r->name);
	bd->by = how;
	return 0;
}

static int
bd_read_row(rs_reader *r, float *row, tl_err *e)
{
	struct bands *bd = r->impl;
	size_t w = (size_t)r->h.width;

	if (read_by(r, 1, e) < 0)
		return -1;
	for (int k = 0; k < bd->n; k++) {
		const struct band *b = &bd->b[k];
		size_t bw = (size_t)b->r->h.width;
		float *t = bw == w ? row : bd->tmp;
		if (rs_read_row(b->r, t, e) < 0)
			return in_list(r, e);
		for (int c = 0; t != row && c < r->h.nch; c++)
			memcpy(row + c * w + (size_t)b->x0, t + c * bw,
			    bw * sizeof *row);
	}
	return 0;
}

/* Brings a band that spans left behind to row y: a stream file whose
 * spans come by pread skips there by position; any other reads and
 * discards the rows in between, checking them as it goes. */
static int
catch_up(rs_reader *b, int y, tl_err *e)
{
	float col[RS_MAXCH];

	if (b->y < y && b->full == NULL && b->skip != NULL &&
	    b->skip(b, y - b->y) == 0)
		b->y = y;
	while (b->y < y)
		if (rs_read_span(b, 0, 1, col, e) < 0)
			return -1;
	return 0;
}

static int
bd_read_span(rs_reader *r, int x0, int n, float *dst, tl_err *e)
{
	struct bands *bd = r->impl;

	if (read_by(r, 2, e) < 0)
		return -1;
	for (int k = 0; k < bd->n && bd->b[k].x0 < x0 + n; k++) {
		const struct band *b = &bd->b[k];
		int lo = x0 > b->x0 ? x0 : b->x0;
		int hi = b->x0 + b->r->h.width;
		float *t;
		if (hi > x0 + n)
			hi = x0 + n;
		if (lo >= hi)
			continue;
		t = hi - lo == n ? dst : bd->tmp;
		if (catch_up(b->r, r->y, e) < 0 ||
		    rs_read_span(b->r, lo - b->x0, hi - lo, t, e) < 0)
			return in_list(r, e);
		for (int c = 0; t != dst && c < r->h.nch; c++)
			memcpy(dst + (size_t)c * n + (lo - x0),
			    t + (size_t)c * (hi - lo),
			    (size_t)(hi - lo) * sizeof *dst);
	}
	return 0;
}

static void
bd_close(rs_reader *r)
{
	struct bands *bd = r->impl;

	if (bd == NULL)
		return;
	for (int k = 0; k < bd->n; k++)
		rs_close(bd->b[k].r);
	free(bd->tmp);
	free(bd);
	r->impl = NULL;
}

static int
open_bands(rs_reader *r, char **ent, int n, tl_err *e)
{
	struct bands *bd;

	bd = tl_alloc(1, sizeof *bd + (size_t)n * sizeof bd->b[0], e);
	if (bd == NULL)
		return -1;
	r->impl = bd;
	r->close = bd_close;
	for (int k = 0; k < n; k++) {
		if ((bd->b[bd->n].r = open_band(r, ent[k], e)) == NULL)
			return -1;
		bd->n++;
	}
	return 0;
}

/* The list is read whole and its descriptor closed: what stays open is
 * one descriptor per band. */
int
rs_list_open_read(rs_reader *r, tl_err *e)
{
	size_t len;
	char *s, **ent = NULL;
	int n, rv;

	if (!r->ownfd)
		return tl_fail(e, "%s: a band list is read from a file only "
		    "(its paths are relative to its directory)", r->name);
	if ((s = slurp(r, &len, e)) == NULL)
		return -1;
	close(r->fd);
	r->fd = -1;
	r->ownfd = 0;
	rv = (n = split(r, s, len, &ent, e)) < 0 ? -1 :
	    open_bands(r, ent, n, e);
	free(ent);
	free(s);
	if (rv < 0 || join(r, e) < 0)
		return -1;
	r->row = bd_read_row;
	r->span = bd_read_span;
	return 0;
}
