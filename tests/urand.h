/* urand.h - the tests' random numbers: a small LCG with the seed in the
 * caller's hands, so every run draws the same values. */
#ifndef TL_TEST_URAND_H
#define TL_TEST_URAND_H

#include <math.h>

/* Uniform in [-1, 1). */
static inline double
urand(unsigned *s)
{
	*s = *s * 1103515245u + 12345u;
	return ((*s >> 8) & 0xffffff) / (double)0x1000000 * 2 - 1;
}

/* A float an FQM could hold, with the values that test signs and
 * edges: zeros of both signs, negatives, tiny and huge magnitudes. */
static inline float
any_float(unsigned *seed)
{
	double u = urand(seed), r = urand(seed);

	if (u < -0.6)
		return 0.0f;
	if (u < -0.4)
		return -0.0f;
	if (u > 0.97)
		return (float)(r * 1e30);
	if (u > 0.94)
		return (float)(r * 1e-30);
	if (u > 0.9)
		return r < 0 ? -1.0f : 1.0f;
	return (float)(r * pow(10, 6 * urand(seed)));
}

/* A rough value for (i, j, salt), the same every run: heights up to
 * 1000 m with float fractions, so no two planes share rounding by
 * accident. */
static inline float
rough(int i, int j, unsigned salt)
{
	unsigned x = (unsigned)i * 73856093u ^ (unsigned)j * 19349663u ^
	    salt * 83492791u;

	x ^= x >> 13, x *= 0x5bd1e995u, x ^= x >> 15;
	return (float)(x % 1000000u) / 997.0f;
}

/* A vertex offset up to 0.45 of a cell (jitter: the cell in metres)
 * for (i, j), salt 7 for x, 8 for y: the pack tests' displaced levels. */
static inline float
rough_offset(double jitter, int i, int j, unsigned salt)
{
	return (float)(jitter * (rough(i, j, salt) / 1003 - 0.5) * 0.9);
}

#endif
