/* rs_header.c - a raster's header: size, channels and typed attributes,
 * and the size caps every reader checks. The leaf of raster: the front
 * door (raster.c) and every backend (exr*.c, stream.c, rs_list.c) use it,
 * it uses none of them. */
#include "raster/rs_impl.h"

#include <stdlib.h>
#include <string.h>

void
rs_header_init(rs_header *h, int width, int height)
{
	memset(h, 0, sizeof *h);
	h->width = width;
	h->height = height;
}

void
rs_header_free(rs_header *h)
{
	for (int i = 0; i < h->nattr; i++) {
		free(h->attr[i].s);
		h->attr[i].s = NULL;
	}
	h->nattr = 0;
}

/* dst is overwritten, not freed first. */
int
rs_header_copy(rs_header *dst, const rs_header *src, tl_err *e)
{
	*dst = *src;
	for (int i = 0; i < src->nattr; i++) {
		if (src->attr[i].s == NULL)
			continue;
		if ((dst->attr[i].s = strdup(src->attr[i].s)) == NULL) {
			dst->nattr = i;
			rs_header_free(dst);
			return tl_fail(e, "header copy: out of memory");
		}
	}
	return 0;
}

int
rs_add_channel(rs_header *h, const char *name, tl_err *e)
{
	size_t n = strlen(name);
	int i;

	if (n == 0 || n >= sizeof h->ch[0])
		return tl_fail(e, "channel \"%s\": name empty or longer than "
		    "%zu bytes", name, sizeof h->ch[0] - 1);
	if (rs_channel(h, name) >= 0)
		return tl_fail(e, "channel %s: already present", name);
	if (h->nch >= RS_MAXCH)
		return tl_fail(e, "channel %s: more than %d channels", name,
		    RS_MAXCH);
	for (i = h->nch; i > 0 && strcmp(h->ch[i - 1], name) > 0; i--)
		memcpy(h->ch[i], h->ch[i - 1], sizeof h->ch[i]);
	memcpy(h->ch[i], name, n + 1);
	h->nch++;
	return 0;
}

void
rs_clear_channels(rs_header *h)
{
	h->nch = 0;
	memset(h->ch, 0, sizeof h->ch);
}

int
rs_channel(const rs_header *h, const char *name)
{
	for (int i = 0; i < h->nch; i++)
		if (strcmp(h->ch[i], name) == 0)
			return i;
	return -1;
}

int
rs_need_channel(const rs_header *h, const char *name, const char *what,
    tl_err *e)
{
	int i = rs_channel(h, name);

	if (i < 0)
		return tl_fail(e, "%s: no channel %s", what, name);
	return i;
}

const rs_attr *
rs_find_attr(const rs_header *h, const char *name)
{
	for (int i = 0; i < h->nattr; i++)
		if (strcmp(h->attr[i].name, name) == 0)
			return &h->attr[i];
	return NULL;
}

/* The setters' way in: the slot is the header's own, writable. */
static rs_attr *
find_attr(rs_header *h, const char *name)
{
	return (rs_attr *)rs_find_attr(h, name);
}

int
rs_attr_same(const rs_attr *a, const rs_attr *b)
{
	if (a->type != b->type)
		return 0;
	switch (a->type) {
	case RS_STRING:
		return strcmp(a->s, b->s) == 0;
	case RS_INT:
		return a->v.i == b->v.i;
	case RS_V2I:
		return memcmp(a->v.v2i, b->v.v2i, sizeof a->v.v2i) == 0;
	case RS_DOUBLE:
		return memcmp(&a->v.d, &b->v.d, sizeof a->v.d) == 0;
	case RS_V2D:
		return memcmp(a->v.v2d, b->v.v2d, sizeof a->v.v2d) == 0;
	}
	return 0;
}

/* The slot for name: the existing one (its old string freed) or a new one. */
static rs_attr *
slot(rs_header *h, const char *name, enum rs_type t, tl_err *e)
{
	rs_attr *a = find_attr(h, name);
	size_t n = strlen(name);

	if (n == 0 || n >= sizeof a->name) {
		tl_fail(e, "attribute \"%s\": name empty or longer than %zu "
		    "bytes", name, sizeof a->name - 1);
		return NULL;
	}
	if (a == NULL) {
		if (h->nattr >= RS_MAXATTR) {
			tl_fail(e, "attribute %s: more than %d attributes",
			    name, RS_MAXATTR);
			return NULL;
		}
		a = &h->attr[h->nattr++];
		memset(a, 0, sizeof *a);
		memcpy(a->name, name, n + 1);
	}
	free(a->s);
	a->s = NULL;
	a->type = t;
	return a;
}

