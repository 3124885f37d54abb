/* paths.c - outputs kept off inputs: paths resolved as the kernel does,
 * compared by device and inode (paths.h). */
#define _GNU_SOURCE
#include "base/paths.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TREE_DEPTH 8
#define BANDS_MAX (1 << 24) /* bytes: a band list's reader refuses more */

struct tl_path_in {
	char *path, *desc;
	int flags;
};

typedef struct {
	dev_t dev;
	ino_t ino;
} fid;

/* A path resolved: real is the realpath of its longest existing prefix
 * (plen bytes), then the rest by name; exists when there is no rest. */
typedef struct {
	char real[PATH_MAX];
	size_t plen;
	int exists;
	struct stat st; /* when it exists */
	fid *anc;       /* the existing directories above it (when it does
	                 * not exist: from its nearest existing one), up to
	                 * "/", nearest first */
	int nanc;
} rpath;

/* Appends the component c (n bytes) to real, or takes one off for "..". */
static int
push(char *real, const char *c, size_t n, size_t *plen)
{
	size_t len = strlen(real);
	char *slash;

	if (n == 0 || (n == 1 && c[0] == '.'))
		return 0;
	if (n == 2 && c[0] == '.' && c[1] == '.') {
		slash = strrchr(real, '/');
		len = slash == real ? 1 : (size_t)(slash - real);
		real[len] = '\0';
		if (*plen > len)
			*plen = len;
		return 1;
	}
	if (len + 1 + n >= PATH_MAX)
		return -1;
	if (len > 1)
		real[len++] = '/';
	memcpy(real + len, c, n);
	real[len + n] = '\0';
	return 0;
}

/* One pass: the realpath of abs's longest existing prefix, the rest
 * appended by name. 1 when the rest held "..", 0, or -1 (too long). */
static int
resolve_once(const char *abs, char *real, size_t *plen)
{
	char buf[PATH_MAX];
	size_t cut = strlen(abs);
	int dots = 0, r;

	memcpy(buf, abs, cut + 1);
	while (realpath(buf, real) == NULL) {
		char *slash;
		while (cut > 1 && buf[cut - 1] == '/')
			buf[--cut] = '\0';
		slash = strrchr(buf, '/');
		cut = slash == buf ? 1 : (size_t)(slash - buf);
		buf[cut] = '\0';
		if (cut == 1)
			buf[0] = '/';
	}
	*plen = strlen(real);
	/* the rest: abs past the prefix kept in buf */
	for (const char *p = abs + cut, *q; *p != '\0'; p = q) {
		while (*p == '/')
			p++;
		q = p + strcspn(p, "/");
		if ((r = push(real, p, (size_t)(q - p), plen)) < 0)
			return -1;
		dots |= r;
	}
	return dots;
}

static int
add_id(rpath *r, const struct stat *st)
{
	fid *a;

	if ((r->nanc & 15) == 0 && (a = realloc(r->anc, (size_t)(r->nanc +
	    16) * sizeof *a)) == NULL)
		return -1;
	else if ((r->nanc & 15) == 0)
		r->anc = a;
	r->anc[r->nanc].dev = st->st_dev;
	r->anc[r->nanc++].ino = st->st_ino;
	return 0;
}

static int
resolve(const char *path, rpath *r, tl_err *e)
{
	char abs[PATH_MAX], dir[PATH_MAX];
	size_t up = PATH_MAX; /* push's bound, unused here */
	struct stat st;
	int n;

	memset(r, 0, sizeof *r);
	if (path[0] == '/')
		n = snprintf(abs, sizeof abs, "%s", path);
	else if (getcwd(dir, sizeof dir) == NULL)
		return tl_failsys(e, "%s: current directory", path);
	else
		n = snprintf(abs, sizeof abs, "%s/%s", dir, path);
	if (n < 0 || (size_t)n >= sizeof abs)
		return tl_fail(e, "%s: name too long", path);
	/* a ".." past a missing directory: once more from what it named */
	if ((n = resolve_once(abs, r->real, &r->plen)) > 0) {
		memcpy(abs, r->real, sizeof abs);
		n = resolve_once(abs, r->real, &r->plen);
	}
	if (n < 0)
		return tl_fail(e, "%s: name too long", path);
	r->exists = r->plen == strlen(r->real) && stat(r->real, &r->st) == 0;
	if (r->exists && strcmp(r->real, "/") == 0)
		return 0;
	memcpy(dir, r->real, r->plen);
	dir[r->plen] = '\0';
	if (r->exists)
		push(dir, "..", 2, &up);
	for (;;) {
		if (stat(dir, &st) == 0 && add_id(r, &st) < 0)
			return tl_fail(e, "%s: out of memory", path);
		if (strcmp(dir, "/") == 0)
			return 0;
		push(dir, "..", 2, &up);
	}
}

static int
same_id(const fid *a, const struct stat *st)
{
	return a->dev == st->st_dev && a->ino == st->st_ino;
}

