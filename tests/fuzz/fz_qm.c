/* fz_qm - a quantized-mesh tile as tilecheck --terrain decodes and
 * checks it (verify/qm.h), untrusted: counts past the bytes, indices
 * past the vertices, damaged gzip, extensions of any length. */
#include <string.h>

#include "fuzz.h"
#include "verify/qm.h"

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	qm_report r;
	qm_tile t;
	tl_err e;

	qm_report_init(&r);
	if (qm_decode(data, size, &t, &e) == 0) {
		(void)qm_checksum(&t);
		qm_tile_check(&t, 3, 8, 5, 1, &r);
	}
	qm_free(&t);
	qm_report_free(&r);
	return 0;
}
