/* stream.c - the fqm(5) stream: a raster framed for pipes, read and written
 * strictly in sequence. Little-endian throughout; a CRC-32 guards the
 * header, every row and the trailer, so truncation and damage are reported
 * by row, never passed on as data. One concern in one file, over 600
 * lines: the format, its writer and its reader, which mirror each
 * other's framing (order, CRCs, attribute encoding) and change together. */
#include "base/byteorder.h"
#include "raster/rs_impl.h"

#include <errno.h>
#include <libdeflate.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

/* PNG-style: a high-bit byte, CR LF, ^Z, LF expose 7-bit and text-mode
 * damage. */
const unsigned char rs_stream_magic[8] = { 0x89, 'F', 'Q', 'M', '\r', '\n',
    0x1a, '\n' };

#define ST_VERSION 1
#define BUFSZ (256 * 1024)

enum { T_INT = 1, T_DOUBLE, T_STRING, T_V2I, T_V2D }; /* type codes */

static const unsigned char st_end[8] = { 0x89, 'E', 'N', 'D', '\r', '\n',
    0x1a, '\n' };

/* CRC-32 (ISO-HDLC, zlib's crc32): libdeflate's uses PCLMUL where the
 * CPU has it, several times zlib's speed, the same values. */
static uint32_t
crc(uint32_t c, const void *p, size_t n)
{
	return libdeflate_crc32(c, p, n);
}

/* --- writing ---------------------------------------------------------- */

struct st_wr {
	int fd;
	size_t len;      /* buffered bytes */
	uint32_t crc;    /* running CRC of the current section */
	size_t rowbytes;
	float *tmp;      /* big-endian hosts: the row swapped */
	unsigned char buf[BUFSZ];
};

static int
drain(rs_writer *w, const unsigned char *p, size_t n, tl_err *e)
{
	struct st_wr *s = w->impl;

	while (n > 0) {
		ssize_t r = write(s->fd, p, n);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return tl_failsys(e, "%s: write", w->name);
		p += r, n -= (size_t)r;
	}
	return 0;
}

static int
flush(rs_writer *w, tl_err *e)
{
	struct st_wr *s = w->impl;
	int r = drain(w, s->buf, s->len, e);

	s->len = 0;
	return r;
}

/* The buffered bytes, then n bytes at p, by writev: a row goes out
 * without a copy through the buffer. */
static int
drain2(rs_writer *w, const unsigned char *p, size_t n, tl_err *e)
{
	struct st_wr *s = w->impl;
	struct iovec v[2] = { { s->buf, s->len }, { (void *)p, n } };
	int k = s->len > 0 ? 0 : 1;

	s->len = 0;
	while (k < 2) {
		ssize_t r = writev(s->fd, v + k, 2 - k);
		size_t m;
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return tl_failsys(e, "%s: write", w->name);
		for (m = (size_t)r; k < 2 && m >= v[k].iov_len; k++)
			m -= v[k].iov_len;
		if (k < 2) {
			v[k].iov_base = (unsigned char *)v[k].iov_base + m;
			v[k].iov_len -= m;
		}
	}
	return 0;
}

/* Buffers n bytes (large ones go out at once, after the buffered ones)
 * and adds them to the running CRC. */
static int
put(rs_writer *w, const void *p, size_t n, tl_err *e)
{
	struct st_wr *s = w->impl;

	s->crc = crc(s->crc, p, n);
	if (n >= BUFSZ / 8)
		return drain2(w, p, n, e);
	if (s->len + n > BUFSZ && flush(w, e) < 0)
		return -1;
	memcpy(s->buf + s->len, p, n);
	s->len += n;
	return 0;
}

static int
put32(rs_writer *w, uint32_t v, tl_err *e)
{
	unsigned char b[4];

	le_put32(b, v);
	return put(w, b, 4, e);
}

static int
put_name(rs_writer *w, const char *name, tl_err *e)
{
	unsigned char n = (unsigned char)strlen(name);

	return put(w, &n, 1, e) < 0 ? -1 : put(w, name, n, e);
}

