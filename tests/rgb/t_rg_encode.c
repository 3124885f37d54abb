/* t_rg_encode - the raster-dem encoders (rgb.h): every code decodes, by
 * the decoders' own formulas (MapLibre's DEMData.unpack, written out
 * here, not the encoder's), to within half a step of the height; the
 * steps and ranges are the formats'; a height past the range, NaN or
 * infinite is refused, never wrapped; halves round to the nearest code
 * up; PNG and WebP images carry the pixels losslessly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tap.h"
#include "rgb/rgb.h"

static double
unpack(enum rg_encoding enc, long c)
{
	double r = (double)(c >> 16), g = (double)(c >> 8 & 255),
	    b = (double)(c & 255);

	return enc == RG_TERRARIUM ? r * 256.0 + g * 1.0 + b / 256.0 - 32768.0 :
	    r * 6553.6 + g * 25.6 + b * 0.1 - 10000.0;
}

static int
sweep(enum rg_encoding enc, double lo, double hi, int n)
{
	double step = rg_step(enc), worst = 0;
	int bad = 0;

	srand(7);
	for (int k = 0; k < n; k++) {
		double h = lo + (hi - lo) * rand() / (double)RAND_MAX;
		long c = rg_code(enc, h);
		if (c < 0 || c > 16777215L) {
			bad++;
			continue;
		}
		worst = fmax(worst, fabs(unpack(enc, c) - h));
	}
	return bad == 0 && worst <= step / 2 * (1 + 1e-9);
}

int
main(void)
{
	double lo, hi;
	unsigned char px[64 * 64 * 3], *buf;
	size_t n;
	tl_err e;

	ok(rg_step(RG_TERRARIUM) == 1.0 / 256 && rg_step(RG_MAPBOX) == 0.1,
	    "steps: 1/256 m and 0.1 m");
	ok(sweep(RG_TERRARIUM, -11000, 9000, 200000),
	    "terrarium: 200000 heights within half a step after decoding");
	ok(sweep(RG_MAPBOX, -10000, 9000, 200000),
	    "mapbox: 200000 heights within half a step after decoding");
	ok(rg_code(RG_TERRARIUM, 0) == 0x800000 &&
	    rg_code(RG_MAPBOX, 0) == 100000, "height 0: 0x800000, 100000");
	/* exact halves: 1/512 above a code is its half step */
	ok(rg_code(RG_TERRARIUM, 1.0 / 512) == 0x800001 &&
	    rg_code(RG_TERRARIUM, -1.0 / 512) == 0x800000 &&
	    rg_code(RG_MAPBOX, -0.05) == 100000,
	    "a half step rounds up (codes are never negative)");
	ok(rg_code(RG_TERRARIUM, 100.0 / 256 + 1e-9) == 0x800000 + 100 &&
	    rg_code(RG_TERRARIUM, 100.49 / 256) == 0x800000 + 100 &&
	    rg_code(RG_TERRARIUM, 100.51 / 256) == 0x800000 + 101,
	    "terrarium: nearest step");
	ok(rg_code(RG_MAPBOX, 123.44) == 101234 &&
	    rg_code(RG_MAPBOX, 123.46) == 101235, "mapbox: nearest step");
	rg_range(RG_TERRARIUM, &lo, &hi);
	ok(rg_code(RG_TERRARIUM, lo) == 0 && rg_code(RG_TERRARIUM, hi) ==
	    16777215L && rg_code(RG_TERRARIUM, lo - 0.01) == -1 &&
	    rg_code(RG_TERRARIUM, hi + 0.01) == -1 &&
	    rg_code(RG_TERRARIUM, 40000) == -1,
	    "terrarium: range -32768 .. 32767.996, past it refused");
	rg_range(RG_MAPBOX, &lo, &hi);
	ok(rg_code(RG_MAPBOX, -10000) == 0 && rg_code(RG_MAPBOX, -10000.1) ==
	    -1 && rg_code(RG_MAPBOX, -11000) == -1 &&
	    rg_code(RG_MAPBOX, hi) == 16777215L &&
	    rg_code(RG_MAPBOX, hi + 1) == -1,
	    "mapbox: range -10000 .. 1667721.5, past it refused");
	ok(rg_code(RG_TERRARIUM, NAN) == -1 && rg_code(RG_MAPBOX, INFINITY) ==
	    -1, "NaN and infinity refused");
	ok(rg_decode(RG_TERRARIUM, 0x123456) == unpack(RG_TERRARIUM,
	    0x123456) && fabs(rg_decode(RG_MAPBOX, 0x123456) -
	    unpack(RG_MAPBOX, 0x123456)) < 1e-9, "rg_decode: the formulas");
	for (size_t i = 0; i < sizeof px; i++)
		px[i] = (unsigned char)(i * 37 + (i >> 7));
	ok(rg_image(RG_PNG, px, 64, &buf, &n, &e) == 0 && n > 8 &&
	    memcmp(buf, "\211PNG", 4) == 0, "PNG: a PNG signature");
	free(buf);
	ok(rg_image(RG_WEBP, px, 64, &buf, &n, &e) == 0 && n > 12 &&
	    memcmp(buf, "RIFF", 4) == 0 && memcmp(buf + 8, "WEBPVP8L", 8) ==
	    0, "WebP: a lossless (VP8L) WebP");
	free(buf);
	return tap_done();
}
