/* qm_decode.c - a quantized-mesh-1.0 tile's bytes into its fields, read
 * from the specification (little-endian): the 88-byte header, the
 * zig-zag delta coded u, v, heights, the high-water-mark coded triangle
 * indices (16-bit, 32-bit above 65536 vertices, aligned to their size),
 * the four edge lists, the extensions. A gzip'd file is inflated first
 * (zlib). Every length is checked against the bytes left before use. */
#include "base/gzip.h"
#include "verify/qm.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define QM_HEADER 88
#define QM_MAXBYTES (1u << 30) /* an inflated tile larger is refused */

typedef struct {
	const unsigned char *b;
	size_t len, pos;
} rd;

static uint32_t
le32(const unsigned char *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
	    (uint32_t)p[3] << 24;
}

static double
le64f(const unsigned char *p)
{
	uint64_t u = (uint64_t)le32(p) | (uint64_t)le32(p + 4) << 32;
	double d;

	memcpy(&d, &u, sizeof d);
	return d;
}

static float
le32f(const unsigned char *p)
{
	uint32_t u = le32(p);
	float f;

	memcpy(&f, &u, sizeof f);
	return f;
}

/* Room for n items of size s at the reader's place? */
static int
room(const rd *r, uint64_t n, unsigned s)
{
	return n <= (r->len - r->pos) / s;
}

static int
zigzag(unsigned v)
{
	return (int)(v >> 1) ^ -(int)(v & 1);
}

static int
read_vertices(rd *r, qm_tile *t, tl_err *e)
{
	int32_t *q[3];
	int32_t acc[3] = { 0, 0, 0 };

	if (!room(r, 1, 4))
		return tl_fail(e, "truncated: no vertex count");
	t->n = le32(r->b + r->pos);
	r->pos += 4;
	if (!room(r, 3 * (uint64_t)t->n, 2))
		return tl_fail(e, "truncated: %u vertices need %llu bytes, "
		    "%zu left", t->n, 6ULL * t->n, r->len - r->pos);
	t->u = malloc((t->n ? t->n : 1) * sizeof *t->u);
	t->v = malloc((t->n ? t->n : 1) * sizeof *t->v);
	t->h = malloc((t->n ? t->n : 1) * sizeof *t->h);
	if (t->u == NULL || t->v == NULL || t->h == NULL)
		return tl_fail(e, "out of memory for %u vertices", t->n);
	q[0] = t->u, q[1] = t->v, q[2] = t->h;
	for (int c = 0; c < 3; c++)
		for (uint32_t i = 0; i < t->n; i++) {
			const unsigned char *p = r->b + r->pos +
			    2 * ((size_t)c * t->n + i);

			acc[c] += zigzag((unsigned)p[0] | (unsigned)p[1] << 8);
			/* a running sum far outside 0..32767 is damage, kept
			 * bounded so that it cannot overflow */
			if (acc[c] < -65536 || acc[c] > 65536)
				acc[c] = acc[c] < 0 ? -65536 : 65536;
			q[c][i] = acc[c];
		}
	r->pos += 6 * (size_t)t->n;
	return 0;
}

/* count indices of the tile's size at r; hwm: undo high-water marks. */
static int
read_indices(rd *r, const qm_tile *t, uint64_t count, int hwm,
    int64_t *out, uint32_t *raw, const char *what, tl_err *e)
{
	unsigned s = t->index32 ? 4 : 2;
	int64_t highest = 0;

	if (!room(r, count, s))
		return tl_fail(e, "truncated: %s: %llu indices need %llu "
		    "bytes, %zu left", what, (unsigned long long)count,
		    (unsigned long long)count * s, r->len - r->pos);
	for (uint64_t k = 0; k < count; k++) {
		const unsigned char *p = r->b + r->pos + k * s;
		uint32_t code = s == 4 ? le32(p) :
		    ((uint32_t)p[0] | (uint32_t)p[1] << 8);

		if (hwm) {
			out[k] = highest - code;
			if (code == 0)
				highest++;
		} else
			raw[k] = code;
	}
	r->pos += count * s;
	return 0;
}

