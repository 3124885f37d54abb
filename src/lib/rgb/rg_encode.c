/* rg_encode.c - heights to the 24-bit codes of Terrarium and Mapbox
 * Terrain-RGB and back (rgb.h): rounded to the nearest step, a height
 * past the encoding's range refused rather than wrapped or clamped. */
#include <math.h>

#include "rgb/rgb.h"

#define CODE_MAX 16777215L /* 2^24 - 1 */

double
rg_step(enum rg_encoding enc)
{
	return enc == RG_TERRARIUM ? 1.0 / 256 : 0.1;
}

const char *
rg_encoding_name(enum rg_encoding enc)
{
	return enc == RG_TERRARIUM ? "terrarium" : "mapbox";
}

/* code = h / step + offset, offset the code of height 0 */
long
rg_code(enum rg_encoding enc, double h)
{
	double c;

	if (!isfinite(h))
		return -1;
	/* Terrarium: h 256 exactly (a power of two); Mapbox: h 10 */
	c = enc == RG_TERRARIUM ? h * 256 + 8388608.0 : h * 10 + 100000.0;
	c = round(c);
	if (!(c >= 0 && c <= CODE_MAX))
		return -1;
	return (long)c;
}

double
rg_decode(enum rg_encoding enc, long code)
{
	int r = (int)(code >> 16), g = (int)(code >> 8 & 255),
	    b = (int)(code & 255);

	/* the decoders' own formulas (MapLibre's DEMData.unpack) */
	if (enc == RG_TERRARIUM)
		return r * 256.0 + g + b / 256.0 - 32768.0;
	return -10000.0 + (r * 65536.0 + g * 256.0 + b) * 0.1;
}

void
rg_range(enum rg_encoding enc, double *lo, double *hi)
{
	if (enc == RG_TERRARIUM)
		*lo = -32768, *hi = 32768 - 1.0 / 256;
	else
		*lo = -10000, *hi = -10000 + CODE_MAX * 0.1;
}
