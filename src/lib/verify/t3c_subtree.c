/* t3c_subtree.c - the subtree files of a 3D Tiles terrain tileset, read
 * from the 3D Tiles 1.1 implicit tiling specification: each file's
 * header, JSON and binary, its buffer views, its availability bitstreams
 * (Morton order, x in the low bit) or constants, the property table of
 * TILE_* metadata, one row per available tile in availability order;
 * the tiles and child subtrees it announces, and the subtrees below. */
#include "verify/t3c.h"

#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/json.h"

#define MAXSUBTREE (1L << 26)   /* bytes */

const char *const t3c_semantic[4] = {
	"TILE_MINIMUM_HEIGHT", "TILE_MAXIMUM_HEIGHT", "TILE_BOUNDING_SPHERE",
	"TILE_HORIZON_OCCLUSION_POINT"
};
static const int width[4] = { 1, 1, 4, 3 };

int
t3c_push(t3c_ents *s, qm_key k, const t3c_meta *m)
{
	if (s->n == s->cap) {
		long cap = s->cap ? 2 * s->cap : 1024;
		t3c_ent *p = realloc(s->e, (size_t)cap * sizeof *p);

		if (p == NULL)
			return -1;
		s->e = p, s->cap = cap;
	}
	s->e[s->n].k = k;
	if (m != NULL)
		s->e[s->n].m = *m;
	s->n++;
	return 0;
}

static void
subtree_name(const t3c_walk *c, int z, int x, int y, char *b, size_t n)
{
	snprintf(b, n, "%s/%d/%d/%d.subtree", c->prefix, z, x, y);
}

/* --- a subtree file -------------------------------------------------- */

typedef struct {
	json_t *j;
	const unsigned char *bin;
	size_t binlen;
} subtree;

/* Buffer view i of the subtree: within its binary, 8-aligned. */
static const unsigned char *
view(const subtree *st, json_t *ji, size_t need, const char *name,
    const char *what, qm_report *r)
{
	json_t *v = json_array_get(json_object_get(st->j, "bufferViews"),
	    json_is_integer(ji) ? (size_t)json_integer_value(ji) : (size_t)-1);
	int off, len, buf;

	if (tl_json_int(json_object_get(v, "buffer"), 0, 0, &buf) < 0 ||
	    tl_json_int(json_object_get(v, "byteOffset"), 0, MAXSUBTREE,
	    &off) < 0 || tl_json_int(json_object_get(v, "byteLength"), 0,
	    MAXSUBTREE, &len) < 0 || (size_t)off + len > st->binlen ||
	    (size_t)len < need || off % 8) {
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "%s: %s: no buffer view "
		    "of %zu bytes (8-aligned) in its binary", name, what, need);
		return NULL;
	}
	return st->bin + off;
}

/* n bits of an availability object into out; -1 reported. */
static int
bits(const subtree *st, json_t *av, long n, unsigned char *out,
    const char *name, const char *what, qm_report *r)
{
	json_t *c = json_object_get(av, "constant");
	const unsigned char *p;
	long count = 0;
	int want;

	if (c != NULL) {
		if (!json_is_integer(c) || json_integer_value(c) < 0 ||
		    json_integer_value(c) > 1) {
			qm_issue_add(r, QM_LAYER, -1, 0, 0, "%s: %s: constant "
			    "not 0 or 1", name, what);
			return -1;
		}
		memset(out, (int)json_integer_value(c), (size_t)n);
		return 0;
	}
	if ((p = view(st, json_object_get(av, "bitstream"), (size_t)(n + 7) /
	    8, name, what, r)) == NULL)
		return -1;
	for (long i = 0; i < n; i++)
		count += out[i] = p[i >> 3] >> (i & 7) & 1;
	if (json_object_get(av, "availableCount") != NULL &&
	    (tl_json_int(json_object_get(av, "availableCount"), 0, n, &want)
	    < 0 || want != count))
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "%s: %s: availableCount "
		    "not the %ld bits set", name, what, count);
	return 0;
}