static int
read_mesh(rd *r, qm_tile *t, tl_err *e)
{
	static const char *side[4] = { "west", "south", "east", "north" };
	unsigned s;

	t->index32 = t->n > 65536;
	s = t->index32 ? 4 : 2;
	if (r->pos % s)
		r->pos += s - r->pos % s;
	if (r->pos > r->len || !room(r, 1, 4))
		return tl_fail(e, "truncated: no triangle count");
	t->ntri = le32(r->b + r->pos);
	r->pos += 4;
	if (!room(r, 3 * (uint64_t)t->ntri, s))
		return tl_fail(e, "truncated: %u triangles need %llu bytes, "
		    "%zu left", t->ntri, 3ULL * s * t->ntri, r->len - r->pos);
	t->idx = malloc((3 * (size_t)t->ntri + 1) * sizeof *t->idx);
	if (t->idx == NULL)
		return tl_fail(e, "out of memory for %u triangles", t->ntri);
	if (read_indices(r, t, 3 * (uint64_t)t->ntri, 1, t->idx, NULL,
	    "triangles", e) < 0)
		return -1;
	for (int k = 0; k < 4; k++) {
		if (!room(r, 1, 4))
			return tl_fail(e, "truncated: no %s edge count",
			    side[k]);
		t->nedge[k] = le32(r->b + r->pos);
		r->pos += 4;
		if (!room(r, t->nedge[k], s))
			return tl_fail(e, "truncated: %s edge: %u indices, "
			    "%zu bytes left", side[k], t->nedge[k],
			    r->len - r->pos);
		t->edge[k] = malloc(((size_t)t->nedge[k] + 1) *
		    sizeof *t->edge[k]);
		if (t->edge[k] == NULL)
			return tl_fail(e, "out of memory");
		if (read_indices(r, t, t->nedge[k], 0, NULL, t->edge[k],
		    side[k], e) < 0)
			return -1;
	}
	return 0;
}

static int
read_extension(rd *r, qm_tile *t, tl_err *e)
{
	unsigned id;
	uint32_t len;
	const unsigned char *p;

	if (!room(r, 5, 1))
		return tl_fail(e, "truncated: %zu trailing bytes make no "
		    "extension (id, length)", r->len - r->pos);
	id = r->b[r->pos];
	len = le32(r->b + r->pos + 1);
	r->pos += 5;
	if (!room(r, len, 1))
		return tl_fail(e, "truncated: extension %u: %u bytes, %zu "
		    "left", id, len, r->len - r->pos);
	p = r->b + r->pos;
	r->pos += len;
	if (id == 1 && t->normals == NULL) {
		t->normals_len = len;
		if ((t->normals = malloc(len + 1)) == NULL)
			return tl_fail(e, "out of memory");
		memcpy(t->normals, p, len);
	} else if (id == 2)
		t->watermask_len = len;
	else if (id == 4 && t->metadata == NULL) {
		t->metadata_len = len;
		if (len < 4 || le32(p) != len - 4)
			return 0; /* qm_tile_check says so */
		if ((t->metadata = malloc(len - 3)) == NULL)
			return tl_fail(e, "out of memory");
		memcpy(t->metadata, p + 4, len - 4);
		t->metadata[len - 4] = '\0';
	} else
		t->unknown_ext++;
	return 0;
}

