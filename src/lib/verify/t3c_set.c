/* t3c_set.c - a 3D Tiles terrain tileset as a whole, read from the 3D
 * Tiles 1.1 specification: tileset.json (the schema's TILE_* semantics,
 * the two implicit quadtree roots), every subtree file (its header,
 * JSON, buffer views, availability bitstreams in Morton order and the
 * property table of TILE_* metadata), the files present, and the
 * quadtree: announced exactly the files, every ancestor present. */
#include "verify/t3c.h"

#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/json.h"

#define MAXANNOUNCED (1L << 26)
#define MAXSUBTREE (1L << 26)   /* bytes */
#define TOLR 1e-3               /* metres: a region's heights */

static const char *semantic[4] = {
	"TILE_MINIMUM_HEIGHT", "TILE_MAXIMUM_HEIGHT", "TILE_BOUNDING_SPHERE",
	"TILE_HORIZON_OCCLUSION_POINT"
};
static const int width[4] = { 1, 1, 4, 3 };

typedef struct {
	qm_key k;
	t3c_meta m;
} ent;

typedef struct {
	ent *e;
	long n, cap;
} ents;

typedef struct {
	const char *dir;
	t3c_set *T;
	qm_report *r;
	char prop[4][128];  /* the tile class's property of each semantic */
	int psize[4];       /* its component's bytes (8 or 4) */
	int levels, k;      /* availableLevels, subtreeLevels of this root */
	int lr[2], kr[2];   /* those of each root */
	ents tiles, subs;   /* announced */
	long budget;
} ctx;

