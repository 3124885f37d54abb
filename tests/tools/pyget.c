/* pyget - Z, E (and X, Y) of a level vertex as stored in every block that
 * holds it (a border vertex is in 2 or 4 blocks). A test tool.
 *
 * usage: pyget dir level gi gj
 * prints one line per block: "bi bj Z E [X Y]" */
#include <stdio.h>
#include <stdlib.h>

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
	pyramid_index ix;
	tl_err e;
	int l, gi, gj, found = 0;

	if (argc != 5) {
		fprintf(stderr, "usage: pyget dir level gi gj\n");
		return 2;
	}
	l = atoi(argv[2]), gi = atoi(argv[3]), gj = atoi(argv[4]);
	if (pyramid_index_read(argv[1], &ix, &e) < 0 || l < 0 || l >= ix.nlevels) {
		fprintf(stderr, "pyget: %s\n", l < 0 ? "bad level" : e.msg);
		return 1;
	}
	pyramid_level *L = &ix.lev[l];
	for (int bj = 0; bj < L->blocks[1]; bj++)
		for (int bi = 0; bi < L->blocks[0]; bi++) {
			int c = gi - bi * BT_CELLS, r = gj - bj * BT_CELLS, k;
			char p[4096];
			pyramid_block b;
			if (c < 0 || r < 0 || c > BT_CELLS || r > BT_CELLS)
				continue;
			pyramid_block_alloc(&b, L->displaced, &e);
			b.level = l, b.bi = bi, b.bj = bj;
			pyramid_block_path(p, sizeof p, argv[1], l, bi, bj);
			if (pyramid_block_read(p, &b, &e) < 0) {
				fprintf(stderr, "pyget: %s\n", e.msg);
				return 1;
			}
			k = r * BT_SIZE + c;
			printf("%d %d %.9g %.9g", bi, bj, b.z[k], b.e[k]);
			if (L->displaced)
				printf(" %.9g %.9g", b.x[k], b.y[k]);
			printf("\n");
			pyramid_block_free(&b);
			found++;
		}
	pyramid_index_free(&ix);
	return found ? 0 : 1;
}
