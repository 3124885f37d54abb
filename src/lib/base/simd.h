/* simd.h - short vectors of doubles and floats for the row loops of the
 * filters (GCC/Clang vector extensions): element-wise IEEE operations,
 * each one the very operation a scalar loop would do on each element, so
 * that vectorised code computes bit for bit what its scalar form does
 * (C11 mode contracts nothing into fused multiply-adds: -ffp-contract=off).
 * Loads and stores are unaligned; 4-double vectors (two SSE registers)
 * are never passed by value, whose ABI would differ with AVX. Plain -O2 leaves loops of unknown
 * length scalar: these say "vector" without -O3 or -march. */
#ifndef TL_VEC_H
#define TL_VEC_H

#include <stdint.h>
#include <string.h>

#define VEC_N 2 /* doubles per vd */
typedef double vd __attribute__((vector_size(VEC_N * sizeof(double))));
typedef int64_t vl __attribute__((vector_size(VEC_N * sizeof(int64_t))));
typedef float vf4 __attribute__((vector_size(4 * sizeof(float))));
typedef double vd4 __attribute__((vector_size(4 * sizeof(double))));
typedef uint32_t vu4 __attribute__((vector_size(4 * sizeof(uint32_t))));

static inline vd
vd_load(const double *p)
{
	vd v;

	memcpy(&v, p, sizeof v);
	return v;
}

static inline void
vd_store(double *p, vd v)
{
	memcpy(p, &v, sizeof v);
}

static inline vd
vd_splat(double x)
{
	vd v;

	for (int i = 0; i < VEC_N; i++)
		v[i] = x;
	return v;
}

static inline vf4
vf4_load(const float *p)
{
	vf4 v;

	memcpy(&v, p, sizeof v);
	return v;
}

static inline void
vf4_store(float *p, vf4 v)
{
	memcpy(p, &v, sizeof v);
}

/* n floats to doubles, exactly. */
static inline void
vec_widen(const float *src, double *dst, size_t n)
{
	size_t i = 0;

	for (; i + 4 <= n; i += 4) {
		vd4 d = __builtin_convertvector(vf4_load(src + i), vd4);
		memcpy(dst + i, &d, sizeof d);
	}
	for (; i < n; i++)
		dst[i] = src[i];
}

/* n doubles to floats, rounded as a (float) cast rounds each. */
static inline void
vec_narrow(const double *src, float *dst, size_t n)
{
	size_t i = 0;

	for (; i + 4 <= n; i += 4) {
		vd4 d;
		memcpy(&d, src + i, sizeof d);
		vf4_store(dst + i, __builtin_convertvector(d, vf4));
	}
	for (; i < n; i++)
		dst[i] = (float)src[i];
}

/* 1 when none of n floats is a NaN or an infinity (exponent all ones). */
static inline int
vec_all_finite(const float *p, size_t n)
{
	const uint32_t e = 0x7f800000u;
	vu4 bad = { 0, 0, 0, 0 }, u;
	size_t i = 0;
	uint32_t b = 0;

	for (; i + 4 <= n; i += 4) {
		memcpy(&u, p + i, sizeof u);
		bad |= (vu4)((u & e) == e);
	}
	for (int k = 0; k < 4; k++)
		b |= bad[k];
	for (; i < n; i++) {
		uint32_t x;
		memcpy(&x, p + i, 4);
		b |= (x & e) == e;
	}
	return b == 0;
}

#endif