static int
push(ents *s, qm_key k, const t3c_meta *m)
{
	if (s->n == s->cap) {
		long cap = s->cap ? 2 * s->cap : 1024;
		ent *p = realloc(s->e, (size_t)cap * sizeof *p);

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

static int
cmpent(const void *a, const void *b)
{
	qm_key x = ((const ent *)a)->k, y = ((const ent *)b)->k;

	return x < y ? -1 : x > y;
}

static void
sort_unique(ents *s)
{
	long m = 0;

	qsort(s->e, (size_t)s->n, sizeof *s->e, cmpent);
	for (long i = 0; i < s->n; i++)
		if (m == 0 || s->e[i].k != s->e[m - 1].k)
			s->e[m++] = s->e[i];
	s->n = m;
}

static void
subtree_name(const ctx *c, int r, int z, int x, int y, char *b, size_t n)
{
	snprintf(b, n, "%s/%d/%d/%d.subtree", c->T->prefix[r], z, x, y);
}

void
t3c_path(const char *dir, const t3c_set *s, int z, int x, int y, char *b,
    size_t n)
{
	int r = x >> z;

	snprintf(b, n, "%s%s%s/%d/%d/%d.glb", dir ? dir : "", dir ? "/" : "",
	    s->prefix[r & 1], z, x - (r << z), y);
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

/* The property table's row of tile metadata into m. */
static void
row(const ctx *c, const subtree *st, json_t *props, long count, long i,
    t3c_meta *m, const char *name)
{
	double *dst[4] = { &m->hmin, &m->hmax, m->sphere, m->hop };

	for (int s = 0; s < 4; s++) {
		int w = width[s], z = c->psize[s];
		const unsigned char *p = view(st, json_object_get(
		    json_object_get(props, c->prop[s]), "values"),
		    (size_t)count * w * z, name, semantic[s], c->r);

		for (int k = 0; k < w; k++) {
			uint64_t u = 0;
			uint32_t h = 0;
			float f;

			dst[s][k] = NAN;
			if (p == NULL)
				continue;
			if (z == 8) {
				memcpy(&u, p + 8 * (i * w + k), 8);
				memcpy(&dst[s][k], &u, 8);
			} else {
				memcpy(&h, p + 4 * (i * w + k), 4);
				memcpy(&f, &h, 4);
				dst[s][k] = f;
			}
		}
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
tiles(ctx *c, int rt, const subtree *st, int s, int sx, int sy,
    const char *name, unsigned char *ta, long ntile)
{
	json_t *j = st->j, *pt, *props;
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
	else
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
			row(c, st, props, rows, n, &m, name);
		else
			m.hmin = m.hmax = m.sphere[0] = m.sphere[1] =
			    m.sphere[2] = m.sphere[3] = m.hop[0] = m.hop[1] =
			    m.hop[2] = NAN;
		n++;
		if (--c->budget < 0 || push(&c->tiles, QM_KEY(z, (sx << d) +
		    lx + ((long)rt << z), (sy << d) + ly), &m) < 0)
			return -1;
	}
	return 0;
}

/* Subtree (s, sx, sy) of root rt and every one below it. */
static int
walk(ctx *c, int rt, int s, int sx, int sy)
{
	char name[256], path[4096];
	long ntile = ((1L << (2 * c->k)) - 1) / 3, nchild = 1L << (2 * c->k);
	unsigned char *buf = NULL, *ta = malloc((size_t)(ntile + nchild));
	subtree st = { NULL, NULL, 0 };
	int rc = -1;

	subtree_name(c, rt, s, sx, sy, name, sizeof name);
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
		if (--c->budget < 0 || push(&c->subs, QM_KEY(z, (sx << c->k) +
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
		subtree_name(c, rt, s + c->k, (sx << c->k) + lx,
		    (sy << c->k) + ly, name, sizeof name);
		snprintf(sub, sizeof sub, "%s/%s", c->dir, name);
		if (access(sub, F_OK) == 0 && walk(c, rt, s + c->k,
		    (sx << c->k) + lx, (sy << c->k) + ly) < 0)
			goto done;
	}
	rc = 0;
done:
	json_decref(st.j);
	free(buf), free(ta);
	return rc;
}

/* --- tileset.json ---------------------------------------------------- */

/* uri is prefix/{level}/{x}/{y}.ext, prefix one plain folder name. */
static int
layout(json_t *uri, const char *ext, char prefix[64])
{
	const char *u = json_string_value(uri), *sl;
	char want[128];

	if (u == NULL || (sl = strchr(u, '/')) == NULL || sl - u >= 64 ||
	    sl == u || strncmp(u, "..", 2) == 0 || memchr(u, '{', sl - u))
		return -1;
	snprintf(want, sizeof want, "/{level}/{x}/{y}.%s", ext);
	if (strcmp(sl, want))
		return -1;
	memcpy(prefix, u, (size_t)(sl - u));
	prefix[sl - u] = '\0';
	return 0;
}

/* The class's property of each TILE_* semantic, FLOAT64 or FLOAT32. */
static void
schema(json_t *ts, ctx *c)
{
	json_t *cls = json_object_get(json_object_get(ts, "schema"),
	    "classes"), *cl, *p;
	const char *cn, *pn;

	json_object_foreach(cls, cn, cl)
		json_object_foreach(json_object_get(cl, "properties"), pn, p)
			for (int s = 0; s < 4; s++) {
				const char *ct = json_string_value(
				    json_object_get(p, "componentType"));

				if (!json_is_string(json_object_get(p,
				    "semantic")) || strcmp(json_string_value(
				    json_object_get(p, "semantic")),
				    semantic[s]) || ct == NULL ||
				    strlen(pn) >= sizeof c->prop[s])
					continue;
				strcpy(c->prop[s], pn);
				c->psize[s] = !strcmp(ct, "FLOAT64") ? 8 :
				    !strcmp(ct, "FLOAT32") ? 4 : 0;
			}
	for (int s = 0; s < 4; s++)
		if (c->psize[s] == 0)
			qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "tileset.json: "
			    "schema: no FLOAT64 or FLOAT32 property of "
			    "semantic %s", semantic[s]);
}

/* Root r's child: its region, error, refinement, layout, tiling. */
static int
root(json_t *t, int r, ctx *c, tl_err *e)
{
	json_t *reg = json_object_get(json_object_get(t, "boundingVolume"),
	    "region"), *it = json_object_get(t, "implicitTiling");
	double want[4] = { r ? 0 : -M_PI, -M_PI / 2, r ? M_PI : 0, M_PI / 2 };
	double ge;
	char sp[64];
	int bad = json_array_size(reg) != 6;

	for (int k = 0; k < 6 && !bad; k++)
		bad |= tl_json_num(json_array_get(reg, k),
		    &c->T->region[r][k]) < 0 || (k < 4 &&
		    fabs(c->T->region[r][k] - want[k]) > 1e-12);
	if (bad)
		qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "tileset.json: root "
		    "child %d: region not the %s hemisphere", r,
		    r ? "eastern" : "western");
	if (tl_json_num(json_object_get(t, "geometricError"), &ge) < 0 ||
	    ge != 78271.52 || !json_is_string(json_object_get(t, "refine")) ||
	    strcmp(json_string_value(json_object_get(t, "refine")),
	    "REPLACE"))
		qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "tileset.json: root "
		    "child %d: geometricError not 78271.52 or refine not "
		    "REPLACE", r);
	if (layout(json_object_get(json_object_get(t, "content"), "uri"),
	    "glb", c->T->prefix[r]) < 0 || layout(json_object_get(
	    json_object_get(it, "subtrees"), "uri"), "subtree", sp) < 0 ||
	    strcmp(sp, c->T->prefix[r]) ||
	    (r == 1 && !strcmp(c->T->prefix[0], c->T->prefix[1])))
		return tl_fail(e, "tileset.json: root child %d: content and "
		    "subtree uris not F/{level}/{x}/{y}.glb and .subtree, one "
		    "folder F per root (the profile's layout, the only one "
		    "read)", r);
	if (!json_is_string(json_object_get(it, "subdivisionScheme")) ||
	    strcmp(json_string_value(json_object_get(it,
	    "subdivisionScheme")), "QUADTREE") ||
	    tl_json_int(json_object_get(it, "subtreeLevels"), 1, 10,
	    &c->kr[r]) < 0 || tl_json_int(json_object_get(it,
	    "availableLevels"), 1, QM_MAXZ + 1, &c->lr[r]) < 0)
		return tl_fail(e, "tileset.json: root child %d: implicitTiling "
		    "not QUADTREE with subtreeLevels 1..10 and availableLevels "
		    "1..%d", r, QM_MAXZ + 1);
	return 0;
}

/* --- the files present ----------------------------------------------- */

static long
number(const char *s, const char *end, long lim)
{
	long v = 0;

	if (s == end || (s[0] == '0' && end - s > 1))
		return -1;
	for (; s < end; s++) {
		if (*s < '0' || *s > '9' || v > lim)
			return -1;
		v = v * 10 + (*s - '0');
	}
	return v < lim ? v : -1;
}

/* dir/prefix/z/x/{y.glb, y.subtree} of root rt into glb and sub. */
static int
scan_level(const char *base, int rt, int z, ents *glb, ents *sub)
{
	char path[4096 + 300];
	DIR *dx, *dy;
	struct dirent *a, *b;

	snprintf(path, sizeof path, "%s/%d", base, z);
	if ((dx = opendir(path)) == NULL)
		return 0;
	while ((a = readdir(dx)) != NULL) {
		long x = number(a->d_name, a->d_name + strlen(a->d_name),
		    1L << z);

		snprintf(path, sizeof path, "%s/%d/%s", base, z, a->d_name);
		if (x < 0 || (dy = opendir(path)) == NULL)
			continue;
		while ((b = readdir(dy)) != NULL) {
			const char *dot = strrchr(b->d_name, '.');
			int g = dot != NULL && !strcmp(dot, ".glb");
			long y = dot == NULL || (!g && strcmp(dot,
			    ".subtree")) ? -1 : number(b->d_name, dot, 1L << z);

			if (y >= 0 && push(g ? glb : sub, QM_KEY(z, x +
			    ((long)rt << z), y), NULL) < 0) {
				closedir(dy), closedir(dx);
				return -1;
			}
		}
		closedir(dy);
	}
	closedir(dx);
	return 0;
}

static int
scan(ctx *c, ents *glb, ents *sub)
{
	char base[4096];

	for (int rt = 0; rt < 2; rt++) {
		snprintf(base, sizeof base, "%s/%s", c->dir, c->T->prefix[rt]);
		for (int z = 0; z <= QM_MAXZ; z++)
			if (scan_level(base, rt, z, glb, sub) < 0)
				return -1;
	}
	sort_unique(glb), sort_unique(sub);
	return 0;
}

/* Announced against present, both sorted; tiles named by their glb,
 * subtrees by their file. */
static void
compare(ctx *c, const ents *ann, const ents *has, int tiles)
{
	long i = 0, j = 0;
	char name[256];

	while (i < ann->n || j < has->n) {
		qm_key a = i < ann->n ? ann->e[i].k : UINT64_MAX;
		qm_key b = j < has->n ? has->e[j].k : UINT64_MAX;
		qm_key k = a < b ? a : b;
		int z = QM_KZ(k), x = QM_KX(k), y = QM_KY(k), rt = x >> z;

		if (a == b) {
			i++, j++;
			continue;
		}
		subtree_name(c, rt & 1, z, x - (rt << z), y, name,
		    sizeof name);
		if (tiles && a < b)
			qm_issue_add(c->r, QM_MISSING, z, x, y, "announced "
			    "by its subtree's tile availability, no file");
		else if (tiles)
			qm_issue_add(c->r, QM_UNANNOUNCED, z, x, y, "a file no "
			    "subtree announces");
		else
			qm_issue_add(c->r, a < b ? QM_MISSING : QM_UNANNOUNCED,
			    -1, 0, 0, "%s: %s", name, a < b ? "announced by "
			    "its parent's child subtree availability, no file" :
			    "a subtree file no parent subtree announces");
		i += a < b, j += b < a;
	}
}

static void
ancestors(const t3c_set *T, qm_report *r)
{
	const qm_set *s = &T->s;

	for (int x = 0; x < 2; x++)
		if (!qm_set_has(s, QM_KEY(0, x, 0)))
			qm_issue_add(r, QM_ANCESTOR, -1, 0, 0, "root tile "
			    "%s/0/0/0.glb missing: the provider asks for both",
			    T->prefix[x]);
	for (long i = 0; i < s->n; i++) {
		qm_key k = s->key[i];
		int z = QM_KZ(k);

		if (z > 0 && !qm_set_has(s, QM_KEY(z - 1, QM_KX(k) / 2,
		    QM_KY(k) / 2)))
			qm_issue_add(r, QM_ANCESTOR, z, QM_KX(k), QM_KY(k),
			    "its parent is missing");
	}
}

/* Each root's region holds every tile's heights. */
static void
regions(const t3c_set *T, qm_report *r)
{
	for (long i = 0; i < T->s.navail; i++) {
		qm_key k = T->s.avail[i];
		int rt = (QM_KX(k) >> QM_KZ(k)) & 1;
		const t3c_meta *m = &T->meta[i];

		if (m->hmin < T->region[rt][4] - TOLR ||
		    m->hmax > T->region[rt][5] + TOLR) {
			qm_issue_add(r, QM_LAYER, QM_KZ(k), QM_KX(k), QM_KY(k),
			    "heights %g..%g outside its root's region's "
			    "%g..%g", m->hmin, m->hmax, T->region[rt][4],
			    T->region[rt][5]);
			return;
		}
	}
}

static int
announce(ctx *c, json_t *ts, tl_err *e)
{
	json_t *kids = json_object_get(json_object_get(ts, "root"),
	    "children");
	const char *v = json_string_value(json_object_get(json_object_get(ts,
	    "asset"), "version"));

	if (v == NULL || strcmp(v, "1.1"))
		qm_issue_add(c->r, QM_LAYER, -1, 0, 0, "tileset.json: asset "
		    "version not 1.1");
	if (json_array_size(kids) != 2)
		return tl_fail(e, "tileset.json: the root has %zu children, "
		    "not the profile's two", json_array_size(kids));
	schema(ts, c);
	for (int r = 0; r < 2; r++)
		if (root(json_array_get(kids, (size_t)r), r, c, e) < 0)
			return -1;
	for (int r = 0; r < 2; r++) {
		char name[256], path[4096];

		c->k = c->kr[r], c->levels = c->lr[r];
		subtree_name(c, r, 0, 0, 0, name, sizeof name);
		snprintf(path, sizeof path, "%s/%s", c->dir, name);
		if (access(path, F_OK) < 0)
			qm_issue_add(c->r, QM_MISSING, -1, 0, 0, "%s: the root "
			    "subtree, no file", name);
		else if (walk(c, r, 0, 0, 0) < 0)
			return tl_fail(e, "%s: out of memory, or over %ld "
			    "tiles announced", c->dir, MAXANNOUNCED);
		if (push(&c->subs, QM_KEY(0, r, 0), NULL) < 0)
			return tl_fail(e, "out of memory");
	}
	c->T->s.maxzoom = (c->lr[0] > c->lr[1] ? c->lr[0] : c->lr[1]) - 1;
	c->T->s.normals = 1;
	return 0;
}

int
t3c_set_read(const char *dir, t3c_set *T, qm_report *r, tl_err *e)
{
	char path[4096];
	json_error_t je;
	json_t *ts;
	ctx c;
	ents glb = { NULL, 0, 0 }, sub = { NULL, 0, 0 };
	int st = -1;

	memset(T, 0, sizeof *T);
	memset(&c, 0, sizeof c);
	c.dir = dir, c.T = T, c.r = r, c.budget = MAXANNOUNCED;
	snprintf(path, sizeof path, "%s/tileset.json", dir);
	if ((ts = json_load_file(path, JSON_REJECT_DUPLICATES, &je)) == NULL)
		return tl_fail(e, "%s: line %d: %s", path, je.line, je.text);
	if (announce(&c, ts, e) < 0 || scan(&c, &glb, &sub) < 0)
		goto done;
	sort_unique(&c.tiles), sort_unique(&c.subs);
	compare(&c, &c.tiles, &glb, 1);
	compare(&c, &c.subs, &sub, 0);
	T->s.key = malloc(((size_t)glb.n + 1) * sizeof *T->s.key);
	T->s.avail = malloc(((size_t)c.tiles.n + 1) * sizeof *T->s.avail);
	T->meta = malloc(((size_t)c.tiles.n + 1) * sizeof *T->meta);
	if (T->s.key == NULL || T->s.avail == NULL || T->meta == NULL) {
		tl_fail(e, "%s: out of memory", dir);
		goto done;
	}
	for (long i = 0; i < glb.n; i++)
		T->s.key[i] = glb.e[i].k;
	for (long i = 0; i < c.tiles.n; i++)
		T->s.avail[i] = c.tiles.e[i].k, T->meta[i] = c.tiles.e[i].m;
	T->s.n = glb.n, T->s.navail = c.tiles.n;
	ancestors(T, r);
	regions(T, r);
	st = 0;
done:
	json_decref(ts);
	free(glb.e), free(sub.e), free(c.tiles.e), free(c.subs.e);
	return st;
}

void
t3c_set_free(t3c_set *T)
{
	qm_set_free(&T->s);
	free(T->meta);
	memset(T, 0, sizeof *T);
}

const t3c_meta *
t3c_set_meta(const t3c_set *T, qm_key k)
{
	long lo = 0, hi = T->s.navail;

	while (lo < hi) {
		long mid = lo + (hi - lo) / 2;

		if (T->s.avail[mid] < k)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo < T->s.navail && T->s.avail[lo] == k ? &T->meta[lo] : NULL;
}