static int
above(const rpath *r, const struct stat *st)
{
	for (int k = 0; k < r->nanc; k++)
		if (same_id(&r->anc[k], st))
			return 1;
	return 0;
}

/* Two paths neither of which exists: under one nearest existing
 * directory, by the names of the rest. */
static int
by_name(const rpath *o, const rpath *i)
{
	const char *a = o->real + o->plen, *b = i->real + i->plen;
	size_t na, nb;

	if (o->nanc == 0 || i->nanc == 0 || o->anc[0].dev != i->anc[0].dev ||
	    o->anc[0].ino != i->anc[0].ino)
		return TL_PATH_APART;
	a += *a == '/', b += *b == '/';
	na = strlen(a), nb = strlen(b);
	if (na == nb && memcmp(a, b, na) == 0)
		return TL_PATH_SAME;
	if (na > nb && memcmp(a, b, nb) == 0 && a[nb] == '/')
		return TL_PATH_INSIDE;
	if (nb > na && memcmp(a, b, na) == 0 && b[na] == '/')
		return TL_PATH_CONTAINS;
	return TL_PATH_APART;
}

static int
relate(const rpath *o, const rpath *i)
{
	if (o->exists && i->exists) {
		if (o->st.st_dev == i->st.st_dev && o->st.st_ino == i->st.st_ino)
			return TL_PATH_SAME;
		if (S_ISDIR(o->st.st_mode) && above(i, &o->st))
			return TL_PATH_CONTAINS;
		return above(o, &i->st) ? TL_PATH_INSIDE : TL_PATH_APART;
	}
	if (o->exists)
		return S_ISDIR(o->st.st_mode) && above(i, &o->st) ?
		    TL_PATH_CONTAINS : TL_PATH_APART;
	if (i->exists)
		return above(o, &i->st) ? TL_PATH_INSIDE : TL_PATH_APART;
	return by_name(o, i);
}

/* The directories a tree's links reached, each walked once (a link
 * loop, two links to one place); past TREE_LINKS of them no more links
 * are followed: the work stays bounded whatever the tree. */
#define TREE_LINKS 64
typedef struct {
	fid id[TREE_LINKS];
	int n;
} walked;

static int
walk_once(walked *w, const struct stat *st)
{
	for (int k = 0; k < w->n; k++)
		if (same_id(&w->id[k], st))
			return 0;
	if (w->n == TREE_LINKS)
		return 0;
	w->id[w->n].dev = st->st_dev;
	w->id[w->n++].ino = st->st_ino;
	return 1;
}

/* What a directory's tree reaches beyond its own paths: its symbolic
 * links' targets, compared as inputs themselves (and walked when they
 * are directories), and, when out is a file with other names, its
 * files by inode. */
static int
tree(const rpath *o, const char *dir, int depth, walked *w, tl_err *e)
{
	int links = o->exists && S_ISREG(o->st.st_mode) && o->st.st_nlink > 1;
	char p[PATH_MAX];
	struct dirent *de;
	struct stat st;
	int rel = TL_PATH_APART;
	DIR *d;

	if (depth > TREE_DEPTH || (d = opendir(dir)) == NULL)
		return TL_PATH_APART;
	while (rel == TL_PATH_APART && (de = readdir(d)) != NULL) {
		int t = de->d_type;
		if (strcmp(de->d_name, ".") == 0 || strcmp(de->d_name, "..") == 0 ||
		    (size_t)snprintf(p, sizeof p, "%s/%s", dir, de->d_name) >=
		    sizeof p)
			continue;
		if (t == DT_UNKNOWN && lstat(p, &st) == 0)
			t = S_ISLNK(st.st_mode) ? DT_LNK : S_ISDIR(st.st_mode) ?
			    DT_DIR : S_ISREG(st.st_mode) ? DT_REG : DT_UNKNOWN;
		if (t == DT_LNK) {
			rpath i;
			if (resolve(p, &i, e) < 0) {
				closedir(d);
				return -1;
			}
			if (i.exists && (rel = relate(o, &i)) == TL_PATH_APART &&
			    S_ISDIR(i.st.st_mode) && walk_once(w, &i.st))
				rel = tree(o, i.real, depth + 1, w, e);
			free(i.anc);
		} else if (t == DT_DIR) {
			rel = tree(o, p, depth + 1, w, e);
		} else if (t == DT_REG && links && stat(p, &st) == 0 &&
		    st.st_dev == o->st.st_dev && st.st_ino == o->st.st_ino) {
			rel = TL_PATH_INSIDE;
		}
	}
	closedir(d);
	return rel == TL_PATH_SAME ? TL_PATH_INSIDE : rel;
}

static int
relation(const rpath *o, const char *in, int flags, tl_err *e)
{
	walked w = { .n = 0 };
	rpath i;
	int rel = TL_PATH_APART;

	if (resolve(in, &i, e) < 0)
		return -1;
	if (i.exists || (flags & TL_PATH_OUT))
		rel = relate(o, &i);
	if (rel == TL_PATH_APART && i.exists && (flags & TL_PATH_TREE) &&
	    S_ISDIR(i.st.st_mode) && walk_once(&w, &i.st))
		rel = tree(o, i.real, 1, &w, e);
	free(i.anc);
	return rel;
}