static int
put_attr(rs_writer *w, const rs_attr *a, tl_err *e)
{
	static const unsigned char code[] = {
		[RS_INT] = T_INT, [RS_DOUBLE] = T_DOUBLE,
		[RS_STRING] = T_STRING, [RS_V2I] = T_V2I, [RS_V2D] = T_V2D,
	};
	unsigned char b[16];
	uint64_t u[2];
	size_t n = 0;

	if (put_name(w, a->name, e) < 0 || put(w, &code[a->type], 1, e) < 0)
		return -1;
	switch (a->type) {
	case RS_INT:
		le_put32(b, (uint32_t)a->v.i), n = 4;
		break;
	case RS_V2I:
		le_put32(b, (uint32_t)a->v.v2i[0]);
		le_put32(b + 4, (uint32_t)a->v.v2i[1]), n = 8;
		break;
	case RS_DOUBLE:
		memcpy(u, &a->v.d, 8);
		le_put64(b, u[0]), n = 8;
		break;
	case RS_V2D:
		memcpy(u, a->v.v2d, 16);
		le_put64(b, u[0]), le_put64(b + 8, u[1]), n = 16;
		break;
	case RS_STRING:
		n = strlen(a->s);
		if (put32(w, (uint32_t)n, e) < 0)
			return -1;
		return put(w, a->s, n, e);
	}
	return put(w, b, n, e);
}

static int
put_header(rs_writer *w, tl_err *e)
{
	struct st_wr *s = w->impl;
	const rs_header *h = &w->h;

	s->crc = 0;
	if (put(w, rs_stream_magic, 8, e) < 0 || put32(w, ST_VERSION, e) < 0 ||
	    put32(w, (uint32_t)h->width, e) < 0 ||
	    put32(w, (uint32_t)h->height, e) < 0 ||
	    put32(w, (uint32_t)h->nch, e) < 0 ||
	    put32(w, (uint32_t)h->nattr, e) < 0)
		return -1;
	for (int i = 0; i < h->nch; i++)
		if (put_name(w, h->ch[i], e) < 0)
			return -1;
	for (int i = 0; i < h->nattr; i++)
		if (put_attr(w, &h->attr[i], e) < 0)
			return -1;
	return put32(w, s->crc, e);
}

static int
st_write_row(rs_writer *w, const float *row, tl_err *e)
{
	struct st_wr *s = w->impl;
	unsigned char b[4];
	const void *p = row;

	if (s->tmp != NULL) {
		memcpy(s->tmp, row, s->rowbytes);
		le_swap32s(s->tmp, s->rowbytes / 4);
		p = s->tmp;
	}
	le_put32(b, (uint32_t)w->y);
	s->crc = crc(0, b, 4);
	if (put(w, p, s->rowbytes, e) < 0)
		return -1;
	return put32(w, s->crc, e);
}

static void
st_wr_free(rs_writer *w)
{
	struct st_wr *s = w->impl;

	if (s != NULL)
		free(s->tmp);
	free(s);
	w->impl = NULL;
}

static int
st_finish(rs_writer *w, tl_err *e)
{
	struct st_wr *s = w->impl;
	int r;

	s->crc = 0;
	r = put(w, st_end, 8, e) < 0 || put32(w, (uint32_t)w->y, e) < 0 ||
	    put32(w, s->crc, e) < 0 || flush(w, e) < 0 ? -1 : 0;
	st_wr_free(w);
	return r;
}

/* Unflushed bytes are dropped and no trailer follows: the reader reports
 * a truncated stream. */
static void
st_abort(rs_writer *w)
{
	st_wr_free(w);
}

int
rs_stream_create(rs_writer *w, int fd, tl_err *e)
{
	struct st_wr *s;

	w->abort = st_abort;
	w->finish = st_finish;
	w->row = st_write_row;
	if (isatty(fd))
		return tl_fail(e, "%s: is a terminal; send the raster to a "
		    "file or a pipe", w->name);
	if ((s = tl_alloc(1, sizeof *s, e)) == NULL)
		return -1;
	w->impl = s;
	s->fd = fd;
	s->rowbytes = (size_t)w->h.nch * (size_t)w->h.width * 4;
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
	if ((s->tmp = tl_alloc(s->rowbytes, 1, e)) == NULL)
		return -1;
#endif
	return put_header(w, e);
}

/* --- reading ---------------------------------------------------------- */

struct st_rd {
	size_t pos, len;  /* unread bytes are buf[pos .. len) */
	uint32_t crc;
	size_t rowbytes;
	long long row0;   /* file offset of row 0's record; -1: not a file */
	int spans;        /* spans by pread: 1 yes, 0 no, -1 not known yet */
	unsigned char *rec; /* a span's whole row record, checked by its CRC */
	unsigned char buf[BUFSZ];
};

