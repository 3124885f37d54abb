/* tiff.h - a float32 TIFF DEM for the tests of the pyramid layer (no
 * georeferencing: dem.c gives it a unit grid, or the cell of -s). */
#ifndef T_TIFF_H
#define T_TIFF_H

#include <stddef.h>
#include <tiffio.h>

static int
write_tiff(const char *path, int w, int h, const float *z)
{
	TIFF *t = TIFFOpen(path, "w");
	int r = 0;

	if (t == NULL)
		return -1;
	TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
	TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
	TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 32);
	TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
	TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
	TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
	TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
	TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, 16);
	for (int j = 0; j < h && r == 0; j++)
		if (TIFFWriteScanline(t, (void *)(z + (size_t)j * w), j, 0) < 0)
			r = -1;
	TIFFClose(t);
	return r;
}

#endif