int
tl_path_relation(const char *out, const char *in, int flags, tl_err *e)
{
	rpath o;
	int rel = -1;

	if (resolve(out, &o, e) == 0)
		rel = relation(&o, in, flags, e);
	free(o.anc);
	return rel;
}

int
tl_paths_add(tl_paths *s, const char *path, int flags, tl_err *e,
    const char *fmt, ...)
{
	struct tl_path_in *n;
	va_list ap;
	int len;

	if (strcmp(path, "-") == 0)
		return 0;
	if (s->n == s->cap) {
		int cap = s->cap ? 2 * s->cap : 8;
		if ((n = realloc(s->in, (size_t)cap * sizeof *n)) == NULL)
			return tl_fail(e, "%s: out of memory", path);
		s->in = n, s->cap = cap;
	}
	n = &s->in[s->n];
	va_start(ap, fmt);
	len = vasprintf(&n->desc, fmt, ap);
	va_end(ap);
	if (len < 0 || (n->path = strdup(path)) == NULL) {
		if (len >= 0)
			free(n->desc);
		return tl_fail(e, "%s: out of memory", path);
	}
	n->flags = flags;
	s->n++;
	return 0;
}

/* A band list (fqm(5)): "fqm-bands 1", then a path a line, relative to
 * the list's directory; the rules of tl_list_entry. Its bands are added
 * as files of it. A list this large is refused by its reader anyway. */
static int
add_bands(tl_paths *s, const char *path, const char *what, tl_err *e)
{
	const char *slash = strrchr(path, '/');
	char head[12], *text = NULL, *dir = NULL, *line, *nl;
	struct stat st;
	size_t n = 0;
	FILE *f;
	int r = 0;

	/* a FIFO is never opened here: that would let its writer go on
	 * before its reader is there, or eat its stream; a raster is not
	 * read past its first bytes */
	if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size >
	    BANDS_MAX || (f = fopen(path, "re")) == NULL)
		return 0;
	if (fread(head, 1, sizeof head, f) != sizeof head ||
	    memcmp(head, "fqm-bands 1\n", sizeof head) != 0 ||
	    getdelim(&text, &n, '\0', f) < 0) {
		free(text);
		fclose(f);
		return 0;
	}
	fclose(f);
	if (slash != NULL && (dir = strndup(path, slash == path ? 1 :
	    (size_t)(slash - path))) == NULL)
		r = tl_fail(e, "%s: out of memory", path);
	for (line = text; r == 0 && line != NULL; line = nl) {
		char *ent, *p;
		if ((nl = strchr(line, '\n')) != NULL)
			*nl++ = '\0';
		if ((ent = tl_list_entry(line)) == NULL)
			continue;
		if ((p = tl_list_path(dir, ent, e)) == NULL)
			r = -1;
		else
			r = tl_paths_add(s, p, 0, e, "%s, a band of the input %s "
			    "%s", p, what, path);
		free(p);
	}
	free(dir);
	free(text);
	return r;
}

int
tl_paths_add_raster(tl_paths *s, const char *path, const char *what,
    tl_err *e)
{
	if (strcmp(path, "-") == 0)
		return 0;
	if (tl_paths_add(s, path, 0, e, "the input %s %s", what, path) < 0)
		return -1;
	return add_bands(s, path, what, e);
}

int
tl_paths_check(const tl_paths *s, const char *out, tl_err *e)
{
	static const char *const verb[] = { "", "is", "is inside",
	    "contains" };
	rpath o;
	int rel = TL_PATH_APART, k;

	if (strcmp(out, "-") == 0 || s->n == 0)
		return 0;
	if (resolve(out, &o, e) < 0)
		return -1;
	for (k = 0; k < s->n && rel == TL_PATH_APART; k++)
		rel = relation(&o, s->in[k].path, s->in[k].flags, e);
	free(o.anc);
	if (rel <= 0)
		return rel;
	return tl_fail(e, "%s: %s %s", out, verb[rel], s->in[k - 1].desc);
}

void
tl_paths_free(tl_paths *s)
{
	for (int k = 0; k < s->n; k++)
		free(s->in[k].path), free(s->in[k].desc);
	free(s->in);
	memset(s, 0, sizeof *s);
}

int
tl_path_check(const char *out, const char *in, const char *what,
    int flags, tl_err *e)
{
	tl_paths s = { 0 };
	int r = tl_paths_add(&s, in, flags, e, "the input %s %s", what, in);

	if (r == 0)
		r = tl_paths_check(&s, out, e);
	tl_paths_free(&s);
	return r;
}

int
tl_path_check_raster(const char *out, const char *in, const char *what,
    tl_err *e)
{
	tl_paths s = { 0 };
	int r = tl_paths_add_raster(&s, in, what, e);

	if (r == 0)
		r = tl_paths_check(&s, out, e);
	tl_paths_free(&s);
	return r;
}