/* Reads up to n bytes, fewer only at end of input; -1 on a read error. */
static long long
get(rs_reader *r, void *dst, size_t n, tl_err *e)
{
	struct st_rd *s = r->impl;
	unsigned char *p = dst;
	size_t got = 0;

	while (got < n) {
		size_t k = s->len - s->pos;
		ssize_t m;
		if (k > 0) {
			k = k < n - got ? k : n - got;
			memcpy(p + got, s->buf + s->pos, k);
			s->pos += k, got += k;
			continue;
		}
		/* Large requests (rows) go straight to the destination,
		 * and only the 4 bytes after them (the row's CRC) into the
		 * buffer: the next row is not read ahead into the buffer,
		 * so it too goes straight to its destination. */
		if (n - got >= BUFSZ / 8) {
			struct iovec v[2] = { { p + got, n - got },
			    { s->buf, 4 } };
			m = readv(r->fd, v, 2);
		} else
			m = read(r->fd, s->buf, BUFSZ);
		if (m < 0 && errno == EINTR)
			continue;
		if (m < 0)
			return tl_failsys(e, "%s: read", r->name);
		if (m == 0)
			break;
		if (n - got >= BUFSZ / 8 && (size_t)m <= n - got)
			got += (size_t)m;
		else if (n - got >= BUFSZ / 8)
			s->pos = 0, s->len = (size_t)m - (n - got), got = n;
		else
			s->pos = 0, s->len = (size_t)m;
	}
	s->crc = crc(s->crc, dst, got);
	return (long long)got;
}

/* Exactly n header bytes, or "truncated". */
static int
hget(rs_reader *r, void *dst, size_t n, tl_err *e)
{
	long long got = get(r, dst, n, e);

	if (got < 0)
		return -1;
	if ((size_t)got < n)
		return tl_fail(e, "%s: truncated in the stream header",
		    r->name);
	return 0;
}

static int
hget32(rs_reader *r, uint32_t *v, tl_err *e)
{
	unsigned char b[4];

	if (hget(r, b, 4, e) < 0)
		return -1;
	*v = le_get32(b);
	return 0;
}

static int
bad(rs_reader *r, const char *why, tl_err *e)
{
	return tl_fail(e, "%s: bad stream header: %s", r->name, why);
}

/* A length-prefixed name into dst (size cap + 1): no NUL, not empty. */
static int
hget_name(rs_reader *r, char *dst, size_t cap, tl_err *e)
{
	unsigned char n;

	if (hget(r, &n, 1, e) < 0)
		return -1;
	if (n == 0 || n > cap)
		return bad(r, "name length out of range", e);
	if (hget(r, dst, n, e) < 0)
		return -1;
	dst[n] = '\0';
	if (strlen(dst) != n)
		return bad(r, "NUL byte in a name", e);
	return 0;
}

static double
dbl(uint64_t u)
{
	double d;

	memcpy(&d, &u, 8);
	return d;
}

static int
hget_string(rs_reader *r, const char *name, tl_err *e)
{
	uint32_t n;
	char *s;
	int rv = -1;

	if (hget32(r, &n, e) < 0)
		return -1;
	if (n > RS_MAXSTR)
		return bad(r, "string longer than 65535 bytes", e);
	if ((s = tl_alloc(n + 1, 1, e)) == NULL)
		return -1;
	if (hget(r, s, n, e) == 0) {
		if (strlen(s) != n)
			bad(r, "NUL byte in a string", e);
		else
			rv = rs_set_string(&r->h, name, s, e);
	}
	free(s);
	return rv;
}

static int
hget_attr(rs_reader *r, tl_err *e)
{
	static const size_t size[] = { [T_INT] = 4, [T_DOUBLE] = 8,
	    [T_V2I] = 8, [T_V2D] = 16 };
	char name[sizeof r->h.attr[0].name];
	unsigned char t, b[16];

	if (hget_name(r, name, sizeof name - 1, e) < 0 || hget(r, &t, 1, e) < 0)
		return -1;
	if (t < T_INT || t > T_V2D)
		return bad(r, "unknown attribute type", e);
	for (int i = 0; i < r->h.nattr; i++)
		if (strcmp(r->h.attr[i].name, name) == 0)
			return bad(r, "duplicate attribute", e);
	if (t == T_STRING)
		return hget_string(r, name, e);
	if (hget(r, b, size[t], e) < 0)
		return -1;
	switch (t) {
	case T_INT:
		return rs_set_int(&r->h, name, (int32_t)le_get32(b), e);
	case T_V2I:
		return rs_set_v2i(&r->h, name, (int32_t)le_get32(b),
		    (int32_t)le_get32(b + 4), e);
	case T_DOUBLE:
		return rs_set_double(&r->h, name, dbl(le_get64(b)), e);
	default:
		return rs_set_v2d(&r->h, name, dbl(le_get64(b)),
		    dbl(le_get64(b + 8)), e);
	}
}

