/* fz_t3c - a glb of the 3D Tiles terrain profile as tilecheck --terrain
 * decodes and checks it (verify/t3c.h), untrusted: chunk lengths past
 * the bytes, accessors past their views, indices past the vertices. */
#include <string.h>

#include "fuzz.h"
#include "verify/t3c.h"

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	/* a level-3 tile's metadata, roughly where it lies */
	t3c_meta m = { 0, 1000, { 4e6, -4e5, 4.9e6, 4e5 }, { 0.6, -0.06,
	    0.8 } };
	qm_report r;
	t3c_tile t;
	tl_err e;

	qm_report_init(&r);
	if (t3c_decode(data, size, &t, &e) == 0)
		t3c_tile_check(&t, &m, 3, 8, 5, &r);
	t3c_free(&t);
	qm_report_free(&r);
	return 0;
}
