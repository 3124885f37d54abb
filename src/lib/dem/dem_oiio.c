/* dem_oiio.c - the DEM adapter for what GDAL 3.6 does not read (EXR):
 * OpenImageIO through the plugin tl_oiio.so, loaded only when needed
 * (linking OpenImageIO costs ~130 MB of RSS). No georeferencing. */
#include <stdio.h>
#include <stdlib.h>

#include "dem/dem_impl.h"

static size_t
px_size(int t)
{
	switch (t) {
	case TL_PX_U8: case TL_PX_I8: return 1;
	case TL_PX_U16: case TL_PX_I16: return 2;
	case TL_PX_U32: case TL_PX_I32: case TL_PX_F32: return 4;
	}
	return 8;
}

static int
rows(dem_load *L, const tl_oiio_api *api, tl_oiio_img *img,
    const tl_oiio_info *info, int nch, tl_err *e)
{
	size_t rowbytes = px_size(info->type) * (size_t)nch * (size_t)L->w;
	char err[512] = "";
	char *buf = tl_alloc(rowbytes, (size_t)info->chunk, e);
	int r = 0;

	if (buf == NULL)
		return -1;
	for (int y = 0; y < L->h && r == 0; y += info->chunk) {
		int ny = L->h - y < info->chunk ? L->h - y : info->chunk;
		if (api->read_rows(img, y, y + ny, nch, buf, err, sizeof err) < 0) {
			r = tl_fail(e, "%s: truncated or corrupt: %s", L->what, err);
			break;
		}
		for (int k = 0; k < ny && r == 0; k++)
			r = dem_load_put(L, buf + k * rowbytes, info->type, nch,
			    0, y + k, L->w, NULL, e);
	}
	free(buf);
	return r;
}

/* dem_adapter's read: an input whose magic says EXR is known to be
 * ours (a failure is then an error, not "not ours"). */
static int
read_oiio(dem_load *L, georef *g, const char *path, const char *base,
    enum dem_input in, const dem_opts *o, tl_err *e)
{
	int known = in == DEM_IN_EXR;
	char why[512] = "";
	const tl_oiio_api *api = tl_oiio_load(why, sizeof why);
	tl_oiio_info info;
	tl_oiio_img *img;
	int nch, r = -1;

	(void)base;
	if (api == NULL)
		return known ? tl_fail(e, "%s: reading this format needs the "
		    "OpenImageIO plugin tl_oiio.so ($TL_OIIO_PLUGIN, beside the "
		    "program, or in its ../lib/terrain-lod): %s", L->what,
		    why) : 1;
	if ((img = api->open(path, &info, why, sizeof why)) == NULL)
		return known ? tl_fail(e, "%s: %s", L->what, why) : 1;
	if (info.chunk < 1)
		info.chunk = 1;
	if (dem_load_encoding(L, o, info.type, info.nchannels, e) < 0)
		goto out;
	nch = L->enc == DEM_ENC_GREY ? 1 : 3;
	geo_init_none(g, o->cell[0], o->cell[1]);
	if (dem_load_begin(L, g, o, info.width, info.height,
	    info.type == TL_PX_F32, e) < 0)
		goto out;
	r = L->info ? 0 : rows(L, api, img, &info, nch, e);
out:
	api->close(img);
	return r;
}

const dem_adapter dem_oiio_adapter = {
	"OpenImageIO", 1u << DEM_IN_NONE | 1u << DEM_IN_EXR, read_oiio, NULL,
};
