/* t3c_set.c - a 3D Tiles terrain tileset as a whole, read from the 3D
 * Tiles 1.1 specification: tileset.json (the schema's TILE_* semantics,
 * the two implicit quadtree roots), each root's subtrees walked
 * (t3c_subtree.c), the files present, and the quadtree: announced
 * exactly the files, every ancestor present, the roots' regions holding
 * every tile's heights. */
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
#define TOLR 1e-3               /* metres: a region's heights */

typedef struct {
	t3c_walk w;         /* the walk of the root at hand */
	t3c_set *T;
	int lr[2], kr[2];   /* availableLevels, subtreeLevels of each root */
} ctx;

static int
cmpent(const void *a, const void *b)
{
	qm_key x = ((const t3c_ent *)a)->k, y = ((const t3c_ent *)b)->k;

	return x < y ? -1 : x > y;
}

static void
sort_unique(t3c_ents *s)
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
				    t3c_semantic[s]) || ct == NULL ||
				    strlen(pn) >= sizeof c->w.prop[s])
					continue;
				strcpy(c->w.prop[s], pn);
				c->w.psize[s] = !strcmp(ct, "FLOAT64") ? 8 :
				    !strcmp(ct, "FLOAT32") ? 4 : 0;
			}
	for (int s = 0; s < 4; s++)
		if (c->w.psize[s] == 0)
			qm_issue_add(c->w.r, QM_LAYER, -1, 0, 0, "tileset.json: "
			    "schema: no FLOAT64 or FLOAT32 property of "
			    "semantic %s", t3c_semantic[s]);
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
		qm_issue_add(c->w.r, QM_LAYER, -1, 0, 0, "tileset.json: root "
		    "child %d: region not the %s hemisphere", r,
		    r ? "eastern" : "western");
	if (tl_json_num(json_object_get(t, "geometricError"), &ge) < 0 ||
	    ge != 78271.52 || !json_is_string(json_object_get(t, "refine")) ||
	    strcmp(json_string_value(json_object_get(t, "refine")),
	    "REPLACE"))
		qm_issue_add(c->w.r, QM_LAYER, -1, 0, 0, "tileset.json: root "
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
scan_level(const char *base, int rt, int z, t3c_ents *glb, t3c_ents *sub)
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

			if (y >= 0 && t3c_push(g ? glb : sub, QM_KEY(z, x +
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
scan(ctx *c, t3c_ents *glb, t3c_ents *sub)
{
	char base[4096];

	for (int rt = 0; rt < 2; rt++) {
		snprintf(base, sizeof base, "%s/%s", c->w.dir, c->T->prefix[rt]);
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
compare(ctx *c, const t3c_ents *ann, const t3c_ents *has, int tiles)
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
			qm_issue_add(c->w.r, QM_MISSING, z, x, y, "announced "
			    "by its subtree's tile availability, no file");
		else if (tiles)
			qm_issue_add(c->w.r, QM_UNANNOUNCED, z, x, y, "a file no "
			    "subtree announces");
		else
			qm_issue_add(c->w.r, a < b ? QM_MISSING : QM_UNANNOUNCED,
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
		qm_issue_add(c->w.r, QM_LAYER, -1, 0, 0, "tileset.json: asset "
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

		c->w.k = c->kr[r], c->w.levels = c->lr[r];
		c->w.prefix = c->T->prefix[r];
		subtree_name(c, r, 0, 0, 0, name, sizeof name);
		snprintf(path, sizeof path, "%s/%s", c->w.dir, name);
		if (access(path, F_OK) < 0)
			qm_issue_add(c->w.r, QM_MISSING, -1, 0, 0, "%s: the root "
			    "subtree, no file", name);
		else if (t3c_walk_subtree(&c->w, r, 0, 0, 0) < 0)
			return tl_fail(e, "%s: out of memory, or over %ld "
			    "tiles announced", c->w.dir, MAXANNOUNCED);
		if (t3c_push(&c->w.subs, QM_KEY(0, r, 0), NULL) < 0)
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
	t3c_ents glb = { NULL, 0, 0 }, sub = { NULL, 0, 0 };
	int st = -1;

	memset(T, 0, sizeof *T);
	memset(&c, 0, sizeof c);
	c.w.dir = dir, c.T = T, c.w.r = r, c.w.budget = MAXANNOUNCED;
	snprintf(path, sizeof path, "%s/tileset.json", dir);
	if ((ts = json_load_file(path, JSON_REJECT_DUPLICATES, &je)) == NULL)
		return tl_fail(e, "%s: line %d: %s", path, je.line, je.text);
	if (announce(&c, ts, e) < 0 || scan(&c, &glb, &sub) < 0)
		goto done;
	sort_unique(&c.w.tiles), sort_unique(&c.w.subs);
	compare(&c, &c.w.tiles, &glb, 1);
	compare(&c, &c.w.subs, &sub, 0);
	T->s.key = malloc(((size_t)glb.n + 1) * sizeof *T->s.key);
	T->s.avail = malloc(((size_t)c.w.tiles.n + 1) * sizeof *T->s.avail);
	T->meta = malloc(((size_t)c.w.tiles.n + 1) * sizeof *T->meta);
	if (T->s.key == NULL || T->s.avail == NULL || T->meta == NULL) {
		tl_fail(e, "%s: out of memory", dir);
		goto done;
	}
	for (long i = 0; i < glb.n; i++)
		T->s.key[i] = glb.e[i].k;
	for (long i = 0; i < c.w.tiles.n; i++)
		T->s.avail[i] = c.w.tiles.e[i].k, T->meta[i] = c.w.tiles.e[i].m;
	T->s.n = glb.n, T->s.navail = c.w.tiles.n;
	ancestors(T, r);
	regions(T, r);
	st = 0;
done:
	json_decref(ts);
	free(glb.e), free(sub.e), free(c.w.tiles.e), free(c.w.subs.e);
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
