/* pycmp - compare two pyramids block by block: the largest |dZ| and |dE|
 * per level and the number of differing vertices. A test tool.
 *
 * usage: pycmp dir1 dir2 */
#include <math.h>
#include <stdio.h>

#include "pyramid/pyramid.h"

/* A test tool exits right after its work: its own leaks are not what
 * make check-asan looks for (the programs' and the library's are). */
const char *__asan_default_options(void);
const char *
__asan_default_options(void)
{
	return "detect_leaks=0";
}

int
main(int argc, char **argv)
{
	pyramid_index a, b;
	tl_err e;
	int bad = 0;

	if (argc != 3) {
		fprintf(stderr, "usage: pycmp dir1 dir2\n");
		return 2;
	}
	if (pyramid_index_read(argv[1], &a, &e) < 0 || pyramid_index_read(argv[2], &b, &e) < 0) {
		fprintf(stderr, "pycmp: %s\n", e.msg);
		return 2;
	}
	if (a.nlevels != b.nlevels) {
		printf("levels %d vs %d\n", a.nlevels, b.nlevels);
		return 1;
	}
	for (int l = 0; l < a.nlevels; l++) {
		pyramid_level *L = &a.lev[l];
		double dz = 0, de = 0;
		long ndiff = 0;
		for (int bj = 0; bj < L->blocks[1]; bj++)
			for (int bi = 0; bi < L->blocks[0]; bi++) {
				pyramid_block x, y;
				char p[4096];
				pyramid_block_alloc(&x, L->displaced, &e);
				pyramid_block_alloc(&y, L->displaced, &e);
				x.level = y.level = l, x.bi = y.bi = bi, x.bj = y.bj = bj;
				pyramid_block_path(p, sizeof p, argv[1], l, bi, bj);
				if (pyramid_block_read(p, &x, &e) < 0)
					goto fail;
				pyramid_block_path(p, sizeof p, argv[2], l, bi, bj);
				if (pyramid_block_read(p, &y, &e) < 0)
					goto fail;
				for (int k = 0; k < PYRAMID_N; k++) {
					double d1 = fabs((double)x.z[k] - y.z[k]);
					double d2 = fabs((double)x.e[k] - y.e[k]);
					dz = fmax(dz, d1), de = fmax(de, d2);
					ndiff += d1 > 0 || d2 > 0;
				}
				pyramid_block_free(&x), pyramid_block_free(&y);
			}
		printf("level %d: max |dZ| %g, max |dE| %g, %ld vertices differ\n",
		    l, dz, de, ndiff);
		bad |= ndiff > 0;
	}
	return bad;
fail:
	fprintf(stderr, "pycmp: %s\n", e.msg);
	return 2;
}