static int
read_subtree(const char *path, const char *name, unsigned char **buf,
    subtree *st, qm_report *r)
{
	struct stat sb;
	json_error_t je;
	size_t n = 0;
	uint64_t jl, bl;
	int fd, oom;
	ssize_t got;
	unsigned char *b;

	if ((fd = open(path, O_RDONLY)) < 0 || fstat(fd, &sb) < 0 ||
	    !S_ISREG(sb.st_mode) || sb.st_size > MAXSUBTREE ||
	    (b = *buf = malloc((size_t)sb.st_size + 1)) == NULL) {
		if (fd >= 0)
			close(fd);
		qm_issue_add(r, QM_LAYER, -1, 0, 0, "%s: unreadable, not a "
		    "file or over 64 MiB", name);
		return -1;
	}
	while (n < (size_t)sb.st_size &&
	    (got = read(fd, b + n, (size_t)sb.st_size - n)) > 0)
		n += (size_t)got;
	close(fd);
	memcpy(&jl, b + 8, 8 * (n >= 24)), memcpy(&bl, b + 16, 8 * (n >= 24));
	if (n < 24 || memcmp(b, "subt", 4) || b[4] != 1 || b[5] || b[6] ||
	    b[7] || jl > n - 24 || bl != n - 24 - jl || jl % 8) {
		qm_issue_add(r, QM_DECODE, -1, 0, 0, "%s: not a subtree of "
		    "version 1 whose JSON (8-padded) and binary lengths are "
		    "its %zu bytes (truncated?)", name, n);
		return -1;
	}
	st->j = tl_json_parse((const char *)b + 24, (size_t)jl, &je, &oom);
	st->bin = b + 24 + jl, st->binlen = (size_t)bl;
	if (st->j == NULL) {
		qm_issue_add(r, QM_DECODE, -1, 0, 0, "%s: JSON: %s", name,
		    je.text);
		return -1;
	}
	return 0;
}

/* The property table's columns of the four semantics, count rows each;
 * 0, or -1 reported. */
static int
columns(const t3c_walk *c, const subtree *st, json_t *props, long count,
    const unsigned char *col[4], const char *name)
{
	for (int s = 0; s < 4; s++)
		if (c->psize[s] == 0 || (col[s] = view(st, json_object_get(
		    json_object_get(props, c->prop[s]), "values"),
		    (size_t)count * width[s] * c->psize[s], name, t3c_semantic[s],
		    c->r)) == NULL)
			return -1;
	return 0;
}

/* Row i of the columns into m. */
static void
row(const t3c_walk *c, const unsigned char *col[4], long i, t3c_meta *m)
{
	double *dst[4] = { &m->hmin, &m->hmax, m->sphere, m->hop };

	for (int s = 0; s < 4; s++)
		for (int k = 0; k < width[s]; k++) {
			const unsigned char *p = col[s] + c->psize[s] *
			    (i * width[s] + k);
			float f;

			if (c->psize[s] == 8)
				memcpy(&dst[s][k], p, 8);
			else
				memcpy(&f, p, 4), dst[s][k] = f;
		}
}

static void
demorton(long m, int *x, int *y)
{
	*x = *y = 0;
	for (int b = 0; b < 31; b++) {
		*x |= (int)((m >> (2 * b)) & 1) << b;
		*y |= (int)((m >> (2 * b + 1)) & 1) << b;
	}
}

/* The tiles of subtree (s, sx, sy) of root rt: announced, with their
 * metadata; its child subtrees onto todo. */
