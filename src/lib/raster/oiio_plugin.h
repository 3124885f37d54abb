/* oiio_plugin.h - the C interface of tl_oiio.so, the OpenImageIO reader
 * that the DEM reader loads with dlopen only for what GDAL does not read
 * (EXR) and the viewer for writing PNGs. Linking OpenImageIO costs ~130
 * MB of RSS, hence the plugin.
 *
 * The plugin exports one C function, TL_OIIO_ENTRY, returning a table of
 * function pointers (ABI 2 added write_u8, for tileplay's screenshots).
 * Errors come back as strings in the caller's buffer; no C++ exception
 * crosses the interface. Pixels are delivered in their native type
 * (OpenImageIO would normalise integers), half as float. */
#ifndef TL_OIIO_PLUGIN_H
#define TL_OIIO_PLUGIN_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TL_OIIO_ABI 2
#define TL_OIIO_ENTRY "tl_oiio_plugin"

enum tl_px {
	TL_PX_U8, TL_PX_I8, TL_PX_U16, TL_PX_I16, TL_PX_U32, TL_PX_I32,
	TL_PX_F32, TL_PX_F64
};

typedef struct {
	int width, height;
	int nchannels;
	enum tl_px type;  /* of every channel as delivered */
	int bits;         /* bits per sample in the file (8 for Terrain-RGB) */
	int chunk;        /* rows per read_rows call: tile height, or any */
	char format[32];  /* OpenImageIO format name, e.g. "png" */
} tl_oiio_info;

typedef struct tl_oiio_img tl_oiio_img;

typedef struct {
	int abi;          /* TL_OIIO_ABI */
	/* Opens the first subimage of path; NULL with err filled on failure. */
	tl_oiio_img *(*open)(const char *path, tl_oiio_info *info,
	    char *err, size_t errlen);
	/* Rows y0 <= y < y1, channels 0 <= c < nch, interleaved, all columns,
	 * into buf (width * (y1-y0) * nch samples of info.type). y0 must be a
	 * multiple of info.chunk, y1 one too or the height. 0, or -1 + err. */
	int (*read_rows)(tl_oiio_img *img, int y0, int y1, int nch, void *buf,
	    char *err, size_t errlen);
	void (*close)(tl_oiio_img *img);
	/* Writes w x h pixels of nch 8-bit channels, top-down rows, to path,
	 * in the format OpenImageIO names by `format` (a format name, an
	 * extension or a file name: "png", "out.png"). 0, or -1 + err. */
	int (*write_u8)(const char *path, const char *format, int w, int h,
	    int nch, const unsigned char *px, char *err, size_t errlen);
} tl_oiio_api;

typedef const tl_oiio_api *(*tl_oiio_entry_fn)(void);

const tl_oiio_api *tl_oiio_plugin(void);

#ifndef __cplusplus
/* The plugin: $TL_OIIO_PLUGIN, else beside the program, else
 * ../lib/terrain-lod from it, else TL_LIBDIR; loaded once and kept
 * (oiio_load.c). NULL with the reason in why. */
const tl_oiio_api *tl_oiio_load(char *why, size_t n);
#endif

#ifdef __cplusplus
}
#endif

#endif
