/* replay.c - runs a fuzz target over files, without libFuzzer: the
 * regression inputs and seeds in make check (tests/cmd/t_fuzz.sh), on
 * the ordinary build. usage: fz_NAME FILE... ; exit 0 when every input
 * was parsed (accepted or refused) without a crash. */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz.h"

int
main(int argc, char **argv)
{
	for (int i = 1; i < argc; i++) {
		FILE *f = fopen(argv[i], "rb");
		unsigned char *buf;
		long n;

		if (f == NULL || fseek(f, 0, SEEK_END) < 0 ||
		    (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) < 0) {
			perror(argv[i]);
			return 2;
		}
		if ((buf = malloc(n ? (size_t)n : 1)) == NULL ||
		    fread(buf, 1, (size_t)n, f) != (size_t)n) {
			perror(argv[i]);
			return 2;
		}
		fclose(f);
		LLVMFuzzerTestOneInput(buf, (size_t)n);
		free(buf);
	}
	return 0;
}
