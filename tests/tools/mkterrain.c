/* mkterrain - write a synthetic but terrain-like SRTM .hgt tile (fractal
 * ridges and valleys, diamond-square with a fixed seed), georeferenced by
 * its file name: the default example's input on a machine without the
 * real DEMs of ../shared/data.
 *
 * usage: mkterrain [-n 1201|3601] out.hgt */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static double
urand(uint64_t *s)
{
	*s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(*s >> 11) / 9007199254740992.0 * 2 - 1;
}

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
	int n = 1201, c, m;
	uint64_t seed = 42;
	double *z, amp = 900;
	FILE *f;

	while ((c = getopt(argc, argv, "n:")) != -1)
		if (c == 'n')
			n = atoi(optarg);
		else
			return 2;
	if (argc - optind != 1 || (n != 1201 && n != 3601)) {
		fprintf(stderr, "usage: mkterrain [-n 1201|3601] out.hgt\n");
		return 2;
	}
	/* diamond-square on the enclosing 2^k+1 grid */
	for (m = 1; m + 1 < n; m *= 2)
		;
	m += 1;
	z = calloc((size_t)m * m, sizeof *z);
	for (int step = m - 1; step > 1; step /= 2, amp *= 0.55) {
		int h = step / 2;
		for (int y = h; y < m; y += step)
			for (int x = h; x < m; x += step)
				z[(size_t)y * m + x] = (z[(size_t)(y - h) * m + x - h] +
				    z[(size_t)(y - h) * m + x + h] +
				    z[(size_t)(y + h) * m + x - h] +
				    z[(size_t)(y + h) * m + x + h]) / 4 +
				    amp * urand(&seed);
		for (int y = 0; y < m; y += h)
			for (int x = (y / h) % 2 ? 0 : h; x < m; x += step) {
				double s = 0;
				int k = 0;
				if (y >= h) s += z[(size_t)(y - h) * m + x], k++;
				if (y + h < m) s += z[(size_t)(y + h) * m + x], k++;
				if (x >= h) s += z[(size_t)y * m + x - h], k++;
				if (x + h < m) s += z[(size_t)y * m + x + h], k++;
				z[(size_t)y * m + x] = s / k + amp * urand(&seed);
			}
	}
	if ((f = fopen(argv[optind], "wb")) == NULL) {
		perror(argv[optind]);
		return 1;
	}
	for (int y = 0; y < n; y++)
		for (int x = 0; x < n; x++) {
			/* ridges: fold the noise, lift it above sea level */
			double v = 1200 + fabs(z[(size_t)y * m + x]) * 1.5 -
			    0.3 * z[(size_t)y * m + x];
			int16_t h = (int16_t)lrint(fmax(0, fmin(8000, v)));
			unsigned char b[2] = { (unsigned char)(h >> 8),
				(unsigned char)h };
			fwrite(b, 1, 2, f);
		}
	if (fclose(f) != 0) {
		perror(argv[optind]);
		return 1;
	}
	free(z);
	return 0;
}
