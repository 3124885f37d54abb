/* fz_raster - the raster layer's readers: the fqm(5) stream and EXR
 * scanline files (detected by magic, as every program reads them), then
 * the FQM and vertex-map meaning of the header (fqm_info_of,
 * fqm_layout_of) and every row. */
#include <stdlib.h>

#include "qem/fqm.h"
#include "raster/raster.h"
#include "fuzz.h"

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *path = fuzz_file("r", data, size);
	const rs_header *h;
	rs_reader *r;
	fqm_info fi;
	fqm_layout L;
	float *row;
	tl_err e;

	if (path == NULL || (r = rs_open(path, &e)) == NULL)
		return 0;
	h = rs_header_of(r);
	(void)fqm_info_of(h, "fqm", &fi, "fuzz", &e);
	(void)fqm_info_of(h, "vertices", &fi, "fuzz", &e);
	(void)fqm_layout_of(h, &L, "fuzz", &e);
	/* rows only for sizes a reader accepted: the header was checked */
	row = malloc((size_t)h->width * (h->nch ? h->nch : 1) * sizeof *row);
	for (int y = 0; row != NULL && y < h->height; y++)
		if (rs_read_row(r, row, &e) < 0)
			break;
	free(row);
	rs_close(r);
	return 0;
}