static int
tiles(t3c_walk *c, int rt, const subtree *st, int s, int sx, int sy,
    const char *name, unsigned char *ta, long ntile)
{
	json_t *j = st->j, *pt, *props;
	const unsigned char *col[4];
	unsigned char *ca = malloc((size_t)ntile + 1);
	long first = 0, n = 0, rows = 0, avail = 0;
	int d = 0, cnt;

	if (ca == NULL)
		return -1;
	if (bits(st, json_object_get(j, "tileAvailability"), ntile, ta, name,
	    "tileAvailability", c->r) < 0 ||
	    bits(st, json_array_get(json_object_get(j, "contentAvailability"),
	    0), ntile, ca, name, "contentAvailability", c->r) < 0) {
		free(ca);
		return 0;
	}
	for (long i = 0; i < ntile; i++)
		avail += ta[i];
	if (memcmp(ta, ca, (size_t)ntile) || !ta[0])
		qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "%s: content "
		    "availability not the tile availability, or its root "
		    "not available", name);
	free(ca);
	pt = json_array_get(json_object_get(j, "propertyTables"),
	    (size_t)json_integer_value(json_object_get(j, "tileMetadata")));
	props = json_object_get(pt, "properties");
	if (!json_is_integer(json_object_get(j, "tileMetadata")) ||
	    tl_json_int(json_object_get(pt, "count"), 0, ntile, &cnt) < 0 ||
	    cnt != avail)
		qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "%s: tileMetadata: "
		    "no property table of a row per available tile (%ld)",
		    name, avail), cnt = 0;
	else if (columns(c, st, props, cnt, col, name) == 0)
		rows = cnt;
	for (long i = 0; i < ntile; i++) {
		t3c_meta m;
		int lx, ly, z;

		if (i == first + (1L << (2 * d)))
			first = i, d++;
		if (!ta[i])
			continue;
		z = s + d;
		demorton(i - first, &lx, &ly);
		if (z >= c->levels) {
			qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "%s: a tile of "
			    "level %d available, availableLevels %d", name, z,
			    c->levels);
			continue;
		}
		if (n < rows)
			row(c, col, n, &m);
		else
			m.hmin = m.hmax = m.sphere[0] = m.sphere[1] =
			    m.sphere[2] = m.sphere[3] = m.hop[0] = m.hop[1] =
			    m.hop[2] = NAN;
		n++;
		if (--c->budget < 0 || t3c_push(&c->tiles, QM_KEY(z, (sx << d) +
		    lx + ((long)rt << z), (sy << d) + ly), &m) < 0)
			return -1;
	}
	return 0;
}

/* Subtree (s, sx, sy) of root rt and every one below it. */
int
t3c_walk_subtree(t3c_walk *c, int rt, int s, int sx, int sy)
{
	char name[256], path[4096];
	long ntile = ((1L << (2 * c->k)) - 1) / 3, nchild = 1L << (2 * c->k);
	unsigned char *buf = NULL, *ta = malloc((size_t)(ntile + nchild));
	subtree st = { NULL, NULL, 0 };
	int rc = -1;

	subtree_name(c, s, sx, sy, name, sizeof name);
	snprintf(path, sizeof path, "%s/%s", c->dir, name);
	if (ta == NULL)
		return -1;
	if (read_subtree(path, name, &buf, &st, c->r) < 0) {
		rc = 0; /* reported */
		goto done;
	}
	if (tiles(c, rt, &st, s, sx, sy, name, ta, ntile) < 0)
		goto done;
	if (bits(&st, json_object_get(st.j, "childSubtreeAvailability"),
	    nchild, ta + ntile, name, "childSubtreeAvailability", c->r) < 0) {
		rc = 0;
		goto done;
	}
	for (long i = 0; i < nchild; i++) {
		int lx, ly, z = s + c->k;

		if (!ta[ntile + i])
			continue;
		demorton(i, &lx, &ly);
		if (z >= c->levels) {
			qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "%s: a child "
			    "subtree at level %d, availableLevels %d", name, z,
			    c->levels);
			continue;
		}
		if (--c->budget < 0 || t3c_push(&c->subs, QM_KEY(z, (sx << c->k) +
		    lx + ((long)rt << z), (sy << c->k) + ly), NULL) < 0)
			goto done;
	}
	json_decref(st.j), st.j = NULL;
	free(buf), buf = NULL;
	for (long i = 0; i < nchild; i++) {
		int lx, ly;
		char sub[4096];

		if (!ta[ntile + i] || s + c->k >= c->levels)
			continue;
		demorton(i, &lx, &ly);
		subtree_name(c, s + c->k, (sx << c->k) + lx,
		    (sy << c->k) + ly, name, sizeof name);
		snprintf(sub, sizeof sub, "%s/%s", c->dir, name);
		if (access(sub, F_OK) == 0 && t3c_walk_subtree(c, rt, s + c->k,
		    (sx << c->k) + lx, (sy << c->k) + ly) < 0)
			goto done;
	}
	rc = 0;
done:
	json_decref(st.j);
	free(buf), free(ta);
	return rc;
}
