/* fz_index - a pyramid's index.json as the viewer (pyramid_index_read)
 * and the checker (vf_index_read, its own reader) read it, untrusted:
 * absurd level counts and sizes, wrong types, NaN, paths. */
#include <string.h>

#include "fuzz.h"
#include "pyramid/pyramid.h"
#include "verify/verify.h"

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *path = fuzz_file("index.json", data, size);
	char dir[512];
	pyramid_index px;
	vf_index vx;
	tl_err e;

	if (path == NULL)
		return 0;
	snprintf(dir, sizeof dir, "%s", path);
	*strrchr(dir, '/') = '\0';
	memset(&px, 0, sizeof px);
	if (pyramid_index_read(dir, &px, &e) == 0)
		pyramid_index_free(&px);
	memset(&vx, 0, sizeof vx);
	if (vf_index_read(dir, &vx, &e) == 0)
		vf_index_free(&vx);
	return 0;
}
