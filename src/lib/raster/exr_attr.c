/* exr_attr.c - header attributes between rs_header and OpenEXRCore:
 * ours are int, double, string, v2i and v2d; EXR's structural ones
 * (channels, windows, compression, ...) are its own business. */
#include "raster/exr_impl.h"

#include <stdlib.h>
#include <string.h>

exr_result_t
rs_exr_attr_put(exr_context_t c, const rs_attr *a)
{
	switch (a->type) {
	case RS_INT:
		return exr_attr_set_int(c, 0, a->name, a->v.i);
	case RS_DOUBLE:
		return exr_attr_set_double(c, 0, a->name, a->v.d);
	case RS_STRING:
		return exr_attr_set_string(c, 0, a->name, a->s);
	case RS_V2I:
		return exr_attr_set_v2i(c, 0, a->name,
		    &(exr_attr_v2i_t){ .x = a->v.v2i[0], .y = a->v.v2i[1] });
	case RS_V2D:
		return exr_attr_set_v2d(c, 0, a->name,
		    &(exr_attr_v2d_t){ .x = a->v.v2d[0], .y = a->v.v2d[1] });
	}
	return EXR_ERR_INVALID_ARGUMENT;
}

/* Structural attributes: EXR's own business, not the raster's. */
static int
standard(const char *name)
{
	static const char *const std[] = {
		"channels", "compression", "dataWindow", "displayWindow",
		"lineOrder", "pixelAspectRatio", "screenWindowCenter",
		"screenWindowWidth", "name", "type", "version", "chunkCount",
		"tiles",
	};

	for (size_t i = 0; i < sizeof std / sizeof std[0]; i++)
		if (strcmp(name, std[i]) == 0)
			return 1;
	return 0;
}

int
rs_exr_attr_get(rs_header *h, const exr_attribute_t *a, tl_err *e)
{
	char *s;
	int rv;

	if (standard(a->name) || strlen(a->name) >= sizeof h->attr[0].name)
		return 0;
	switch (a->type) {
	case EXR_ATTR_INT:
		return rs_set_int(h, a->name, a->i, e);
	case EXR_ATTR_DOUBLE:
		return rs_set_double(h, a->name, a->d, e);
	case EXR_ATTR_V2I:
		return rs_set_v2i(h, a->name, a->v2i->x, a->v2i->y, e);
	case EXR_ATTR_V2D:
		return rs_set_v2d(h, a->name, a->v2d->x, a->v2d->y, e);
	case EXR_ATTR_STRING:
		/* Not NUL-terminated in every version: copy by length. */
		s = tl_alloc((size_t)a->string->length + 1, 1, e);
		if (s == NULL)
			return -1;
		if (a->string->length > 0)
			memcpy(s, a->string->str, (size_t)a->string->length);
		rv = rs_set_string(h, a->name, s, e);
		free(s);
		return rv;
	default:
		return 0;
	}
}