/* The rows a header declares must be rows the input can hold, before
 * anyone allocates one (a caller allocates a row of rowbytes): a regular
 * file's size says what follows the header, and a stream declaring more
 * than that (plus 1 MiB, so that a short file still says at which row it
 * ends) is refused as truncated now. A pipe's size is unknown: there the
 * width is bounded instead, so that no row of a forged header costs more
 * than the 2^24 columns of a genuine level 0 of 10^14 samples would. */
#define ST_SLACK (1LL << 20)
#define ST_PIPEDIM (1 << 24)

static int
check_size(rs_reader *r, tl_err *e)
{
	struct st_rd *s = r->impl;
	long long rows = (long long)r->h.height * ((long long)s->rowbytes + 4)
	    + 16, left;
	struct stat st;
	off_t pos;

	if (fstat(r->fd, &st) == 0 && S_ISREG(st.st_mode) &&
	    (pos = lseek(r->fd, 0, SEEK_CUR)) >= 0) {
		left = (long long)st.st_size - (long long)pos +
		    (long long)(s->len - s->pos);
		s->row0 = (long long)st.st_size - left;
		if (rows > left + ST_SLACK)
			return tl_fail(e, "%s: truncated: the header declares "
			    "%d rows of %zu bytes (%lld bytes with their "
			    "checksums and the trailer), the file holds %lld "
			    "after the header", r->name, r->h.height,
			    s->rowbytes, rows, left);
		return 0;
	}
	if (r->h.width > ST_PIPEDIM)
		return tl_fail(e, "%s: rows of %d columns, more than %d: "
		    "refused on a pipe, where the stream's size cannot be "
		    "checked (give it as a file)", r->name, r->h.width,
		    ST_PIPEDIM);
	return 0;
}

static int
read_header(rs_reader *r, tl_err *e)
{
	struct st_rd *s = r->impl;
	uint32_t v[5], stored, sum;
	char name[sizeof r->h.ch[0]];

	s->crc = crc(0, r->pre, 8);
	for (int i = 0; i < 5; i++)
		if (hget32(r, &v[i], e) < 0)
			return -1;
	if (v[0] != ST_VERSION)
		return tl_fail(e, "%s: fqm stream version %u, this program "
		    "reads version %d", r->name, v[0], ST_VERSION);
	if (v[1] < 1 || v[1] > RS_MAXDIM || v[2] < 1 || v[2] > RS_MAXDIM)
		return bad(r, "width or height out of range", e);
	if (v[3] < 1 || v[3] > RS_MAXCH || v[4] > RS_MAXATTR)
		return bad(r, "channel or attribute count out of range", e);
	rs_header_init(&r->h, (int)v[1], (int)v[2]);
	for (uint32_t i = 0; i < v[3]; i++) {
		if (hget_name(r, name, sizeof name - 1, e) < 0)
			return -1;
		/* Sorted and unique, as writers must store them. */
		if (rs_add_channel(&r->h, name, NULL) < 0 ||
		    strcmp(r->h.ch[i], name) != 0)
			return bad(r, "channels not in ascending order", e);
	}
	if (rs_check_size(&r->h, r->name, e) < 0)
		return -1;
	for (uint32_t i = 0; i < v[4]; i++)
		if (hget_attr(r, e) < 0)
			return -1;
	sum = s->crc;
	if (hget32(r, &stored, e) < 0)
		return -1;
	if (stored != sum)
		return bad(r, "checksum mismatch", e);
	s->rowbytes = (size_t)r->h.nch * (size_t)r->h.width * 4;
	return check_size(r, e);
}

/* After the last row: the trailer, then nothing at all. */
static int
read_trailer(rs_reader *r, tl_err *e)
{
	struct st_rd *s = r->impl;
	unsigned char b[16], extra;
	long long got;

	s->crc = 0;
	if ((got = get(r, b, 16, e)) < 0)
		return -1;
	if (got == 0)
		return tl_fail(e, "%s: truncated after the last row (no "
		    "end-of-stream trailer)", r->name);
	if (got < 16)
		return tl_fail(e, "%s: truncated in the end-of-stream trailer",
		    r->name);
	if (memcmp(b, st_end, 8) != 0)
		return tl_fail(e, "%s: bad end-of-stream trailer", r->name);
	if (le_get32(b + 12) != crc(0, b, 12))
		return tl_fail(e, "%s: corrupt end-of-stream trailer",
		    r->name);
	if (le_get32(b + 8) != (uint32_t)r->h.height)
		return tl_fail(e, "%s: trailer counts %u rows, header %d",
		    r->name, le_get32(b + 8), r->h.height);
	if ((got = get(r, &extra, 1, e)) < 0)
		return -1;
	if (got > 0)
		return tl_fail(e, "%s: garbage after the end of the stream",
		    r->name);
	return 0;
}