int
rs_set_int(rs_header *h, const char *name, int v, tl_err *e)
{
	rs_attr *a = slot(h, name, RS_INT, e);

	if (a == NULL)
		return -1;
	a->v.i = v;
	return 0;
}

int
rs_set_double(rs_header *h, const char *name, double v, tl_err *e)
{
	rs_attr *a = slot(h, name, RS_DOUBLE, e);

	if (a == NULL)
		return -1;
	a->v.d = v;
	return 0;
}

int
rs_set_string(rs_header *h, const char *name, const char *v, tl_err *e)
{
	char *s = strdup(v);
	rs_attr *a;

	if (s == NULL)
		return tl_fail(e, "attribute %s: out of memory", name);
	if ((a = slot(h, name, RS_STRING, e)) == NULL) {
		free(s);
		return -1;
	}
	a->s = s;
	return 0;
}

int
rs_set_v2i(rs_header *h, const char *name, int x, int y, tl_err *e)
{
	rs_attr *a = slot(h, name, RS_V2I, e);

	if (a == NULL)
		return -1;
	a->v.v2i[0] = x;
	a->v.v2i[1] = y;
	return 0;
}

int
rs_set_v2d(rs_header *h, const char *name, double x, double y, tl_err *e)
{
	rs_attr *a = slot(h, name, RS_V2D, e);

	if (a == NULL)
		return -1;
	a->v.v2d[0] = x;
	a->v.v2d[1] = y;
	return 0;
}

void
rs_unset(rs_header *h, const char *name)
{
	rs_attr *a = find_attr(h, name);

	if (a == NULL)
		return;
	free(a->s);
	memmove(a, a + 1, (size_t)(&h->attr[h->nattr] - (a + 1)) * sizeof *a);
	h->nattr--;
}

static const rs_attr *
typed(const rs_header *h, const char *name, enum rs_type t)
{
	const rs_attr *a = rs_find_attr(h, name);

	return a != NULL && a->type == t ? a : NULL;
}

int
rs_get_int(const rs_header *h, const char *name, int *v)
{
	const rs_attr *a = typed(h, name, RS_INT);

	if (a == NULL)
		return -1;
	*v = a->v.i;
	return 0;
}

int
rs_get_double(const rs_header *h, const char *name, double *v)
{
	const rs_attr *a = typed(h, name, RS_DOUBLE);

	if (a == NULL)
		return -1;
	*v = a->v.d;
	return 0;
}

const char *
rs_get_string(const rs_header *h, const char *name)
{
	const rs_attr *a = typed(h, name, RS_STRING);

	return a != NULL ? a->s : NULL;
}

int
rs_get_v2i(const rs_header *h, const char *name, int v[2])
{
	const rs_attr *a = typed(h, name, RS_V2I);

	if (a == NULL)
		return -1;
	v[0] = a->v.v2i[0];
	v[1] = a->v.v2i[1];
	return 0;
}

int
rs_get_v2d(const rs_header *h, const char *name, double v[2])
{
	const rs_attr *a = typed(h, name, RS_V2D);

	if (a == NULL)
		return -1;
	v[0] = a->v.v2d[0];
	v[1] = a->v.v2d[1];
	return 0;
}

int
rs_check_size(const rs_header *h, const char *name, tl_err *e)
{
	if (h->width < 1 || h->height < 1 || h->width > RS_MAXDIM ||
	    h->height > RS_MAXDIM)
		return tl_fail(e, "%s: bad raster size %dx%d", name, h->width,
		    h->height);
	if (h->nch < 1 || h->nch > RS_MAXCH)
		return tl_fail(e, "%s: %d channels (1 to %d)", name, h->nch,
		    RS_MAXCH);
	if (4LL * h->nch * h->width > RS_MAXROW)
		return tl_fail(e, "%s: rows of %lld bytes, more than %d",
		    name, 4LL * h->nch * h->width, RS_MAXROW);
	return 0;
}
