/* fqm.c - the FQM and vertex-map headers: channels, fqm:* and geo:*
 * attributes, the level a raster is, a filter's input opened (fqm.h,
 * fqm(5)). Rows are fqm_rows.c's, level 0's quadrics fqm0_kernel.c's. */
#include "qem/fqm.h"

#include <string.h>

static const char *const qch[10] = {
	"Q.a11", "Q.a12", "Q.a13", "Q.a22", "Q.a23", "Q.a33",
	"Q.b1", "Q.b2", "Q.b3", "Q.c",
};
_Static_assert(sizeof qch / sizeof qch[0] ==
    sizeof ((fqm_layout *)0)->q / sizeof ((fqm_layout *)0)->q[0],
    "one channel per quadric coefficient");

static int
set_info(rs_header *h, const fqm_info *fi, const char *kind, tl_err *e)
{
	if (rs_set_int(h, FQM_ATTR_VERSION, FQM_VERSION, e) < 0 ||
	    rs_set_string(h, FQM_ATTR_KIND, kind, e) < 0 ||
	    rs_set_int(h, FQM_ATTR_LEVEL, fi->level, e) < 0 ||
	    rs_set_v2i(h, FQM_ATTR_SIZE0, fi->size0[0], fi->size0[1], e) < 0)
		return -1;
	rs_unset(h, RS_ATTR_X0);
	if (fi->x0 != 0 && rs_set_int(h, RS_ATTR_X0, fi->x0, e) < 0)
		return -1;
	return rs_put_georef(&fi->geo, h, e);
}

int
fqm_header(rs_header *h, const fqm_info *fi, const char *kernel, tl_err *e)
{
	rs_header_init(h, geo_level_size(fi->size0[0], fi->level) - fi->x0,
	    geo_level_size(fi->size0[1], fi->level));
	for (int k = 0; k < 10; k++)
		if (rs_add_channel(h, qch[k], e) < 0)
			return -1;
	if (rs_add_channel(h, "Z", e) < 0 || rs_add_channel(h, "S", e) < 0 ||
	    rs_add_channel(h, "V", e) < 0)
		return -1;
	if (set_info(h, fi, "fqm", e) < 0)
		return -1;
	return rs_set_string(h, FQM_ATTR_KERNEL, kernel, e);
}

int
fqm_info_of(const rs_header *h, const char *want, fqm_info *fi,
    const char *what, tl_err *e)
{
	const char *kind = rs_get_string(h, FQM_ATTR_KIND);
	int version;

	memset(fi, 0, sizeof *fi);
	if (kind == NULL || rs_get_int(h, FQM_ATTR_VERSION, &version) < 0)
		return tl_fail(e, "%s: not a quadric or vertex map "
		    "(no fqm:kind / fqm:version attribute)", what);
	if (version != FQM_VERSION)
		return tl_fail(e, "%s: fqm version %d, this program reads %d",
		    what, version, FQM_VERSION);
	if (want != NULL && strcmp(kind, want) != 0)
		return tl_fail(e, "%s: is a %s map, expected %s", what, kind,
		    want);
	if (rs_get_int(h, FQM_ATTR_LEVEL, &fi->level) < 0 ||
	    rs_get_v2i(h, FQM_ATTR_SIZE0, fi->size0) < 0)
		return tl_fail(e, "%s: fqm:level or fqm:size0 missing", what);
	if (fi->level < 0 || fi->level > 30 || fi->size0[0] < 1 ||
	    fi->size0[1] < 1)
		return tl_fail(e, "%s: bad fqm:level %d or fqm:size0 %dx%d",
		    what, fi->level, fi->size0[0], fi->size0[1]);
	if (rs_get_int(h, RS_ATTR_X0, &fi->x0) < 0)
		fi->x0 = 0;
	if (fi->x0 < 0 || h->width < 1 || h->width >
	    geo_level_size(fi->size0[0], fi->level) - fi->x0 ||
	    h->height != geo_level_size(fi->size0[1], fi->level))
		return fi->x0 != 0 ? tl_fail(e, "%s: size %dx%d from column "
		    "%d is not inside level %d of a %dx%d DEM", what, h->width,
		    h->height, fi->x0, fi->level, fi->size0[0], fi->size0[1]) :
		    tl_fail(e, "%s: size %dx%d is not that of level %d of a "
		    "%dx%d DEM", what, h->width, h->height, fi->level,
		    fi->size0[0], fi->size0[1]);
	if (rs_get_georef(&fi->geo, h, e) < 0)
		return -1;
	fi->geo.width = fi->size0[0];
	fi->geo.height = fi->size0[1];
	return 0;
}

int
fqm_whole(const rs_header *h, const fqm_info *fi, const char *what,
    tl_err *e)
{
	if (fi->x0 == 0 && h->width == geo_level_size(fi->size0[0], fi->level))
		return 0;
	return tl_fail(e, "%s: columns %d..%d of level %d, not the whole "
	    "level (a band: give the band list)", what, fi->x0,
	    fi->x0 + h->width - 1, fi->level);
}

int
fqm_layout_of(const rs_header *h, fqm_layout *L, const char *what, tl_err *e)
{
	for (int k = 0; k < 10; k++)
		if ((L->q[k] = rs_need_channel(h, qch[k], what, e)) < 0)
			return -1;
	if ((L->z = rs_need_channel(h, "Z", what, e)) < 0 ||
	    (L->s = rs_need_channel(h, "S", what, e)) < 0 ||
	    (L->v = rs_need_channel(h, "V", what, e)) < 0)
		return -1;
	return 0;
}

rs_reader *
fqm_open(const char *path, fqm_info *fi, fqm_layout *L, tl_err *e)
{
	const char *what = tl_name(path, 0);
	rs_reader *in;

	if ((in = rs_open(path, e)) == NULL)
		return NULL;
	if (fqm_info_of(rs_header_of(in), "fqm", fi, what, e) < 0 ||
	    fqm_layout_of(rs_header_of(in), L, what, e) < 0) {
		rs_close(in);
		return NULL;
	}
	return in;
}