static int
truncated(rs_reader *r, tl_err *e)
{
	return tl_fail(e, "%s: truncated at row %d of %d", r->name, r->y,
	    r->h.height);
}

static int
st_read_row(rs_reader *r, float *row, tl_err *e)
{
	struct st_rd *s = r->impl;
	unsigned char b[4];
	uint32_t sum;
	long long got;

	le_put32(b, (uint32_t)r->y);
	s->crc = crc(0, b, 4);
	if ((got = get(r, row, s->rowbytes, e)) < 0)
		return -1;
	if ((size_t)got < s->rowbytes)
		return truncated(r, e);
	sum = s->crc;
	if ((got = get(r, b, 4, e)) < 0)
		return -1;
	if (got < 4)
		return truncated(r, e);
	if (le_get32(b) != sum)
		return tl_fail(e, "%s: corrupt row %d of %d (checksum "
		    "mismatch)", r->name, r->y, r->h.height);
	le_swap32s(row, s->rowbytes / 4);
	if (r->y == r->h.height - 1)
		return read_trailer(r, e);
	return 0;
}

/* Whether spans can be read by pread: a file exactly the header, the
 * rows and a sound trailer long, nothing read past the header yet. */
static int
spannable(rs_reader *r)
{
	struct st_rd *s = r->impl;
	long long end = s->row0 + (long long)r->h.height *
	    ((long long)s->rowbytes + 4);
	unsigned char b[16];
	struct stat st;

	return s->row0 >= 0 && r->y == 0 && fstat(r->fd, &st) == 0 &&
	    (long long)st.st_size == end + 16 &&
	    pread(r->fd, b, 16, end) == 16 && memcmp(b, st_end, 8) == 0 &&
	    le_get32(b + 12) == crc(0, b, 12) &&
	    le_get32(b + 8) == (uint32_t)r->h.height;
}

/* Columns x0 .. x0+n-1 of the next row by pread: the whole row record
 * is read, for its CRC covers the whole row (fqm(5): damage is reported
 * by row, windowed reads included); only the span is copied out. */
static int
st_read_span(rs_reader *r, int x0, int n, float *dst, tl_err *e)
{
	struct st_rd *s = r->impl;
	long long rec = s->row0 + (long long)r->y * ((long long)s->rowbytes + 4);
	size_t plane = 4 * (size_t)r->h.width;
	unsigned char b[4];

	if (s->spans < 0)
		s->spans = spannable(r);
	if (!s->spans)
		return 1;
	if (s->rec == NULL &&
	    (s->rec = tl_alloc(s->rowbytes + 4, 1, e)) == NULL)
		return -1;
	if (tl_pread(r->fd, s->rec, s->rowbytes + 4, rec, r->name, e) < 0)
		return -1;
	le_put32(b, (uint32_t)r->y);
	if (le_get32(s->rec + s->rowbytes) !=
	    crc(crc(0, b, 4), s->rec, s->rowbytes))
		return tl_fail(e, "%s: corrupt row %d of %d (checksum "
		    "mismatch)", r->name, r->y, r->h.height);
	for (int c = 0; c < r->h.nch; c++)
		memcpy(dst + (size_t)c * n, s->rec + c * plane + 4 * (size_t)x0,
		    (size_t)n * 4);
	le_swap32s(dst, (size_t)n * r->h.nch);
	return 0;
}

/* Rows of a span reader come by position: skipping them is moving y.
 * Called before any span, it decides as the first span would. */
static int
st_skip(rs_reader *r, int n)
{
	struct st_rd *s = r->impl;

	if (s->spans < 0)
		s->spans = spannable(r);
	return s->spans ? 0 : 1;
}

static void
st_close(rs_reader *r)
{
	struct st_rd *s = r->impl;

	if (s != NULL)
		free(s->rec);
	free(r->impl);
	r->impl = NULL;
}

int
rs_stream_open_read(rs_reader *r, tl_err *e)
{
	struct st_rd *s;

	if ((r->impl = s = tl_alloc(1, sizeof(struct st_rd), e)) == NULL)
		return -1;
	s->row0 = -1, s->spans = -1;
	r->row = st_read_row;
	r->span = st_read_span;
	r->skip = st_skip;
	r->close = st_close;
	return read_header(r, e);
}