static int
decode_raw(const unsigned char *b, size_t len, qm_tile *t, tl_err *e)
{
	rd r = { b, len, 0 };

	if (len < QM_HEADER)
		return tl_fail(e, "truncated: %zu bytes, the header alone "
		    "has %d", len, QM_HEADER);
	for (int k = 0; k < 3; k++) {
		t->center[k] = le64f(b + 8 * k);
		t->sphere[k] = le64f(b + 32 + 8 * k);
		t->occlusion[k] = le64f(b + 64 + 8 * k);
	}
	t->hmin = le32f(b + 24);
	t->hmax = le32f(b + 28);
	t->sphere[3] = le64f(b + 56);
	r.pos = QM_HEADER;
	if (read_vertices(&r, t, e) < 0 || read_mesh(&r, t, e) < 0)
		return -1;
	while (r.pos < r.len)
		if (read_extension(&r, t, e) < 0)
			return -1;
	return 0;
}

/* A gzip member inflated into *out (malloc'd). */
static int
gunzip(const unsigned char *b, size_t len, unsigned char **out,
    size_t *outlen, tl_err *e)
{
	tl_err z;

	if (tl_gunzip(b, len, QM_MAXBYTES, out, outlen, &z) < 0)
		return tl_fail(e, "truncated: %s", z.msg);
	return 0;
}

int
qm_decode(const unsigned char *buf, size_t len, qm_tile *t, tl_err *e)
{
	unsigned char *in = NULL;
	size_t n = 0;
	int r;

	memset(t, 0, sizeof *t);
	t->normals_len = t->watermask_len = t->metadata_len = -1;
	if (len >= 2 && buf[0] == 0x1f && buf[1] == 0x8b) {
		if (gunzip(buf, len, &in, &n, e) < 0)
			return -1;
		t->gzip = 1;
		buf = in, len = n;
	}
	r = decode_raw(buf, len, t, e);
	free(in);
	return r;
}

int
qm_read(const char *path, qm_tile *t, tl_err *e)
{
	struct stat st;
	unsigned char *b;
	ssize_t got;
	size_t n = 0;
	int fd, r;

	memset(t, 0, sizeof *t);
	if ((fd = tl_open_regular(path, e)) < 0)
		return -1;
	if (fstat(fd, &st) < 0 || st.st_size > QM_MAXBYTES) {
		close(fd);
		return tl_fail(e, "%s: unreadable or over 1 GiB", path);
	}
	if ((b = malloc((size_t)st.st_size + 1)) == NULL) {
		close(fd);
		return tl_fail(e, "%s: out of memory", path);
	}
	while (n < (size_t)st.st_size &&
	    (got = read(fd, b + n, (size_t)st.st_size - n)) > 0)
		n += (size_t)got;
	close(fd);
	r = qm_decode(b, n, t, e);
	free(b);
	return r;
}

void
qm_free(qm_tile *t)
{
	free(t->u), free(t->v), free(t->h), free(t->idx);
	for (int k = 0; k < 4; k++)
		free(t->edge[k]);
	free(t->normals), free(t->metadata);
	memset(t, 0, sizeof *t);
}

void
qm_rect(int z, int x, int y, double r[4])
{
	double d = 180 / ldexp(1, z);

	r[0] = -180 + x * d, r[1] = -90 + y * d;
	r[2] = r[0] + d, r[3] = r[1] + d;
}

double
qm_level_error(int z)
{
	return 6378137.0 * 2 * M_PI * 0.25 / (65 * 2) / ldexp(1, z);
}

uint32_t
qm_checksum(const qm_tile *t)
{
	const int32_t *q[3] = { t->u, t->v, t->h };
	uint32_t hash = 2166136261u;
	unsigned char b[4];

	for (int c = 0; c < 3; c++)
		for (uint32_t i = 0; i < t->n; i++) {
			b[0] = q[c][i] & 0xff, b[1] = (q[c][i] >> 8) & 0xff;
			for (int k = 0; k < 2; k++)
				hash = (hash ^ b[k]) * 16777619u;
		}
	for (size_t i = 0; i < 3 * (size_t)t->ntri; i++) {
		uint32_t v = (uint32_t)t->idx[i];

		for (int k = 0; k < 4; k++)
			hash = (hash ^ ((v >> (8 * k)) & 0xff)) * 16777619u;
	}
	return hash;
}
